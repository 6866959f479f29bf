# SPDX-License-Identifier: Apache-2.0
"""The specular unit's formal jobs (make formal; docs/formal.md): its configuration and
parameters, property numbers, covers, induction helper connections and deliberate errors.

``model.hw.formal`` runs them like the divider's and the Gouraud unit's; this module holds the
unit's data only.  The property file is ``formal/specular_unit_props.v``: port-level timing
(busy, valid), the n error flag and reset at the default configuration; the data output is not
observed but in the proof of ``intensity_zero_on_n_err`` (ARITH), and both ROMs are removed
with their read data left free (``MEMORY``): the ROM contents take no part.  Layer 2: imports
``model.units`` and ``model.hw.formal_gouraud`` (``Mutant``).
"""

from __future__ import annotations

from pathlib import Path

from model.hw.formal_gouraud import Mutant
from model.units import specular

UNIT = "specular_unit"
# default: SpecularConfig's default (the RTL's default parameters, LEN_WIDTH 11, FILL_LATENCY 8)
CONFIGS = {"default": specular.DEFAULT}
# Property labels of formal/specular_unit_props.v and the CHECK number that selects each alone.
PROPERTIES = {
    "busy_exact": 1,
    "valid_exact": 2,
    "n_err_of_the_line": 3,
    "reset_idle": 4,
    "intensity_zero_on_n_err": 5,
}
COVERS = (
    "c_idle",
    "c_busy",
    "c_valid_busy",
    "c_len_zero",
    "c_long_line",
    "c_back_to_back",
    "c_start_while_busy",
    "c_write_in_start",
    "c_strobes_while_busy",
    "c_reset_while_busy",
    "c_n_err",
    "c_n_ok",
    "c_n_write_in_start",
)
# Registers the induction helpers read: wire in the property file -> register of the unit.
INTERNALS = {
    "f_int_len": "len_reg",
    "f_int_nerr": "nerr_reg",
    "f_int_nerr_run": "nerr_run_reg",
    "f_int_busy": "busy_reg",
    "f_int_cnt": "cnt_reg",
    "f_int_v": "v_reg",
    "f_int_last": "last_reg",
    "f_int_zero": "zero_reg",
    "f_int_rom_d": "rom_d_reg",
    "f_int_out_prod": "out_prod_reg",
}
DEFINE = "-DSPECULAR_INTERNALS"
# The ROM words take no part: both ROMs are removed, their read data left free in every cycle
# (sby makes an undriven wire a free input); without ARITH the data path goes with them.
MEMORY = "memory_collect; delete t:$mem_v2; opt_clean"

MUTANTS = {
    m.name: m
    for m in (
        Mutant(
            "busy_stuck",
            "        if (last_reg[LAST_STAGE]) begin\n            busy_reg <= 1'b0;\n",
            "        if (last_reg[LAST_STAGE]) begin\n            busy_reg <= 1'b1;\n",
            "busy_exact",
        ),
        Mutant(
            "start_while_busy_restarts",
            "wire start_ok = start && !busy_reg;\n",
            "wire start_ok = start;\n",
            "busy_exact",
        ),
        Mutant(
            "len_write_in_start_reaches_line",
            "        cnt_reg <= len_reg;\n",
            "        cnt_reg <= len_we ? len_in : len_reg;\n",
            "busy_exact",
        ),
        Mutant(
            "len_write_while_busy",
            "    // Control unit, stage S0: counter 5 and the pixel flags\n",
            "    if (len_we) len_reg <= len_in;\n",
            "busy_exact",
        ),
        Mutant(
            "valid_held",
            "    valid_reg <= 1'b0;\n\n    // Operand registers",
            "\n    // Operand registers",
            "valid_exact",
        ),
        Mutant(
            "one_pixel_too_many",
            "        cnt_reg <= len_reg;\n",
            "        cnt_reg <= len_reg + 1'b1;\n",
            "valid_exact",
        ),
        Mutant(
            "n_err_leak",
            "        n_err_reg <= nerr_run_reg;\n",
            "        n_err_reg <= nerr_reg;\n",
            "n_err_of_the_line",
        ),
        Mutant(
            "reset_keeps_busy",
            "        busy_reg <= 1'b0;\n        valid_reg <= 1'b0;\n        n_err_reg <= 1'b0;\n",
            "        valid_reg <= 1'b0;\n        n_err_reg <= 1'b0;\n",
            "reset_idle",
        ),
        Mutant(
            "no_zero_gate_on_n_err",
            "    zero_reg <= rom_ovf || nerr_run_reg;\n",
            "    zero_reg <= rom_ovf;\n",
            "intensity_zero_on_n_err",
        ),
    )
}


def rom_files(config: str) -> list[Path]:
    """The committed ROM images a configuration reads (copied into the job's folder)."""
    cfg = CONFIGS[config]
    return [specular.rom_path(cfg, "a"), specular.rom_path(cfg, "cos")]


def params(config: str, kind: str = "prove") -> dict[str, object]:
    """The parameters of the property file (or, for equiv, of the unit): the ROM images by the
    names they are copied under."""
    a, cos = rom_files(config)
    return {"A_ROM_FILE": f'"{a.name}"', "COS_ROM_FILE": f'"{cos.name}"'}


def jobs(make, quick: bool = False) -> list:
    """The unit's jobs, made by ``make(name, unit, kind, config, **fields)`` (FormalJob);
    ``quick``: the proof, the covers and one mutant."""
    out = []

    def add(name: str, kind: str, config: str, **kw) -> None:
        out.append(make(f"{UNIT}_{name}", UNIT, kind, config, **kw))

    add("prove_default", "prove", "default", arith=True, properties=tuple(PROPERTIES))
    if not quick:  # RESET_ALL = 1 resets the data path too (intensity_zero_on_n_err reads it)
        kw = {"reset_all": 1, "arith": True, "properties": tuple(PROPERTIES)}
        add("prove_default_r1", "prove", "default", **kw)
    add("cover_default", "cover", "default", depth=24, properties=COVERS)
    for m in ["n_err_leak"] if quick else list(MUTANTS):
        prop = MUTANTS[m].breaks
        arith = prop == "intensity_zero_on_n_err"
        kw = {"arith": arith, "properties": (prop,), "mutant": m}
        add(f"mutant_{m}", "mutant", "default", depth=24, **kw)
    return out
