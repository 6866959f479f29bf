# SPDX-License-Identifier: Apache-2.0
"""The formal equivalence checks of ``make mutants`` (sim/mutation.py): a mutant that every
check passes, against the original design, in Yosys.

The ROM tables are cut out of both designs (``cut_roms``).  Two kinds of proof
(``equivalence``):

* Yosys's equivalence flow, ``equiv_make`` (a ``$equiv`` cell per bit of every named wire the
  two designs share) and ``equiv_simple -seq N`` (each cell proven from its own logic cone, N
  cycles back, with the cells at the cone's edge taken as holding), the wires whose cells it
  cannot prove unmatched and the flow run again until every cell is proven or an output's
  cell is not (``_prove_local``): equal from any state the two designs share.
* ``equiv_make -make_assert`` (an assert per matched named wire) and ``sat -tempinduct``: the
  base case from the same all-zero state with rst_n low in the first cycle, the induction step
  from any state, up to a few cycles long (``_prove``).

A verdict is kept per folder for the same netlists and script.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import threading
from pathlib import Path

from sim.gate import yosys_exe


def mutate_field(command: str, name: str) -> str:
    """The value of option ``-<name>`` of a ``mutate`` command ('' if it has none)."""
    found = re.search(rf"-{name} (\S+)", command)
    return found.group(1) if found else ""


def run_yosys(script: str, folder: Path, log: str) -> None:
    """Run the Yosys script ``script`` as ``<log>.ys`` in ``folder`` (log ``<log>.log``)."""
    (folder / f"{log}.ys").write_text(script)
    ran = subprocess.run(
        [yosys_exe(), "-q", "-l", f"{log}.log", "-s", f"{log}.ys"],
        capture_output=True,
        text=True,
        cwd=folder,
        timeout=3600,
    )
    if ran.returncode != 0:
        raise RuntimeError(f"yosys {log}.ys in {folder} failed:\n{ran.stdout}{ran.stderr}")


def cut_roms(il: str) -> str:
    """The RTLIL ``il`` with every ROM (a ``$mem_v2`` without write ports) cut out: its read
    address (and enable) become output ports, its read data an input port.  Equivalence through
    the cut is proven for any read data, the same in both designs whenever their addresses are
    (proven, as outputs): sound, and SAT never sees a table."""
    lines = il.split("\n")
    out: list[str] = []
    extra_wires: list[str] = []
    k = 0
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.strip().startswith("cell $mem_v2 "):
            block = [line]
            while lines[i].strip() != "end":
                i += 1
                block.append(lines[i])
            params = dict(re.findall(r"^\s*parameter \\(\w+) (.*)$", "\n".join(block), re.M))
            conns = dict(re.findall(r"^\s*connect \\(\w+) (.*)$", "\n".join(block), re.M))
            if params.get("WR_PORTS") != "0":
                out.extend(block)
                i += 1
                continue
            while out and out[-1].strip().startswith("attribute "):
                out.pop()  # the cell's attributes go with it
            ports = int(params["RD_PORTS"])
            abits, width = int(params["ABITS"]) * ports, int(params["WIDTH"]) * ports
            name = f"\\mutation_rom{k}"
            extra_wires.append(f"  wire width {abits} output {{port}} {name}_addr")
            extra_wires.append(f"  wire width {width} input {{port}} {name}_data")
            out.append(f"  connect {name}_addr {conns['RD_ADDR']}")
            out.append(f"  connect {conns['RD_DATA']} {name}_data")
            if not re.fullmatch(r"\d+'1+", conns["RD_EN"]):
                extra_wires.append(f"  wire width {ports} output {{port}} {name}_en")
                out.append(f"  connect {name}_en {conns['RD_EN']}")
            k += 1
        else:
            out.append(line)
        i += 1
    if not extra_wires:
        return il
    text = "\n".join(out)
    port = max(int(n) for n in re.findall(r"^\s*wire .*(?:input|output) (\d+) ", text, re.M))
    numbered = []
    for w in extra_wires:
        port += 1
        numbered.append(w.format(port=port))
    head, rest = text.split("\nmodule ", 1)
    first, body = rest.split("\n", 1)
    return f"{head}\nmodule {first}\n" + "\n".join(numbered) + "\n" + body


def observed(il: str, top: str, wires: list[str], condition: str) -> str:
    """The RTLIL ``il`` with a wire ``<w>__while_<condition>`` = ``condition ? w : 0`` for
    each wire ``w`` of ``wires``: what ``w`` shows while ``condition`` holds."""
    widths = dict(
        (name, int(width or 1))
        for width, name in re.findall(r"^\s*wire (?:width (\d+) )?(?:\w+ \d+ )?(\\\S+)$", il, re.M)
    )
    decls, cells = [], []
    for k, w in enumerate(wires):
        name = f"\\{w}"
        if name not in widths:
            continue
        n = widths[name]
        obs = f"{name}__while_{condition}"
        decls.append(f"  wire width {n} {obs}")
        cells += [
            f"  cell $mux $mutation_observe{k}",
            f"    parameter \\WIDTH {n}",
            f"    connect \\A {n}'{'0' * n}",
            f"    connect \\B {name}",
            f"    connect \\S \\{condition}",
            f"    connect \\Y {obs}",
            "  end",
        ]
    head, rest = il.split(f"\nmodule \\{top}\n", 1)
    body, tail = rest.rsplit("\nend\n", 1)
    return (
        f"{head}\nmodule \\{top}\n" + "\n".join(decls) + "\n" + body + "\n"
        + "\n".join(cells) + "\nend\n" + tail
    )  # fmt: skip


# A unit's registers that its start loads and only a busy unit reads: a mutation that changes
# them while the unit is idle changes nothing it shows (``equivalence``, the second method).
BUSY = "busy_reg"
# Ports whose mutation no proof here can judge: Yosys's SAT model steps every flip-flop once a
# cycle, whatever drives its clock, so an inverted clock would look unchanged.
CLOCK_PORTS = ("CLK", "RD_CLK", "WR_CLK")


def unread_clock(il: str, command: str) -> str | None:
    """Why the clock the mutation ``command`` changes is never read, or None: a ROM's
    (``$mem_v2``'s) read clock where every read port is asynchronous (``RD_CLK_ENABLE`` all 0:
    Yosys's cell reads the port's clock only for a clocked port), its write clock where it has
    no write port."""
    port, cell = mutate_field(command, "port"), mutate_field(command, "cell")
    found = re.search(rf"^\s*cell \$mem_v2 \\{re.escape(cell)}\n(.*?)^\s*end$", il, re.M | re.S)
    if found is None:
        return None
    params = dict(re.findall(r"^\s*parameter \\(\w+) (\S+)$", found.group(1), re.M))
    if port == "RD_CLK" and re.fullmatch(r"\d+'0+", params.get("RD_CLK_ENABLE", "")):
        return (
            "the ROM's read ports are asynchronous (RD_CLK_ENABLE = 0): the cell never reads RD_CLK"
        )
    if port == "WR_CLK" and params.get("WR_PORTS") == "0":
        return "the memory has no write port: the cell never reads WR_CLK"
    return None


_verdict_lock = threading.Lock()


def _prove(folder: Path, top: str, blacklist: list[str], steps: int, timeout: float) -> bool:
    """Every named wire of ``gold_cut.il`` and ``gate_cut.il`` but ``blacklist``'s equal in
    every cycle: ``equiv_make -make_assert`` (an assert per matched wire), then ``sat
    -tempinduct``: the base case from the same all-zero state with rst_n low in the first
    cycle, the induction step for any state, up to ``steps`` cycles long."""
    (folder / "blacklist.txt").write_text("".join(f"{w}\n" for w in blacklist))
    script = (
        f"read_rtlil gate_cut.il\nrename {top} gate\nread_rtlil gold_cut.il\nrename {top} gold\n"
        "equiv_make -make_assert -blacklist blacklist.txt gold gate equiv\nhierarchy -top equiv\n"
        "flatten\nopt_clean\n"
        f"sat -verify -tempinduct -prove-asserts -set-init-zero -set-at 1 rst_n 0 "
        f"-maxsteps {steps} equiv\n"
    )
    (folder / "equiv.ys").write_text(script)
    # a verdict is kept for the same netlists, script and time limit (a rerun proves nothing twice)
    digest = hashlib.sha256(repr((script, timeout)).encode())
    for name in ("gold_cut.il", "gate_cut.il", "blacklist.txt"):
        digest.update((folder / name).read_bytes())
    verdicts = folder.parent / "verdicts.json"
    known = json.loads(verdicts.read_text()) if verdicts.exists() else {}
    key = digest.hexdigest()
    if key in known:
        return bool(known[key])
    try:
        ran = subprocess.run(
            [yosys_exe(), "-q", "-l", "equiv.log", "-s", "equiv.ys"],
            capture_output=True,
            text=True,
            cwd=folder,
            timeout=timeout,
        )
        proven = (
            ran.returncode == 0
            and "Induction step proven: SUCCESS!" in (folder / "equiv.log").read_text()
        )
    except subprocess.TimeoutExpired:
        proven = False
    with _verdict_lock:
        known = json.loads(verdicts.read_text()) if verdicts.exists() else {}
        known[key] = proven
        verdicts.write_text(json.dumps(known, indent=1) + "\n")
    return proven


def _ports(il: str, top: str) -> set[str]:
    """The port names of module ``top`` in the RTLIL ``il``."""
    body = il.split(f"\nmodule \\{top}\n", 1)[1].split("\nend\n", 1)[0]
    port = r"^\s*wire (?:width \d+ )?(?:input|output|inout) \d+ \\(\S+)$"
    return set(re.findall(port, body, re.M))


# Rounds of the local flow: each leaves the wires whose cells the last could not prove unmatched
LOCAL_ROUNDS = 8


def _prove_local(folder: Path, top: str, blacklist: list[str], steps: int, timeout: float) -> (
    list[str] | None
):  # fmt: skip
    """Every cell of Yosys's equivalence flow proven between ``gold_cut.il`` and
    ``gate_cut.il``, the wires of ``blacklist`` and those the flow finds unequal left unmatched:
    ``equiv_make -blacklist``, ``equiv_simple -seq <steps>`` (each bit of each matched wire
    proven from its logic cone, ``steps`` cycles back, the matched bits at the cone's edge taken
    as equal), ``equiv_status``.  A wire with an unproven bit is left unmatched and the flow run
    again (a bit below a rounding point differs, and so does the sum it feeds; the rounded
    value does not), up to LOCAL_ROUNDS times; a port with an unproven bit ends it (not
    proven).  What it proves: from any state the two designs share, every matched wire, and
    so every output, is equal in every cycle (each cell by its cone; the cones' edges by
    induction over cycles and over the logic's order).  The wires left unmatched, or None if
    not proven."""
    gold = (folder / "gold_cut.il").read_text()
    ports = _ports(gold, top)
    black = list(dict.fromkeys(w for w in blacklist if w))
    for _ in range(LOCAL_ROUNDS):
        (folder / "local_blacklist.txt").write_text("".join(f"{w}\n" for w in black))
        script = (
            f"read_rtlil gate_cut.il\nrename {top} gate\n"
            f"read_rtlil gold_cut.il\nrename {top} gold\n"
            "equiv_make -blacklist local_blacklist.txt gold gate equiv\nhierarchy -top equiv\n"
            f"flatten\nopt_clean\nequiv_simple -seq {steps}\nequiv_status\n"
        )
        (folder / "local.ys").write_text(script)
        try:
            subprocess.run(
                [yosys_exe(), "-q", "-l", "local.log", "-s", "local.ys"],
                capture_output=True,
                text=True,
                cwd=folder,
                timeout=timeout,
            )
        except subprocess.TimeoutExpired:
            return None
        log = (folder / "local.log").read_text()
        if "Equivalence successfully proven!" in log:
            return black
        # "Unproven $equiv <cell>: \<wire>_gold \<wire>_gate", a bit index after each name
        unproven = set(re.findall(r"Unproven \$equiv \S+: \\(\S+)_gold\s", log))
        if not unproven or unproven & ports or unproven <= set(black):
            return None
        black += sorted(unproven - set(black))
    return None


def equivalence(
    folder: Path, top: str, design_il: Path, command: str, unit: bool, seq: int = 4,
    timeout: float = 90,
) -> str | None:  # fmt: skip
    """Prove the design ``design_il`` (RTLIL, module ``top``) with the mutation ``command``
    equal to the original, the ROMs cut (``cut_roms``), in ``folder``: every matched named
    wire equal in every cycle (``_prove``); ``unit``: the second method may be tried.

    First method: every named wire is matched but the one the mutation drives (a dead bit
    differs there and nowhere else).  Second (a unit): the named wires the mutation reaches up
    to the next registers and on to the registers after them are left out, and each is matched
    as what it shows while the unit is busy (``observed``): a register the mutation changes
    only while the unit is idle, which the next start loads again.  The method's text, or None
    if neither proves it."""
    if mutate_field(command, "port") in CLOCK_PORTS:
        # SAT steps every flip-flop on one clock: a clock mutation is out of its reach, unless
        # the cell never reads that clock
        return unread_clock(design_il.read_text(), command)
    folder.mkdir(parents=True, exist_ok=True)
    original = os.path.relpath(design_il, folder)  # the WebAssembly Yosys: relative paths
    run_yosys(
        f"read_rtlil {original}\n{command}\nwrite_rtlil gate.il\n"
        f"design -reset\nread_rtlil {original}\n"
        f"select -write fanout.txt c:{mutate_field(command, 'cell')} %co*:-[Q] %co:+[Q] "
        "%co*:-[Q] w:* %i\n",
        folder,
        "mutate",
    )
    gold, gate = design_il.read_text(), (folder / "gate.il").read_text()
    (folder / "gold_cut.il").write_text(cut_roms(gold))
    (folder / "gate_cut.il").write_text(cut_roms(gate))
    unmatched = _prove_local(folder, top, [mutate_field(command, "wire")], seq, timeout)
    if unmatched is not None:
        but = f" but {', '.join(unmatched)}" if unmatched else ""
        return f"equiv_simple -seq {seq} from any shared state, every named wire matched{but}"
    if _prove(folder, top, [mutate_field(command, "wire")], seq, timeout):
        return f"sat -tempinduct (to {seq} cycles), every named wire but the mutated one matched"
    if not unit:
        return None
    fanout = [
        line.split("/", 1)[1]
        for line in (folder / "fanout.txt").read_text().splitlines()
        if "/" in line and not line.split("/", 1)[1].startswith("$")
    ]
    (folder / "gold_cut.il").write_text(observed(cut_roms(gold), top, fanout, BUSY))
    (folder / "gate_cut.il").write_text(observed(cut_roms(gate), top, fanout, BUSY))
    if _prove(folder, top, fanout, seq, timeout):
        return f"sat -tempinduct (to {seq} cycles), the mutation's fanout matched while {BUSY}"
    return None
