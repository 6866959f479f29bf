# SPDX-License-Identifier: Apache-2.0
"""The segment Gouraud unit's formal jobs (make formal; docs/formal.md): its configurations and
parameters, property numbers, covers, induction helper connections and deliberate errors.

``model.hw.formal`` runs them like the divider's; this module holds the unit's data only (its
deliberate errors are ``model.hw.mutants.Mutant`` snippets).  The property file is
``formal/gouraud_segment_props.v``.  Layer 2: imports ``model.units`` and ``model.hw.mutants``.
"""

from __future__ import annotations

from model.hw.mutants import Mutant
from model.units import gouraud

UNIT = "gouraud_segment"
# default: GouraudConfig's default (P = 8, Q8.12, 11-bit length); small: a reduced unit where
# the arithmetic is also proven with a multiplication (I0 + (s*P)*dI) and the mutants run
CONFIGS = {
    "default": gouraud.DEFAULT,
    "small": gouraud.GouraudConfig(i_int=4, i_frac=4, p=4, len_width=4),
}
# Property labels of formal/gouraud_segment_props.v and the CHECK number that selects each alone.
PROPERTIES = {
    "busy_exact": 1,
    "valid_exact": 2,
    "last_exact": 3,
    "segments_per_line": 4,
    "mask_exact": 5,
    "reset_idle": 6,
    "pixels_held": 7,
    "lanes": 8,
}
PROTOCOL = tuple(p for p in PROPERTIES if p != "lanes")
PRODUCT = "acc_is_i0_plus_i_di"  # the accumulated start is I0 + (s*P)*dI (small configuration)
COVERS = (
    "c_idle",
    "c_busy",
    "c_valid_segment",
    "c_last",
    "c_len_zero",
    "c_partial_mask",
    "c_back_to_back",
    "c_write_in_start",
    "c_reset_while_busy",
    "c_clamp_zero",
    "c_clamp_max",
)
# Registers the induction helpers read: wire in the property file -> register of the unit.
INTERNALS = {
    "f_int_i0": "i0_reg",
    "f_int_di": "di_reg",
    "f_int_len": "len_reg",
    "f_int_busy": "busy_reg",
    "f_int_seg": "seg_reg",
    "f_int_last_mask": "last_mask_reg",
    "f_int_inc": "inc_reg",
    "f_int_start": "start_reg",
}
DEFINE = "-DGOURAUD_INTERNALS"


MUTANTS = {
    m.name: m
    for m in (
        Mutant(
            "busy_stuck",
            "            busy_reg <= 1'b0;\n            last_reg <= 1'b1;\n",
            "            busy_reg <= 1'b1;\n            last_reg <= 1'b1;\n",
            "busy_exact",
        ),
        Mutant(
            "valid_held",
            "    valid_reg <= 1'b0;\n    last_reg <= 1'b0;\n",
            "    last_reg <= 1'b0;\n",
            "valid_exact",
        ),
        Mutant(
            "last_held",
            "    valid_reg <= 1'b0;\n    last_reg <= 1'b0;\n",
            "    valid_reg <= 1'b0;\n",
            "last_exact",
        ),
        Mutant(
            "one_segment_too_many",
            "(len_m1 >> LOG2P);",
            "(len_reg >> LOG2P);",
            "segments_per_line",
        ),
        Mutant(
            "mask_one_lane_short",
            "~({P{1'b1}} << len_rem);",
            "~({P{1'b1}} << (len_rem - 1'b1));",
            "mask_exact",
        ),
        Mutant(
            "len_write_in_start_reaches_line",
            "            seg_reg <= seg_first;\n",
            "            seg_reg <= len_we ? ((len_in - 1'b1) >> LOG2P) : seg_first;\n",
            "busy_exact",
        ),
        Mutant(
            "reset_keeps_busy",
            "        busy_reg <= 1'b0;\n        valid_reg <= 1'b0;\n",
            "        valid_reg <= 1'b0;\n",
            "reset_idle",
        ),
        Mutant(
            "pixels_at_start",
            "            busy_reg <= 1'b1;\n",
            "            busy_reg <= 1'b1;\n            pixels_reg <= lane_pixels;\n",
            "pixels_held",
        ),
        Mutant(
            "no_clamp_to_max",
            "(sum[I_FRAC+I_INT-1:I_FRAC] | {I_INT{overflow}})",
            "sum[I_FRAC+I_INT-1:I_FRAC]",
            "lanes",
        ),
        Mutant(
            "di_write_while_busy",
            "        // One segment per clock\n",
            "        if (di_we) inc_reg <= di_in;\n",
            "lanes",
        ),
    )
}


def params(config: str, kind: str = "prove") -> dict[str, object]:
    """The RTL parameters of a configuration; for the property file (every kind but equiv)
    also PRODUCT: 1 for the small configuration."""
    cfg = CONFIGS[config]
    out: dict[str, object] = {
        "I_INT": cfg.i_int,
        "I_FRAC": cfg.i_frac,
        "P": cfg.p,
        "LEN_WIDTH": cfg.len_width,
    }
    if kind != "equiv":
        out["PRODUCT"] = int(config == "small")
    return out


def jobs(make, quick: bool = False) -> list:
    """The unit's jobs, made by ``make(name, unit, kind, config, **fields)`` (FormalJob);
    ``quick``: the protocol proof and the covers at the small configuration and one mutant."""
    out = []

    def add(name: str, kind: str, config: str, **kw) -> None:
        out.append(make(f"{UNIT}_{name}", UNIT, kind, config, **kw))

    if quick:
        add("prove_small", "prove", "small", properties=PROTOCOL)
        add("cover_small", "cover", "small", depth=10, arith=True, properties=COVERS)
        add(
            "mutant_valid_held",
            "mutant",
            "small",
            depth=8,
            properties=("valid_exact",),
            mutant="valid_held",
        )
        return out
    add("prove_default", "prove", "default", arith=True, properties=tuple(PROPERTIES))
    add("prove_small_r1", "prove", "small", reset_all=1, properties=PROTOCOL)
    add("prove_small_arith", "prove", "small", arith=True, properties=(*PROPERTIES, PRODUCT))
    add("cover_default", "cover", "default", depth=10, arith=True, properties=COVERS)
    add("cover_small", "cover", "small", depth=10, arith=True, properties=COVERS)
    for m in MUTANTS.values():
        arith = m.breaks == "lanes"
        add(
            f"mutant_{m.name}",
            "mutant",
            "small",
            depth=12,
            arith=arith,
            properties=(m.breaks,),
            mutant=m.name,
        )
    for c in ("default", "small"):
        add(f"equiv_{c}", "equiv", c, depth=0, properties=("netlist_equals_rtl",))
    return out
