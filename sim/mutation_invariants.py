# SPDX-License-Identifier: Apache-2.0
"""The invariants ``make mutants``' fourth proof asserts alongside the outputs
(sim/mutation_proof.py ``equivalence``): facts about the original and a mutant from reset on
that pdr does not find by itself in its time, each proven together with the outputs' equality
(so none is assumed: a wrong one gives a counterexample, never a proof).

An invariant is a Verilog expression over the wires of the two copies, ``gold:<wire>`` (the
original) and ``gate:<wire>`` (the mutant), by the flattened design's names (dots for its
hierarchy), read as each copy's flip-flops show them; a bit select counts from the wire's least
significant bit as 0, whatever its declared range (the core's ``v_reg[10:1]`` is ``[9:0]``
here).  ``DESIGN`` holds a design's (or finds them in its netlist: the BRDF unit's stages,
``_brdf_stages``), given to every mutant of it that the earlier proofs leave; ``STRONGER``
more of a design's, added for one more try where those fail; ``MUTANT`` a
mutation's own (by its ``selector``: its mode, wire and bits, which a new list of the same RTL
names alike under another id, where the cell names carry Yosys's running numbers), given
together with its design's.

Size: data and their reasons; the module only lists them.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from model.units import brdf
from sim import mutation_stages


def _staged(stages: list[tuple[str, tuple[str, ...]]]) -> tuple[str, ...]:
    """One invariant per pipeline stage: while the stage's valid bit is set in the original,
    each of its registers holds the same value in the two copies."""
    return tuple(
        f"!gold:{valid} || (" + " && ".join(f"gold:{r} == gate:{r}" for r in regs) + ")"
        for valid, regs in stages
    )


# The specular unit's pipeline (rtl/specular_unit.v, "Pipeline"): stage s's registers hold a
# pixel while v_reg[s] is set; a mutation that changes them only between lines (the
# accumulator stepping once more after the line's last pixel) changes no pixel, but only
# this says so to the proof (scorr merges registers equal in every state; these are equal
# only while their pixel is valid)
SPECULAR_STAGES = _staged(
    [
        ("v_reg[0]", ("acc_reg",)),
        ("v_reg[1]", ("low_reg", "neg_reg", "big_reg")),
        ("v_reg[2]", ("mag_reg",)),
        ("v_reg[3]", ("prod_reg",)),
        ("v_reg[4]", ("addr_reg",)),
        ("v_reg[5]", ("zero_reg", "rom12_q")),
        ("v_reg[6]", ("rom_d_reg",)),
        ("v_reg[7]", ("out_prod_reg",)),
    ]
)


def _brdf_stages(il: str) -> tuple[str, ...]:
    """The BRDF unit's pipeline (rtl/brdf_unit.v, "Pipeline"), as the specular unit's: stage
    s's registers hold a pixel while v_reg[s] is set.  Each form's datapath has stages and
    registers of its own (the log2 form's 7, the piecewise form's 24 with delay lines packed
    into one vector), so they are found in the form's netlist (sim/mutation_stages.py: the
    accumulator stage 0, every other stage the flip-flop bits that read only the stage
    before), not listed: for the log2 form the front's S1..S5, the product's partial
    products and sum, the table address with the octave and zero flags and their two delays
    beside the second table's two read registers, lv, y, C x F."""
    return mutation_stages.staged_invariants(il, "brdf_unit", "acc_reg", "v_reg")


# A design's invariants: Verilog over the two copies, or a function of the design's netlist
# (its prepared RTLIL) that gives them
DESIGN: dict[str, tuple[str, ...] | Callable[[str], tuple[str, ...]]] = {
    "specular_unit": SPECULAR_STAGES,
    **{f"brdf_unit_{form}": _brdf_stages for form in brdf.RTL_FORMS},
}


def _brdf_unstaged(il: str) -> tuple[str, ...]:
    """The BRDF unit's other registers (the operand, run and control registers, the output):
    the same in the two copies in every cycle (sim/mutation_stages.py
    ``unstaged_equalities``).  The proof's scorr should find these itself, and for the
    step-condition mutants (the accumulator stepping once more after a line's last pixel) does
    not: with them beside the stage invariants pdr proves each in seconds, without them not in
    15 minutes.  Given after the stage invariants alone fail (a mutant of a control register
    breaks its own equality)."""
    return mutation_stages.unstaged_equalities(il, "brdf_unit", "acc_reg", "v_reg")


# Invariants added to a design's for one more try where those alone do not prove a mutant
STRONGER: dict[str, Callable[[str], tuple[str, ...]]] = {
    f"brdf_unit_{form}": _brdf_unstaged for form in brdf.RTL_FORMS
}


def _magnitude(wire: str) -> str:
    """|x| of a 33-bit two's complement wire, 40 bits wide."""
    return f"({wire}[32] ? 40'h200000000 - {wire} : {{7'd0, {wire}}})"


# The Gouraud unit at its default configuration (I_INT 8, I_FRAC 12, P 8, LEN_WIDTH 11):
# start_reg is 33 bits (sign 32), inc_reg 21 (sign 20), a line at most 256 segments.
_S, _G = "gold:start_reg", "gate:start_reg"
_INC, _SEG, _BUSY = "gold:inc_reg", "gold:seg_reg", "gold:busy_reg"
# Room left: |start| + (segments to come + 1) x (2^23 + 2^8) + 2^17 < 2^32.  Each segment adds
# 8 dI, |8 dI| <= 2^23, to the start (the mutant's up to 2^8 more), so what holds at a start
# (|start| <= 2^20 + 2^11, at most 255 segments to come) holds to the line's end: no sum wraps.
_ROOM = (
    f"{{{{1'b0, {_SEG}}} + 12'd1, 23'd0}} + {{{{1'b0, {_SEG}}} + 12'd1, 8'd0}} + 40'd131072"
    " < 40'd4294967296"
)
# Gouraud 174 (start_reg bit 8 flipped while its bit 23 is set): bit 23 is set only once the
# line's start is negative (dI < 0: it stays negative) or at least 2^23 (2048 levels, dI >= 0:
# it stays there), where every lane clamps, to 0 or to 255; a flip of bit 8 (1/16 level) keeps a
# negative start negative and one of at least 2^23 above 2^20 (every lane 255), so the two
# copies' starts differ only while both clamp every lane the same way.  The original's facts
# it needs: a line has at most 256 segments, the room above, the start negative only with dI
# negative and above 2^21 only with dI >= 0.
GOURAUD_CLAMPED = (
    f"{_SEG} < 11'd256",
    f"!{_BUSY} || {_magnitude(_S)} + {_ROOM}",
    f"!{_BUSY} || !{_S}[32] || {_INC}[20]",
    f"!{_BUSY} || {_S}[32] || {_S} < 33'd2097152 || !{_INC}[20]",
    f"{_S} == {_G} || !{_BUSY} || ({_magnitude(_G)} + {_ROOM}"
    f" && (({_INC}[20] && {_S}[32] && {_G}[32])"
    f" || (!{_INC}[20] && !{_S}[32] && !{_G}[32] && {_S} >= 33'd1048576"
    f" && {_G} >= 33'd1048576)))",
)


# The shading core at its default configuration (three channels, 10 stages, FIFO_DEPTH 32):
# the span register's accumulators and increments (``gacc_reg``, ``di_reg``), a side-band slice
# of 50 bits per stage (``side_reg``, S1 in the low bits, each stage's Gouraud values in it),
# then the FIFO's 32 words of 50 bits.
_CORE_STAGES, _CORE_SIDE, _CORE_FIFO = 10, 50, 32
# Core 244 (the ``l == 0`` test of a span's take never true: a one-pixel span loads the
# divider's increment instead of 0): that span's one pixel is the accumulator's first value,
# and the increment is added only after it, to an accumulator the next take loads again.  So
# the two copies' accumulators agree while a span is active, their increments too while
# pixels are left after the present one; a stage's side band (its Gouraud values) agrees while
# the stage holds a pixel, and the FIFO's words, written only with such pixels, always.
CORE_ONE_PIXEL_SPAN = (
    "!gold:act_reg || (gold:gacc_reg == gate:gacc_reg"
    " && (gold:cnt_reg == 11'd0 || gold:di_reg == gate:di_reg))",
    *_staged(
        [
            (f"v_reg[{s}]", (f"side_reg[{(s + 1) * _CORE_SIDE - 1}:{s * _CORE_SIDE}]",))
            for s in range(_CORE_STAGES)
        ]
    ),
    *(f"gold:\\u_fifo.mem[{w}] == gate:\\u_fifo.mem[{w}] " for w in range(_CORE_FIFO)),
    "gold:u_fifo.out_reg == gate:u_fifo.out_reg",
)


def selector(command: str) -> str:
    """What names a mutation across netlists: its mode, the wire and bit it changes (and the
    bit that controls it), not the cell, whose name carries Yosys's running numbers; the
    whole command for a mutation of a cell's port with no wire named."""
    fields = dict(re.findall(r"-(mode|wire|wirebit|ctrlbit) (\S+)", command))
    if "wire" not in fields:
        return command
    return " ".join(
        f"-{k} {fields[k]}" for k in ("mode", "wire", "wirebit", "ctrlbit") if k in fields
    )


MUTANT: dict[tuple[str, str], tuple[str, ...]] = {
    ("gouraud_segment", "-mode cnot1 -wire start_reg -wirebit 8 -ctrlbit 23"): GOURAUD_CLAMPED,
    (
        "shading_core",
        "mutate -mode const1 -module shading_core -cell $eq$shading_core.v:725$166 -port A"
        " -portbit 3 -src shading_core.v:725.49-725.72",
    ): CORE_ONE_PIXEL_SPAN,
}


def invariants(design: str, command: str, design_il: str = "") -> tuple[str, ...]:
    """The invariants the fourth proof asserts for the mutation ``command`` of ``design``
    (``design_il``: its prepared netlist, RTLIL, for a design whose invariants are found in
    it)."""
    given = DESIGN.get(design, ())
    if callable(given):
        given = given(design_il)
    return given + MUTANT.get((design, selector(command)), ())


def stronger(design: str, design_il: str = "") -> tuple[str, ...]:
    """The invariants added to ``invariants``' for the fourth proof's last try (``STRONGER``)
    of a mutant of ``design`` (``design_il``: its prepared netlist, RTLIL)."""
    given = STRONGER.get(design)
    return given(design_il) if given is not None else ()
