# SPDX-License-Identifier: Apache-2.0
"""The knob search: the cheapest pipeline configuration whose image meets an accuracy target.

Owns ``Target`` (NMSE, and optionally max error and PSNR, against the exact reference),
``Evaluator`` (a configuration's image and its figures, cached in memory and on disk),
``scene_sized`` (the default units cut to what the scene needs: interval counters and divider
depth to the longest span, only the cos^k tables of the n used), ``modes``, ``FAMILIES`` and
``KNOBS`` (what the search moves) and ``search`` (the search itself).

How it searches (it scales with the number of knobs, not with the size of their grid):

1. The shading modes, cheapest hardware first (``MODES``): no specular unit at all (specular at
   the vertices), then the unit on the triangles the highlight test flags, then the unit on every
   span, then the diffuse term through the unit as well (method (h)) where the pipeline has it.
   The first mode whose scene-sized design meets the target is kept; if none does, the search
   stops and says so, with the closest design.
   In that mode, when it puts the highlight through a unit and the diffuse term is Gouraud's,
   the highlight's unit is a knob too (``FAMILIES``): the patent's cos^k unit and each BRDF
   family unit with RTL (``brdf.RTL_FORMS``, at its default widths, its angle formats the
   specular configuration's).  Every family whose design meets the target there starts a
   descent of its own; the families that do not are listed with their NMSE.
2. Each width knob (``KNOBS``, widest-cost first) in turn is lowered to the smallest value that
   still meets the target, by bisection between its lower bound and its current value; the
   passes repeat until a pass changes nothing.  Every design the search keeps was rendered and
   met the target: the bisection assumes only that a knob's error grows as it narrows, and a
   design that breaks that assumption is simply not kept.  A BRDF family's knobs are its
   unit's widths (``BRDF_KNOBS``) beside the shared angle and C formats, the divider's and the
   Gouraud unit's.

Each family and descent policy gives a candidate; with synthesis, ``shading fit`` places each
and keeps the cheapest (``model.fit.run``), so the family is chosen by its placed cost.

Size: about 550 lines, one idea: what the search moves (modes, families, knobs) and how (the
evaluator, the starts, the descents) are kept together, as each step's order depends on them.

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
from model.study import metrics, trade
from model.units import brdf, specular

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
    unit = cfg.brdf
    if unit is not None:  # the highlight registers come in the specular formats
        shared = {name: getattr(spec, name) for name in brdf.ANGLE_FIELDS}
        unit = dataclasses.replace(unit, angle=dataclasses.replace(unit.angle, **shared))
    return dataclasses.replace(cfg, divider=div, specular=spec, brdf=unit)


def scene_sized(
    needs: SceneNeeds, lanes: int = 2, mode: dict[str, object] | None = None
) -> pipeline.PipelineConfig:
    """The default units cut to the scene and shading ``mode`` (``PipelineConfig`` fields, and
    ``"brdf"``: a family name of ``FAMILIES``): lines as long as its longest span, ``lanes``
    Gouraud lanes, the cos^k tables of the n it uses (n = 1 too when the diffuse term goes
    through the unit) and ROM 9 holding only their range, or the BRDF family's unit at its
    default widths (its n range is always 1..1000); every width otherwise the default's."""
    from model.units import gouraud

    mode = dict(mode or {})
    family = mode.pop("brdf", COS_K)
    if family != COS_K:
        mode["brdf"] = brdf.UNIT_CONFIGS[check_family(family)]
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


COS_K = trade.PATENT_FAMILY
"""The family name of the patent's specular unit (``PipelineConfig.brdf`` None)."""
FAMILIES = trade.FAMILIES
"""The highlight's unit: the patent's cos^k unit, or each BRDF family unit with RTL (the trade
study's families)."""


def check_family(name: str) -> str:
    """``name`` if it is a family of ``FAMILIES``, else ValueError naming it and the legal ones."""
    if name not in FAMILIES:
        raise ValueError(f"family {name!r} is out of range: legal are {', '.join(FAMILIES)}")
    return name


def family(cfg: pipeline.PipelineConfig) -> str:
    """The family of the highlight's unit of ``cfg`` (``FAMILIES``)."""
    return COS_K if cfg.brdf is None else cfg.brdf.form


def _brdf_bits(unit: brdf.FixedConfig) -> int:
    """The BRDF unit's table bits and the registers of its data path: the angle word, the form's
    P-bit intermediates, its output word."""
    angle = unit.angle
    regs = angle.acc_width + angle.c_width + unit.cos_data_bits + 2 * unit.work_bits
    return brdf.table_bits(unit)["total"] + regs + unit.out_bits


def design_bits(cfg: pipeline.PipelineConfig) -> int:
    """The search's step order: the bits the design stores (ROM images) and registers in its
    data paths, a proxy that falls with every knob; the costs reported are synthesised."""
    d, g, s = cfg.divider, cfg.gouraud, cfg.specular
    bits = d.rom_bits + 2 * d.q_width + g.p * g.acc_width + 2 * g.i_width
    if cfg.brdf is not None:
        bits += _brdf_bits(cfg.brdf)
    elif cfg.uses_specular_unit:
        bits += s.rom_bits + s.acc_width + s.mag_width + s.a_width + s.c_width + s.rom_data_bits
    return bits


@dataclass(frozen=True)
class Knob:
    """A width the search lowers: ``table.field`` of the configuration, down to ``lo``."""

    table: str
    name: str
    lo: int
    specular_only: bool = False

    def applies(self, cfg: pipeline.PipelineConfig) -> bool:
        """True when the knob changes ``cfg``'s design: a specular-only knob needs a unit, the
        ROM knobs of the patent's unit need that unit (not a BRDF one), a BRDF knob its unit."""
        if self.table == "brdf":
            return cfg.brdf is not None
        if self.name in COS_K_ONLY:
            return cfg.uses_specular_unit and cfg.brdf is None
        return cfg.uses_specular_unit or not self.specular_only

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
COS_K_ONLY = ("rom_addr_bits", "rom_data_bits", "a_frac_bits")
"""The patent unit's own knobs (ROM 12 and ROM 9): nothing of them reaches a BRDF unit."""
BRDF_KNOBS = (
    Knob("brdf", "cos_addr_bits", 2),
    Knob("brdf", "cos_data_bits", 4),
    Knob("brdf", "coef_bits", 4),
    Knob("brdf", "work_bits", 4),
    Knob("brdf", "out_bits", 1),
    Knob("brdf", "log_addr_bits", 2),
    Knob("brdf", "log_data_bits", 4),
)
"""A BRDF family unit's widths (``brdf.FixedConfig``): each down to the least its configuration
allows (a value its form refuses, e.g. the quadratic's coefficient word under 10 bits, is not a
step); a field the form does not read is not a knob of its designs (``FixedConfig.widths_read``)."""


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
    if cfg.brdf is not None:
        return cfg.divider.rom_bits + brdf.table_bits(cfg.brdf)["total"]
    return cfg.divider.rom_bits + (cfg.specular.rom_bits if cfg.uses_specular_unit else 0)


def knobs_of(cfg: pipeline.PipelineConfig) -> list[Knob]:
    """The knobs that change ``cfg``'s design, in the search's order."""
    found = [k for k in (*KNOBS, *BRDF_KNOBS) if k.applies(cfg)]
    if cfg.brdf is not None:  # only the widths its form reads
        read = cfg.brdf.widths_read
        found = [k for k in found if k.table != "brdf" or k.name in read]
    return found


def _score(policy: str, old, new, old_comp, new_comp) -> tuple[float, ...]:
    worse = max(new_comp.nmse - old_comp.nmse, 0.0)
    saved = design_bits(old) - design_bits(new)
    if policy == "error":
        return (worse, -saved)
    if policy == "storage":
        rom = _rom_bits(old) - _rom_bits(new)
        return (0.0, worse / rom) if rom > 0 else (1.0, worse / max(saved, 1))
    return (worse / max(saved, 1),)


def _label(mode: dict[str, object]) -> str:
    return ", ".join(f"{k} = {v}" for k, v in mode.items())


def mode_families(mode: dict[str, object], families: tuple[str, ...]) -> tuple[str | None, ...]:
    """The families ``mode`` is tried with: None for a mode without a unit for the highlight
    (vertex), cos^k alone where the diffuse term goes through the unit (a BRDF unit makes the
    highlight only), else every one of ``families``."""
    if mode.get("specular_mode") == "vertex":
        return (None,)
    if mode.get("diffuse_mode", "gouraud") != "gouraud":
        return (COS_K,) if COS_K in families else ()
    return families


def choose_starts(
    evaluate: Evaluator,
    needs: SceneNeeds,
    target: Target,
    lanes: int = 2,
    tick=None,
    families: tuple[str, ...] = FAMILIES,
) -> list[SearchResult]:
    """Step 1 of the search (module doc): the first shading mode in which a family's
    scene-sized design meets ``target``, and there every family that does, in ``families``'
    order (each a start of its own descents); or the closest design (``met`` False, with the
    reason) when none does."""
    families = tuple(check_family(f) for f in families) or FAMILIES
    tick = tick or (lambda: None)
    steps: list[str] = []
    best = None
    for mode in modes():
        met = []
        for fam in mode_families(mode, families):
            design = dict(mode) if fam is None else {**mode, "brdf": fam}
            tried = _try(evaluate, lambda design=design: scene_sized(needs, lanes, design))
            tick()
            if tried is None:
                continue
            cfg, comp = tried
            name = "" if fam is None else f", family {fam}"
            steps.append(
                f"mode {_label(mode)}{name}: NMSE {comp.nmse:.6f}, "
                f"max error {comp.max_abs_error:.0f}"
            )
            if target.met(comp):
                met.append((cfg, comp))
            elif best is None or comp.nmse < best[1].nmse:
                best = (cfg, comp)
        if met:
            return [SearchResult(True, cfg, comp, {}, list(steps)) for cfg, comp in met]
    assert best is not None
    cfg, comp = best
    fam = "" if cfg.brdf is None else f", family {family(cfg)}"
    return [
        SearchResult(
            False,
            cfg,
            comp,
            evaluate.figures(cfg)["counters"],
            steps,
            closest_reason=(
                f"no shading mode meets {target.describe()} even at the default widths (every "
                f"width at its widest: the error is the method's, not the widths'); the closest "
                f"is specular_mode = {cfg.specular_mode}, diffuse_mode = {cfg.diffuse_mode}"
                f"{fam} with NMSE {comp.nmse:.6f}, max error {comp.max_abs_error:.0f} levels "
                f"({comp.highlight_max_abs_error:.0f} in the highlight)"
            ),
        )
    ]


def choose_mode(
    evaluate: Evaluator,
    needs: SceneNeeds,
    target: Target,
    lanes: int = 2,
    tick=None,
    families: tuple[str, ...] = FAMILIES,
) -> SearchResult:
    """The first start of ``choose_starts`` (the first family of ``families`` that meets the
    target in the first mode where one does), or the closest design."""
    return choose_starts(evaluate, needs, target, lanes, tick, families)[0]


def descend(
    evaluate: Evaluator, start: SearchResult, target: Target, policy: str = "bits", tick=None
) -> SearchResult:
    """Step 2 (module doc): from the mode's design, one-bit steps chosen by ``policy``
    (``POLICIES``) while the target holds."""
    if policy not in POLICIES:
        raise ValueError(f"policy = {policy!r} is out of range: legal are {', '.join(POLICIES)}")
    tick = tick or (lambda: None)
    cfg, comp, steps = start.config, start.comparison, list(start.steps)
    knobs = knobs_of(cfg)
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
    families: tuple[str, ...] = FAMILIES,
) -> SearchResult:
    """The design meeting ``target`` that ``policy``'s descent reaches from the first start
    (module doc)."""
    start = choose_mode(evaluate, needs, target, lanes, progress, families)
    if not start.met:
        evaluate.save()
        return start
    return descend(evaluate, start, target, policy, progress)


def search_candidates(
    evaluate: Evaluator,
    needs: SceneNeeds,
    target: Target,
    lanes: int = 2,
    progress=None,
    families: tuple[str, ...] = FAMILIES,
) -> list[SearchResult]:
    """One design per start (a family meeting the target in the chosen mode) and descent
    policy (``POLICIES``), different designs only, in start and policy order; the closest
    design alone when the target cannot be met."""
    starts = choose_starts(evaluate, needs, target, lanes, progress, families)
    if not starts[0].met:
        evaluate.save()
        return starts
    found: list[SearchResult] = []
    for start in starts:
        for policy in POLICIES:
            result = descend(evaluate, start, target, policy, progress)
            if all(r.config != result.config for r in found):
                found.append(result)
    return found


def scene_error(evaluate: Evaluator, cfg: pipeline.PipelineConfig) -> np.ndarray:
    """(H, W) largest channel error of ``cfg``'s image against (a), levels."""
    img = evaluate.frame(cfg).rgb.astype(np.int64)
    return np.abs(img - evaluate.reference.rgb.astype(np.int64)).max(axis=2).astype(np.float64)
