# SPDX-License-Identifier: Apache-2.0
"""The knob search: the cheapest pipeline configuration whose image meets an accuracy target.

Owns ``Target`` (NMSE, and optionally max error and PSNR, against the exact reference),
``Evaluator`` (a configuration's image and its figures, cached in memory and on disk),
``scene_sized`` (the default units cut to what the scene needs: interval counters and divider
depth to the longest span, only the cos^k tables of the n used), ``MODES`` and ``KNOBS`` (what the
search moves) and ``search`` (the search itself).

How it searches (it scales with the number of knobs, not with the size of their grid):

1. The shading modes, cheapest hardware first (``MODES``): no specular unit at all (specular at
   the vertices), then the unit on the triangles the highlight test flags, then the unit on every
   span, then the diffuse term through the unit as well (method (h)) where the pipeline has it.
   The first mode whose scene-sized design meets the target is kept; if none does, the search
   stops and says so, with the closest design.
2. Each width knob (``KNOBS``, widest-cost first) in turn is lowered to the smallest value that
   still meets the target, by bisection between its lower bound and its current value; the
   passes repeat until a pass changes nothing.  Every design the search keeps was rendered and
   met the target: the bisection assumes only that a knob's error grows as it narrows, and a
   design that breaks that assumption is simply not kept.

May import numpy and ``model.render``, ``model.units`` and ``model.study``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.fit.analyse import SceneNeeds
from model.render import configfile, pipeline, raster, reference, shade
from model.study import metrics
from model.units import specular

CACHE_VERSION = 1
"""Bump when the model's images change: the figures cached under an older version are unused."""


@dataclass(frozen=True)
class Target:
    """What "accurate enough" means: NMSE against (a), optionally the largest error in levels
    and the PSNR in dB; every one given must hold."""

    nmse: float = metrics.NMSE_VISUALLY_IDENTICAL
    max_error: float | None = None
    psnr: float | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.nmse, int | float) and 0 < self.nmse < math.inf):
            raise ValueError(f"target nmse = {self.nmse!r} is out of range: legal is > 0")
        if self.max_error is not None and not 0 <= self.max_error <= 255:
            raise ValueError(
                f"target max_error = {self.max_error!r} is out of range: legal is 0..255 levels"
            )
        if self.psnr is not None and not 0 < self.psnr < math.inf:
            raise ValueError(f"target psnr = {self.psnr!r} is out of range: legal is > 0 dB")

    def met(self, c: metrics.Comparison) -> bool:
        return (
            c.nmse <= self.nmse
            and (self.max_error is None or c.max_abs_error <= self.max_error)
            and (self.psnr is None or c.psnr >= self.psnr)
        )

    def describe(self) -> str:
        parts = [f"NMSE <= {self.nmse:g}"]
        if self.max_error is not None:
            parts.append(f"max error <= {self.max_error:g} levels")
        if self.psnr is not None:
            parts.append(f"PSNR >= {self.psnr:g} dB")
        return ", ".join(parts)


def config_key(cfg: pipeline.PipelineConfig) -> str:
    """A stable key of a configuration (its TOML dictionary, hashed)."""
    text = json.dumps(configfile.config_dict(cfg), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


@dataclass
class Evaluator:
    """Renders a configuration's image of one rasterised scene and compares it with (a).

    ``cache``: a JSON file of earlier figures for this scene (``scene_key`` names the scene and
    its size), read at the start and written by ``save``: a second fit of the same scene renders
    only designs it has not seen."""

    frame_raster: raster.Raster
    scene_key: str
    cache: Path | None = None
    renders: int = 0
    hits: int = 0
    _seen: dict[str, dict] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.reference = shade.shade(self.frame_raster, reference.exact_blinn)
        self.highlight = metrics.highlight_mask(self.reference.specular)
        if self.cache is not None and self.cache.is_file():
            data = json.loads(self.cache.read_text())
            if data.get("scene") == self.scene_key:
                self._seen = data["designs"]

    def frame(self, cfg: pipeline.PipelineConfig) -> shade.Frame:
        return shade.shade(self.frame_raster, pipeline.unit_shader(cfg))

    def figures(self, cfg: pipeline.PipelineConfig) -> dict:
        """{"comparison": Comparison.as_dict(), "counters": {...}} of ``cfg`` (cached)."""
        key = config_key(cfg)
        if key in self._seen:
            self.hits += 1
            return self._seen[key]
        frame = self.frame(cfg)
        self.renders += 1
        comp = metrics.compare(frame.rgb, self.reference.rgb, highlight=self.highlight)
        found = {"comparison": comp.as_dict(), "counters": dict(frame.stats.counters)}
        self._seen[key] = found
        return found

    def comparison(self, cfg: pipeline.PipelineConfig) -> metrics.Comparison:
        return metrics.Comparison(**self.figures(cfg)["comparison"])

    def known(self) -> dict[str, dict]:
        """Every design's figures this evaluator holds (a copy), by ``config_key``."""
        return dict(self._seen)

    def absorb(self, figures: dict[str, dict]) -> None:
        """Take the figures another evaluator of the same scene found (``known``)."""
        self._seen.update(figures)

    def save(self) -> None:
        if self.cache is not None:
            self.cache.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.cache.with_suffix(".tmp")
            tmp.write_text(json.dumps({"scene": self.scene_key, "designs": self._seen}))
            tmp.replace(self.cache)


# ------------------------------------------------------------------------------------------------
# the designs the search moves between


def k_ranges_for(n_values: tuple[int, ...]) -> tuple[tuple[int, int, int], ...]:
    """The fewest decoder ranges that give every used n its patent k (one table per distinct k):
    each range ends at the largest used n of its k, the last one at n = 1000."""
    if not n_values:
        return ((1, specular.N_MAX, 1),)
    groups: dict[int, int] = {}
    for n in sorted(n_values):
        groups[specular.decode_k(n)] = n
    ranges, lo = [], 1
    items = sorted(groups.items(), key=lambda kv: kv[1])
    for i, (k, hi) in enumerate(items):
        hi = specular.N_MAX if i == len(items) - 1 else hi
        ranges.append((lo, hi, k))
        lo = hi + 1
    return tuple(ranges)


def consistent(cfg: pipeline.PipelineConfig) -> pipeline.PipelineConfig:
    """``cfg`` with the fields that follow from others set: the divider's dividend holds the
    difference of two Gouraud intensities, its divisor and the specular interval counter reach
    the Gouraud unit's longest line."""
    g = cfg.gouraud
    bits = max(1, (g.len_max - 1).bit_length())
    div = dataclasses.replace(cfg.divider, a_width=g.di_width, k_width=bits)
    if div.k_width > div.recip_bits + 1:
        div = dataclasses.replace(div, recip_bits=div.k_width - 1)
    spec = dataclasses.replace(cfg.specular, len_width=bits)
    return dataclasses.replace(cfg, divider=div, specular=spec)


def scene_sized(
    needs: SceneNeeds, lanes: int = 2, mode: dict[str, object] | None = None
) -> pipeline.PipelineConfig:
    """The default units cut to the scene and shading ``mode`` (``PipelineConfig`` fields):
    lines as long as its longest span, ``lanes`` Gouraud lanes, the cos^k tables of the n it uses
    (n = 1 too when the diffuse term goes through the unit) and ROM 9 holding only their range;
    every width otherwise the default's."""
    from model.units import gouraud

    mode = mode or {}
    n_values = tuple(needs.n_values)
    if mode.get("diffuse_mode", "gouraud") != "gouraud":
        n_values = tuple(sorted({1, *n_values}))

    log2_p = lanes.bit_length() - 1
    g = gouraud.GouraudConfig(p=lanes, len_width=max(needs.longest_span.bit_length(), log2_p + 1))
    kw: dict[str, object] = {"k_ranges": k_ranges_for(n_values)}
    if n_values:
        kw.update(n_first=min(n_values), n_last=max(n_values))
    spec = dataclasses.replace(specular.DEFAULT, **kw)
    return consistent(pipeline.PipelineConfig(gouraud=g, specular=spec, **mode))


def modes() -> list[dict[str, object]]:
    """The shading modes, cheapest hardware (then fewest unit cycles) first."""
    found: list[dict[str, object]] = [
        {"specular_mode": "vertex"},
        {"specular_mode": "adaptive"},
        {"specular_mode": "unit"},
    ]
    for diffuse in ("adaptive", "unit"):  # method (h): the diffuse term through the unit (n = 1)
        found += [{"specular_mode": s, "diffuse_mode": diffuse} for s in ("adaptive", "unit")]
    return found


def design_bits(cfg: pipeline.PipelineConfig) -> int:
    """The search's step order: the bits the design stores (ROM images) and registers in its
    data paths, a proxy that falls with every knob; the costs reported are synthesised."""
    d, g, s = cfg.divider, cfg.gouraud, cfg.specular
    bits = d.rom_bits + 2 * d.q_width + g.p * g.acc_width + 2 * g.i_width
    if cfg.uses_specular_unit:
        bits += s.rom_bits + s.acc_width + s.mag_width + s.a_width + s.c_width + s.rom_data_bits
    return bits


@dataclass(frozen=True)
class Knob:
    """A width the search lowers: ``table.field`` of the configuration, down to ``lo``."""

    table: str
    name: str
    lo: int
    specular_only: bool = False

    def get(self, cfg: pipeline.PipelineConfig) -> int:
        return getattr(getattr(cfg, self.table), self.name)

    def set(self, cfg: pipeline.PipelineConfig, value: int) -> pipeline.PipelineConfig:
        unit = dataclasses.replace(getattr(cfg, self.table), **{self.name: value})
        return consistent(dataclasses.replace(cfg, **{self.table: unit}))

    @property
    def label(self) -> str:
        return f"{self.table}.{self.name}"


KNOBS = (
    Knob("specular", "rom_addr_bits", 3, True),
    Knob("specular", "rom_data_bits", 3, True),
    Knob("specular", "z_frac_bits", 6, True),
    Knob("specular", "a_frac_bits", 2, True),
    Knob("specular", "c_frac_bits", 0, True),
    Knob("gouraud", "i_frac", 1),
    Knob("divider", "recip_bits", 1),
)


# ------------------------------------------------------------------------------------------------
# the search


@dataclass
class SearchResult:
    """The search's outcome: the chosen design (or the closest one), and how it got there."""

    met: bool
    config: pipeline.PipelineConfig
    comparison: metrics.Comparison
    counters: dict
    steps: list[str]  # one line per decision, in order
    closest_reason: str = ""  # why no design met the target (when ``met`` is False)
    policy: str = ""  # the descent policy that reached it (``POLICIES``)


def _try(evaluate: Evaluator, cfg_fn: Callable[[], pipeline.PipelineConfig]):
    """(config, comparison) or None when the configuration is refused."""
    try:
        cfg = cfg_fn()
    except ValueError:
        return None
    return cfg, evaluate.comparison(cfg)


POLICIES: dict[str, str] = {
    "bits": "the step costing the least NMSE per bit of storage and datapath saved",
    "storage": "the step costing the least NMSE per ROM bit saved (datapath steps after them)",
    "error": "the step adding the least NMSE, whatever it saves",
}
"""How the descent picks its next one-bit step: each gives a design meeting the target; with
synthesis, ``shading fit`` places and routes each and keeps the cheapest (``model.fit.run``)."""


def _rom_bits(cfg: pipeline.PipelineConfig) -> int:
    return cfg.divider.rom_bits + (cfg.specular.rom_bits if cfg.uses_specular_unit else 0)


def _score(policy: str, old, new, old_comp, new_comp) -> tuple[float, ...]:
    worse = max(new_comp.nmse - old_comp.nmse, 0.0)
    saved = design_bits(old) - design_bits(new)
    if policy == "error":
        return (worse, -saved)
    if policy == "storage":
        rom = _rom_bits(old) - _rom_bits(new)
        return (0.0, worse / rom) if rom > 0 else (1.0, worse / max(saved, 1))
    return (worse / max(saved, 1),)


def choose_mode(
    evaluate: Evaluator, needs: SceneNeeds, target: Target, lanes: int = 2, tick=None
) -> SearchResult:
    """Step 1 of the search (module doc): the cheapest shading mode meeting ``target`` at the
    scene-sized widths, or the closest one (``met`` False, with the reason)."""
    tick = tick or (lambda: None)
    steps: list[str] = []
    best = None
    for mode in modes():
        tried = _try(evaluate, lambda mode=mode: scene_sized(needs, lanes, mode))
        tick()
        if tried is None:
            continue
        cfg, comp = tried
        label = ", ".join(f"{k} = {v}" for k, v in mode.items())
        steps.append(f"mode {label}: NMSE {comp.nmse:.6f}, max error {comp.max_abs_error:.0f}")
        if target.met(comp):
            return SearchResult(True, cfg, comp, {}, steps)
        if best is None or comp.nmse < best[1].nmse:
            best = (cfg, comp)
    assert best is not None
    cfg, comp = best
    return SearchResult(
        False,
        cfg,
        comp,
        evaluate.figures(cfg)["counters"],
        steps,
        closest_reason=(
            f"no shading mode meets {target.describe()} even at the default widths (every "
            f"width at its widest: the error is the method's, not the widths'); the closest "
            f"is specular_mode = {cfg.specular_mode}, diffuse_mode = {cfg.diffuse_mode} "
            f"with NMSE {comp.nmse:.6f}, max error {comp.max_abs_error:.0f} levels "
            f"({comp.highlight_max_abs_error:.0f} in the highlight)"
        ),
    )


def descend(
    evaluate: Evaluator, start: SearchResult, target: Target, policy: str = "bits", tick=None
) -> SearchResult:
    """Step 2 (module doc): from the mode's design, one-bit steps chosen by ``policy``
    (``POLICIES``) while the target holds."""
    if policy not in POLICIES:
        raise ValueError(f"policy = {policy!r} is out of range: legal are {', '.join(POLICIES)}")
    tick = tick or (lambda: None)
    cfg, comp, steps = start.config, start.comparison, list(start.steps)
    knobs = [k for k in KNOBS if cfg.uses_specular_unit or not k.specular_only]
    while True:
        moves = []
        for knob in knobs:
            if knob.get(cfg) <= knob.lo:
                continue
            tried = _try(evaluate, lambda knob=knob, cfg=cfg: knob.set(cfg, knob.get(cfg) - 1))
            tick()
            if tried is None or not target.met(tried[1]):
                continue
            if design_bits(tried[0]) < design_bits(cfg):
                moves.append((_score(policy, cfg, tried[0], comp, tried[1]), knob.label, tried))
        if not moves:
            break
        _, label, (new_cfg, new_comp) = min(moves, key=lambda m: (m[0], m[1]))
        knob = next(k for k in knobs if k.label == label)
        steps.append(f"{label}: {knob.get(cfg)} -> {knob.get(new_cfg)} (NMSE {new_comp.nmse:.6f})")
        cfg, comp = new_cfg, new_comp
    evaluate.save()
    return SearchResult(True, cfg, comp, evaluate.figures(cfg)["counters"], steps, policy=policy)


def search(
    evaluate: Evaluator,
    needs: SceneNeeds,
    target: Target,
    lanes: int = 2,
    progress=None,
    policy: str = "bits",
) -> SearchResult:
    """The design meeting ``target`` that ``policy``'s descent reaches (module doc)."""
    start = choose_mode(evaluate, needs, target, lanes, progress)
    if not start.met:
        evaluate.save()
        return start
    return descend(evaluate, start, target, policy, progress)


def search_candidates(
    evaluate: Evaluator, needs: SceneNeeds, target: Target, lanes: int = 2, progress=None
) -> list[SearchResult]:
    """One design per descent policy (``POLICIES``), different designs only, in policy order;
    the closest design alone when the target cannot be met."""
    start = choose_mode(evaluate, needs, target, lanes, progress)
    if not start.met:
        evaluate.save()
        return [start]
    found: list[SearchResult] = []
    for policy in POLICIES:
        result = descend(evaluate, start, target, policy, progress)
        if all(r.config != result.config for r in found):
            found.append(result)
    return found


def scene_error(evaluate: Evaluator, cfg: pipeline.PipelineConfig) -> np.ndarray:
    """(H, W) largest channel error of ``cfg``'s image against (a), levels."""
    img = evaluate.frame(cfg).rgb.astype(np.int64)
    return np.abs(img - evaluate.reference.rgb.astype(np.int64)).max(axis=2).astype(np.float64)
