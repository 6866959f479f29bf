# SPDX-License-Identifier: Apache-2.0
"""BRDF family: the fixed-point forms' exhaustive worst errors and their table (docs/brdf.md).

Owns ``fixed_accuracy`` (every n = 1..1000 and every angle register value in the epicentre: the
output against the form's own float value and against cos^n), its result ``FixedAccuracy``,
``epicentre_codes`` and ``format_fixed_table``.  May import numpy, ``model.units.fixed``,
``model.units.specular``'s public names, ``approx`` and ``fixed``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from model.units import fixed
from model.units.brdf.approx import approximate, check_n, max_rel_error
from model.units.brdf.fixed import CONFIGS, FixedConfig, evaluate, table_bits
from model.units.specular import N_MAX, REL_FLOOR, epicentre

N_FROM = 8
"""The budget study's n range starts here (n = 8..1000, docs/brdf.md)."""


def epicentre_codes(n: int, z_frac_bits: int) -> int:
    """The largest angle register value z (units of 2**-zf pi/2) in n's epicentre
    (zeta = z 2**-zf pi/2 <= arctan(1/sqrt(n-1))) where also cos^n zeta >= ``REL_FLOOR``, as
    ``model.units.specular.fixed_point_accuracy`` takes it (the floor only cuts n = 1, whose
    epicentre runs down to cos = 0)."""
    n = check_n(n)
    scale = math.pi / 2 / 2.0**z_frac_bits
    d_end = epicentre(n)

    def inside(z: int) -> bool:
        return z * scale <= d_end and math.cos(z * scale) ** n >= REL_FLOOR

    z = int(d_end / scale)
    while inside(z + 1):
        z += 1
    while z > 0 and not inside(z):
        z -= 1
    return z


def interval_ends(cfg: FixedConfig, z_end: int) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi): the least and largest |z| in 0..z_end of every angle-table address reached."""
    s = cfg.addr_shift
    if s == 0:
        z = np.arange(z_end + 1, dtype=np.int64)
        return z, z
    last = fixed.round_shift(z_end, s)
    i = np.arange(last + 1, dtype=np.int64)
    lo = np.maximum(0, (i << s) - (1 << (s - 1)))
    hi = np.minimum(z_end, ((i + 1) << s) - (1 << (s - 1)) - 1)
    return lo, hi


@dataclass(frozen=True)
class FixedAccuracy:
    """One configuration's worst errors for every n = 1..1000 (arrays indexed n - 1), each over
    every angle register value of the epicentre (``epicentre_codes``), with a z reaching it."""

    cfg: FixedConfig
    abs_lsb: np.ndarray  # |output - 2**O f|, f the float form clipped to [0, 1 - 2**-O] (LSB)
    abs_z: np.ndarray
    rel: np.ndarray  # |output 2**-O / f - 1| where f >= REL_FLOOR too
    rel_z: np.ndarray
    rel_cos: np.ndarray  # |output 2**-O / cos^n - 1|
    rel_cos_z: np.ndarray
    float_rel: np.ndarray  # the float form against cos^n: max_rel_error (exact)

    def worst(self, name: str, lo: int = 1, hi: int = N_MAX) -> tuple[float, int, int]:
        """(the largest value of field ``name`` over n = lo..hi, its n, its z: -1 for
        ``float_rel``, an exact maximum over the real angles)."""
        values = getattr(self, name)[lo - 1 : hi]
        j = int(np.argmax(values))
        zs = {"abs_lsb": self.abs_z, "rel": self.rel_z, "rel_cos": self.rel_cos_z}.get(name)
        return float(values[j]), lo + j, int(zs[lo - 1 + j]) if zs is not None else -1


def fixed_accuracy(cfg: FixedConfig) -> FixedAccuracy:
    """``cfg``'s unit against its own float form and against cos^n, for every n = 1..1000 and
    every angle register value z in the epicentre (exhaustive; cached per configuration).

    Why both ends of every angle-table address's interval of |z| are enough (as in
    ``model.units.specular.fixed_point_accuracy``): the unit's output depends on z only
    through the address round(|z| 2**-(zf - A)), so it is constant on each address's integer
    interval [lo, hi] of |z|, while the references, the float form and cos^n, are monotone
    (non-increasing) in |z| over the epicentre (every form's value falls with the angle there:
    ``tests/test_brdf_fixed.py`` checks it on a dense sample for every n).  A constant against
    a monotone reference is farthest from it, absolutely and relatively, at an end.  The sign
    of z does not matter (the unit takes |z|, the forms are even)."""
    return _fixed_accuracy(cfg)


@functools.cache
def _fixed_accuracy(cfg: FixedConfig) -> FixedAccuracy:
    zf, o = cfg.angle.z_frac_bits, cfg.out_bits
    top = 1.0 - 2.0**-o  # the largest output word, 2**O - 1
    per = {name: np.zeros(N_MAX) for name in ("abs_lsb", "rel", "rel_cos")}
    at = {name: np.zeros(N_MAX, dtype=np.int64) for name in per}
    for n in range(1, N_MAX + 1):
        lo, hi = interval_ends(cfg, epicentre_codes(n, zf))
        z = np.concatenate([lo, hi])
        out = evaluate(cfg, z, n) / 2.0**o
        delta = z * (math.pi / 2 / 2.0**zf)
        ref = approximate(cfg.form, delta, n)
        cos_n = np.cos(delta) ** n
        errors = {
            "abs_lsb": np.abs(out - np.clip(ref, 0.0, top)) * 2.0**o,
            "rel": np.where(ref >= REL_FLOOR, np.abs(out / np.maximum(ref, REL_FLOOR) - 1), 0.0),
            "rel_cos": np.abs(out / cos_n - 1.0),
        }
        for name, err in errors.items():
            j = int(np.argmax(err))
            per[name][n - 1], at[name][n - 1] = float(err[j]), int(z[j])
    float_rel = np.array([max_rel_error(cfg.form, n).error for n in range(1, N_MAX + 1)])
    return FixedAccuracy(
        cfg=cfg,
        abs_lsb=per["abs_lsb"],
        abs_z=at["abs_lsb"],
        rel=per["rel"],
        rel_z=at["rel"],
        rel_cos=per["rel_cos"],
        rel_cos_z=at["rel_cos"],
        float_rel=float_rel,
    )


def widths_text(cfg: FixedConfig) -> str:
    """The widths that set the form's accuracy, as the tables print them."""
    text = f"angle 2^{cfg.cos_addr_bits} x {cfg.cos_data_bits}"
    if cfg.coefficients:
        text += f", coef {len(cfg.coefficients)} x {cfg.coef_bits}"
    if cfg.form == "log2":
        text += f", log2 2^{cfg.log_addr_bits} x {cfg.log_data_bits}"
    if cfg.form != "log2":
        text += f", work {cfg.work_bits}"
    return text + f", out {cfg.out_bits}"


def _pct(value: float) -> str:
    return f"{fixed.format_up(value, 4, 100)} %"


def format_fixed_table(configs: dict[str, FixedConfig] | None = None) -> str:
    """Each form's fixed-point unit: widths, table bits and its exhaustive worst errors
    (markdown; rounded up; "at" gives n and the angle register value z)."""
    configs = CONFIGS if configs is None else configs
    lines = [
        "| form | widths | table bits | output vs own float form (LSB) "
        "| relative vs own float form | the same, n = 2..1000 | output vs cos^n, n = 8..1000 "
        "| float form vs cos^n, n = 8..1000 |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name, cfg in configs.items():
        acc = fixed_accuracy(cfg)
        a, an, az = acc.worst("abs_lsb")
        cells = [
            f"{_pct(v)} at n = {vn}, z = {vz}"
            for v, vn, vz in (
                acc.worst("rel"),
                acc.worst("rel", 2),
                acc.worst("rel_cos", N_FROM),
            )
        ]
        f, fn, _ = acc.worst("float_rel", N_FROM)
        lines.append(
            f"| {name} | {widths_text(cfg)} | {table_bits(cfg)['total']} "
            f"| {fixed.format_up(a, 4)} at n = {an}, z = {az} | {' | '.join(cells)} "
            f"| {_pct(f)} at n = {fn} |"
        )
    return "\n".join(lines)
