# SPDX-License-Identifier: Apache-2.0
"""The fifth proof of ``make mutants`` (sim/mutation.py), after the four of
sim/mutation_proof.py: a window of a unit's datapath (``Window``; the BRDF unit's is
sim/mutation_brdf.py's ``brdf_window``) with the tables' words and the multipliers kept.

The original and the mutant start from two unrelated arbitrary states, the pixel's table
address free in every cycle, the line's word loaded by the unit's own schedule, and the word
the window computes is compared in the cycle it is ready (``window_verilog``).  ABC unrolls
that miter to the cycle (``_unrolled``) and keeps the cone of its one assertion, which reads
a few dozen inputs at most (n and the address); sim/aiger_eval.py evaluates it on every
assignment of them (``prove_window``): what holds only for the tables' words and the products
they give, where a SAT solver would have to enumerate them.  ``in_window`` says which
mutations the window's claim covers.
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass
from pathlib import Path

from sim.aiger_eval import Aig, first_one, read_aiger, support
from sim.mutation_cuts import add_ports, module_parts, probe_name, probed, roms_filled
from sim.mutation_proof import (
    ABC_HOST,
    CLOCK_PORTS,
    FIRST,
    POWER_UP,
    flip_flops,
    keep_verdict,
    known_verdict,
    memories_mapped,
    mutant_netlist,
    mutate_field,
    port_widths,
    run_yosys,
    shared_power_up,
    yosys_within,
)


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
    head, body, tail = module_parts(il, top)
    pattern = rf"^(\s*connect \\Q )\\{re.escape(wire)}$"
    if len(re.findall(pattern, body, re.M)) != 1:
        raise ValueError(f"{top} has no one flip-flop whose Q is all of {wire}")
    width = re.search(rf"^\s*wire (?:width (\d+) )?\\{re.escape(wire)}$", body, re.M)
    bits = int(width.group(1) or 1) if width else 1
    body = re.sub(pattern, rf"\1\\{WINDOW_CUT}_raw", body, count=1, flags=re.M)
    text = (
        f"{head}\nmodule \\{top}\n  wire width {bits} \\{WINDOW_CUT}_raw\n{body}\n"
        f"  connect \\{wire} \\{WINDOW_CUT}\nend\n{tail}"
    )
    return add_ports(text, [f"  wire width {bits} input {{port}} \\{WINDOW_CUT}"])


def power_up_input(il: str, top: str, wire: str) -> str:
    """The ``shared_power_up`` input that the flip-flop driving ``wire`` starts from."""
    _, body, _ = module_parts(il, top)
    cells, order = flip_flops(body)
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
    (folder / "abc_host.v").write_text(ABC_HOST)
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
    if not yosys_within(folder, "window.ys", timeout) or not cone.exists():
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
        text = cut_register(memories_mapped(folder, roms_filled(il), name), top, window.cut)
        idle = power_up_input(text, top, window.idle)
        return probed(shared_power_up(text, top), top, [window.observe]), idle

    gold, idle = prepared(gold_il, "gold")
    gate, idle_gate = prepared(gate_il, "gate")
    ports = port_widths(gold, top)
    if ports != port_widths(gate, top) or idle != idle_gate:
        return "undecided", 0
    (folder / "gold_window.il").write_text(gold)
    (folder / "gate_window.il").write_text(gate)
    miter = window_verilog(ports, window, idle)
    digest = hashlib.sha256(repr((_WINDOW_METHOD, WINDOW_SUPPORT, window, miter)).encode())
    digest.update(gold.encode())
    digest.update(gate.encode())
    key = digest.hexdigest()
    cached = known_verdict(folder, key)
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
    keep_verdict(folder, key, f"{verdict} {inputs}")
    return verdict, inputs


def window_equivalence(
    folder: Path, top: str, design_il: Path, command: str, window: Window
) -> str | None:  # fmt: skip
    """The fifth proof as ``make mutants`` gives it a mutant the other proofs leave: the
    method's text if the mutation lies inside ``window`` and ``prove_window`` proves it, else
    None (a clock port's mutation too: the unrolling steps every flip-flop on one clock)."""
    if mutate_field(command, "port") in CLOCK_PORTS:
        return None
    verdict, inputs = prove_in_window(folder, top, design_il, command, window)
    if verdict != "proven":
        return None
    small = f", or both below {window.tiny}" if window.tiny else ""
    return (
        f"every address and line word swept ({inputs} inputs) through the datapath unrolled "
        f"from two arbitrary states, tables and multipliers kept: {window.observe} equal{small}"
    )


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
    gate = mutant_netlist(folder, design_il, command)
    return prove_window(folder, top, design_il.read_text(), gate, window, timeout)
