# SPDX-License-Identifier: Apache-2.0
"""The shading core's sixth proof in ``make mutants`` (sim/mutation_induction.py's method): a
mutation of a Gouraud value's saturation (rtl/shading_core.v, ``g_gouraud``) that changes
the value only where the span register's accumulator is negative.

The accumulator of a channel never is negative while a span issues pixels: a span of length l
starts it at i_start + bias (bias = 2^(I_FRAC - 1)) and adds dI = round(a r / 2^N) l times,
a = i_end - i_start and r = round(2^N / l) the reciprocal ROM's word, so it moves in a
straight line to e = i_start + bias + l dI, which lies in [LOW, HIGH): l dI - a >= -2044 for
every length and every a (the lemma, decided per length with the ROM word a constant; at
l = 2046, a = -1047554 it is -2044 exactly, so LOW = 5 fails there), hence
e >= i_end + 4.  The invariants (``Accumulator.invariants``):

* every flip-flop, FIFO word and ROM equal in the two copies, the side band's slots where
  their valid bit is set (a slot holds the Gouraud values of the pixel issued into it);
* the channel's increment pipeline (rtl/shading_increment.v) under the valid bits va..ve:
  the ROM word read for the stage's length, the stage's products as the RTL forms them from
  the stage's a (the harness's shadows ``mutation_a_c`` .. ``_e``) and that word, and
  i_start + a in [0, 2^I_WIDTH) (i_end, the span's own field);
* while a span is active, with the harness's count k (``mutation_k``) and end value e
  (``mutation_e``, 48 bits, set as the span is taken): k = cnt, acc + k dI = e exactly,
  LOW <= e < HIGH, and the accumulator's sign bit 0.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import z3

from sim.mutation_induction import Induction, functional_miter, prove, rom_images
from sim.mutation_proof import CLOCK_PORTS, mutant_netlist, mutate_field, port_widths

# The accumulator's end value e lies in [LOW, 2^HIGH_BITS) for every span (the lemma: i_end
# < 2^20, plus the bias 2^11, plus l dI - a <= 2044)
LOW = 4
HIGH_BITS = 22
# The harness's 48-bit count and end value (wide enough for l dI exactly)
WIDE = 48
# The reciprocal ROM's field, and its registered read (recip_q)
RECIP_ROM = "u_recip_rom.rom"
RECIP_Q = "u_recip_rom.q_a_reg"


@dataclass(frozen=True)
class Shape:
    """The widths of the core the proof reads off its netlist (``shape``), and the mutated
    channel."""

    channel: int
    channels: int
    len_width: int  # LEN_WIDTH
    i_width: int  # I_INT + I_FRAC
    i_int: int
    di_width: int  # I_WIDTH + 1 (the increment, and the dividend a)
    g_width: int  # the accumulator
    recip_bits: int  # N (the ROM word has N + 1 bits)
    x_width: int
    y_width: int
    fb_width: int  # stage C..E's field register
    stages: int
    side: int  # one side band slot

    @property
    def bias(self) -> int:
        return 1 << (self.i_width - self.i_int - 1)

    @property
    def l_at(self) -> int:
        """The length's lowest bit in fc_reg..fe_reg ({x, y, l, spec, diff, i, ...})."""
        return self.fb_width - self.x_width - self.y_width - self.len_width

    @property
    def i_at(self) -> int:
        return self.l_at - 2 - self.channels * self.i_width + self.channel * self.i_width


def _width(il: str, wire: str) -> int:
    found = re.search(rf"^\s*wire (?:width (\d+) )?(?:\S+ )*\\{re.escape(wire)}$", il, re.M)
    if found is None:
        raise ValueError(f"the core's netlist has no wire {wire}")
    return int(found.group(1) or 1)


def _channels(il: str) -> int:
    """The core's colour channels: its increment units."""
    return len(re.findall(r"^\s*wire (?:\S+ )*\\g_increment\[\d+\]\.u_increment\.a_reg$", il, re.M))


def gouraud_channel(il: str, command: str) -> int | None:
    """The channel whose Gouraud value the mutation ``command`` changes (its cell drives a
    slice of ``g_val`` or reads a wire of that channel's ``g_gouraud`` block), or None."""
    cell = re.escape(mutate_field(command, "cell"))
    found = re.search(rf"^\s*cell \S+ {cell}\n(.*?)^\s*end$", il, re.M | re.S)
    if found is None:
        return None
    i_int = _width(il, "g_val") // _channels(il)
    value = re.search(r"\\g_val \[(\d+)(?::(\d+))?\]", found.group(1))
    if value:
        return int(value.group(2) or value.group(1)) // i_int
    block = re.search(r"\\g_gouraud\[(\d+)\]\.", found.group(1))
    return int(block.group(1)) if block else None


def shape(il: str, channel: int) -> Shape:
    """The core's widths from its netlist ``il`` (the original's), for ``channel``."""
    channels = _channels(il)
    stages = _width(il, "v_reg")
    return Shape(
        channel=channel,
        channels=channels,
        len_width=_width(il, "ld"),
        i_width=_width(il, "id") // channels,
        i_int=_width(il, "g_val") // channels,
        di_width=_width(il, "di_b") // channels,
        g_width=_width(il, "gacc_reg") // channels,
        recip_bits=_width(il, "recip_q") - 1,
        x_width=_width(il, "x_reg"),
        y_width=_width(il, "y_reg"),
        fb_width=_width(il, "fe_reg"),
        stages=stages,
        side=_width(il, "side_reg") // stages,
    )


def harness(ports: dict[str, tuple[str, int]], s: Shape) -> str:
    """The miter's top: both copies on the same inputs, the original's outputs ``gold_*``
    and the mutant's ``gate_*``, the original's ce, take and issue, and the shadows: the
    channel's dividend a through stages C, D and E (beside rtl/shading_increment.v's
    products), the span's count k and end value e."""
    decl: list[str] = []
    conn_gold: list[str] = []
    conn_gate: list[str] = []
    for name, (direction, width) in sorted(ports.items()):
        rng = f"[{width - 1}:0] " if width > 1 else ""
        if direction == "input":
            decl.append(f"    input  wire {rng}{name}")
            conn_gold.append(f".{name}({name})")
            conn_gate.append(f".{name}({name})")
        else:
            for copy, conn in (("gold", conn_gold), ("gate", conn_gate)):
                decl.append(f"    output wire {rng}{copy}_{name}")
                conn.append(f".{name}({copy}_{name})")
    c, i, d, w = s.channel, s.i_width, s.di_width, WIDE
    decl += [
        "    output wire ce", "    output wire take", "    output wire issue",
        f"    output wire [{s.len_width - 1}:0] ld",
        # the shadows (outputs: the functional back end keeps only what reaches one)
        *(f"    output reg  [{d - 1}:0] mutation_a_{stage}" for stage in "cde"),
        f"    output reg  [{w - 1}:0] mutation_k", f"    output reg  [{w - 1}:0] mutation_e",
    ]  # fmt: skip
    # the original's wires the harness reads (made ports by ``expose``)
    conn_gold += [
        ".ce(ce)", ".take(take)", ".issue(issue)", ".ld(ld)", ".id(id)", ".di_b(di_b)",
        f".\\g_increment[{c}].u_increment.a_reg (a_b)",
    ]  # fmt: skip
    ports_text = ",\n".join(decl)
    return f"""// The sixth proof's miter (sim/mutation_accumulator.py), channel {c}
module mutation_miter (
{ports_text}
);
wire [{s.channels * i - 1}:0] id;
wire [{s.channels * d - 1}:0] di_b;
wire [{d - 1}:0] a_b;
mutation_gold gold ({", ".join(conn_gold)});
mutation_gate gate ({", ".join(conn_gate)});
wire [{i - 1}:0] i_e = id[{c * i} +: {i}];
// the increment the span register takes (0 for a span of one pixel, as it does)
wire [{d - 1}:0] d_e = (ld == {s.len_width}'d0) ? {d}'d0 : di_b[{c * d} +: {d}];
always @(posedge clk) begin
    if (ce) begin
        mutation_a_c <= a_b;
        mutation_a_d <= mutation_a_c;
        mutation_a_e <= mutation_a_d;
    end
    if (take) begin
        mutation_k <= {{{w - s.len_width}'d0, ld}};
        mutation_e <= {{{w - i}'d0, i_e}} + {w}'d{s.bias}
                      + {{{w - s.len_width}'d0, ld}} * {{{{{w - d}{{d_e[{d - 1}]}}}}, d_e}};
    end else if (issue) begin
        mutation_k <= mutation_k - {w}'d1;
    end
end
endmodule
"""


def _reg(name: str) -> str:
    """The state field of the register ``name`` (``autoname``: after its output)."""
    return f"{name}_$ff_Q"


def _ff(copy: str, wire: str) -> str:
    return _reg(f"{copy}.{wire}")


class Accumulator(Induction):
    """The invariants, contract, cases and lemma of the module's docstring, for ``shape``;
    ``low`` the lemma's and invariant's lower bound; ``dropped``: invariants left out of the
    assumptions (the tests show the proof fail without them)."""

    def __init__(self, smt2: str, s: Shape, low: int = LOW, dropped: tuple[str, ...] = ()) -> (
        None
    ):  # fmt: skip
        super().__init__(smt2)
        self.s, self.low, self.dropped = s, low, frozenset(dropped)
        # the reciprocal ROM's image, the lemma's word of each length
        self.words = rom_images(smt2)[f"gold.{RECIP_ROM}"]

    # -- the pieces of a state
    def _rtl_products(self, a: z3.BitVecRef, r: z3.BitVecRef) -> dict[str, z3.BitVecRef]:
        """rtl/shading_increment.v's registers from a and r, formed as its Verilog forms
        them (widths and signedness)."""
        s = self.s
        aw, rb = s.di_width, s.recip_bits
        al, ah, rl, rh = aw // 2, aw - aw // 2, (rb + 1) // 2, rb + 1 - (rb + 1) // 2
        q = aw + rb + 1
        a_lo, a_hi = z3.Extract(al - 1, 0, a), z3.Extract(aw - 1, al, a)
        r_lo, r_hi = z3.Extract(rl - 1, 0, r), z3.Extract(rb, rl, r)

        def zx(v: z3.BitVecRef, n: int) -> z3.BitVecRef:
            return z3.ZeroExt(n - v.size(), v)

        def sx(v: z3.BitVecRef, n: int) -> z3.BitVecRef:
            return z3.SignExt(n - v.size(), v)

        ll = zx(a_lo, al + rl) * zx(r_lo, al + rl)
        lh = zx(a_lo, al + rh) * zx(r_hi, al + rh)
        hl = sx(a_hi, ah + rl + 1) * sx(zx(r_lo, rl + 1), ah + rl + 1)
        hh = sx(a_hi, ah + rh + 1) * sx(zx(r_hi, rh + 1), ah + rh + 1)
        lo = zx(ll, q) + (zx(lh, q) << rl)
        hi = sx(hl, q) + (sx(hh, q) << rl)
        return {"ll": ll, "lh": lh, "hl": hl, "hh": hh, "lo": lo, "hi": hi, "q": lo + (hi << al)}

    def invariants(self, st: dict[str, z3.ExprRef]) -> list[tuple[str, z3.BoolRef]]:
        s = self.s
        found: list[tuple[str, z3.BoolRef]] = []
        for f in self.machine.fields:
            if f.startswith("gold.") and f != _ff("gold", "side_reg"):
                found.append((f"copies equal: {f[5:]}", st[f] == st["gate." + f[5:]]))
        valid = st[_ff("gold", "v_reg")]
        side_g, side_m = st[_ff("gold", "side_reg")], st[_ff("gate", "side_reg")]
        for k in range(s.stages):
            lo, hi = k * s.side, (k + 1) * s.side - 1
            found.append((
                f"side band slot {k + 1} equal while valid",
                z3.Implies(z3.Extract(k, k, valid) == 1,
                           z3.Extract(hi, lo, side_g) == z3.Extract(hi, lo, side_m)),
            ))  # fmt: skip

        def g(wire: str) -> z3.BitVecRef:
            return st[_ff("gold", wire)]

        def inc(reg: str) -> z3.BitVecRef:
            return g(f"g_increment_{s.channel}_.u_increment.{reg}")

        rom = st[f"gold.{RECIP_ROM}"]
        abits = rom.sort().domain().size()

        def word(length: z3.BitVecRef) -> z3.BitVecRef:
            return z3.Select(rom, z3.ZeroExt(abits - length.size(), length))

        def chan(v: z3.BitVecRef, width: int) -> z3.BitVecRef:
            return z3.Extract((s.channel + 1) * width - 1, s.channel * width, v)

        def field_l(reg: str) -> z3.BitVecRef:
            return z3.Extract(s.l_at + s.len_width - 1, s.l_at, g(reg))

        def field_i(reg: str) -> z3.BitVecRef:
            return z3.Extract(s.i_at + s.i_width - 1, s.i_at, g(reg))

        def in_range(i: z3.BitVecRef, a: z3.BitVecRef) -> z3.BoolRef:
            n = s.di_width + 1
            return z3.ULT(z3.ZeroExt(n - i.size(), i) + z3.SignExt(n - a.size(), a), 1 << s.i_width)

        def under(bit: str, name: str, claim: z3.BoolRef) -> None:
            found.append((f"stage {bit[1]}: {name}", z3.Implies(g(f"{bit}_reg") == 1, claim)))

        under("va", "ROM word of the length", g(RECIP_Q) == word(g("la_reg")))
        under(
            "va",
            "i_start + a in range",
            in_range(chan(g("ia_reg"), s.i_width), chan(g("da_reg"), s.di_width)),
        )
        under("vb", "ROM word of the length", inc("r_reg") == word(g("lb_reg")))
        under("vb", "i_start + a in range", in_range(chan(g("ib_reg"), s.i_width), inc("a_reg")))
        for stage, regs in (("c", ("ll", "lh", "hl", "hh")), ("d", ("lo", "hi")), ("e", ("q",))):
            a = st[_reg(f"mutation_a_{stage}")]
            want = self._rtl_products(a, word(field_l(f"f{stage}_reg")))
            for reg in regs:
                under(f"v{stage}", f"{reg} of a and the word", inc(f"{reg}_reg") == want[reg])
            under(f"v{stage}", "i_start + a in range", in_range(field_i(f"f{stage}_reg"), a))
        act = g("act_reg") == 1
        acc, di = chan(g("gacc_reg"), s.g_width), chan(g("di_reg"), s.di_width)
        k, e = st[_reg("mutation_k")], st[_reg("mutation_e")]
        w, w_acc = WIDE, s.g_width
        found += [
            ("span: k = cnt", z3.Implies(act, k == z3.ZeroExt(w - s.len_width, g("cnt_reg")))),
            ("span: acc + k dI = e", z3.Implies(
                act, z3.SignExt(w - s.g_width, acc) + k * z3.SignExt(w - s.di_width, di) == e)),
            ("span: e in range", z3.Implies(act, self._e_range(e))),
            ("span: acc sign 0", z3.Implies(act, z3.Extract(w_acc - 1, w_acc - 1, acc) == 0)),
        ]  # fmt: skip
        return found

    def _e_range(self, e: z3.BitVecRef) -> z3.BoolRef:
        return z3.And(z3.ULE(self.low, e), z3.ULT(e, 1 << HIGH_BITS))

    def contract(self, out: dict[str, z3.ExprRef]) -> z3.BoolRef:
        """The core's: tready and tvalid equal, the beat equal while tvalid."""
        beat = ("m_axis_tdata", "m_axis_tlast", "m_axis_tuser")
        return z3.And(
            out["gold_s_axis_tready"] == out["gate_s_axis_tready"],
            out["gold_m_axis_tvalid"] == out["gate_m_axis_tvalid"],
            z3.Implies(out["gold_m_axis_tvalid"] == 1,
                       z3.And(*(out[f"gold_{p}"] == out[f"gate_{p}"] for p in beat))),
        )  # fmt: skip

    def cases(self, out: dict[str, z3.ExprRef]) -> list[z3.BoolRef]:
        return [out["ce"], out["take"], out["issue"]]

    def lemma_when(self, out: dict[str, z3.ExprRef]) -> z3.BoolRef:
        return out["take"] == 1

    def lemma_premise(self, st: dict, out: dict, value: int) -> z3.BoolRef:
        """A span of length ``value`` taken, the ROM's word of that length the netlist's
        own."""
        rom = st[f"gold.{RECIP_ROM}"]
        return z3.And(out["ld"] == value, z3.Select(rom, value) == self.words[value])

    def lemma_claim(self, after: dict[str, z3.ExprRef]) -> z3.BoolRef:
        """The span's end value in range."""
        return self._e_range(after[_reg("mutation_e")])

    def lemma_values(self) -> list[int]:
        return list(range(1 << self.s.len_width))

    def base_state(self) -> dict[str, z3.ExprRef]:
        return self.machine.state(lambda f: "s." + f.removeprefix("gold.").removeprefix("gate."))

    def reset(self, inputs: dict[str, z3.ExprRef]) -> z3.BoolRef:
        return inputs["rst_n"] == 0


def accumulator_miter(folder: Path, design_il: Path, command: str, s: Shape) -> Path:
    """The functional netlist of the original and the mutant under ``harness``."""
    folder.mkdir(parents=True, exist_ok=True)
    mutant_netlist(folder, design_il, command)
    ports = port_widths(design_il.read_text(), "shading_core")
    expose = [
        "ce",
        "take",
        "issue",
        "ld",
        "id",
        "di_b",
        f"g_increment?{s.channel}?.u_increment.a_reg",
    ]
    gate = folder / "gate.il"
    miter = harness(ports, s)
    return functional_miter(folder / "induction", design_il, gate, "shading_core", expose, miter)


def accumulator_equivalence(folder: Path, design_il: Path, command: str, jobs: int = 2) -> (
    str | None
):  # fmt: skip
    """The sixth proof as ``make mutants`` gives it a mutant of the core the others leave: the
    method's text if the mutation changes a Gouraud value (``gouraud_channel``) and every
    query holds, else None (a clock port's mutation too: every flip-flop of the functional
    netlist steps on one clock)."""
    if mutate_field(command, "port") in CLOCK_PORTS:  # the functional netlist has one clock
        return None
    il = design_il.read_text()
    channel = gouraud_channel(il, command)
    if channel is None:
        return None
    s = shape(il, channel)
    smt2 = accumulator_miter(folder, design_il, command, s)
    verdict, counts = prove(folder, Accumulator, smt2, (s,), jobs)
    return proven_text(channel, counts) if verdict == "proven" else None


def proven_text(channel: int, counts: dict[str, int]) -> str:
    """The record's text for a mutant the sixth proof proves on ``channel`` with ``counts``
    queries of each kind."""
    return (
        f"induction in z3 over the two netlists ({counts['base']} base, {counts['step']} step "
        f"queries), channel {channel}'s accumulator shown in range for every span "
        f"({counts['lemma']} lengths): the Gouraud value of a negative accumulator never issued"
    )
