# SPDX-License-Identifier: Apache-2.0
"""The formal equivalence checks of ``make mutants`` (sim/mutation.py): a mutant that every
check passes, against the original design, in Yosys.

The ROM tables are cut out of both designs (``cut_roms``).  Five kinds of proof
(``equivalence``):

* Yosys's equivalence flow, ``equiv_make`` (a ``$equiv`` cell per bit of every named wire the
  two designs share) and ``equiv_simple -seq N`` (each cell proven from its own logic cone, N
  cycles back, with the cells at the cone's edge taken as holding), the wires whose cells it
  cannot prove unmatched and the flow run again until every cell is proven or an output's
  cell is not (``_prove_local``): equal from any state the two designs share.
* ``equiv_make -make_assert`` (an assert per matched named wire) and ``sat -tempinduct``: the
  base case from the same all-zero state with rst_n low in the first cycle, the induction step
  from any state, up to a few cycles long (``_prove``).
* A miter of the two, both from the same power-up state with rst_n low in the first cycle,
  asserting the outputs equal after reset as the design's contract defines them (``Contract``:
  the data outputs only where defined), proven unbounded by ABC's ``scorr`` and ``pdr``
  (``_prove_from_reset``): equal from reset, which needs no invariant to be spelled out (a
  counter's bound), if pdr finds it in its time.
* The same miter with the multipliers cut as the ROMs are (``cut_products``: the mutant's
  product is the original's where their operands agree, any value where not), then with
  invariants over both copies' wires (sim/mutation_invariants.py, ``probed``) asserted
  alongside the outputs: what pdr does not find through a multiplier, or at all in its time
  (a stage register equal in the two copies while its valid bit is set), then with a
  design's stronger set (the BRDF unit's other registers equal in every cycle).
* A window of a unit's datapath (``Window``, ``prove_window``): the two designs from two
  unrelated arbitrary states, the pixel's table address free, the line's constant loaded
  from the tables, whose words are kept, as are the multipliers, the word the window computes
  compared in the cycle it is ready: the miter unrolled by ABC to that cycle, then evaluated
  on every assignment of the few inputs its cone reads (sim/aiger_eval.py): what holds only
  for the tables' words and the products they give.

A verdict is kept per folder for the same netlists and script.

The netlist surgery they share (the ROM and product cuts, the probes of the invariants) is
sim/mutation_cuts.py.

Size: about 900 lines: the five proofs share the miter's netlists, the verdict cache and the
Yosys runs; each is one method of telling a mutant from the original.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import threading
from dataclasses import dataclass
from pathlib import Path

from sim.aiger_eval import Aig, first_one, read_aiger, support
from sim.gate import yosys_exe
from sim.mutation_cuts import (
    PROBE,
    PRODUCT,
    add_ports,
    cut_products,
    cut_roms,
    invariant_verilog,
    invariant_wires,
    observed,
    probe_name,
    probed,
    product_cuts,
    rom_reads,
    roms_filled,
)


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


# A unit's registers that its start loads and only a busy unit reads: a mutation that changes
# them while the unit is idle changes nothing it shows (``equivalence``, the second method).
BUSY = "busy_reg"
# Ports whose mutation no proof here can judge: Yosys's SAT model steps every flip-flop once a
# cycle, whatever drives its clock, so an inverted clock would look unchanged.
CLOCK_PORTS = ("CLK", "RD_CLK", "WR_CLK")
# The ports of a ``$mem_v2`` read port that an asynchronous one (``RD_CLK_ENABLE`` 0) never
# reads: its clock, and its enable and resets, which Yosys requires to be the constants 1, 0
# and 0 there (kernel/mem.cc asserts it, so ``write_verilog`` refuses a netlist where a
# mutation drives one: ``unbuildable``)
ASYNC_UNREAD = ("RD_CLK", "RD_EN", "RD_ARST", "RD_SRST")


def unread_port(il: str, command: str) -> str | None:
    """Why the port of a memory the mutation ``command`` changes is never read, or None: a
    ROM's (``$mem_v2``'s) read clock, enable or resets where every read port is asynchronous
    (``RD_CLK_ENABLE`` all 0: Yosys's cell reads them only for a clocked port, and requires
    the enable 1 and the resets 0), its write clock where it has no write port."""
    port, cell = mutate_field(command, "port"), mutate_field(command, "cell")
    found = re.search(rf"^\s*cell \$mem_v2 \\{re.escape(cell)}\n(.*?)^\s*end$", il, re.M | re.S)
    if found is None:
        return None
    params = dict(re.findall(r"^\s*parameter \\(\w+) (\S+)$", found.group(1), re.M))
    if port in ASYNC_UNREAD and re.fullmatch(r"\d+'0+", params.get("RD_CLK_ENABLE", "")):
        why = "the ROM's read ports are asynchronous (RD_CLK_ENABLE = 0)"
        return f"{why}: the cell never reads {port}"
    if port == "WR_CLK" and params.get("WR_PORTS") == "0":
        return "the memory has no write port: the cell never reads WR_CLK"
    return None


def unbuildable(il: str, command: str) -> bool:
    """The mutation ``command`` drives a port of an asynchronous read port that Yosys requires
    to be constant (``ASYNC_UNREAD`` but the clock): no netlist can hold it, and the cell never
    reads the port (``unread_port``), so the mutant is the original."""
    return mutate_field(command, "port") != "RD_CLK" and (
        mutate_field(command, "port") in ASYNC_UNREAD and unread_port(il, command) is not None
    )


_verdict_lock = threading.Lock()


def _known(folder: Path, key: str) -> str | bool | None:
    """The verdict kept for ``key`` beside ``folder`` (its parent's verdicts.json), or None."""
    verdicts = folder.parent / "verdicts.json"
    return (json.loads(verdicts.read_text()) if verdicts.exists() else {}).get(key)


def _keep(folder: Path, key: str, verdict: str | bool) -> None:
    """Keep ``verdict`` for ``key`` beside ``folder`` (a rerun proves nothing twice)."""
    with _verdict_lock:
        verdicts = folder.parent / "verdicts.json"
        known = json.loads(verdicts.read_text()) if verdicts.exists() else {}
        known[key] = verdict
        verdicts.write_text(json.dumps(known, indent=1) + "\n")


def _yosys_within(folder: Path, script: str, timeout: float) -> bool:
    """Run the Yosys script file ``script`` in ``folder`` (log ``<script>.log``), stopped after
    ``timeout`` seconds: whether it ran to its end without an error."""
    try:
        ran = subprocess.run(
            [yosys_exe(), "-q", "-l", f"{script}.log", "-s", script],
            capture_output=True,
            text=True,
            cwd=folder,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return False
    return ran.returncode == 0


def _mutant(folder: Path, design_il: Path, command: str) -> str:
    """The design ``design_il`` with the mutation ``command`` (RTLIL, ``folder``/gate.il)."""
    original = os.path.relpath(design_il, folder)  # the WebAssembly Yosys: relative paths
    run_yosys(f"read_rtlil {original}\n{command}\nwrite_rtlil gate.il\n", folder, "mutate")
    return (folder / "gate.il").read_text()


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
    key = digest.hexdigest()
    cached = _known(folder, key)
    if cached is not None:
        return bool(cached)
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
    _keep(folder, key, proven)
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


# ---------------------------------------------------------------- the third proof: from reset
@dataclass(frozen=True)
class Contract:
    """What a design's outputs must show after reset, as the from-reset proof compares them
    (``_prove_from_reset``): every output but ``data`` in every cycle (busy, valid, flags,
    strobes, handshakes); ``data`` only where defined, from a cycle with ``valid`` = 1 until the
    next reset (``held``: a unit's data outputs hold the last result, rule 5 of
    docs/architecture.md and the protocol model's "data" outputs) or in the cycles with
    ``valid`` = 1 only (an AXI4-Stream payload, the core's ``m_axis_tdata`` while
    ``m_axis_tvalid``)."""

    valid: str
    data: tuple[str, ...]
    held: bool


# The first cycle's flag and the power-up state the two copies share (``shared_power_up``)
FIRST = "mutation_first"
POWER_UP = "mutation_init"
# The ABC engine and the verdict file it writes (``write_status``)
PDR_STATUS = "pdr_status.txt"
# Seconds given to ``pdr`` (the conversion and ``scorr`` come on top, a minute at most)
PDR_TIMEOUT = 300.0
# The miter after ABC's ``scorr`` (the registers it proves equal merged), which ``pdr`` is given
REDUCED = "pdr_reduced.aig"
# With invariants: ABC's ``ind`` (k-induction to IND_FRAMES frames) first, and its verdict file.
# The outputs and invariants together are often inductive as they stand, and ``scorr``'s
# reduction can hide that from ``pdr`` (the quadratic form's step-condition mutant: ``ind``
# proves it in seconds, ``pdr`` in 15 s on the miter itself, not in 900 s after ``scorr``)
IND_FRAMES = 2
IND_STATUS = "ind_status.txt"


def _constant_false(aig: Path) -> bool:
    """The AIGER file ``aig`` has no latch, no gate and every output the constant 0 (ABC's
    ``scorr`` left nothing for ``pdr``, which needs a latch, to prove)."""
    if not aig.exists():
        return False
    lines = aig.read_bytes().split(b"\n")
    header = lines[0].split()
    if header[:1] not in ([b"aig"], [b"aag"]) or len(header) < 6:
        return False
    inputs, latches, outputs, ands = (int(x) for x in header[2:6])
    skip = inputs if header[0] == b"aag" else 0
    listed = lines[1 + skip : 1 + skip + outputs]
    return (
        latches == 0
        and ands == 0
        and len(listed) == outputs
        and all(ln.strip() == b"0" for ln in listed)
    )


def shared_power_up(il: str, top: str) -> str:
    """The RTLIL ``il`` with the power-up state of every ``$dff`` of ``top`` (``prep`` leaves
    no other kind of flip-flop in these designs; a memory's words, mapped later, start free in
    each copy) an input: an input
    ``mutation_first`` (1 in the first cycle only) and, for the k-th flip-flop by cell name, an
    input ``mutation_init<k>`` of its width, which its readers see in the first cycle instead
    of its output (``first ? init : Q``).  Two designs with the same flip-flop cells, the same
    inputs given to both, start from the same arbitrary state: what a register without a reset
    holds at power-up is the same in both, as in one chip."""
    body = il.split(f"\nmodule \\{top}\n", 1)[1].split("\nend\n", 1)[0]
    cells = re.findall(r"^\s*cell \$dff (\S+)\n(.*?)^\s*end$", body, re.M | re.S)
    order = {name: k for k, name in enumerate(sorted(name for name, _ in cells))}
    port = max(int(n) for n in re.findall(r"^\s*wire .*(?:input|output) (\d+) ", body, re.M))
    decls = [f"  wire input {port + 1} \\{FIRST}"]
    extra = []
    for name, block in cells:
        width = int(re.search(r"^\s*parameter \\WIDTH (\d+)$", block, re.M).group(1))
        k = order[name]
        q = re.search(r"^\s*connect \\Q (.*)$", block, re.M).group(1)
        raw = f"\\{POWER_UP}{k}__q"
        decls += [
            f"  wire width {width} input {port + 2 + k} \\{POWER_UP}{k}",
            f"  wire width {width} {raw}",
        ]
        extra += [
            f"  cell $mux $mutation_power_up{k}",
            f"    parameter \\WIDTH {width}",
            f"    connect \\A {raw}",
            f"    connect \\B \\{POWER_UP}{k}",
            f"    connect \\S \\{FIRST}",
            f"    connect \\Y {q}",
            "  end",
        ]
        body = re.sub(
            rf"(^\s*cell \$dff {re.escape(name)}\n(?:(?!^\s*end$).)*?^\s*connect \\Q )[^\n]*",
            lambda m, raw=raw: m.group(1) + raw,
            body,
            count=1,
            flags=re.M | re.S,
        )
    head, rest = il.split(f"\nmodule \\{top}\n", 1)
    tail = rest.split("\nend\n", 1)[1]
    return (
        f"{head}\nmodule \\{top}\n" + "\n".join(decls) + "\n" + body + "\n" + "\n".join(extra)
        + "\nend\n" + tail
    )  # fmt: skip


# Where ``_memories_mapped`` starts Yosys's cell numbering, the same for both copies: above any
# number the netlists use, so the flip-flops ``memory_map`` makes are named alike in the two
MAPPED_AUTOIDX = 10_000_000


def _memories_mapped(folder: Path, il: str, name: str) -> str:
    """The RTLIL ``il`` with its memories that have write ports (a FIFO's; the ROMs are cut)
    made flip-flops by Yosys's ``memory_map``, the new cells numbered from ``MAPPED_AUTOIDX``
    (the original and the mutant map the same memories alike: ``shared_power_up`` gives their
    words the same power-up state too), in ``folder`` as ``<name>_mapped.il``; ``il`` itself
    if it has none."""
    if not re.search(r"^\s*cell \$mem_v2 ", il, re.M):
        return il
    # read_rtlil takes the numbering on from the file's autoidx line
    numbered = re.sub(r"^autoidx \d+$", f"autoidx {MAPPED_AUTOIDX}", il, count=1, flags=re.M)
    (folder / f"{name}_unmapped.il").write_text(numbered)
    run_yosys(
        f"read_rtlil {name}_unmapped.il\nmemory_map\nopt_clean\nwrite_rtlil {name}_mapped.il\n",
        folder,
        f"{name}_map",
    )
    return (folder / f"{name}_mapped.il").read_text()


def _port_widths(il: str, top: str) -> dict[str, tuple[str, int]]:
    """name -> (direction, width) of every port of ``top`` in the RTLIL ``il``."""
    body = il.split(f"\nmodule \\{top}\n", 1)[1].split("\nend\n", 1)[0]
    found = re.findall(r"^\s*wire (?:width (\d+) )?(input|output|inout) \d+ \\(\S+)$", body, re.M)
    return {name: (direction, int(width or 1)) for width, direction, name in found}


def miter_verilog(
    ports: dict[str, tuple[str, int]], contract: Contract, roms: list[tuple[int, int, int, bool]],
    products: list[tuple[int, int]] = (),  # type: ignore[assignment]
    invariants: tuple[str, ...] = (),
) -> str:  # fmt: skip
    """The top of the from-reset proof: ``gold`` and ``gate`` on the same inputs, ``rst_n``
    held low in the first cycle (``mutation_first``, a register that starts at 1), one
    assertion: from the second cycle on every output agrees, the data outputs where defined
    (``Contract``).  The ROMs cut out (``roms``, ``rom_reads``): a read port of an
    asynchronous ROM gives the mutant what it gives the original wherever their addresses
    agree (the same table) and anything where they do not (another word of it); a clocked
    ROM's addresses and enables must agree in every cycle, the first too, and its data is
    the same in both (as ``_prove`` has it).  A cut multiplier (``products``,
    ``product_cuts``) is cut as an asynchronous ROM's read port is: the mutant's product is the
    original's wherever their operands agree, anything where they do not.  ``invariants``
    (Verilog expressions over ``gold:wire`` and ``gate:wire``, ``probed``) are asserted with
    the outputs, from the second cycle on: proven together, each may serve the others as a
    strengthening (pdr need not find it)."""
    inputs = {n: w for n, (d, w) in ports.items() if d == "input" and n != FIRST}
    outputs = {n: w for n, (d, w) in ports.items() if d == "output"}
    data = [n for n in outputs if n in contract.data]
    agree, gate_in, other = [], {}, {}
    for k, (nports, abits, width, asynchronous) in enumerate(roms):
        name = f"mutation_rom{k}"
        if not asynchronous:
            agree += [n for n in (f"{name}_addr", f"{name}_en") if n in outputs]
            continue
        other[f"{name}_other"] = nports * width
        gate_in[f"{name}_data"] = "{" + ", ".join(
            f"gold_{name}_addr[{p * abits + abits - 1}:{p * abits}] == "
            f"gate_{name}_addr[{p * abits + abits - 1}:{p * abits}] ? "
            f"{name}_data[{p * width + width - 1}:{p * width}] : "
            f"{name}_other[{p * width + width - 1}:{p * width}]"
            for p in reversed(range(nports))
        ) + "}"  # fmt: skip
    for k, (_operands, width) in enumerate(products):
        name = f"{PRODUCT}{k}"
        other[f"{name}_other"] = width
        gate_in[f"{name}_y"] = f"gold_{name}_in == gate_{name}_in ? {name}_y : {name}_other"
    cut = {f"{PRODUCT}{k}_in" for k in range(len(products))}
    control = [
        n for n in outputs
        if n not in agree and n not in data and not n.endswith("_addr") and n not in cut
        and not n.startswith(PROBE)
    ]  # fmt: skip
    lines = ["module mutation_miter ("]
    lines.append(
        ",\n".join(f"    input wire [{w - 1}:0] {n}" for n, w in {**inputs, **other}.items())
    )
    lines += [
        ");",
        "    reg first = 1'b1;",
        "    always @(posedge clk) first <= 1'b0;",
        "    wire reset_n = rst_n & ~first;",
    ]
    for n, w in outputs.items():
        lines.append(f"    wire [{w - 1}:0] gold_{n}, gate_{n};")
    for copy in ("gold", "gate"):
        given = {n: ("reset_n" if n == "rst_n" else n) for n in inputs}
        if copy == "gate":
            given.update(gate_in)
        conns = [f".{n}({v})" for n, v in given.items()]
        conns += [f".{FIRST}(first)"] + [f".{n}({copy}_{n})" for n in outputs]
        lines.append(f"    {copy} {copy}_copy ({', '.join(conns)});")
    valid = f"gold_{contract.valid}"
    if contract.held:
        lines += [
            "    reg defined = 1'b0;",
            f"    always @(posedge clk) defined <= reset_n & (defined | {valid});",
            f"    wire shown = defined | {valid};",
        ]
    else:
        lines.append(f"    wire shown = {valid};")
    same = lambda names: " && ".join(f"gold_{n} == gate_{n}" for n in names) or "1'b1"  # noqa: E731
    held = " && ".join(f"({invariant_verilog(i)})" for i in invariants) or "1'b1"
    checked = "control_agrees && data_agrees" + (" && invariants_hold" if invariants else "")
    lines += [
        f"    wire roms_agree = {same(agree)};",
        f"    wire control_agrees = {same(control)};",
        f"    wire data_agrees = !shown || ({same(data)});",
        f"    wire invariants_hold = {held};",
        f"    always @* assert (roms_agree && (first || ({checked})));",
        "endmodule",
        "",
    ]
    return "\n".join(lines)


# The module the ABC pass is handed (one gate: the pass calls ABC only with logic to map); the
# ABC script reads the miter's AIGER instead, and gives the gate back (``backup``/``restore``)
_ABC_HOST = (
    "module mutation_abc_host (input a, input b, output y);\n  assign y = a & b;\nendmodule\n"
)


def _prove_from_reset(
    folder: Path, top: str, gold_il: str, gate_il: str, contract: Contract, timeout: float,
    products: bool = False, invariants: tuple[str, ...] = (),
) -> str:  # fmt: skip
    """The original ``gold_il`` and the mutant ``gate_il`` (RTLIL, ROMs cut), both from the
    same power-up state (``shared_power_up``) with ``rst_n`` low in the first cycle and the
    same inputs from then on: the assertion of ``miter_verilog`` in every cycle, unbounded.
    Yosys makes the miter's AIGER (``write_aiger -zinit``) and hands it to ABC (linked into
    the WebAssembly Yosys, reached through its ``abc`` pass with a script of ours): ``scorr``
    (the registers it proves equal in the two copies by induction from the initial state,
    merged), then ``pdr`` (property-directed reachability) on what is left, given ``timeout``
    seconds; with ``invariants``, ABC's ``ind`` (k-induction, ``IND_FRAMES``) first.
    'proven', 'failed' (a counterexample: a trace from reset that tells the two apart,
    ``pdr_cex.txt``) or 'undecided' (time out).  ``products``: the multipliers cut
    too (``cut_products``); ``invariants`` asserted with the outputs (``miter_verilog``).  A
    verdict is kept for the same netlists, script and time limit."""
    cut = (lambda il: cut_products(cut_roms(il))) if products else cut_roms
    wires = invariant_wires(invariants)
    gold = shared_power_up(_memories_mapped(folder, cut(gold_il), "gold"), top)
    gate = shared_power_up(_memories_mapped(folder, cut(gate_il), "gate"), top)
    if wires:
        gold, gate = probed(gold, top, wires), probed(gate, top, wires)
    ports = _port_widths(gold, top)
    if ports != _port_widths(gate, top):
        return "undecided"  # not the same flip-flops, or ports: no shared power-up state
    (folder / "gold_reset.il").write_text(gold)
    (folder / "gate_reset.il").write_text(gate)
    muls = product_cuts(gold_il) if products else []
    miter = miter_verilog(ports, contract, rom_reads(gold_il), muls, invariants)
    (folder / "miter.v").write_text(miter)
    (folder / "abc_host.v").write_text(_ABC_HOST)
    limit = max(1, int(timeout))
    (folder / "pdr.abc").write_text(
        f"backup\nread_aiger miter.aig\nstrash\nscorr\nwrite_aiger {REDUCED}\npdr -T {limit}\n"
        f"write_status {PDR_STATUS}\nwrite_cex -a pdr_cex.txt\nrestore\n"
    )
    (folder / "ind.abc").write_text(
        f"backup\nread_aiger miter.aig\nstrash\nind -F {IND_FRAMES}\nwrite_status {IND_STATUS}\n"
        "restore\n"
    )
    host = (
        "design -reset\nread_verilog abc_host.v\nhierarchy -top mutation_abc_host\nproc\ntechmap\n"
    )
    script = (
        f"read_rtlil gold_reset.il\nrename {top} gold\n"
        f"read_rtlil gate_reset.il\nrename {top} gate\n"
        "read_verilog -formal miter.v\nhierarchy -top mutation_miter\n"
        "proc\nchformal -lower\nflatten\nmemory_map\n"
        # x constants (none but in the ROMs' parameters) and undriven bits: free in each copy
        "techmap\nsetundef -undriven -anyseq\nopt -fast -keepdc\ndffunmap\naigmap\nopt_clean\n"
        "write_aiger -zinit miter.aig\n" + (f"{host}abc -script ind.abc\n" if invariants else "")
    )
    (folder / "reset.ys").write_text(script)
    (folder / "pdr.ys").write_text(f"{host}abc -script pdr.abc\n")
    digest = hashlib.sha256(repr((script, timeout, contract)).encode())
    for name in ("gold_reset.il", "gate_reset.il", "miter.v", "pdr.abc", "ind.abc", "pdr.ys"):
        digest.update((folder / name).read_bytes())
    key = digest.hexdigest()
    cached = _known(folder, key)
    if cached is not None:
        return str(cached)
    for name in (PDR_STATUS, REDUCED, IND_STATUS):
        (folder / name).unlink(missing_ok=True)

    def run(script: str) -> bool:
        # the conversion, scorr, and ABC's own limit overrun: a minute more
        return _yosys_within(folder, script, timeout + 60)

    # the miter's AIGER (and k-induction, with invariants), then scorr and pdr unless proven
    done = run("reset.ys") and (folder / "miter.aig").exists()
    ind = (folder / IND_STATUS).read_text().split() if done and invariants else []
    if ind[:1] == ["snl_UNSAT"]:
        verdict = "proven"
    else:
        done = done and run("pdr.ys") and (folder / PDR_STATUS).exists()
        status = (folder / PDR_STATUS).read_text().split() if done else []
        verdict = {"snl_UNSAT": "proven", "snl_SAT": "failed"}.get(status[0] if status else "", "")
        if not verdict:
            verdict = "proven" if done and _constant_false(folder / REDUCED) else "undecided"
    _keep(folder, key, verdict)
    return verdict


def prove_from_reset(
    folder: Path, top: str, design_il: Path, command: str, contract: Contract,
    timeout: float = PDR_TIMEOUT, products: bool = False, invariants: tuple[str, ...] = (),
) -> str:  # fmt: skip
    """The third proof alone (``_prove_from_reset``) of the design ``design_il`` with the
    mutation ``command`` against the original, in ``folder``: 'proven', 'failed' or
    'undecided'."""
    folder.mkdir(parents=True, exist_ok=True)
    gold, gate = design_il.read_text(), _mutant(folder, design_il, command)
    return _prove_from_reset(folder, top, gold, gate, contract, timeout, products, invariants)


def equivalence(
    folder: Path, top: str, design_il: Path, command: str, unit: bool, seq: int = 4,
    timeout: float = 90, contract: Contract | None = None, pdr_timeout: float = PDR_TIMEOUT,
    earlier: bool = True, invariants: tuple[str, ...] = (), stronger: tuple[str, ...] = (),
    window: Window | None = None,
) -> str | None:  # fmt: skip
    """Prove the design ``design_il`` (RTLIL, module ``top``) with the mutation ``command``
    equal to the original, the ROMs cut (``cut_roms``), in ``folder``: every matched named
    wire equal in every cycle (``_prove``); ``unit``: the second method may be tried;
    ``contract``: the third.

    First method: every named wire is matched but the one the mutation drives (a dead bit
    differs there and nowhere else).  Second (a unit): the named wires the mutation reaches up
    to the next registers and on to the registers after them are left out, and each is matched
    as what it shows while the unit is busy (``observed``): a register the mutation changes
    only while the unit is idle, which the next start loads again.  Third: from reset, the
    outputs as ``contract`` defines them, by ABC's ``pdr`` (``_prove_from_reset``, given
    ``pdr_timeout`` seconds): what holds only in the states a reset leads to (a counter's
    bound, a stage register read only while its valid bit is set).  Fourth: the third with the
    multipliers cut as well (``cut_products``: pdr then faces control and adders, not
    products), then with ``invariants`` (Verilog over ``gold:wire`` and ``gate:wire``,
    sim/mutation_invariants.py) asserted alongside the outputs (ABC's ``ind`` first, then
    ``scorr`` and ``pdr``), each try given ``pdr_timeout`` seconds: what pdr does not find by
    itself (each stage's registers equal in the two copies
    while its valid bit is set), then with ``stronger`` added (the other registers equal in
    every cycle).  Fifth, for a mutation inside ``window`` (``in_window``): the window's word
    for one pixel from two arbitrary states, its address free and the line's constant loaded
    from the tables (``prove_window``): what holds only for the tables' words.  ``earlier`` =
    False: the proofs from reset alone, and the window (the others already failed on it).  The
    method's text, or None if none proves it."""
    unread = unread_port(design_il.read_text(), command)
    if unread is not None:
        return unread
    if mutate_field(command, "port") in CLOCK_PORTS:
        # SAT steps every flip-flop on one clock: a clock mutation is out of its reach, unless
        # the cell never reads that clock (above)
        return None
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
    wire = [mutate_field(command, "wire")]
    unmatched = _prove_local(folder, top, wire, seq, timeout) if earlier else None
    if unmatched is not None:
        but = f" but {', '.join(unmatched)}" if unmatched else ""
        return f"equiv_simple -seq {seq} from any shared state, every named wire matched{but}"
    if earlier and _prove(folder, top, wire, seq, timeout):
        return f"sat -tempinduct (to {seq} cycles), every named wire but the mutated one matched"
    if unit and earlier:
        fanout = [
            line.split("/", 1)[1]
            for line in (folder / "fanout.txt").read_text().splitlines()
            if "/" in line and not line.split("/", 1)[1].startswith("$")
        ]
        (folder / "gold_cut.il").write_text(observed(cut_roms(gold), top, fanout, BUSY))
        (folder / "gate_cut.il").write_text(observed(cut_roms(gate), top, fanout, BUSY))
        if _prove(folder, top, fanout, seq, timeout):
            return f"sat -tempinduct (to {seq} cycles), the mutation's fanout matched while {BUSY}"
    if contract is None:
        return None
    outputs = f"every output equal after reset, {', '.join(contract.data)} where defined"
    if _prove_from_reset(folder, top, gold, gate, contract, pdr_timeout) == "proven":
        return f"scorr and pdr from reset, the same power-up state: {outputs}"
    # the fourth: the multipliers cut too, then with the invariants asserted alongside
    tries = [()] if product_cuts(gold) else []
    tries += [invariants] if invariants else []
    tries += [invariants + stronger] if stronger else []
    for given in tries:
        verdict = _prove_from_reset(
            folder, top, gold, gate, contract, pdr_timeout, products=True, invariants=given
        )
        if verdict == "proven":
            cut = "ROMs and multipliers" if product_cuts(gold) else "ROMs"
            also = f", with {len(given)} invariants proven alongside" if given else ""
            engine = "k-induction (ind) or scorr and pdr" if given else "scorr and pdr"
            return f"{engine} from reset, {cut} cut{also}: {outputs}"
    if window is not None and in_window(folder, design_il, command, window):
        verdict, inputs = prove_window(folder, top, gold, gate, window)
        if verdict == "proven":
            small = f", or both below {window.tiny}" if window.tiny else ""
            return (
                f"every address and line word swept ({inputs} inputs) through the datapath "
                f"unrolled from two arbitrary states, tables and multipliers kept: "
                f"{window.observe} equal{small}"
            )
    return None


# ---------------------------------------------------------------- the fifth proof: a window
@dataclass(frozen=True)
class Window:
    """A feed-forward stretch of a unit, from the wires that carry one pixel's operands into it
    to the word it computes for that pixel, for the fifth proof (``prove_window``).

    ``cut``: the register whose output is replaced by a free input in every cycle (the pixel's
    angle-table address: every value of it is one the unit can hold).  ``loaded``: the
    registers the window's schedule loads (the line's constant word); a mutation upstream of
    them or of ``cut`` is out of the window's reach.  ``idle``: a control register that
    starts at 0 in both copies (the unit idle, so the schedule's writes and start are taken).
    ``schedule``:
    inputs held to a Verilog expression of the cycle ``t``; every other input is free in every
    cycle.  ``observe``: the wire the mutation must reach the outputs through, compared in cycle
    ``frame`` only (the pixel whose address was cut in cycle ``frame - latency``).  ``tiny``:
    words below it may differ (no operand scales them above 0: the unit's output stage rounds
    C x word, and C x (tiny - 1) rounds to 0 at the largest C); 0: every word must agree."""

    cut: str
    loaded: tuple[str, ...]
    idle: str
    schedule: tuple[tuple[str, str], ...]
    observe: str
    frame: int
    tiny: int = 0


# The cut wire's free input, and its old driver's output (left unread)
WINDOW_CUT = "mutation_cut"
# Seconds given to each Yosys and ABC run of a window's proof
WINDOW_TIMEOUT = 300.0
# The most inputs an unrolled miter's cone may read to be swept (2^24 assignments)
WINDOW_SUPPORT = 24


def in_window(folder: Path, design_il: Path, command: str, window: Window) -> bool:
    """The cell the mutation ``command`` changes lies inside ``window`` (Yosys ``select`` on the
    original netlist): in the fan-in cone of neither ``cut`` nor a ``loaded`` register, across
    any number of registers (so the window's free address and its schedule's loads carry
    whatever the mutant would give them), and reaching no output port but through
    ``window.observe`` (its fan-out cone, with that wire cut, holds no output)."""
    cell = mutate_field(command, "cell")
    original = os.path.relpath(design_il, folder)
    upstream = "".join(
        f"select -assert-none c:{cell} w:{s} %ci* %i\n" for s in (window.cut, *window.loaded)
    )
    try:
        run_yosys(
            f"read_rtlil {original}\nopt_clean\n{upstream}expose -cut w:{window.observe}\n"
            f"select -assert-none c:{cell} %co* o:* %i o:{window.observe} %d\n",
            folder,
            "window_reach",
        )
    except RuntimeError:
        return False
    return True


def cut_register(il: str, top: str, wire: str) -> str:
    """The RTLIL ``il`` with the flip-flop that drives ``wire`` (its whole Q) left driving an
    unread wire, and ``wire`` driven by a new input port ``WINDOW_CUT`` of its width."""
    body = il.split(f"\nmodule \\{top}\n", 1)[1].split("\nend\n", 1)[0]
    pattern = rf"^(\s*connect \\Q )\\{re.escape(wire)}$"
    if len(re.findall(pattern, body, re.M)) != 1:
        raise ValueError(f"{top} has no one flip-flop whose Q is all of {wire}")
    width = re.search(rf"^\s*wire (?:width (\d+) )?\\{re.escape(wire)}$", body, re.M)
    bits = int(width.group(1) or 1) if width else 1
    head, rest = il.split(f"\nmodule \\{top}\n", 1)
    inner, tail = rest.split("\nend\n", 1)
    inner = re.sub(pattern, rf"\1\\{WINDOW_CUT}_raw", inner, count=1, flags=re.M)
    text = (
        f"{head}\nmodule \\{top}\n  wire width {bits} \\{WINDOW_CUT}_raw\n{inner}\n"
        f"  connect \\{wire} \\{WINDOW_CUT}\nend\n{tail}"
    )
    return add_ports(text, [f"  wire width {bits} input {{port}} \\{WINDOW_CUT}"])


def power_up_input(il: str, top: str, wire: str) -> str:
    """The ``shared_power_up`` input that the flip-flop driving ``wire`` starts from."""
    body = il.split(f"\nmodule \\{top}\n", 1)[1].split("\nend\n", 1)[0]
    cells = re.findall(r"^\s*cell \$dff (\S+)\n(.*?)^\s*end$", body, re.M | re.S)
    order = {name: k for k, name in enumerate(sorted(name for name, _ in cells))}
    for name, block in cells:
        if re.search(rf"^\s*connect \\Q \\{re.escape(wire)}$", block, re.M):
            return f"{POWER_UP}{order[name]}"
    raise ValueError(f"{top} has no flip-flop whose Q is all of {wire}")


def window_verilog(ports: dict[str, tuple[str, int]], window: Window, idle: str) -> str:
    """The top of the fifth proof: ``gold`` and ``gate``, each from its own power-up state
    (``mutation_init*`` inputs apiece) but ``idle``, which is 0 in both; the inputs of
    ``window.schedule`` held to their expressions of the cycle count ``t`` and every other input
    free and the same in both.  One assertion: in cycle ``window.frame`` the observed words
    agree, or both lie below ``window.tiny``."""
    fixed = dict(window.schedule) | {FIRST: "t == 0", idle: "1'b0"}
    inputs = {n: w for n, (d, w) in ports.items() if d == "input" and n not in fixed}
    own = {n for n in inputs if n.startswith(POWER_UP)}
    shared = {n: w for n, w in inputs.items() if n not in own}
    seen = probe_name(window.observe)
    width = ports[seen][1]
    decls = [f"    input wire [{w - 1}:0] {n}" for n, w in shared.items()]
    decls += [
        f"    input wire [{inputs[n] - 1}:0] {c}_{n}" for n in sorted(own) for c in ("gold", "gate")
    ]
    last = window.frame + 1
    lines = ["module mutation_window (", ",\n".join(decls), ");", "    reg [15:0] t = 16'd0;"]
    lines.append(f"    always @(posedge clk) if (t != 16'd{last}) t <= t + 16'd1;")
    lines.append(f"    wire [{width - 1}:0] gold_seen, gate_seen;")
    for copy in ("gold", "gate"):
        given = {n: n for n in shared} | {n: f"{copy}_{n}" for n in own} | fixed
        conns = [f".{n}({v})" for n, v in given.items()] + [f".{seen}({copy}_seen)"]
        lines.append(f"    {copy} {copy}_copy ({', '.join(conns)});")
    small = f"(gold_seen < {window.tiny} && gate_seen < {window.tiny})" if window.tiny else "1'b0"
    lines += [
        f"    always @* assert (t != 16'd{window.frame} || gold_seen == gate_seen || {small});",
        "endmodule",
        "",
    ]
    return "\n".join(lines)


def window_inputs(folder: Path, found: dict[int, int]) -> list[str]:
    """The assignment ``found`` of the unrolled cone's inputs (``first_one``) as the miter's
    input words, ``<name> = <value> in cycle <t>``, one a line, by cycle then name: ABC's
    ``frames`` numbers frame t's inputs t x I + 1 .. (t + 1) x I, each in the order of
    ``window.aig``'s, whose names and bits ``window.map`` (Yosys ``write_aiger -map``) gives."""
    header = (folder / "window.aig").read_bytes().split(b"\n", 1)[0].split()
    per_frame = int(header[2])
    names = {}
    for line in (folder / "window.map").read_text().splitlines():
        fields = line.split()
        if fields[0] == "input":
            names[int(fields[1])] = (fields[3], int(fields[2]))
    words: dict[tuple[int, str], int] = {}
    for v, value in found.items():
        cycle, index = divmod(v - 1, per_frame)
        name, bit = names.get(index, (f"unnamed input {index}", 0))
        words[cycle, name] = words.get((cycle, name), 0) | (value << bit)
    return [f"{name} = {value} in cycle {t}" for (t, name), value in sorted(words.items())]


def _unrolled(folder: Path, top: str, miter: str, frames: int, timeout: float) -> Aig | None:
    """The fifth proof's miter ``miter`` (Verilog, ``window_verilog``) over
    ``gold_window.il`` and ``gate_window.il`` in ``folder``, unrolled by ABC over ``frames``
    cycles from its initial values (``frames -i``) to the cone of its one output
    (``window_cone.aig``), or None if Yosys and ABC overran ``timeout`` seconds."""
    (folder / "window.v").write_text(miter)
    (folder / "abc_host.v").write_text(_ABC_HOST)
    cone = folder / "window_cone.aig"
    (folder / "window.abc").write_text(
        f"backup\nread_aiger window.aig\nstrash\nframes -F {frames} -i\nstrash\norpos\n"
        f"cone -O 0\nstrash\nwrite_aiger {cone.name}\nrestore\n"
    )
    (folder / "window.ys").write_text(
        f"read_rtlil gold_window.il\nrename {top} gold\nread_rtlil gate_window.il\n"
        f"rename {top} gate\nread_verilog -formal window.v\nhierarchy -top mutation_window\n"
        "proc\nchformal -lower\nflatten\nmemory_map\n"
        "techmap\nsetundef -undriven -anyseq\nopt -fast -keepdc\ndffunmap\naigmap\nopt_clean\n"
        "write_aiger -zinit -map window.map window.aig\ndesign -reset\nread_verilog abc_host.v\n"
        "hierarchy -top mutation_abc_host\nproc\ntechmap\nabc -script window.abc\n"
    )
    cone.unlink(missing_ok=True)
    if not _yosys_within(folder, "window.ys", timeout) or not cone.exists():
        return None
    return read_aiger(cone)


# What prove_window does, in the key of its verdicts (a change of method runs them again)
_WINDOW_METHOD = "unrolled by ABC frames -i, the cone swept (sim/aiger_eval.py), its inputs counted"


def prove_window(
    folder: Path, top: str, gold_il: str, gate_il: str, window: Window,
    timeout: float = WINDOW_TIMEOUT,
) -> tuple[str, int]:  # fmt: skip
    """The fifth proof: the original ``gold_il`` and the mutant ``gate_il`` (RTLIL, ROMs and
    multipliers kept: the tables' words and the products are the design's; a table's words
    beyond its image 0, ``roms_filled``) through ``window``: ``window_verilog``'s miter
    unrolled by ABC over cycles 0 .. ``window.frame`` (``_unrolled``) to one output, the
    assertion's, whose cone is swept over every assignment of the inputs it reads
    (``first_one``, sim/aiger_eval.py).  From two unrelated arbitrary states, with the line's
    word loaded by the schedule and the pixel's address free: an input the cone does not read
    (a power-up state, another cycle's input) cannot change the observed word in that cycle,
    so the sweep decides it for every value of everything else.  'proven', 'failed' (the
    first assignment that asserts, in ``window_cex.txt``) or 'undecided' (the cone reads more
    than ``WINDOW_SUPPORT`` inputs, or Yosys and ABC overran ``timeout`` seconds), with the
    number of inputs the cone reads (0 where it was not built).  A verdict is kept for the
    same netlists, window and method.

    The tables' filling is sound where a filled table is read only at the addresses the unit
    gives it: in the BRDF unit only the coefficient tables are filled (2000 words of the 2048
    their address reaches; the angle table, which the free address reads, has a word at
    every address), and for a mutation in the window (``in_window``) their address logic lies
    upstream of the loaded register, the original's in both copies, which reads 2 (n - 1)
    and 2 (n - 1) + 1 < 2000 only."""

    def prepared(il: str, name: str) -> tuple[str, str]:
        text = cut_register(_memories_mapped(folder, roms_filled(il), name), top, window.cut)
        idle = power_up_input(text, top, window.idle)
        return probed(shared_power_up(text, top), top, [window.observe]), idle

    gold, idle = prepared(gold_il, "gold")
    gate, idle_gate = prepared(gate_il, "gate")
    ports = _port_widths(gold, top)
    if ports != _port_widths(gate, top) or idle != idle_gate:
        return "undecided", 0
    (folder / "gold_window.il").write_text(gold)
    (folder / "gate_window.il").write_text(gate)
    miter = window_verilog(ports, window, idle)
    digest = hashlib.sha256(repr((_WINDOW_METHOD, WINDOW_SUPPORT, window, miter)).encode())
    digest.update(gold.encode())
    digest.update(gate.encode())
    key = digest.hexdigest()
    cached = _known(folder, key)
    if cached is not None:
        verdict, inputs = str(cached).split()
        return verdict, int(inputs)
    cone = _unrolled(folder, top, miter, window.frame + 1, timeout)
    inputs = len(support(cone)) if cone is not None else 0
    verdict = "undecided"
    if cone is not None and inputs <= WINDOW_SUPPORT:
        found = first_one(cone, limit=WINDOW_SUPPORT)
        verdict = "proven" if found is None else "failed"
        if found is not None:
            (folder / "window_cex.txt").write_text(
                "".join(f"{line}\n" for line in window_inputs(folder, found))
            )
    _keep(folder, key, f"{verdict} {inputs}")
    return verdict, inputs


def prove_in_window(
    folder: Path, top: str, design_il: Path, command: str, window: Window,
    timeout: float = WINDOW_TIMEOUT,
) -> tuple[str, int]:  # fmt: skip
    """The fifth proof alone of the design ``design_il`` with the mutation ``command`` against
    the original, in ``folder``: ('outside', 0) (the mutation is not inside ``window``:
    ``in_window``), else ``prove_window``'s verdict and the inputs its cone reads."""
    folder.mkdir(parents=True, exist_ok=True)
    if not in_window(folder, design_il, command, window):
        return "outside", 0
    gate = _mutant(folder, design_il, command)
    return prove_window(folder, top, design_il.read_text(), gate, window, timeout)
