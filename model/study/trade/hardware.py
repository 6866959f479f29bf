# SPDX-License-Identifier: Apache-2.0
"""The synthesised cost of a trade configuration: every unit it uses through Yosys and nextpnr.

Owns ``run_synthesis`` (one ``model.hw.synthesise`` run per distinct unit configuration, on the
sweep's Dask cluster or in this process, under a tqdm bar), ``unit_configs`` (the units a
pipeline configuration uses), ``combine`` (one configuration's figures: the sum of its units' own
LUTs, flip-flops, block RAMs and DSPs, and the slowest unit's Fmax), ``attach`` (those figures on
every result of the configuration, with the hardware's Mpx/s: the shading core's pixels per clock
x that Fmax, NaN for a configuration the core cannot build) and the part option
(``DEFAULT_PART``, ``PART_CHOICES``, ``check_part``).  May import ``model.hw`` and
``model.render``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from model.hw import synthesise
from model.hw.parts import PARTS
from model.render import pipeline

DEFAULT_PART = "ecp5-25f"
"""``--part``'s default: the part every unit fits at every configuration of the small grid."""
PART_CHOICES: tuple[str, ...] = (*PARTS, "none")
"""Legal ``--part`` values: a part of ``model.hw.parts.PARTS``, or "none" (no synthesis)."""
HW_FIELDS = ("part", "lut", "ff", "bram", "dsp", "fmax_mhz", "hw_mpx_per_s")
"""The columns ``attach`` adds to every result (NaN where there is no synthesis)."""


def check_part(part: str | None) -> str | None:
    """``part`` (None for "none" or None: no synthesis), or ``ValueError`` naming the legal
    values."""
    if part is None or part == "none":
        return None
    if part not in PARTS:
        raise ValueError(
            f"part = {part!r} is not a part: legal values are {', '.join(PART_CHOICES)}"
        )
    return part


def unit_configs(cfg: pipeline.PipelineConfig) -> list[tuple[str, object]]:
    """(unit, unit configuration) of every unit ``cfg`` uses: the divider and the Gouraud unit
    always, then the BRDF unit (``("brdf_unit", cfg.brdf)``) when the highlight goes through
    one (``cfg.brdf``: the diffuse term is then Gouraud's, so no specular unit), else the
    specular unit unless ``cfg.uses_specular_unit`` is False."""
    units: list[tuple[str, object]] = [
        ("divider_shift", cfg.divider),
        ("gouraud_segment", cfg.gouraud),
    ]
    if cfg.brdf is not None:
        units.append(("brdf_unit", cfg.brdf))
    elif cfg.uses_specular_unit:
        units.append(("specular_unit", cfg.specular))
    return units


def synth_unit(unit: str, unit_cfg: object, part: str) -> dict[str, object]:
    """One unit's figures (``model.hw.synthesise``: cached under ``SYNTH_CACHE``)."""
    r = synthesise(unit, unit_cfg, part)
    return {
        "lut": r.lut,
        "ff": r.ff,
        "bram": r.bram,
        "dsp": r.dsp,
        "fmax_mhz": r.fmax_mhz,
        "fits": r.fits,
        "overflow": r.overflow,
        "seconds": r.seconds,
    }


def combine(units: Sequence[dict[str, object]], part: str) -> dict[str, object]:
    """A configuration's figures from its units': sums of the cells, the slowest Fmax (NaN when a
    unit has none: it did not fit)."""
    fmax = [u["fmax_mhz"] for u in units]
    return {
        "part": part,
        **{k: int(sum(int(u[k]) for u in units)) for k in ("lut", "ff", "bram", "dsp")},
        "fmax_mhz": float(min(fmax)) if all(f is not None for f in fmax) else math.nan,
        "fits": all(bool(u["fits"]) for u in units),
    }


@dataclass(frozen=True)
class SynthOutcome:
    figures: dict[str, dict[str, object]]  # config_key -> ``combine``
    jobs: int  # distinct unit configurations
    failed: dict[str, str] = field(default_factory=dict)  # "unit (config_key...)" -> error
    seconds: float = 0.0


def run_synthesis(
    configs: Mapping[str, pipeline.PipelineConfig],
    part: str,
    *,
    client=None,
    progress: bool = True,
) -> SynthOutcome:
    """Synthesise every distinct unit configuration of ``configs`` (config_key -> pipeline
    configuration) on ``part``: on ``client``'s cluster (one future each), or in this process
    without one.  A run that fails is reported in ``failed`` and its configurations get no
    figures; the others still do."""
    from tqdm import tqdm

    began = time.perf_counter()
    needs = {key: unit_configs(cfg) for key, cfg in configs.items()}
    jobs = list(dict.fromkeys(u for units in needs.values() for u in units))
    done: dict[tuple[str, object], dict[str, object]] = {}
    failed: dict[str, str] = {}
    bar = tqdm(total=len(jobs), desc=f"synth {part}", unit="unit", disable=not progress)

    def fail(job: tuple[str, object], exc: BaseException) -> None:
        failed[f"{job[0]} {job[1]!r}"] = " ".join(f"{type(exc).__name__}: {exc}".split())

    if client is None:
        for job in jobs:
            try:
                done[job] = synth_unit(*job, part)
            except Exception as exc:
                fail(job, exc)
            bar.update(1)
    else:
        from dask.distributed import as_completed

        futures = {
            client.submit(synth_unit, *job, part, pure=False, priority=-1): job for job in jobs
        }
        for fut in as_completed(futures):
            job = futures[fut]
            try:
                done[job] = fut.result()
            except Exception as exc:
                fail(job, exc)
            fut.release()
            bar.update(1)
    bar.close()
    figures = {
        key: combine([done[u] for u in units], part)
        for key, units in needs.items()
        if all(u in done for u in units)
    }
    return SynthOutcome(figures, len(jobs), failed, time.perf_counter() - began)


def attach(
    results: Sequence[dict], figures: Mapping[str, dict[str, object]], part: str | None
) -> list[dict]:
    """Every result with its configuration's hardware columns (``HW_FIELDS``): the synthesised
    figures and ``hw_mpx_per_s`` = ``px_per_clock_core`` (shaded pixels / the shading core's
    clocks, ``sweep.core_clocks``) x Fmax (the slowest synthesised unit's, not the core's own);
    NaN (and ``part`` "none" or the part) where there are none."""
    out = []
    for r in results:
        hw = figures.get(r["config_key"])
        if hw is None:
            extra = dict.fromkeys(HW_FIELDS[1:], math.nan)
            extra["part"] = part or "none"
        else:
            extra = {k: hw[k] for k in HW_FIELDS[:-1]}
            extra["hw_mpx_per_s"] = r["px_per_clock_core"] * hw["fmax_mhz"]
        out.append({**r, **extra})
    return out
