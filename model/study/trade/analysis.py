# SPDX-License-Identifier: Apache-2.0
"""The fronts of a trade run: per-configuration rows, Pareto masks and where the default lies.

Owns ``aggregate`` (one row per configuration over the scenes, with its Pareto marks),
``pareto_mask``, ``eps_dominates`` and ``near_front`` (``NEAR``), ``front_objectives`` and
``default_position``, ``throughput_axis``, ``front_families``.  The fronts span every BRDF
family (the patent's cos^k unit and each BRDF form: ``points.family``), each row naming its
``family``; a BRDF configuration has no shading-core throughput (NaN), so it is on no
throughput front.  May import numpy and ``model.study.trade.points``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from model.study.trade.points import KNOBS, family

NEAR = 0.05
"""Tolerance of "near the front": see ``eps_dominates``."""


# ================================================================================ analysis
def pareto_mask(objectives: np.ndarray) -> np.ndarray:
    """(m,) bool: rows no other row dominates (<= in every column, < in one); all minimised."""
    obj = np.asarray(objectives, dtype=np.float64)
    m = obj.shape[0]
    mask = np.ones(m, dtype=bool)
    for i in range(m):
        le = np.all(obj <= obj[i], axis=1)
        lt = np.any(obj < obj[i], axis=1)
        if np.any(le & lt):
            mask[i] = False
    return mask


def eps_dominates(a: Sequence[float], b: Sequence[float], eps: float = NEAR) -> bool:
    """True when ``a`` beats ``b`` by more than a factor (1 + eps) in one objective while it is
    no worse than a factor (1 + eps) in every other (all objectives minimised, positive).

    "``b`` is near the front" means no point eps-dominates it: nothing is markedly better in one
    figure without being markedly worse in another."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    tol = 1.0 + eps
    return bool(np.all(a <= b * tol) and np.any(a * tol < b))


def near_front(objectives: np.ndarray, index: int, eps: float = NEAR) -> list[int]:
    """Rows that eps-dominate row ``index`` (empty: it is on or near the front)."""
    obj = np.asarray(objectives, dtype=np.float64)
    return [j for j in range(obj.shape[0]) if j != index and eps_dominates(obj[j], obj[index], eps)]


SUM_FIELDS = (
    "cycles",
    "frame_clocks",
    "core_clocks",
    "pixels_shaded",
    "shade_seconds",
    "specular_pixels",
)


def aggregate(results: list[dict]) -> list[dict]:
    """One row per configuration (in first-seen order): the scenes' mean NMSE, worst PSNR and
    max error, mean cycles, frame clocks and core clocks per frame, pooled pixels per clock and
    per second; ``hw_mpx_per_s`` = the core's pooled pixels per clock x Fmax."""
    groups: dict[str, list[dict]] = {}
    for r in results:
        groups.setdefault(r["config_key"], []).append(r)
    rows = []
    for rs in groups.values():
        first = rs[0]
        row = {k: first[k] for k in (*KNOBS, "config_key", "label")}
        row["family"] = family(first)
        tot = {f: sum(r[f] for r in rs) for f in SUM_FIELDS}
        core = tot["core_clocks"]  # NaN for a configuration the core cannot build
        row.update(
            scenes=",".join(r["scene"] for r in rs),
            size=first["size"],
            nmse=float(np.mean([r["nmse"] for r in rs])),
            psnr=float(min(r["psnr"] for r in rs)),
            max_abs_error=float(max(r["max_abs_error"] for r in rs)),
            highlight_max_abs_error=float(np.nanmax([r["highlight_max_abs_error"] for r in rs])),
            epicentre_rel_error=first["epicentre_rel_error"],
            epicentre_worst_n=first["epicentre_worst_n"],
            unit_error_lsb=first["unit_error_lsb"],
            line_drift_levels=first["line_drift_levels"],
            angle_drift_steps=first["angle_drift_steps"],
            cycles=tot["cycles"] / len(rs),
            frame_clocks=tot["frame_clocks"] / len(rs),
            px_per_clock=tot["pixels_shaded"] / max(tot["cycles"], 1),
            px_per_clock_parallel=tot["pixels_shaded"] / max(tot["frame_clocks"], 1),
            core_clocks=tot["core_clocks"] / len(rs),
            px_per_clock_core=math.nan if math.isnan(core) else tot["pixels_shaded"] / max(core, 1),
            specular_share=tot["specular_pixels"] / max(tot["pixels_shaded"], 1),
            table_bits=first["table_bits"],
            adders=first["adders"],
            multipliers=first["multipliers"],
            mult_bits=first["mult_bits"],
            sw_pixels_per_second=tot["pixels_shaded"] / max(tot["shade_seconds"], 1e-12),
            config_name=first.get("config_label", ""),
        )
        fmax = float(first.get("fmax_mhz", np.nan))
        row.update({k: first.get(k, np.nan) for k in ("lut", "ff", "bram", "dsp")})
        row.update(part=first.get("part", "none"), fmax_mhz=fmax)
        row["hw_mpx_per_s"] = row["px_per_clock_core"] * fmax
        rows.append(row)
    objectives = {
        "cycles": np.array([[r["nmse"], r["cycles"]] for r in rows]),
        "bits": np.array([[r["nmse"], r["table_bits"]] for r in rows]),
        "lut": np.array([[r["nmse"], r["lut"]] for r in rows], dtype=np.float64),
        # throughput is maximised: its negative minimised
        "throughput": np.array([[r["nmse"], -r[throughput_axis(rows)]] for r in rows]),
    }
    for name, obj in objectives.items():
        obj = obj.reshape(len(rows), 2)
        ok = np.all(np.isfinite(obj), axis=1)
        on = np.zeros(len(rows), dtype=bool)
        on[ok] = pareto_mask(obj[ok])
        for r, v in zip(rows, on, strict=True):
            r[f"pareto_{name}"] = bool(v)
    return rows


def throughput_axis(rows: list[dict]) -> str:
    """The throughput the rows are compared on: the hardware's Mpx/s (``hw_mpx_per_s``: the
    shading core's pixels per clock x the synthesised Fmax) when some row has it, else the
    core's pixels per clock (``px_per_clock_core``: shaded pixels / core clocks)."""
    has_hw = any(np.isfinite(float(r.get("hw_mpx_per_s", np.nan))) for r in rows)
    return "hw_mpx_per_s" if has_hw else "px_per_clock_core"


FRONT_NAMES = {
    "pareto_cycles": "NMSE vs cycles",
    "pareto_bits": "NMSE vs table bits",
    "pareto_lut": "NMSE vs LUTs",
    "pareto_throughput": "NMSE vs throughput",
}
"""The fronts ``aggregate`` marks (row field -> name)."""


def front_families(rows: list[dict]) -> dict[str, list[tuple[str, str]]]:
    """Per front (``FRONT_NAMES``): (label, family) of every configuration on it, from the most
    accurate (lowest NMSE) on."""
    out = {}
    for key, name in FRONT_NAMES.items():
        on = sorted((r for r in rows if r.get(key)), key=lambda r: r["nmse"])
        out[name] = [(r["label"], r["family"]) for r in on]
    return out


def default_row(rows: list[dict]) -> int | None:
    for i, r in enumerate(rows):
        if r["label"] == "default":
            return i
    return None


def worst_figures(r: dict) -> list[float]:
    """The worst-case unit figures (NaN = no specular unit: counted as infinitely bad)."""
    return [
        r["epicentre_rel_error"],
        r["unit_error_lsb"],
        r["line_drift_levels"],
        r["angle_drift_steps"],
    ]


ALL_COSTS = ("cycles", "table_bits", "adders", "mult_bits")


def front_objectives(rows: list[dict]) -> dict[str, np.ndarray]:
    """The fronts the study reports, all figures minimised: NMSE against cycles, NMSE against
    table bits, and "all": NMSE, the worst-case unit figures and every cost at once."""
    worst = np.array([worst_figures(r) for r in rows], dtype=np.float64).reshape(len(rows), 4)
    worst = np.nan_to_num(worst, nan=np.inf)
    nmse = np.array([[r["nmse"]] for r in rows], dtype=np.float64).reshape(len(rows), 1)
    costs = np.array([[r[c] for c in ALL_COSTS] for r in rows], dtype=np.float64)
    fronts = {
        "cycles": np.hstack([nmse, costs[:, :1]]),
        "table bits": np.hstack([nmse, costs[:, 1:2]]),
        "all figures": np.hstack([nmse, worst, costs]),
    }
    lut = np.array([[r.get("lut", np.nan)] for r in rows], dtype=np.float64).reshape(-1, 1)
    if rows and np.all(np.isfinite(lut)):
        fronts["LUTs"] = np.hstack([nmse, lut])
    return fronts


def default_position(rows: list[dict], eps: float = NEAR) -> dict[str, list[str]]:
    """For each front (``front_objectives``): labels of the configurations that eps-dominate
    the default (empty: the default is on or near that front)."""
    d = default_row(rows)
    if d is None:
        return {}
    return {
        name: [rows[j]["label"] for j in near_front(obj, d, eps)]
        for name, obj in front_objectives(rows).items()
    }
