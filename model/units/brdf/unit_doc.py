# SPDX-License-Identifier: Apache-2.0
"""BRDF family: the hardware unit's data sheet tables (docs/brdf_unit.md), printed from the model.

``format_hardware()`` is the markdown docs/brdf_unit.md carries between its ``hardware tables``
marks (``python scripts/brdf_unit.py`` prints it; tests/test_brdf_unit.py fails if the page
differs): the ports, every parameter with both ends of its legal range (found by asking
``check_unit`` and the configuration classes, not written down), the timing and what each
form's structure costs (multipliers with their operand widths, table bits) beside the patent's
specular unit.  May import ``model.units.specular``'s public names, ``fixed`` and ``unit``.
"""

from __future__ import annotations

from dataclasses import dataclass

from model.units.brdf.fixed import FixedConfig, table_bits
from model.units.brdf.unit import (
    ANGLE_FIELDS,
    FRONT_STAGES,
    UNIT_CONFIGS,
    check_unit,
    fill_latency,
    form_latency,
)
from model.units.specular import DEFAULT, N_MAX, N_WIDTH, SpecularConfig

PROBE = range(-2, 80)
"""The values tried for each width when the legal range is looked for."""


def unit_config(form: str = "cosine_quadratic", **fields: int) -> FixedConfig:
    """A checked ``FixedConfig`` from the unit's parameters as flat model fields (the angle's
    six among them, its other fields at ``SpecularConfig``'s defaults)."""
    angle = SpecularConfig(**{k: fields.pop(k) for k in ANGLE_FIELDS if k in fields})
    return check_unit(FixedConfig(form, angle=angle, **fields))


@dataclass(frozen=True)
class ParameterRange:
    """One RTL parameter: its model field, the legal values with the others at ``base``."""

    name: str
    field: str
    meaning: str
    lo: int
    hi: int
    default: int
    base: str  # the other fields the range holds with ("" = the defaults)


MEANINGS = {
    "c_int_bits": "C register integer bits (output LSBs)",
    "c_frac_bits": "C register fraction bits",
    "z_int_bits": "dz, z0 integer bits including the sign (units of pi/2)",
    "z_frac_bits": "dz, z0 and accumulator fraction bits",
    "len_width": "interval counter width: l = 0 .. 2^LEN_WIDTH - 1",
    "out_width": "intensity bits (saturated)",
    "cos_addr_bits": "angle-table address bits A (fraction bits of \\|zeta\\|, units of pi/2)",
    "cos_data_bits": (
        "angle-table word bits D (w = 1 - cos, D fraction bits; the log2 form: -log2 cos, "
        "D - 2 fraction bits)"
    ),
    "coef_bits": (
        "coefficient word bits (the quadratic's a, each of the cubic's r, p0, b1, b2 and of the "
        "piecewise form's r, p0, b1, b2, s2, beta; unused by the cosine-quadratic and the log2)"
    ),
    "work_bits": "fraction bits P of the form's intermediate values (unused by the log2)",
    "out_bits": (
        "fraction bits O of the form's output word F (the piecewise form's quotient bits: "
        "O + 1 divider stages)"
    ),
    "log_addr_bits": "the log2 form's second table: address bits E (f rounded to E bits)",
    "log_data_bits": "the log2 form's second table: word bits L (log2(1 + f), L fraction bits)",
}
"""What each parameter is, in the RTL's order."""


def _legal(form: str, name: str, base: dict[str, int]) -> list[int]:
    legal = []
    for value in PROBE:
        try:
            unit_config(form, **{**base, name: value})
        except ValueError:
            continue
        legal.append(value)
    return legal


def parameter_ranges() -> list[ParameterRange]:
    """Each width parameter with both ends of its legal range, found by trying ``PROBE``
    (every legal set is contiguous: checked here); the default is the default configuration's.
    Z_FRAC_BITS is tried with COS_ADDR_BITS = 2 (it must be at least COS_ADDR_BITS), the
    quadratic's, the cubic's and the piecewise form's COEF_BITS and the cubic's and the
    piecewise form's WORK_BITS get rows of their own."""
    default = UNIT_CONFIGS["cosine_quadratic"]
    rows = []
    for name, meaning in MEANINGS.items():
        cases = [("cosine_quadratic", {}, "")]
        if name == "z_frac_bits":
            cases = [("cosine_quadratic", {"cos_addr_bits": 2}, "COS_ADDR_BITS = 2")]
        if name == "cos_addr_bits":
            cases = [("cosine_quadratic", {}, "at most Z_FRAC_BITS")]
        if name == "coef_bits":
            cases = [
                ("cosine_quadratic", {}, "cosine_quadratic"),
                ("quadratic", {}, "quadratic"),
                ("cubic", {}, "cubic"),
                ("piecewise", {}, "piecewise"),
            ]
        if name == "work_bits":
            cases = [
                ("cosine_quadratic", {}, ""),
                ("cubic", {}, "cubic"),
                ("piecewise", {}, "piecewise"),
            ]
        for form, base, note in cases:
            legal = _legal(form, name, base)
            if legal != list(range(legal[0], legal[-1] + 1)):
                raise AssertionError(f"{name}: the legal values {legal} are not one range")
            value = getattr(default.angle if name in ANGLE_FIELDS else default, name)
            rows.append(
                ParameterRange(name.upper(), name, meaning, legal[0], legal[-1], value, note)
            )
    return rows


def multipliers(cfg: FixedConfig) -> list[tuple[str, int, int]]:
    """The unit's multipliers as (what, operand bits, operand bits): the form's (two, the
    cubic's four: b2 x tau and tau x h signed, the piecewise form's the cubic's four and
    beta x (r w - 1), the log2's one: n times the table word) and C x F.  The piecewise form's
    divider is not a multiplier: one subtractor per quotient bit."""
    check_unit(cfg)
    d, p = cfg.cos_data_bits, cfg.work_bits
    cubic = [
        ("r x w", cfg.coef_bits, d + 1),
        ("b2 x tau", cfg.coef_bits + 1, p + 5),
        ("tau x h", p + 5, p + 5),
        ("c x max(0, P)", d + 1, p + 9),
    ]
    form = {
        "cosine_quadratic": [("7n x w", 13, d + 1), ("base x base", p + 1, p + 1)],
        "quadratic": [("a x w", cfg.coef_bits, d + 1), ("c x (1 - a w)", d + 1, p + 1)],
        "cubic": cubic,
        "piecewise": [*cubic, ("beta x (r w - 1)", cfg.coef_bits, p + 11)],
        "log2": [("n x -log2 cos", N_WIDTH, d)],
    }[cfg.form]
    c_width = cfg.angle.c_int_bits + cfg.angle.c_frac_bits
    return [*form, ("C x F", c_width, cfg.out_bits)]


def _specular_multipliers(cfg: SpecularConfig) -> list[tuple[str, int, int]]:
    """The patent's unit: multiplier 11 (|zeta| x a) and 13 (C x cos^k)."""
    return [
        ("\\|zeta\\| x a", cfg.mag_width, cfg.a_width),
        ("C x cos^k", cfg.c_width, cfg.rom_data_bits),
    ]


def format_ports(cfg: FixedConfig) -> str:
    fmt = cfg.angle
    c, z = fmt.c_int_bits + fmt.c_frac_bits, fmt.z_int_bits + fmt.z_frac_bits
    rows = [
        ("clk", "in", 1, "rising-edge clock"),
        ("rst_n", "in", 1, "synchronous, active low: idle, busy = 0, valid = 0, operands cleared"),
        ("c_in, c_we", "in", c, "C, unsigned Q(C_INT_BITS).(C_FRAC_BITS), output LSBs"),
        ("dz_in, dz_we", "in", z, "the angle step, signed Q(Z_INT_BITS).(Z_FRAC_BITS), pi/2"),
        ("z0_in, z0_we", "in", z, "the first pixel's angle, the same format"),
        ("n_in, n_we", "in", N_WIDTH, f"n: 1..{N_MAX}; any other gives 0 with n_err = 1"),
        ("len_in, len_we", "in", fmt.len_width, "l, the intervals: l + 1 pixels"),
        ("start", "in", 1, "one-cycle pulse: run a line (ignored while busy)"),
        ("busy", "out", 1, "1 while the unit works: writes and start are ignored"),
        ("valid", "out", 1, "one cycle per pixel"),
        ("intensity", "out", fmt.out_width, "C x F rounded, saturated (OUT_WIDTH bits)"),
        ("n_err", "out", 1, f"1: n outside 1..{N_MAX} (held with each result)"),
    ]
    lines = ["| port | dir | bits (default) | meaning |", "|---|---|---|---|"]
    lines += [f"| `{p}` | {d} | {b} | {m} |" for p, d, b, m in rows]
    return "\n".join(lines)


def format_parameters() -> str:
    lines = ["| parameter | meaning | legal | default |", "|---|---|---|---|"]
    for r in parameter_ranges():
        note = f" ({r.base})" if r.base else ""
        lines.append(f"| `{r.name}` | {r.meaning} | {r.lo}..{r.hi}{note} | {r.default} |")
    forms = ", ".join(f'"{f}"' for f in UNIT_CONFIGS)
    lines.append(f'| `FORM` | the form | {forms} | "cosine_quadratic" |')
    lines.append(
        "| `ANGLE_ROM_FILE`, `COEF_ROM_FILE`, `LOG_ROM_FILE` | the tables' images (`make roms`) | "
        "files by model.units.brdf | in `` `SHADING_ROM_DIR `` |"
    )
    lines.append("| `RESET_ALL` | 1: rst_n also resets the data path | 0..1 | 0 |")
    return "\n".join(lines)


def format_timing() -> str:
    lines = [
        "| form | pipeline stages | first valid (cycles after the start edge) | busy cycles, "
        "line of l intervals | back to back, clocks per line |",
        "|---|---|---|---|---|",
    ]
    for form, cfg in UNIT_CONFIGS.items():
        first = fill_latency(cfg)
        lines.append(
            f"| {form} | {FRONT_STAGES} + {form_latency(cfg)} + 1 = {first + 1} | {first} | "
            f"{first} + l | {first + 1} + l |"
        )
    return "\n".join(lines)


def format_costs() -> str:
    lines = [
        "| unit | multipliers (operand bits) | tables | table bits |",
        "|---|---|---|---|",
    ]
    for form, cfg in UNIT_CONFIGS.items():
        mults = ", ".join(f"{w} ({a} x {b})" for w, a, b in multipliers(cfg))
        bits = table_bits(cfg)
        tables = [f"angle 2^{cfg.cos_addr_bits} x {cfg.cos_data_bits}"]
        if "coef" in bits:
            words = len(cfg.coefficients)
            each = f"{words} x {cfg.coef_bits}" if words > 1 else f"{cfg.coef_bits}"
            tables.append(f"coef {N_MAX} x {each}")
        if "log2" in bits:
            tables.append(f"log2 2^{cfg.log_addr_bits} x {cfg.log_data_bits}")
        lines.append(
            f"| brdf_unit, {form} | {len(multipliers(cfg))}: {mults} | {', '.join(tables)} | "
            f"{bits['total']} |"
        )
    spec = DEFAULT
    mults = ", ".join(f"{w} ({a} x {b})" for w, a, b in _specular_multipliers(spec))
    lines.append(
        f"| specular_unit (the patent, default) | 2: {mults} | ROM 9 {spec.rom9_depth} x "
        f"{spec.a_width}, ROM 12 {spec.num_tables} x 2^{spec.rom_addr_bits} x "
        f"{spec.rom_data_bits} | {spec.rom_bits} |"
    )
    return "\n".join(lines)


def format_hardware() -> str:
    """Every table of docs/brdf_unit.md's hardware sections, each after a heading line."""
    cfg = UNIT_CONFIGS["cosine_quadratic"]
    return "\n\n".join(
        [
            "Ports (bits at the default configuration):",
            format_ports(cfg),
            "Parameters (the legal range of each with the others at their defaults):",
            format_parameters(),
            "Timing (one pixel per clock):",
            format_timing(),
            "Cost at the default widths:",
            format_costs(),
        ]
    )
