# SPDX-License-Identifier: Apache-2.0
"""The formal equivalence checks of ``make mutants`` (sim/mutation.py): a mutant that every
check passes, against the original design, in Yosys.

The ROM tables are cut out of both designs (``cut_roms``).  Four kinds of proof
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

The fifth, a window of a unit's datapath with the tables and multipliers kept, swept over
every input its unrolled cone reads, is sim/mutation_window.py's; it uses the miter parts
here (``shared_power_up``, ``memories_mapped``, ``port_widths``) and the verdict cache, as
does the sixth, an induction in z3 over the two netlists (sim/mutation_induction.py).

A verdict is kept per folder for the same netlists and script.

The netlist surgery they share (the ROM and product cuts, the probes of the invariants) is
sim/mutation_cuts.py.

Size: about 700 lines: the four proofs share the miter's netlists, the verdict cache and the
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

from sim.gate import yosys_exe
from sim.mutation_cuts import (
    PROBE,
    PRODUCT,
    cut_products,
    cut_roms,
    invariant_verilog,
    invariant_wires,
    module_parts,
    observed,
    probed,
    product_cuts,
    rom_reads,
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


def known_verdict(folder: Path, key: str) -> str | bool | None:
    """The verdict kept for ``key`` beside ``folder`` (its parent's verdicts.json), or None."""
    verdicts = folder.parent / "verdicts.json"
    return (json.loads(verdicts.read_text()) if verdicts.exists() else {}).get(key)


def keep_verdict(folder: Path, key: str, verdict: str | bool) -> None:
    """Keep ``verdict`` for ``key`` beside ``folder`` (a rerun proves nothing twice)."""
    with _verdict_lock:
        verdicts = folder.parent / "verdicts.json"
        known = json.loads(verdicts.read_text()) if verdicts.exists() else {}
        known[key] = verdict
        verdicts.write_text(json.dumps(known, indent=1) + "\n")


def yosys_within(folder: Path, script: str, timeout: float) -> bool:
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


def mutant_netlist(folder: Path, design_il: Path, command: str) -> str:
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
    cached = known_verdict(folder, key)
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
    keep_verdict(folder, key, proven)
    return proven


def _ports(il: str, top: str) -> set[str]:
    """The port names of module ``top`` in the RTLIL ``il``."""
    _, body, _ = module_parts(il, top)
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


def flip_flops(body: str) -> tuple[list[tuple[str, str]], dict[str, int]]:
    """The ``$dff`` cells of an RTLIL module's ``body`` as (name, text), and each one's number
    by name (``shared_power_up``'s ``mutation_init<k>``)."""
    cells = re.findall(r"^\s*cell \$dff (\S+)\n(.*?)^\s*end$", body, re.M | re.S)
    return cells, {name: k for k, name in enumerate(sorted(name for name, _ in cells))}


def shared_power_up(il: str, top: str) -> str:
    """The RTLIL ``il`` with the power-up state of every ``$dff`` of ``top`` (``prep`` leaves
    no other kind of flip-flop in these designs; a memory's words, mapped later, start free in
    each copy) an input: an input
    ``mutation_first`` (1 in the first cycle only) and, for the k-th flip-flop by cell name, an
    input ``mutation_init<k>`` of its width, which its readers see in the first cycle instead
    of its output (``first ? init : Q``).  Two designs with the same flip-flop cells, the same
    inputs given to both, start from the same arbitrary state: what a register without a reset
    holds at power-up is the same in both, as in one chip."""
    _, body, _ = module_parts(il, top)
    cells, order = flip_flops(body)
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
    head, _, tail = module_parts(il, top)
    return (
        f"{head}\nmodule \\{top}\n" + "\n".join(decls) + "\n" + body + "\n" + "\n".join(extra)
        + "\nend\n" + tail
    )  # fmt: skip


# Where ``_memories_mapped`` starts Yosys's cell numbering, the same for both copies: above any
# number the netlists use, so the flip-flops ``memory_map`` makes are named alike in the two
MAPPED_AUTOIDX = 10_000_000


def memories_mapped(folder: Path, il: str, name: str) -> str:
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


def port_widths(il: str, top: str) -> dict[str, tuple[str, int]]:
    """name -> (direction, width) of every port of ``top`` in the RTLIL ``il``."""
    _, body, _ = module_parts(il, top)
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
ABC_HOST = (
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
    gold = shared_power_up(memories_mapped(folder, cut(gold_il), "gold"), top)
    gate = shared_power_up(memories_mapped(folder, cut(gate_il), "gate"), top)
    if wires:
        gold, gate = probed(gold, top, wires), probed(gate, top, wires)
    ports = port_widths(gold, top)
    if ports != port_widths(gate, top):
        return "undecided"  # not the same flip-flops, or ports: no shared power-up state
    (folder / "gold_reset.il").write_text(gold)
    (folder / "gate_reset.il").write_text(gate)
    muls = product_cuts(gold_il) if products else []
    miter = miter_verilog(ports, contract, rom_reads(gold_il), muls, invariants)
    (folder / "miter.v").write_text(miter)
    (folder / "abc_host.v").write_text(ABC_HOST)
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
    cached = known_verdict(folder, key)
    if cached is not None:
        return str(cached)
    for name in (PDR_STATUS, REDUCED, IND_STATUS):
        (folder / name).unlink(missing_ok=True)

    def run(script: str) -> bool:
        # the conversion, scorr, and ABC's own limit overrun: a minute more
        return yosys_within(folder, script, timeout + 60)

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
    keep_verdict(folder, key, verdict)
    return verdict


def prove_from_reset(
    folder: Path, top: str, design_il: Path, command: str, contract: Contract,
    timeout: float = PDR_TIMEOUT, products: bool = False, invariants: tuple[str, ...] = (),
) -> str:  # fmt: skip
    """The third proof alone (``_prove_from_reset``) of the design ``design_il`` with the
    mutation ``command`` against the original, in ``folder``: 'proven', 'failed' or
    'undecided'."""
    folder.mkdir(parents=True, exist_ok=True)
    gold, gate = design_il.read_text(), mutant_netlist(folder, design_il, command)
    return _prove_from_reset(folder, top, gold, gate, contract, timeout, products, invariants)


def equivalence(
    folder: Path, top: str, design_il: Path, command: str, unit: bool, seq: int = 4,
    timeout: float = 90, contract: Contract | None = None, pdr_timeout: float = PDR_TIMEOUT,
    earlier: bool = True, invariants: tuple[str, ...] = (), stronger: tuple[str, ...] = (),
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
    every cycle).  ``earlier`` = False: the proofs from reset alone (the others already failed
    on it).  The method's text, or None if none proves it; the fifth proof, a window of the
    datapath with the tables kept, is sim/mutation_window.py's."""
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
    return None
