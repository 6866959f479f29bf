# SPDX-License-Identifier: Apache-2.0
"""The BRDF unit's formal jobs (make formal; docs/formal.md): its configuration and parameters,
property numbers, covers, induction helper connections and deliberate errors.

``model.hw.formal`` runs them like the other units'; this module holds the unit's data only.
The property file is ``formal/brdf_unit_props.v``: port-level timing (busy, valid), the n error
flag and reset, proven by k-induction at each form's default widths (``brdf.UNIT_CONFIGS``).
Every table is removed with its read data left free (``MEMORY``) and the data path, which no
property observes, goes with them: the protocol holds whatever the table words.  Layer 2:
imports ``model.units`` and ``model.hw.mutants`` (``Mutant``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

from model.hw.mutants import Mutant
from model.units import brdf


class FormalJob(Protocol):
    """What is read of a ``model.hw.formal.FormalJob`` (not imported: formal imports this)."""

    config: str
    kind: str


UNIT = "brdf_unit"
# Each form with RTL at its default widths (the RTL's default parameters, LEN_WIDTH 11)
CONFIGS = dict(brdf.UNIT_CONFIGS)
# Property labels of formal/brdf_unit_props.v and the CHECK number that selects each alone.
PROPERTIES = {
    "busy_exact": 1,
    "valid_exact": 2,
    "n_err_of_the_line": 3,
    "reset_idle": 4,
}
PROTOCOL = tuple(PROPERTIES)
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
}
DEFINE = "-DBRDF_INTERNALS"
# The table words take no part: both tables are removed, their read data left free in every
# cycle (sby makes an undriven wire a free input); the unobserved data path goes with them.
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
    )
}
MUTANT_DEPTH = 24  # reset, writes, start, 11 fill cycles, a line of a few pixels


def rom_files(config: str) -> list[Path]:
    """The committed table images the configuration reads (copied into the job's folder)."""
    cfg = CONFIGS[config]
    return [brdf.rom_path(cfg, which) for which in brdf.rom_kinds(cfg)]


def params(config: str, kind: str = "prove") -> dict[str, object]:
    """The parameters of the property file: the configuration's RTL parameters, the table
    images by the names they are copied under."""
    out: dict[str, object] = {}
    for name, value in brdf.hdl_parameters(CONFIGS[config]).items():
        if name.endswith("ROM_FILE"):
            value = Path(str(value)).name
        out[name] = f'"{value}"' if isinstance(value, str) else value
    return out


def jobs(make, quick: bool = False) -> list:
    """The unit's jobs, made by ``make(name, unit, kind, config, **fields)`` (FormalJob);
    ``quick``: the protocol proof of the cosine-quadratic form, its covers and one mutant; else
    also the quadratic's, the cubic's, the log2's and the piecewise form's proofs, every form
    with RESET_ALL = 1, and every mutant."""
    out = []

    def add(name: str, kind: str, config: str, **kw) -> None:
        out.append(make(f"{UNIT}_{name}", UNIT, kind, config, **kw))

    forms = ["cosine_quadratic"] if quick else list(CONFIGS)
    for form in forms:
        add(f"prove_{form}", "prove", form, properties=PROTOCOL)
        if not quick:
            add(f"prove_{form}_r1", "prove", form, reset_all=1, properties=PROTOCOL)
    add("cover_cosine_quadratic", "cover", "cosine_quadratic", depth=24, properties=COVERS)
    for m in ["n_err_leak"] if quick else list(MUTANTS):
        kw = {"properties": (MUTANTS[m].breaks,), "mutant": m}
        add(f"mutant_{m}", "mutant", "cosine_quadratic", depth=MUTANT_DEPTH, **kw)
    return out
