# SPDX-License-Identifier: Apache-2.0
"""Specular unit: the fixed-point unit's accuracy, exhaustively, and the README's tables.

Owns ``fixed_point_accuracy`` (the unit against cos^n and against its float approximation, for
every n, every angle register value and every C, by the walk that proves two angles per ROM-12
address enough) with its results ``Accuracy`` and ``Worst``, the analytic bounds
(``approx_lsb_bound``, ``angle_drift_steps``, ``angle_drift_example``) and the markdown tables
(``format_brdf_table``, ``format_accuracy_table``, ``format_config_table``).  May import numpy,
numba, ``model.units.fixed`` and every other module of the package (it sits on top of them).
``rom_rel_errors`` is the same walk's ROM-12 figure alone, stopped at the epicentre's end.

Size: about 510 lines: the exhaustive walk, its epicentre-only form and the tables that print
their results are one measurement.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from model.units import fixed
from model.units.specular.approx import brdf_max_rel_error, cos_power_max_slope
from model.units.specular.config import (
    DEFAULT,
    INFLECTION,
    N_MAX,
    ROM_CONFIGS,
    SpecularConfig,
    alpha_value,
)
from model.units.specular.datapath import line_angles
from model.units.specular.roms import decode_k, rom9_words, tables


# ==================================================================== fixed-point accuracy
@dataclass(frozen=True)
class Worst:
    """A worst case and registers that reach it: ``shade_line(c, 0, z, n, 0)`` (one pixel, angle
    register z0 = z) gives the output whose distance from the reference is ``value``."""

    value: float
    n: int
    c: int
    z: int


@dataclass(frozen=True)
class Accuracy:
    """Accuracy of one configuration for every n = 1..1000 (arrays indexed n - 1).

    Every figure is a worst case over every input it names (``fixed_point_accuracy`` says why
    the inputs it evaluates are enough); "full scale" is C = 2**out_width - 1 (255).
    """

    float_rel: np.ndarray  # float cos^k(a d) vs cos^n d, epicentre where cos^n >= REL_FLOOR
    rom_rel: np.ndarray  # the ROM-12 word vs cos^n, every angle register value of that range
    out_lsb_exact: np.ndarray  # output vs C max(0, cos)^n, C full scale, |zeta| <= 3pi/2 (LSB)
    out_lsb_approx: np.ndarray  # output vs C cos^k(a zeta), C full scale, every angle (LSB)
    rom_rel_z: np.ndarray  # an angle register value where rom_rel is reached
    out_exact_z: np.ndarray  # ... out_lsb_exact
    out_approx_z: np.ndarray  # ... out_lsb_approx
    approx_c_full: Worst  # output vs C cos^k(a zeta): every n, angle and C <= full scale
    approx_any_c: Worst  # ... every C register value (up to 255.996: the output saturates)
    exact_c_full: Worst  # output vs C max(0, cos)^n: every n, |zeta| <= 3pi/2, C <= full scale
    exact_any_c: Worst  # ... every C register value


REL_FLOOR = 1.0 / 255
"""The relative error of the ROM-12 path is taken where cos^n >= 1/255 (one 8-bit level): only
n = 1's epicentre (the whole quadrant, down to cos = 0) reaches below it."""


def fixed_point_accuracy(cfg: SpecularConfig = DEFAULT) -> Accuracy:
    """The unit against float cos^n and against its float approximation, every n = 1..1000,
    every angle register value (exhaustive; cached per configuration).

    Why evaluating two angles per ROM-12 address is exhaustive: the unit's word depends on the
    angle register z only through the address round(|z| a / 2**addr_shift), so the |z| of one
    address form an integer interval [lo, hi] (computed exactly; past the last address, from
    the overflow on, the word is 0).  On it the word, and for a given C the output, are
    constant, while each reference (cos^n, cos^k(a zeta), both non-increasing in |zeta| on the
    ranges used) is monotone: the distance |constant - reference| is largest at lo or hi.  So
    the ROM-12 path's relative error (|z| from 0 to the last register value in the epicentre
    with cos^n >= ``REL_FLOOR``), the output at full scale against cos^n (|zeta| <= 3pi/2,
    every angle ``setup_line`` produces: beyond it cos^n would rise again) and against
    cos^k(a zeta) (every register value) are exact maxima over every integer angle.  The sign
    does not matter (the unit takes |acc|, the references are even) and the clamp of |zeta|
    before multiplier 11 never changes a word (``mag_int_bits``).

    Every C at once: for one table and address the output round(C w) is fixed by C and the
    word w, and the distance |round(C w) - C f| is linear in the reference value f, so it is
    largest at the smallest or largest f any n of that table reaches at that address (both
    kept).  Every (table, address) gets the bound max(1/2, C_max w - out_max) + C_max |w - f|
    (rounding or saturation, plus the reference's distance); in decreasing order of that bound
    each is scanned over every C register value until the bound cannot beat the worst found.
    ``tests/test_accuracy.py`` checks all of it against a brute force over every n, angle and C
    of a reduced unit, and replays each worst case through ``shade_line``.
    """
    return _accuracy(cfg)


@functools.cache
def _accuracy(cfg: SpecularConfig) -> Accuracy:
    t = tables(cfg)
    every = np.arange(1, N_MAX + 1, dtype=np.int64)
    ks_every = np.asarray(cfg.ks, dtype=np.int64)[t.tsel[1 : N_MAX + 1]]
    float_rel = np.array(
        [
            brdf_max_rel_error(n, k, cfg.alpha, REL_FLOOR)
            for n, k in zip(every.tolist(), ks_every.tolist(), strict=True)
        ]
    )
    # Only the kept n (n_first..n_last): the unit refuses every other n (n_err, pixels 0), so
    # the per-n figures of a dropped n are 0 and it reaches no worst case.
    lo, hi = cfg.n_first, cfg.n_last
    ns = np.arange(lo, hi + 1, dtype=np.int64)
    tsel = np.ascontiguousarray(t.tsel[lo : hi + 1])
    ks = np.asarray(cfg.ks, dtype=np.int64)[tsel]
    pairs = list(zip(ns.tolist(), ks.tolist(), strict=True))
    a_float = np.array([alpha_value(n, k, cfg.alpha) for n, k in pairs])
    size = 1 << cfg.rom_addr_bits
    shape = (2, cfg.num_tables, size + 1)
    f_min, f_max = np.full(shape, np.inf), np.full(shape, -np.inf)
    f_n, f_z = np.zeros((2, *shape), dtype=np.int64), np.zeros((2, *shape), dtype=np.int64)
    per_n = np.zeros((3, N_MAX))
    per_z = np.zeros((3, N_MAX), dtype=np.int64)
    kept_n, kept_z = per_n[:, lo - 1 : hi], per_z[:, lo - 1 : hi]  # views: the kernel fills them
    c_full = cfg.out_max << cfg.c_frac_bits
    _exhaustive_angles(
        ns, ks, a_float, np.ascontiguousarray(t.rom9[lo : hi + 1]), tsel, t.rom12,
        cfg.rom_addr_bits, cfg.addr_shift, cfg.z_frac_bits, cfg.rom_data_bits, c_full,
        cfg.c_frac_bits, cfg.out_max, REL_FLOOR, kept_n, kept_z, f_min, f_max, f_n, f_z,
    )  # fmt: skip
    words = np.zeros((cfg.num_tables, size + 1), dtype=np.int64)
    for j in range(cfg.num_tables):
        words[j, :size] = t.rom12[j * size : (j + 1) * size]
    worst = {}
    for ref in (0, 1):
        for c_lim in (c_full, cfg.c_format.hi):
            value, j, i, c, side = _every_c(
                words, f_min[ref], f_max[ref], c_lim, cfg.c_frac_bits, cfg.rom_data_bits,
                cfg.out_max,
            )  # fmt: skip
            n, z = int(f_n[ref, side, j, i]), int(f_z[ref, side, j, i])
            worst[ref, c_lim] = Worst(float(value), n, int(c), z)
    return Accuracy(
        float_rel=float_rel,
        rom_rel=per_n[0],
        out_lsb_exact=per_n[2],
        out_lsb_approx=per_n[1],
        rom_rel_z=per_z[0],
        out_exact_z=per_z[2],
        out_approx_z=per_z[1],
        approx_c_full=worst[0, c_full],
        approx_any_c=worst[0, cfg.c_format.hi],
        exact_c_full=worst[1, c_full],
        exact_any_c=worst[1, cfg.c_format.hi],
    )


@njit(cache=True)
def _references(z: int, zf: int, n: int, k: int, a: float) -> tuple[float, float]:
    """(cos^k(a zeta) clipped at pi/2, max(0, cos zeta)^n) at angle register value z."""
    zeta = z / 2.0**zf * (np.pi / 2)
    return np.cos(min(a * zeta, np.pi / 2)) ** k, max(np.cos(zeta), 0.0) ** n


@njit(cache=True)
def _in_epicentre(z: int, zf: int, n: int, d_e: float, floor: float) -> bool:
    zeta = z / 2.0**zf * (np.pi / 2)
    return zeta <= d_e and np.cos(zeta) ** n >= floor


@njit(cache=True)
def _epicentre_end(n: int, zf: int, floor: float) -> int:
    """The largest angle register value in the epicentre with cos^n >= floor."""
    d_e = np.pi / 2 if n == 1 else np.arctan(1.0 / np.sqrt(n - 1.0))
    z = int(d_e / (np.pi / 2) * 2.0**zf)
    while _in_epicentre(z + 1, zf, n, d_e, floor):
        z += 1
    while z > 0 and not _in_epicentre(z, zf, n, d_e, floor):
        z -= 1
    return z


@njit(cache=True)
def _extremes(f_min, f_max, f_n, f_z, ref: int, tab: int, i: int, f: float, n: int, z: int):
    """Keep the smallest and largest reference value seen at (table, address), and where."""
    if f < f_min[ref, tab, i]:
        f_min[ref, tab, i] = f
        f_n[ref, 0, tab, i], f_z[ref, 0, tab, i] = n, z
    if f > f_max[ref, tab, i]:
        f_max[ref, tab, i] = f
        f_n[ref, 1, tab, i], f_z[ref, 1, tab, i] = n, z


@njit(cache=True)
def _exhaustive_angles(
    ns: np.ndarray,
    ks: np.ndarray,
    a_float: np.ndarray,
    a_word: np.ndarray,
    tsel: np.ndarray,
    rom12: np.ndarray,
    addr_bits: int,
    shift: int,
    zf: int,
    data_bits: int,
    c_full: int,
    c_frac: int,
    out_max: int,
    floor: float,
    per_n: np.ndarray,
    per_z: np.ndarray,
    f_min: np.ndarray,
    f_max: np.ndarray,
    f_n: np.ndarray,
    f_z: np.ndarray,
) -> None:
    """``fixed_point_accuracy``'s walk over both ends of every address's angle interval.

    per_n[0] / per_z[0]: ROM-12 relative error in the epicentre; [1]: output vs cos^k(a zeta) at
    full scale; [2]: output vs cos^n at full scale.  f_min / f_max[ref, table, address] (ref 0:
    cos^k(a zeta), 1: cos^n), with the n and z reaching them in f_n / f_z[ref, 0 (min) | 1].
    """
    size = 1 << addr_bits
    half = 1 << (shift - 1)
    z_cap = 3 << zf  # |zeta| <= 3 pi/2: where the exact reference is compared
    out_shift = c_frac + data_bits
    c_val = c_full / 2.0**c_frac
    for j in range(ns.size):
        n, k, a, aw, tab = ns[j], ks[j], a_float[j], a_word[j], tsel[j]
        z_rel = _epicentre_end(n, zf, floor)
        for i in range(size + 1):
            num = (i << shift) - half
            lo = 0 if num <= 0 else (num + aw - 1) // aw  # the least |z| with address i
            if i < size:
                hi = (((i + 1) << shift) - half + aw - 1) // aw - 1
                word = rom12[(tab << addr_bits) | i]
            else:  # overflow (a |zeta| >= pi/2): 0 from lo on, for every larger |z|
                hi = max(lo, z_cap)
                word = 0
            if lo > hi:
                continue
            out = min(fixed.round_shift(c_full * word, out_shift), out_max)
            for end in range(2):
                z = lo if end == 0 else hi
                approx = _references(z, zf, n, k, a)[0]
                if i == size and end == 1:
                    approx = 0.0  # far past pi/2 (a |zeta| >= pi/2) the approximation is 0
                err = abs(out - c_val * approx)
                if err > per_n[1, j]:
                    per_n[1, j], per_z[1, j] = err, z
                _extremes(f_min, f_max, f_n, f_z, 0, tab, i, approx, n, z)
                if lo <= z_cap:  # the exact reference on the part with |zeta| <= 3pi/2
                    z = min(z, z_cap)
                    exact = _references(z, zf, n, k, a)[1]
                    err = abs(out - c_val * exact)
                    if err > per_n[2, j]:
                        per_n[2, j], per_z[2, j] = err, z
                    _extremes(f_min, f_max, f_n, f_z, 1, tab, i, exact, n, z)
            if lo <= z_rel:  # (the overflow's word 0 too: a relative error of 1)
                for end in range(2):
                    z = lo if end == 0 else min(hi, z_rel)
                    exact = _references(z, zf, n, k, a)[1]
                    rel = abs(word / 2.0**data_bits / exact - 1.0)
                    if rel > per_n[0, j]:
                        per_n[0, j], per_z[0, j] = rel, z


def rom_rel_errors(cfg: SpecularConfig = DEFAULT) -> tuple[np.ndarray, np.ndarray]:
    """(``rom_rel``, ``rom_rel_z``) of ``fixed_point_accuracy(cfg)`` alone: the ROM-12 word's
    relative error against cos^n over every angle register value of the epicentre, per n (0 for
    an n the unit does not keep), by the same walk over the addresses' angle intervals stopped
    at the epicentre's end (for n >= 8 a few dozen addresses of 4096: the budget search in
    ``model.units.brdf.budget`` needs this figure of many configurations and no other)."""
    return _rom_rel_errors(cfg)


@functools.cache
def _rom_rel_errors(cfg: SpecularConfig) -> tuple[np.ndarray, np.ndarray]:
    t = tables(cfg)
    lo, hi = cfg.n_first, cfg.n_last
    rel, rel_z = np.zeros(N_MAX), np.zeros(N_MAX, dtype=np.int64)
    _epicentre_rom_rel(
        np.arange(lo, hi + 1, dtype=np.int64), np.ascontiguousarray(t.rom9[lo : hi + 1]),
        np.ascontiguousarray(t.tsel[lo : hi + 1]), t.rom12, cfg.rom_addr_bits, cfg.addr_shift,
        cfg.z_frac_bits, cfg.rom_data_bits, REL_FLOOR, rel[lo - 1 : hi], rel_z[lo - 1 : hi],
    )  # fmt: skip
    return rel, rel_z


@njit(cache=True)
def _epicentre_rom_rel(
    ns, a_word, tsel, rom12, addr_bits, shift, zf, data_bits, floor, rel, rel_z
) -> None:
    """``_exhaustive_angles``' ROM-12 relative error (its per_n[0], per_z[0]) alone: the same
    address intervals, the same two ends, in address order until an interval starts past the
    epicentre (the intervals' starts only grow with the address)."""
    size = 1 << addr_bits
    half = 1 << (shift - 1)
    z_cap = 3 << zf
    for j in range(ns.size):
        n, aw, tab = ns[j], a_word[j], tsel[j]
        z_rel = _epicentre_end(n, zf, floor)
        for i in range(size + 1):
            num = (i << shift) - half
            lo = 0 if num <= 0 else (num + aw - 1) // aw
            if lo > z_rel:
                break
            if i < size:
                hi = (((i + 1) << shift) - half + aw - 1) // aw - 1
                word = rom12[(tab << addr_bits) | i]
            else:
                hi = max(lo, z_cap)
                word = 0
            if lo > hi:
                continue
            for end in range(2):
                z = lo if end == 0 else min(hi, z_rel)
                exact = _references(z, zf, n, 1, 1.0)[1]
                err = abs(word / 2.0**data_bits / exact - 1.0)
                if err > rel[j]:
                    rel[j], rel_z[j] = err, z


@njit(cache=True)
def _every_c(
    words: np.ndarray,
    f_min: np.ndarray,
    f_max: np.ndarray,
    c_lim: int,
    c_frac: int,
    data_bits: int,
    out_max: int,
):
    """max over (table, address) and C register c = 0..c_lim of |out(c, word) - C f|, f the
    smallest or largest reference value at that address: (value, table, address, c, 0 | 1)."""
    tables, count = words.shape
    bound = np.full(tables * count, -1.0)
    c_top = c_lim / 2.0**c_frac
    for j in range(tables):
        for i in range(count):
            if f_max[j, i] >= f_min[j, i]:
                u = words[j, i] / 2.0**data_bits
                residue = max(0.5, c_top * u - out_max)  # rounding, or saturation
                far = max(abs(u - f_min[j, i]), abs(u - f_max[j, i]))
                bound[j * count + i] = residue + c_top * far
    best, best_j, best_i, best_c, best_side = -1.0, 0, 0, 0, 0
    for idx in np.argsort(-bound):
        if bound[idx] <= best:
            break
        j, i = idx // count, idx % count
        word, lo_f, hi_f = words[j, i], f_min[j, i], f_max[j, i]
        for c in range(c_lim + 1):
            out = min(fixed.round_shift(c * word, c_frac + data_bits), out_max)
            cv = c / 2.0**c_frac
            for side in range(2):
                err = abs(out - cv * (lo_f if side == 0 else hi_f))
                if err > best:
                    best, best_j, best_i, best_c, best_side = err, j, i, c, side
    return best, best_j, best_i, best_c, best_side


def approx_lsb_bound(n: int, cfg: SpecularConfig = DEFAULT) -> float:
    """An analytic bound on |output - C cos^k(a zeta)| at full scale (and any C below it):
    1/2 (output rounding) + C (2**-D (table rounding, the 1.0 saturated) + S_k pi/2 e), e the
    error of the scaled angle in units of pi/2: half an address step plus |zeta| times the
    rounding of a in ROM 9, at the largest |zeta| where either side is not yet 0."""
    k = decode_k(n, cfg)
    a = alpha_value(n, k, cfg.alpha)
    zeta_max = 1.0 / (a - 2.0 ** -(cfg.a_frac_bits + 1))
    angle = 2.0 ** -(cfg.rom_addr_bits + 1) + zeta_max * 2.0 ** -(cfg.a_frac_bits + 1)
    slope = cos_power_max_slope(k)
    return 0.5 + cfg.out_max * (2.0**-cfg.rom_data_bits + slope * math.pi / 2 * angle)


def angle_drift_steps(cfg: SpecularConfig = DEFAULT) -> float:
    """The largest error of the accumulated angle over the longest line, in ROM-12 address
    steps of the largest a: dz and z0 each rounded by at most half an LSB, so after l <= len_max
    intervals |acc - (z0 + l dz)| <= (l + 1) 2**-(z_frac_bits+1); reached exactly when both sit
    half an LSB off the grid the same way (``angle_drift_example``)."""
    a_max = int(rom9_words(cfg).max()) / 2.0**cfg.a_frac_bits
    return (cfg.len_max + 1) * 2.0 ** -(cfg.z_frac_bits + 1) * a_max * 2.0**cfg.rom_addr_bits


def angle_drift_example(cfg: SpecularConfig = DEFAULT) -> float:
    """The drift (address steps, largest a) of a line whose exact z0 and dz both lie exactly
    half an LSB above a grid point: the register values the host's rounding (half away from
    zero) gives, run through ``line_angles``, against the exact angles."""
    lsb = 2.0**-cfg.z_frac_bits
    z0, dz = 1000.5 * lsb, 777.5 * lsb  # exact values, both ties
    fmt = cfg.z_format
    acc = line_angles(fmt.quantise(dz), fmt.quantise(z0), cfg.len_max, cfg)
    exact = (1000.5 + 777.5 * np.arange(cfg.len_max + 1)) * lsb
    a_max = int(rom9_words(cfg).max()) / 2.0**cfg.a_frac_bits
    return float(np.max(np.abs(acc * lsb - exact)) * a_max * 2**cfg.rom_addr_bits)


# ==================================================================== report tables (README)
N_RANGES = ((1, 1), (2, 2), (3, 6), (7, 7), (8, 1000), (1000, 1000))


def _worst(values: np.ndarray, lo: int, hi: int) -> tuple[float, int]:
    part = values[lo - 1 : hi]
    i = int(np.argmax(part))
    return float(part[i]), lo + i


def _up(value: float, digits: int, scale: int = 1) -> str:
    return fixed.format_up(value, digits, scale)


def float_errors(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """brdf_max_rel_error of the configuration's mapping (its k and alpha) for n = 1..1000."""
    ks = decode_k(np.arange(1, N_MAX + 1), cfg)
    return np.array([brdf_max_rel_error(n, int(k), cfg.alpha) for n, k in enumerate(ks, 1)])


SINGLE_TABLES = (
    ("cos (prototype's k = 1)", 1, "taylor", 2),
    ("cos^2 (prototype)", 2, "taylor", 3),
    ("cos^2", 2, "inflection", 3),
    ("cos^3", 3, "taylor", 4),
    ("cos^3", 3, "inflection", 4),
    ("cos^16", 16, "taylor", 17),
    ("cos^16", 16, "inflection", 17),
)
"""Single-table approximations: (label, k, alpha, smallest n), worst over n = that..1000."""


def single_table_worst(k: int, alpha: str, lo: int) -> tuple[float, int]:
    """The worst ``brdf_max_rel_error`` of one cos^k table over n = lo..1000, and its n."""
    errs = np.array([brdf_max_rel_error(n, k, alpha) for n in range(lo, N_MAX + 1)])
    i = int(np.argmax(errs))
    return float(errs[i]), lo + i


def format_brdf_table() -> str:
    """The float approximation's worst relative error in the epicentre, per n range (markdown;
    exact maxima, rounded up)."""
    taylor = float_errors(DEFAULT)
    infl = float_errors(INFLECTION)
    lines = [
        "| n | k | a = sqrt(n/k) (patent): worst | at n | a exact at the inflection point "
        "(thesis): worst | at n |",
        "|---|---|---|---|---|---|",
    ]
    for lo, hi in N_RANGES:
        k = decode_k(lo)
        (t, tn), (f, fn) = _worst(taylor, lo, hi), _worst(infl, lo, hi)
        rng = str(lo) if lo == hi else f"{lo}..{hi}"
        lines.append(f"| {rng} | {k} | {_up(t, 3, 100)} % | {tn} | {_up(f, 3, 100)} % | {fn} |")
    lines += ["", "| single table | a | worst over n | at n |", "|---|---|---|---|"]
    for label, k, alpha, lo in SINGLE_TABLES:
        worst, at = single_table_worst(k, alpha, lo)
        lines.append(f"| {label} | {alpha} | {_up(worst, 3, 100)} % | {at} |")
    return "\n".join(lines)


def format_accuracy_table(cfg: SpecularConfig = DEFAULT, acc: Accuracy | None = None) -> str:
    """The fixed-point unit against float cos^n, per n range (markdown; worst cases over every
    angle register value, rounded up)."""
    acc = fixed_point_accuracy(cfg) if acc is None else acc
    full = cfg.out_max
    lines = [
        "| n | float approximation (epicentre) | ROM-12 path vs cos^n (epicentre) "
        f"| output vs C cos^n (LSB, C = {full}) | output vs C cos^k(a d) (LSB, C = {full}) |",
        "|---|---|---|---|---|",
    ]
    for lo, hi in N_RANGES:
        rng = str(lo) if lo == hi else f"{lo}..{hi}"
        cells = [
            f"{_up(_worst(acc.float_rel, lo, hi)[0], 4, 100)} %",
            f"{_up(_worst(acc.rom_rel, lo, hi)[0], 4, 100)} %",
            _up(_worst(acc.out_lsb_exact, lo, hi)[0], 4),
            _up(_worst(acc.out_lsb_approx, lo, hi)[0], 4),
        ]
        lines.append(f"| {rng} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def format_config_table(accs: dict[str, Accuracy]) -> str:
    """Worst figures over n = 1..1000 for several configurations (markdown, rounded up)."""
    lines = [
        "| config | tables | ROM 12 | worst ROM-12 path vs cos^n (n >= 2) | at n "
        "| output vs C cos^n (LSB): C = full scale | any C <= full scale | any C "
        "| output vs C cos^k(a d) (LSB): C = full scale | any C <= full scale | any C |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, acc in accs.items():
        cfg = ROM_CONFIGS[name]
        rom_worst, rom_n = _worst(acc.rom_rel, 2, N_MAX)
        cells = [
            acc.out_lsb_exact.max(),
            acc.exact_c_full.value,
            acc.exact_any_c.value,
            acc.out_lsb_approx.max(),
            acc.approx_c_full.value,
            acc.approx_any_c.value,
        ]
        lines.append(
            f"| {name} | k = {', '.join(map(str, cfg.ks))} ({cfg.alpha}) "
            f"| {cfg.num_tables} x 2^{cfg.rom_addr_bits} x {cfg.rom_data_bits} bits "
            f"| {_up(rom_worst, 4, 100)} % | {rom_n} | "
            + " | ".join(_up(v, 4) for v in cells)
            + " |"
        )
    return "\n".join(lines)
