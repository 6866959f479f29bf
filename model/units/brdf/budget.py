# SPDX-License-Identifier: Apache-2.0
"""BRDF family: the most accurate unit for n >= 8 at the patent's own table budget.

Owns ``budget_bits`` (the patent default's ROM 9 + ROM 12, from ``model.units.specular``),
``Candidate`` and ``candidates`` (every configuration the search tries: each thesis form at the
widths that fit, and the patent's cos^k(a d) with k sets chosen for n >= 8), ``best_k_ranges``
(those k sets), ``winner`` and ``format_budget_table`` (scripts/brdf_budget.py, docs/brdf.md).
May import numpy, ``model.units.fixed``, ``model.units.specular``'s public names and the
package's ``approx``, ``fixed`` and ``fixed_accuracy``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np

from model.units.brdf.approx import FORMS
from model.units.brdf.claims import format_error
from model.units.brdf.fixed import CONFIGS, FixedConfig, table_bits
from model.units.brdf.fixed_accuracy import N_FROM, fixed_accuracy, widths_text
from model.units.specular import (
    DEFAULT,
    INFLECTION,
    MAX_TABLES,
    N_MAX,
    SpecularConfig,
    alpha_value,
    brdf_max_rel_error,
    epicentre,
    float_errors,
    rom_rel_errors,
)

K_MAX = 64
"""The largest k a ROM-12 table may hold (``SpecularConfig``'s check)."""
N_SMALL = N_FROM - 1
"""n = 1..7: not scored, but no winner may be worse there (in float) than the patent's unit."""


def budget_bits() -> int:
    """The patent default unit's table bits: ROM 9 (a per n) + ROM 12 (the cos^k tables)."""
    return DEFAULT.rom_bits


@dataclass(frozen=True)
class Candidate:
    """One configuration tried: its family, widths, table bits and worst relative errors in the
    epicentre against cos^n (float form and fixed-point unit over n = 8..1000, float over
    n = 1..7), each with its n."""

    family: str
    widths: str
    bits: int
    float_worst: tuple[float, int]
    fixed_worst: tuple[float, int]
    small_worst: tuple[float, int]
    config: FixedConfig | SpecularConfig

    @property
    def fits(self) -> bool:
        return self.bits <= budget_bits()


def _worst(values: np.ndarray, lo: int, hi: int) -> tuple[float, int]:
    part = values[lo - 1 : hi]
    j = int(np.argmax(part))
    return float(part[j]), lo + j


# ==================================================================== the thesis's forms
def family_widths() -> list[FixedConfig]:
    """Each form at angle-table address bits A = 12, 13, 14 with the most data bits D (<= 24)
    that keep its tables within the budget (the other widths as ``fixed.CONFIGS``)."""
    found = []
    for form in FORMS:
        base = CONFIGS[form]
        for a in (12, 13, 14):
            probe = replace(base, cos_addr_bits=a, cos_data_bits=4)
            rest = table_bits(probe)["total"] - table_bits(probe)["angle"]
            d = min(24, (budget_bits() - rest) // (1 << a))
            if d >= 12:
                found.append(replace(base, cos_addr_bits=a, cos_data_bits=d))
    return found


def family_candidate(cfg: FixedConfig) -> Candidate:
    acc = fixed_accuracy(cfg)
    return Candidate(
        family=cfg.form,
        widths=widths_text(cfg),
        bits=table_bits(cfg)["total"],
        float_worst=_worst(acc.float_rel, N_FROM, N_MAX),
        fixed_worst=_worst(acc.rel_cos, N_FROM, N_MAX),
        small_worst=_worst(acc.float_rel, 1, N_SMALL),
        config=cfg,
    )


# ==================================================================== cos^k(a d)
@functools.cache
def _errors(alpha: str) -> np.ndarray:
    """brdf_max_rel_error(n, k, alpha) for n = 1..1000 (rows), k = 1..K_MAX (columns)."""
    return np.array(
        [[brdf_max_rel_error(n, k, alpha) for k in range(1, K_MAX + 1)] for n in range(1, 1001)]
    )


def _table_estimate(alpha: str, addr_bits: int) -> np.ndarray:
    """A first guess of what a table of 2**addr_bits adds to n's error with table k: half an
    address step (pi/2 2**-(A+1)) times cos^k's relative slope k tan(a d) at the epicentre's
    end (``fixed_point_accuracy`` measures it exactly)."""
    est = np.zeros((N_MAX, K_MAX))
    step = math.pi / 2 * 2.0 ** -(addr_bits + 1)
    for n in range(1, N_MAX + 1):
        for k in range(1, K_MAX + 1):
            x = min(alpha_value(n, k, alpha) * epicentre(n), 1.5)
            est[n - 1, k - 1] = k * math.tan(x) * step
    return est


def best_k_ranges(
    tables: int,
    alpha: str,
    addr_bits: int,
    fixed_small: tuple[tuple[int, int, int], ...] = (),
    exact: bool = False,
) -> tuple[tuple[int, int, int], ...]:
    """The k ranges (``SpecularConfig.k_ranges``) that minimise the largest float error plus
    ``_table_estimate`` (``exact``: the exact fixed-point error, ``_fixed_errors``) over
    n = 8..1000 with ``tables`` tables: the smallest bound for which
    a greedy split (each range as long as one k keeps every n of it under the bound, which is
    optimal for a min-max split into contiguous ranges) needs at most the tables left after
    ``fixed_small`` (ranges kept as given for the small n); the first scored range reaches down
    to the first n ``fixed_small`` leaves."""
    if exact:
        cost = _fixed_errors(alpha, addr_bits)
    else:
        cost = _errors(alpha) + _table_estimate(alpha, addr_bits)
    start = fixed_small[-1][1] + 1 if fixed_small else 1
    left = tables - len(fixed_small)

    def split(bound: float) -> list[tuple[int, int, int]] | None:
        ranges, n = [], N_FROM
        while n <= N_MAX:
            run = cost[n - 1].copy()
            if not (run <= bound).any():
                return None
            hi = n
            while hi < N_MAX and (np.maximum(run, cost[hi]) <= bound).any():
                run, hi = np.maximum(run, cost[hi]), hi + 1
            ranges.append((n, hi, int(np.argmin(run)) + 1))
            n = hi + 1
        return ranges

    lo, hi = 0.0, 1.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        got = split(mid)
        lo, hi = (lo, mid) if got is not None and len(got) <= left else (mid, hi)
    ranges = split(hi)
    assert ranges is not None
    first = (start, ranges[0][1], ranges[0][2])
    return (*fixed_small, first, *ranges[1:])


def cos_k_candidate(cfg: SpecularConfig, label: str) -> Candidate:
    rom_rel = rom_rel_errors(cfg)[0]
    ranges = ", ".join(f"{lo}..{hi}: {k}" for lo, hi, k in cfg.k_ranges)
    return Candidate(
        family=f"cos^k(a d), {label}",
        widths=f"k = {ranges}; ROM 12 {cfg.num_tables} x 2^{cfg.rom_addr_bits} x "
        f"{cfg.rom_data_bits}, ROM 9 Q{cfg.a_int_bits}.{cfg.a_frac_bits}",
        bits=cfg.rom_bits,
        float_worst=_worst(float_errors(cfg), N_FROM, N_MAX),
        fixed_worst=_worst(rom_rel, N_FROM, N_MAX),
        small_worst=_worst(float_errors(cfg), 1, N_SMALL),
        config=cfg,
    )


SMALL_N_TABLES = ((1, 1, 1), (2, 2, 2))
"""The patent's exact tables for n = 1 (cos) and n = 2 (cos^2): any other k is 100 % off at
n = 1 (its epicentre reaches pi/2) and at least 0.71 % at n = 2."""


def _rom9_fitted(cfg: SpecularConfig) -> SpecularConfig:
    """``cfg`` with ROM 9's words kept at the patent's width (17 bits) and the fewest integer
    bits that hold its largest a (a = sqrt(n/k) exceeds 8 for k < 16 at n = 1000)."""
    width = DEFAULT.a_width
    for int_bits in range(1, width):
        try:
            return replace(cfg, a_int_bits=int_bits, a_frac_bits=width - int_bits)
        except ValueError:
            continue
    raise ValueError(f"k_ranges = {cfg.k_ranges!r}: no ROM 9 format of {width} bits holds a")


def cos_k_configs() -> list[tuple[SpecularConfig, str]]:
    """The patent's unit, its thesis variant, and k sets for n >= 8 (``best_k_ranges``) at the
    address bits that fit 1..4 tables of 16-bit words in the budget, each a or the thesis's,
    with n = 1 (and 2) on the patent's exact tables or not; a k set the greedy split fills
    with fewer tables than it may use appears once, under the tables it has.  Last, the four
    tables at the patent's 2^12 x 16 bits with n = 1, 2 exact split on the exact fixed-point
    errors (``best_k_ranges(..., exact=True)``): the estimate only guesses the tables' share."""
    found = [(DEFAULT, "patent"), (INFLECTION, "patent tables, thesis a")]
    rom12 = budget_bits() - DEFAULT.rom9_bits
    for alpha in ("inflection", "taylor"):
        for tables in range(1, MAX_TABLES + 1):
            addr = int(math.log2(rom12 // (tables * 16)))
            small_sets = [()] + [SMALL_N_TABLES[:m] for m in (1, 2) if m < tables]
            for small in small_sets:
                ranges = best_k_ranges(tables, alpha, addr, small)
                wide = SpecularConfig(
                    k_ranges=ranges, alpha=alpha, rom_addr_bits=addr, a_int_bits=8
                )
                cfg = _rom9_fitted(wide)
                label = f"{cfg.num_tables} tables, {alpha} a"
                if small:
                    label += f", n <= {small[-1][1]} exact"
                if all(cfg != seen for seen, _ in found):
                    found.append((cfg, label))
    ranges = best_k_ranges(MAX_TABLES, "inflection", 12, SMALL_N_TABLES, exact=True)
    wide = SpecularConfig(k_ranges=ranges, alpha="inflection", a_int_bits=8)
    found.append((_rom9_fitted(wide), "4 tables, inflection a, n <= 2 exact, exact split"))
    return found


@functools.cache
def _fixed_errors(alpha: str, addr_bits: int) -> np.ndarray:
    """The exact fixed-point worst (``rom_rel_errors``: ``fixed_point_accuracy(cfg).rom_rel``)
    of n = 8..1000 on a table k = 1..K_MAX (columns) of 2**addr_bits 16-bit words, a in Q8.14
    (rows n - 1; inf for n < 8).  An n's ROM-12 path depends only on its own table, its a
    word (round(a 2**14) in any Q.14) and the address bits: the clamp before multiplier 11
    never changes a word, so a unit of one table k per n range has exactly these per-n errors."""
    errors = np.full((N_MAX, K_MAX), np.inf)
    for k in range(1, K_MAX + 1):
        cfg = SpecularConfig(
            k_ranges=((1, N_MAX, k),), alpha=alpha, rom_addr_bits=addr_bits, a_int_bits=8,
            n_first=N_FROM,
        )  # fmt: skip
        errors[N_FROM - 1 :, k - 1] = rom_rel_errors(cfg)[0][N_FROM - 1 :]
    return errors


# ==================================================================== the search
@functools.cache
def candidates() -> tuple[Candidate, ...]:
    """Every configuration tried, the thesis's forms first (each fits the budget), then the
    cos^k(a d) k sets."""
    family = [family_candidate(cfg) for cfg in family_widths()]
    cos_k = [cos_k_candidate(cfg, label) for cfg, label in cos_k_configs()]
    return tuple(family + cos_k)


def winner(found: tuple[Candidate, ...] | None = None) -> Candidate:
    """The smallest fixed-point worst error over n = 8..1000 among the candidates that fit the
    budget and are, in float, no worse than the patent's unit over n = 1..7 (ties: the float
    worst, then the fewer bits)."""
    found = candidates() if found is None else found
    patent_small = _worst(float_errors(DEFAULT), 1, N_SMALL)[0]
    legal = [c for c in found if c.fits and c.small_worst[0] <= patent_small]
    return min(legal, key=lambda c: (c.fixed_worst[0], c.float_worst[0], c.bits))


def _cell(worst: tuple[float, int]) -> str:
    return f"{format_error(worst[0])} at {worst[1]}"


def format_budget_table(found: tuple[Candidate, ...] | None = None) -> str:
    """Every candidate (markdown; worst relative errors against cos^n in the epicentre, rounded
    up, with their n), then the winner."""
    found = candidates() if found is None else found
    lines = [
        f"table budget (the patent's default unit, ROM 9 + ROM 12): {budget_bits()} bits",
        "",
        "| family | widths | table bits | float worst, n = 8..1000 | fixed worst, n = 8..1000 "
        "| float worst, n = 1..7 |",
        "|---|---|---|---|---|---|",
    ]
    for c in found:
        lines.append(
            f"| {c.family} | {c.widths} | {c.bits} | {_cell(c.float_worst)} "
            f"| {_cell(c.fixed_worst)} | {_cell(c.small_worst)} |"
        )
    best = winner(found)
    lines += [
        "",
        f"winner: {best.family}: {best.widths}; {best.bits} bits; float "
        f"{_cell(best.float_worst)}, fixed {_cell(best.fixed_worst)} (n = 8..1000)",
    ]
    return "\n".join(lines)
