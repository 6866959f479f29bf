# SPDX-License-Identifier: Apache-2.0
"""The pipeline stages of a flattened design, found in its netlist, for the stage invariants
of ``make mutants``' fourth proof (sim/mutation_invariants.py, sim/mutation_proof.py).

A unit whose pixels march down a pipeline beside a valid vector (``v_reg[s]``: a pixel is in
stage s) holds in each stage register a value that matters only while that stage's valid bit
is set.  Written by hand for the specular unit (``SPECULAR_STAGES``), the registers of each
stage are found here from the prepared netlist (``prep -flatten``'s RTLIL) for designs whose
datapath differs by a parameter (each form of the BRDF unit, whose piecewise form alone has 31
stages and delay lines packed into one vector): a flip-flop bit is in stage s + 1 when every
pipeline bit its next value reads is in stage s (``stages``), the first stage's register given
(the accumulator, stage 0).  A bit that reads itself (a register that holds: the run registers,
the counters, the output register) is no stage's; neither is one that reads bits of two
stages.  ``staged_invariants`` gives one invariant a stage: while ``v_reg[s]`` is set in the
original, each of the stage's register bits is the same in the two copies; ``unstaged_equalities``
one for every other register (the control state, the run registers, the output): the same in
the two copies in every cycle.  A wrong grouping
costs nothing but the proof: the invariants are proven with the outputs, never assumed.

Only what the stage analysis needs of RTLIL is read: wires (width, offset), module-level
connections, cells and their port connections; every cell but ``$dff`` and a ROM's read port
is combinational, a ``$mux`` and the bitwise cells bit by bit, the others each output bit
reading every input bit (coarser than the logic, never wrong about which registers it reads).
"""

from __future__ import annotations

import re
from collections import defaultdict

# Cell output ports (everything else a cell connects is an input)
_OUTPUTS = ("Y", "Q", "RD_DATA")
# Cells whose output bit i reads bit i of each data input (and every bit of a select)
_BITWISE = ("$mux", "$and", "$or", "$xor", "$xnor", "$not", "$pos")
# Clock-like inputs that carry no data
_CLOCKS = ("CLK", "RD_CLK", "WR_CLK")

Bit = tuple[str, int]  # (wire, bit from its least significant, 0 first)


def _tokens(spec: str) -> list[str]:
    """The words of a sigspec: braces, names (which may hold brackets: ``$0\\q[19:0]``),
    slices (a word of their own: ``\\w [3:0]``), constants."""
    return spec.split()


def _bits(tokens: list[str], wires: dict[str, tuple[int, int]]) -> list[Bit | None]:
    """The bits of a sigspec's tokens, least significant first (None: a constant bit)."""
    chunks: list[list[Bit | None]] = []
    k = 0
    while k < len(tokens):
        tok = tokens[k]
        k += 1
        if tok in "{}":
            continue
        const = re.fullmatch(r"(\d+)'([01xzm-]*)", tok)
        if const:
            chunks.append([None] * int(const.group(1)))
            continue
        if re.fullmatch(r"\d+", tok):  # a plain integer: a 32-bit constant
            chunks.append([None] * 32)
            continue
        width, offset = wires[tok]
        lo, hi = 0, width - 1
        if k < len(tokens) and tokens[k].startswith("["):
            sel = tokens[k][1:-1].split(":")
            hi = int(sel[0]) - offset
            lo = int(sel[-1]) - offset
            k += 1
        chunks.append([(tok, b) for b in range(lo, hi + 1)])
    return [b for chunk in reversed(chunks) for b in chunk]  # the first chunk is the top


def _split_connect(rest: str) -> tuple[list[str], list[str]]:
    """The two sigspecs of a module-level ``connect`` (a braced group, a wire with an optional
    slice or a constant, then the other)."""
    tokens = _tokens(rest)
    if tokens[0] == "{":
        end = tokens.index("}") + 1
    else:
        end = 2 if len(tokens) > 1 and tokens[1].startswith("[") else 1
    return tokens[:end], tokens[end:]


class Netlist:
    """The bit-level connectivity of module ``top`` of the RTLIL ``il``."""

    def __init__(self, il: str, top: str) -> None:
        body = il.split(f"\nmodule \\{top}\n", 1)[1].split("\nend\n", 1)[0]
        self.wires: dict[str, tuple[int, int]] = {}
        for m in re.finditer(r"^\s*wire ((?:\S+ )*)(\S+)$", body, re.M):
            opts = m.group(1).split()
            width = int(opts[opts.index("width") + 1]) if "width" in opts else 1
            offset = int(opts[opts.index("offset") + 1]) if "offset" in opts else 0
            self.wires[m.group(2)] = (width, offset)
        self.alias: dict[Bit, Bit | None] = {}
        # (cell type, its inputs by port, its outputs by port), and which cell drives a bit
        self.cells: list[tuple[str, dict[str, list[Bit | None]], dict[str, list[Bit | None]]]] = []
        self.driver: dict[Bit, tuple[int, str, int]] = {}
        cell: tuple[str, dict, dict] | None = None
        for line in body.splitlines():
            words = line.split(None, 2)
            if not words:
                continue
            if words[0] == "cell":
                cell = (words[1], {}, {})
            elif words[0] == "end":
                if cell is not None:
                    self.cells.append(cell)
                cell = None
            elif words[0] == "connect" and cell is not None:
                port = words[1][1:]
                bits = _bits(_tokens(words[2]), self.wires)
                (cell[2] if port in _OUTPUTS else cell[1])[port] = bits
            elif words[0] == "connect":
                lhs, rhs = _split_connect(line.split(None, 1)[1])
                for a, b in zip(_bits(lhs, self.wires), _bits(rhs, self.wires), strict=True):
                    if a is not None:
                        self.alias[a] = b
        for k, (_kind, _ins, outs) in enumerate(self.cells):
            for port, bits in outs.items():
                for i, b in enumerate(bits):
                    if b is not None:
                        self.driver[b] = (k, port, i)
        self._cone: dict[Bit, frozenset[Bit]] = {}
        self._cell_cone: dict[int, frozenset[Bit]] = {}

    def source(self, bit: Bit | None) -> Bit | None:
        """The bit ``bit`` is connected to at the end of the module's connections."""
        seen = set()
        while bit is not None and bit in self.alias and bit not in seen:
            seen.add(bit)
            bit = self.alias[bit]
        return bit

    def flops(self) -> list[tuple[list[Bit | None], list[Bit | None]]]:
        """(Q bits, D bits) of every ``$dff``."""
        return [(outs["Q"], ins["D"]) for kind, ins, outs in self.cells if kind == "$dff"]

    def registers_read(self, bit: Bit | None) -> frozenset[Bit]:
        """The flip-flop output bits (as their ``$dff`` names them) the bit ``bit`` reads
        through combinational cells."""
        todo: list[Bit] = []
        start = self.source(bit)
        if start is None:
            return frozenset()
        todo.append(start)
        # iterative post-order: a cone is known once the cones of its inputs are
        while todo:
            b = todo[-1]
            if b in self._cone:
                todo.pop()
                continue
            inputs = self._inputs(b)
            if inputs is None:  # a flip-flop's output or a module input
                k = self.driver.get(b)
                flop = k is not None and self.cells[k[0]][0] == "$dff"
                self._cone[b] = frozenset([b]) if flop else frozenset()
                todo.pop()
                continue
            missing = [i for i in inputs if i not in self._cone]
            if missing:
                todo.extend(missing)
                continue
            self._cone[b] = frozenset().union(*(self._cone[i] for i in inputs))
            todo.pop()
        return self._cone[start]

    def _inputs(self, bit: Bit) -> list[Bit] | None:
        """The bits a combinational bit reads (sources), or None for a flip-flop's output or a
        bit no cell drives."""
        found = self.driver.get(bit)
        if found is None:
            return None
        k, _port, i = found
        kind, ins, _outs = self.cells[k]
        if kind == "$dff":
            return None
        if kind in _BITWISE:
            picked = [bits[i] for p, bits in ins.items() if p != "S" and i < len(bits)]
            picked += ins.get("S", [])
        else:
            picked = [b for p, bits in ins.items() if p not in _CLOCKS for b in bits]
        return [s for s in (self.source(b) for b in picked) if s is not None]


def stages(il: str, top: str, first: str) -> dict[Bit, int]:
    """Each pipeline flip-flop bit's stage (the wire ``first``'s bits stage 0), named by the
    wire its ``$dff`` drives: a bit is in stage s + 1 when the pipeline bits its next value
    reads are all in stage s; one that reads itself, or bits of two stages, has none."""
    net = Netlist(il, top)
    reads: dict[Bit, frozenset[Bit]] = {}
    for q_bits, d_bits in net.flops():
        for q, d in zip(q_bits, d_bits, strict=True):
            if q is not None:
                reads[q] = net.registers_read(d)
    stage = {q: 0 for q in reads if q[0] == f"\\{first}"}
    level = 0
    while True:
        found = {}
        for q, regs in reads.items():
            if q in stage or q in regs:
                continue
            levels = {stage[r] for r in regs if r in stage}
            if levels == {level}:
                found[q] = level + 1
        if not found:
            return stage
        stage.update(found)
        level += 1


def _ranges(by_wire: dict[str, list[int]]) -> list[str]:
    """``gold:w[hi:lo] == gate:w[hi:lo]`` for each run of consecutive bits of each wire."""
    terms = []
    for wire, bits in sorted(by_wire.items()):
        bits.sort()
        runs: list[list[int]] = []
        for b in bits:
            if runs and b == runs[-1][1] + 1:
                runs[-1][1] = b
            else:
                runs.append([b, b])
        for lo, hi in runs:
            sel = f"[{hi}:{lo}]" if hi > lo else f"[{lo}]"
            terms.append(f"gold:{wire}{sel} == gate:{wire}{sel}")
    return terms


def unstaged_equalities(il: str, top: str, first: str, valid: str) -> tuple[str, ...]:
    """One invariant per public register bit range that no stage of ``stages`` (below the
    valid vector's width) holds: the same in the two copies in every cycle.  scorr (the
    proof's signal correspondence) is meant to find these, and for the BRDF unit's step
    condition does not: given, pdr proves those mutants in seconds."""
    found = stages(il, top, first)
    net = Netlist(il, top)
    width = net.wires[f"\\{valid}"][0]
    staged = {bit for bit, s in found.items() if s < width}
    rest: dict[str, list[int]] = defaultdict(list)
    for q_bits, _ in net.flops():
        for bit in q_bits:
            if bit is not None and bit[0].startswith("\\") and bit not in staged:
                rest[bit[0][1:]].append(bit[1])
    return tuple(_ranges({w: sorted(set(b)) for w, b in rest.items()}))


def staged_invariants(il: str, top: str, first: str, valid: str) -> tuple[str, ...]:
    """One invariant per stage s found (``stages``): ``!gold:<valid>[s] || (...)``, each bit
    range of a register of the stage the same in the two copies (``gold:w[hi:lo] ==
    gate:w[hi:lo]``).  Only public wires (a name without ``$``), stages the valid vector has."""
    found = stages(il, top, first)
    width = Netlist(il, top).wires[f"\\{valid}"][0]
    by_stage: dict[int, dict[str, list[int]]] = defaultdict(lambda: defaultdict(list))
    for (wire, b), s in found.items():
        if wire.startswith("\\") and s < width:
            by_stage[s][wire[1:]].append(b)
    out = []
    for s in sorted(by_stage):
        terms = _ranges(by_stage[s])
        out.append(f"!gold:{valid}[{s}] || (" + " && ".join(terms) + ")")
    return tuple(out)
