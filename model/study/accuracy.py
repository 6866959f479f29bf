# SPDX-License-Identifier: Apache-2.0
"""Every accuracy figure the unit pages state, each a worst case (``python -m model accuracy``).

``figures()`` computes them (the heavy work is in the units' accuracy sections: exhaustive
walks in numba), ``format_figures`` prints the table the unit pages carry: figure, value, the
conditions under which it holds and why the value is the worst case.  Values are rounded *up*
to the printed digits (``format_up``), so a printed bound is never below what was measured.

``format_up`` lives in ``model.units.fixed`` (the units' report tables use it too).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from model.units import divider
from model.units.fixed import format_up


@dataclass(frozen=True)
class Figure:
    """One documented figure: what it is, its worst-case value, where it holds, why it is the
    worst case.  ``text`` is the value as printed (``format_up``: rounded up)."""

    key: str
    unit: str
    name: str
    value: float
    digits: int
    suffix: str
    holds: str
    why: str
    scale: int = 1

    @property
    def text(self) -> str:
        return format_up(self.value, self.digits, self.scale) + self.suffix


@dataclass(frozen=True)
class Figures:
    """Every figure of ``figures()`` by key, plus the accuracy of each specular configuration."""

    items: tuple[Figure, ...]
    specular: dict[str, Any]  # name -> specular.Accuracy of every config in ROM_CONFIGS

    def __getitem__(self, key: str) -> Figure:
        return next(f for f in self.items if f.key == key)


def figures() -> Figures:
    """Compute every accuracy figure of docs/<unit>.md (default configurations unless named)."""
    import numpy as np

    from model.units import divider, gouraud, specular

    s_cfg = specular.DEFAULT
    accs = {name: specular.fixed_point_accuracy(c) for name, c in specular.ROM_CONFIGS.items()}
    acc = accs["default"]
    taylor = specular.float_errors(specular.DEFAULT)
    infl = specular.float_errors(specular.INFLECTION)
    out: list[Figure] = []

    def add(
        key: str,
        unit: str,
        name: str,
        value: float,
        digits: int,
        suffix: str,
        holds: str,
        why: str,
        scale: int = 1,
    ) -> None:
        out.append(Figure(key, unit, name, float(value), digits, suffix, holds, why, scale))

    def worst(values: np.ndarray, lo: int, hi: int = specular.N_MAX) -> tuple[float, int]:
        part = np.asarray(values)[lo - 1 : hi]
        return float(part.max()), lo + int(part.argmax())

    # ---------------------------------------------------------------- specular: float
    epi = "every d in the epicentre 0..arctan(1/sqrt(n-1)), float"
    grows = "exact: the error grows with d (tan(ad) >= a tan d): the epicentre's edge"
    v, n = worst(taylor, 1)
    add(
        "float_patent",
        "specular",
        "float approximation cos^k(a d), patent k, a = sqrt(n/k): "
        f"relative error vs cos^n d (at n = {n})",
        v,
        4,
        " %",
        f"n = 1..1000, {epi}",
        grows,
        100,
    )
    for lo, hi, note in (
        (6, 6, ""),
        (7, 7, ""),
        (8, 1000, ""),
        (9, 1000, "; the patent's 0.6 % holds from n = 9"),
    ):
        v, n = worst(taylor, lo, hi)
        rng = f"n = {lo}" if lo == hi else f"n = {lo}..{hi}"
        at = "" if lo == hi else f" (at n = {n})"
        add(
            f"float_patent_{lo}",
            "specular",
            f"the same, {rng}{at}{note}",
            v,
            4,
            " %",
            f"{rng}, {epi}",
            grows,
            100,
        )
    between = "exact: one interior extremum at most (bisection), or the end point"
    v, n = worst(infl, 1)
    add(
        "float_inflection",
        "specular",
        f"the same with a exact at the inflection point (thesis) (at n = {n})",
        v,
        4,
        " %",
        f"n = 1..1000, {epi}",
        between,
        100,
    )
    for label, k, alpha, lo in specular.SINGLE_TABLES:
        v, n = specular.single_table_worst(k, alpha, lo)
        add(
            f"single_{k}_{alpha}",
            "specular",
            f"single table {label}, {alpha} a (at n = {n})",
            v,
            4,
            " %",
            f"n = {lo}..1000, {epi}",
            between,
            100,
        )
    absolute = np.array(
        [specular.brdf_max_abs_error(n, int(specular.decode_k(n))) for n in range(1, 1001)]
    )
    bb = "branch and bound, abs(e'') <= 2ka^2 + 2n: at most 1e-9 of full scale above the maximum"
    v, n = worst(absolute, 1)
    add(
        "float_abs",
        "specular",
        f"float approximation vs max(0, cos d)^n, absolute (at n = {n})",
        255 * v,
        4,
        " LSB",
        "C = 255, n = 1..1000, every d in 0..pi, float",
        bb,
    )
    add(
        "float_abs_1000",
        "specular",
        "the same, n = 1000",
        255 * absolute[-1],
        4,
        " LSB",
        "C = 255, n = 1000, every d in 0..pi, float",
        bb,
    )
    # ---------------------------------------------------------------- specular: fixed point
    every_z = "every angle register value"
    ends = "both ends of every ROM-12 address's angle interval (constant word, monotone cos)"
    v, n = worst(acc.rom_rel, 2)
    add(
        "rom_rel",
        "specular",
        "ROM-12 path (fixed-point angle, a, address, table) vs cos^n, "
        f"relative (at n = {n}, z = {int(acc.rom_rel_z[n - 1])})",
        v,
        4,
        " %",
        f"n = 2..1000, {every_z} in the epicentre",
        ends,
        100,
    )
    add(
        "rom_rel_1",
        "specular",
        f"the same, n = 1 (z = {int(acc.rom_rel_z[0])})",
        acc.rom_rel[0],
        4,
        " %",
        f"n = 1, {every_z} with cos >= 1/255",
        ends,
        100,
    )
    v, n = worst(acc.rom_rel - acc.float_rel, 2)
    add(
        "tables_add",
        "specular",
        f"what the tables add: ROM-12 path minus float (at n = {n})",
        v,
        4,
        " %",
        "n = 2..1000, the epicentre",
        "difference of the two exact maxima",
        100,
    )
    c_max = s_cfg.c_format.hi / 2**s_cfg.c_frac_bits
    scan = "the extreme references per address, every C scanned until a proven bound stops it"
    v, n = worst(acc.out_lsb_approx, 1)
    add(
        "lsb_approx",
        "specular",
        "output vs C cos^k(a zeta): the unit's own error "
        f"(at n = {n}, z = {int(acc.out_approx_z[n - 1])})",
        v,
        4,
        " LSB",
        f"C = 255, n = 1..1000, {every_z}",
        ends,
    )
    w = acc.approx_c_full
    add(
        "lsb_approx_c",
        "specular",
        f"the same, every C <= 255 (at C = {w.c}/256, n = {w.n}, z = {w.z})",
        w.value,
        4,
        " LSB",
        f"every C <= 255, n = 1..1000, {every_z}",
        scan,
    )
    w = acc.approx_any_c
    add(
        "lsb_approx_any_c",
        "specular",
        f"the same, every C (at C = {w.c}/256, n = {w.n}, z = {w.z}: 255 saturated)",
        w.value,
        4,
        " LSB",
        f"every C up to {c_max:.4f}, n = 1..1000, {every_z}",
        scan,
    )
    bounds = [specular.approx_lsb_bound(n, s_cfg) for n in range(7, 1001)]
    derived = "1/2 + C (2^-16 + S_k pi/2 e), e the scaled angle's error (approx_lsb_bound)"
    add(
        "lsb_bound_lo",
        "specular",
        "analytic bound on the unit's own error, k = 16: smallest",
        min(bounds),
        4,
        " LSB",
        "C <= 255, n = 7..1000",
        derived,
    )
    add(
        "lsb_bound_hi",
        "specular",
        "the same: largest",
        max(bounds),
        4,
        " LSB",
        "C <= 255, n = 7..1000",
        derived,
    )
    v, n = worst(acc.out_lsb_exact, 1)
    add(
        "lsb_exact",
        "specular",
        "output vs C max(0, cos zeta)^n (exact Blinn) "
        f"(at n = {n}, z = {int(acc.out_exact_z[n - 1])})",
        v,
        4,
        " LSB",
        f"C = 255, n = 1..1000, {every_z} with abs(zeta) <= 3pi/2",
        ends,
    )
    w = acc.exact_c_full
    add(
        "lsb_exact_c",
        "specular",
        f"the same, every C <= 255 (at C = {w.c}/256, n = {w.n}, z = {w.z})",
        w.value,
        4,
        " LSB",
        "every C <= 255, n = 1..1000, abs(zeta) <= 3pi/2",
        scan,
    )
    w = acc.exact_any_c
    add(
        "lsb_exact_any_c",
        "specular",
        f"the same, every C (at C = {w.c}/256, n = {w.n}, z = {w.z})",
        w.value,
        4,
        " LSB",
        f"every C up to {c_max:.4f}, n = 1..1000, abs(zeta) <= 3pi/2",
        scan,
    )
    reached = "(l + 1) half LSBs, reached when dz and z0 both sit half an LSB off the grid"
    add(
        "angle_drift",
        "specular",
        "accumulated angle at the end of a line, in ROM-12 address steps of the largest a",
        specular.angle_drift_steps(s_cfg),
        4,
        " steps",
        "l <= 2047, dz and z0 rounded to nearest, 26 fraction bits",
        reached,
    )
    add(
        "angle_drift_23",
        "specular",
        "the same with 23 angle fraction bits",
        specular.angle_drift_steps(specular.SpecularConfig(z_frac_bits=23)),
        4,
        " steps",
        "l <= 2047, dz and z0 rounded to nearest, 23 fraction bits",
        reached,
    )
    # ---------------------------------------------------------------- divider
    err, rel = divider.article_table1()
    i = int(np.argmax(np.abs(err)))
    add(
        "table1_max",
        "divider",
        f"Table 1: largest error of 255/k (at k = {i + 2})",
        abs(err[i]),
        5,
        "",
        "N = 8, dividend 255, k = 2..16",
        "every row computed",
    )
    i = int(np.argmax(np.abs(rel)))
    add(
        "table1_max_rel",
        "divider",
        f"Table 1: largest relative error (first at k = {i + 2})",
        abs(rel[i]),
        4,
        " %",
        "N = 8, dividend 255, k = 2..16",
        "every row computed",
        100,
    )
    add(
        "table1_mean",
        "divider",
        "Table 1: mean relative error (a mean, not a bound)",
        float(np.mean(np.abs(rel))),
        4,
        " %",
        "N = 8, dividend 255, k = 2..16",
        "every row computed",
        100,
    )
    for bits, span in ((20, 255), (20, 256), (19, 255), (11, 255)):
        v, k = divider.line_drift(bits, divider.DEFAULT.k_max, span)
        add(
            f"divider_drift_{bits}_{span}",
            "divider",
            f"a line's end value after k exact quotients (I_b - I_a) / k, N = {bits} (at k = {k})",
            v,
            4,
            " levels",
            f"I_b - I_a within +-{span} levels, every k = 1..2047",
            "exact: abs(a) abs(k r - 2^N) / 2^N for every k, linear in abs(a)",
        )
    # ---------------------------------------------------------------- gouraud
    for frac in (12, 11):
        add(
            f"gouraud_drift_{frac}",
            "gouraud",
            f"a line's end value after the increment rounded to {frac} fraction bits",
            gouraud.drift_worst(gouraud.GouraudConfig(i_frac=frac)),
            4,
            " levels",
            f"every line of 2..2047 pixels, every Q8.{frac} start and end value",
            "exact: the distance of I_b - I_a to a multiple of m - 1, reached",
        )
    return Figures(tuple(out), accs)


def format_figures(figs: Figures) -> str:
    """The table ``python -m model accuracy`` prints and the unit pages carry (markdown)."""
    lines = [
        "| unit | figure | worst case | holds for | why it is the worst case |",
        "|---|---|---|---|---|",
    ]
    lines += [f"| {f.unit} | {f.name} | {f.text} | {f.holds} | {f.why} |" for f in figs.items]
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------------
# the divider's tables (make accuracy, shading divider-table, shading divider-trade)


def divider_table1(recip_bits: int = 8, dividend: int = 255) -> list[dict]:
    """Table 1 of the article, recomputed: terms, error and relative error for k = 2..16."""
    cfg = divider.DividerConfig(a_width=9, k_width=5, recip_bits=recip_bits)
    rows = []
    for k in range(2, 17):
        approx = divider.divide(dividend, k, cfg) / 2.0**recip_bits
        exact = dividend / k
        rows.append(
            {
                "k": k,
                "terms": "+".join(f"1/{2**j}" for j in divider.reciprocal_terms(k, recip_bits)),
                "error": approx - exact,
                "relative_pct": 100.0 * (approx - exact) / exact,
            }
        )
    return rows


def format_table1() -> str:
    rows = divider_table1()
    lines = ["| k | terms | error | relative % |", "|---|---|---|---|"]
    lines += [
        f"| {r['k']} | {r['terms']} | {r['error']:+.4f} | {r['relative_pct']:+.2f} |" for r in rows
    ]
    worst = max(rows, key=lambda r: abs(r["error"]))
    mean_rel = sum(abs(r["relative_pct"]) for r in rows) / len(rows)
    lines.append("")
    lines.append(  # the largest rounded up (a bound), like every worst case (accuracy.format_up)
        f"max |error| {format_up(abs(worst['error']), 5)} at k = {worst['k']}; "
        f"mean |relative error| over k = 2..16: {format_up(mean_rel, 4)} %"
    )
    return "\n".join(lines)


def format_trade(k_max: int = 2047, bits: range = range(4, 21)) -> str:
    lines = [
        f"| N | worst abs error (255/k) | at k | worst rel error | at k | k with r = 0 "
        f"| cycles max | cycles mean | (k = 1..{k_max}) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for n in bits:
        r = divider.trade_row(n, k_max)
        lines.append(
            f"| {n} | {format_up(r.worst_abs_error, 4)} | {r.worst_abs_k} "
            f"| {format_up(r.worst_rel_error, 3, 100)} % "
            f"| {r.worst_rel_k} | {r.useless_k} | {r.cycles_max} | {r.cycles_mean:.2f} | |"
        )
    lines.append("")
    lines.append(
        f"exact restoring divider, default widths: {divider.cycles_exact()} cycles for every k"
    )
    return "\n".join(lines)
