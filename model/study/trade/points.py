# SPDX-License-Identifier: Apache-2.0
"""Trade points: the knobs, their values, the grids of configurations, the scenes a point names.

Owns ``TradePoint`` (a scene, a size, one value per knob) with its cache ``key``
(``CACHE_VERSION``), the knobs (``KNOBS``, ``K_SETS``, ``BRDF_CHOICES``, ``BRDF_KNOBS``,
``DEFAULT_POINT``, ``row_knobs``, ``family``), the grids (``Sweep``, ``SMALL_SWEEPS``, ``NAMED``,
``FULL_PRODUCT``, ``FULL_BRDF_PRODUCT``, ``grid_configs``, ``grid_points``) and
the scenes a point can name: a built-in scene, or a scene file or mesh file by its key
(``FILE_KEY``, ``point_scene``).  May import ``model.units`` and ``model.render``.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import itertools
import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from model.render import pipeline, scene, scenefile
from model.units import brdf, divider, gouraud, specular

CACHE_VERSION = 9
"""Part of every key: bump it when a figure's definition changes, so old cache files are unused."""
DEFAULT_SIZE = 128
K_SETS: dict[str, tuple[tuple[int, int, int], ...]] = {
    "patent": specular.PATENT_K_RANGES,  # k = 1, 2, 4, 16 (fig. 13)
    "k1-2-16": ((1, 1, 1), (2, 2, 2), (3, 1000, 16)),  # no cos^4 table: n = 3..6 use cos^16
    "k16": ((1, 1000, 16),),  # a single cos^16 table
    "cos2": specular.PROTOTYPE_K_RANGES,  # the prototype's single cos^2 table
}
"""The decoder's n -> k maps.  Without the cos^4 table, n = 3..6 are better served by cos^16
(worst float epicentre error 3.4 % at n = 3) than by cos^2 (4.4 % at n = 15)."""

KNOBS: tuple[str, ...] = (
    "rom_addr_bits",
    "rom_data_bits",
    "z_frac_bits",
    "k_set",
    "alpha",
    "recip_bits",
    "p",
    "specular_mode",
    "highlight_levels",
    "diffuse_mode",
    "brdf",
)

PATENT = "none"
"""The ``brdf`` knob's default: the highlight through the patent's cos^k specular unit."""
BRDF_CHOICES: tuple[str, ...] = (PATENT, *brdf.RTL_FORMS)
"""Legal ``brdf`` values: "none" (the patent's unit) or a BRDF family form with RTL
(``brdf.unit.RTL_FORMS``, read when this module loads: a form with new RTL is a value at once)."""
BRDF_KNOBS = ("z_frac_bits", "recip_bits", "p", "specular_mode", "highlight_levels")
"""The knobs that still reach a point whose highlight goes through a BRDF unit: the angle
format (``brdf.unit.ANGLE_FIELDS``: of these knobs only ``z_frac_bits``), the divider, the
Gouraud unit and the highlight's route.  ``rom_addr_bits``, ``rom_data_bits``, ``k_set`` and
``alpha`` are the patent unit's tables: legal with a BRDF unit but without effect (another key,
the same figures), so no grid varies them there."""


PATENT_FAMILY = "cos^k"
"""The family name of the patent's specular unit (``brdf`` "none"); a BRDF unit's family is its
form."""
FAMILIES: tuple[str, ...] = (PATENT_FAMILY, *brdf.RTL_FORMS)
"""Every family of the highlight's unit: the patent's, then each BRDF form with RTL."""


def family(knobs: Mapping[str, object]) -> str:
    """The BRDF family a point or row belongs to: ``PATENT_FAMILY`` (the patent's specular unit,
    ``brdf`` "none") or the BRDF unit's form."""
    form = knobs.get("brdf", PATENT)
    return PATENT_FAMILY if form == PATENT else str(form)


FILE_KEY = re.compile(r"(?P<kind>mesh|scene):(?P<name>[^/\\]+)@(?P<sha1>[0-9a-f]{12})")
"""A mesh file's or scene file's key (``scenefile.SceneSource.key``): ``mesh:<file name>@<12 hex>``
or ``scene:<file name>@<12 hex>``, the hex from the sha1 of the files' bytes (and of the mesh's
up axis)."""


def row_knobs(row: dict) -> dict:
    """The knob values of a result or an aggregated row (``TradePoint.with_knobs`` takes them)."""
    return {k: row[k] for k in KNOBS}


def _hash(payload: dict) -> str:
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class TradePoint:
    """One scene at one resolution through one configuration (the knobs: ``model.study.trade``).

    ``scene`` is a built-in scene's name (``scenefile.SCENE_NAMES``) or a file's key
    (``FILE_KEY``); ``point_scene`` makes the scene."""

    scene: str = "sphere"
    size: int = DEFAULT_SIZE
    rom_addr_bits: int = specular.DEFAULT.rom_addr_bits
    rom_data_bits: int = specular.DEFAULT.rom_data_bits
    z_frac_bits: int = specular.DEFAULT.z_frac_bits
    k_set: str = "patent"
    alpha: str = specular.DEFAULT.alpha
    recip_bits: int = divider.DEFAULT.recip_bits
    p: int = gouraud.DEFAULT.p
    specular_mode: str = "unit"
    highlight_levels: float = 0.5
    diffuse_mode: str = "gouraud"
    brdf: str = PATENT

    def __post_init__(self) -> None:
        if not FILE_KEY.fullmatch(self.scene):
            try:
                scene.check_choice("scene", self.scene, scenefile.SCENE_NAMES)
            except ValueError as exc:
                raise ValueError(
                    f"{exc} or a file key 'mesh:<file name>@<sha1: 12 hex>' or "
                    "'scene:<file name>@<sha1: 12 hex>'"
                ) from None
        self._check_k_set()
        self._check_brdf()
        # Canonical types, so that equal points have equal keys (1 and 1.0, numpy ints).
        for name in ("size", "rom_addr_bits", "rom_data_bits", "z_frac_bits", "recip_bits", "p"):
            object.__setattr__(self, name, int(getattr(self, name)))
        object.__setattr__(self, "highlight_levels", float(self.highlight_levels))

    def _check_k_set(self) -> None:
        scene.check_choice("k_set", self.k_set, tuple(K_SETS))

    def _check_brdf(self) -> None:
        """The ``brdf`` knob is a legal value, and the point's routes are ones a BRDF unit takes
        (it makes the highlight only: ``PipelineConfig._check_brdf``'s rule, named by knob)."""
        scene.check_choice("brdf", self.brdf, BRDF_CHOICES)
        if self.brdf != PATENT and (
            self.specular_mode == "vertex" or self.diffuse_mode != "gouraud"
        ):
            raise ValueError(
                f"brdf = {self.brdf!r} is out of range with specular_mode = "
                f"{self.specular_mode!r} and diffuse_mode = {self.diffuse_mode!r}: a BRDF unit "
                "makes the highlight only; legal are brdf = 'none', or specular_mode unit or "
                "adaptive with diffuse_mode gouraud"
            )

    @property
    def knobs(self) -> dict[str, object]:
        return {k: getattr(self, k) for k in KNOBS}

    @property
    def config_name(self) -> str:
        """ "" for a configuration of the grid; a configuration file's label (``ConfigPoint``)."""
        return ""

    @property
    def key(self) -> str:
        """Stable cache key: hash of the canonical JSON of every field (and CACHE_VERSION)."""
        return _hash({"version": CACHE_VERSION, **dataclasses.asdict(self)})

    @property
    def config_key(self) -> str:
        """The same for the knobs only: equal for the scenes of one configuration."""
        return _hash({"version": CACHE_VERSION, **self.knobs})

    def with_knobs(self, **knobs) -> TradePoint:
        return dataclasses.replace(self, **knobs)

    def changed_knobs(self) -> dict[str, object]:
        """The knobs that differ from the default configuration."""
        base = TradePoint(scene=self.scene, size=self.size)
        return {k: v for k, v in self.knobs.items() if getattr(base, k) != v}

    @property
    def label(self) -> str:
        changed = self.changed_knobs()
        for name, knobs in NAMED.items():
            if changed == knobs:
                return name
        return ", ".join(f"{k}={v}" for k, v in changed.items()) if changed else "default"

    @property
    def family(self) -> str:
        """ "cos^k" (the patent's unit) or the BRDF unit's form (``family``)."""
        return family(self.knobs)

    @property
    def group(self) -> str:
        """The sweep the configuration belongs to (its changed knob), for the plots."""
        changed = self.changed_knobs()
        if len(changed) == 1:
            return next(iter(changed))
        if set(changed) == {"specular_mode", "highlight_levels"}:
            return "highlight_levels"
        return "default" if not changed else "combined"

    def to_pipeline_config(self) -> pipeline.PipelineConfig:
        """The unit configurations this point's knobs select (every knob is one field)."""
        k_ranges = K_SETS[self.k_set]
        a_frac = specular.DEFAULT.a_frac_bits
        spec = specular.SpecularConfig(
            rom_addr_bits=self.rom_addr_bits,
            rom_data_bits=self.rom_data_bits,
            z_frac_bits=self.z_frac_bits,
            k_ranges=k_ranges,
            alpha=self.alpha,
            a_int_bits=a_int_bits_for(k_ranges, self.alpha, a_frac),
            a_frac_bits=a_frac,
        )
        return pipeline.PipelineConfig(
            divider=dataclasses.replace(divider.DEFAULT, recip_bits=self.recip_bits),
            gouraud=dataclasses.replace(gouraud.DEFAULT, p=self.p),
            specular=spec,
            specular_mode=self.specular_mode,
            highlight_levels=self.highlight_levels,
            diffuse_mode=self.diffuse_mode,
            brdf=self.brdf_config(spec),
        )

    def brdf_config(self, spec: specular.SpecularConfig) -> brdf.FixedConfig | None:
        """None (``brdf`` "none"), or the form's default unit (``brdf.unit.UNIT_CONFIGS``: the
        widths whose ROM images are committed) with ``angle`` = the point's specular
        configuration, so the angle knobs reach it; ``ValueError`` naming the knobs when the
        form's widths do not fit that angle format (its angle table's address bits are at
        most ``z_frac_bits``)."""
        if self.brdf == PATENT:
            return None
        try:
            return dataclasses.replace(brdf.UNIT_CONFIGS[self.brdf], angle=spec)
        except ValueError as exc:
            raise ValueError(
                f"brdf = {self.brdf!r} is out of range with z_frac_bits = {self.z_frac_bits}: {exc}"
            ) from None


@functools.cache
def a_int_bits_for(k_ranges: tuple, alpha: str, a_frac_bits: int) -> int:
    """The narrowest ROM-9 integer part holding the largest rounded a of the k-set (>= 1)."""
    a_max = max(
        specular.alpha_value(n, k, alpha) for lo, hi, k in k_ranges for n in range(lo, hi + 1)
    )
    word = math.floor(a_max * 2**a_frac_bits + 0.5)
    return max(1, word.bit_length() - a_frac_bits)


DEFAULT_POINT = TradePoint()


def _tuples(value: object) -> object:
    """Lists (JSON, TOML) as tuples, the way the configurations hold them."""
    return tuple(_tuples(v) for v in value) if isinstance(value, list | tuple) else value


def config_from_dict(tables: Mapping[str, Mapping[str, object]]) -> pipeline.PipelineConfig:
    """The ``PipelineConfig`` of ``configfile.config_dict(cfg)`` (its inverse)."""
    units = {
        "divider": divider.DividerConfig,
        "gouraud": gouraud.GouraudConfig,
        "specular": specular.SpecularConfig,
    }
    kwargs: dict[str, object] = {k: _tuples(v) for k, v in tables.get("pipeline", {}).items()}
    for name, cls in units.items():
        if name in tables:
            kwargs[name] = cls(**{k: _tuples(v) for k, v in tables[name].items()})
    if "brdf" in tables:  # its angle format is the specular table's (``configfile``)
        angle = kwargs.get("specular", specular.DEFAULT)
        fields = {k: _tuples(v) for k, v in tables["brdf"].items()}
        kwargs["brdf"] = brdf.FixedConfig(**fields, angle=angle)
    return pipeline.PipelineConfig(**kwargs)


@dataclass(frozen=True)
class ConfigPoint(TradePoint):
    """A configuration file's configuration (``--config FILE``, e.g. the ``config.toml`` of a
    ``shading fit`` bundle) on one scene: labelled ``config_label`` (``fit:teapot``), keyed by
    its content (``config_json``: the canonical JSON of ``configfile.config_dict``), so an
    edited file is another configuration.  The knob fields say what the file sets where a knob
    can (``k_set`` "custom" for a decoder map no grid k-set has); they are not what the point
    runs: ``to_pipeline_config`` is the file's configuration, every field."""

    config_label: str = ""
    config_json: str = ""

    @classmethod
    def from_config(
        cls, label: str, cfg: pipeline.PipelineConfig, scene_key: str, size: int = DEFAULT_SIZE
    ) -> ConfigPoint:
        from model.render import configfile

        names = {v: k for k, v in K_SETS.items()}
        s = cfg.specular
        return cls(
            scene=scene_key,
            size=size,
            rom_addr_bits=s.rom_addr_bits,
            rom_data_bits=s.rom_data_bits,
            z_frac_bits=s.z_frac_bits,
            k_set=names.get(tuple(s.k_ranges), "custom"),
            alpha=s.alpha,
            recip_bits=cfg.divider.recip_bits,
            p=cfg.gouraud.p,
            specular_mode=cfg.specular_mode,
            highlight_levels=cfg.highlight_levels,
            diffuse_mode=cfg.diffuse_mode,
            brdf=PATENT if cfg.brdf is None else cfg.brdf.form,
            config_label=label,
            config_json=json.dumps(configfile.config_dict(cfg), sort_keys=True),
        )

    def _check_brdf(self) -> None:
        pass  # the file's configuration was checked when it was read (any form it names)

    def _check_k_set(self) -> None:
        if self.k_set != "custom":
            super()._check_k_set()
        if not self.config_label or not self.config_json:
            raise ValueError(
                "config_label and config_json must be given: make a ConfigPoint with "
                "ConfigPoint.from_config(label, cfg, scene)"
            )

    def __repr__(self) -> str:  # the file's JSON would make every message a page long
        return f"ConfigPoint({self.config_label}, scene={self.scene!r}, size={self.size})"

    @property
    def config_name(self) -> str:
        return self.config_label

    @property
    def config_key(self) -> str:
        return _hash({"version": CACHE_VERSION, "config": json.loads(self.config_json)})

    @property
    def label(self) -> str:
        return self.config_label

    @property
    def group(self) -> str:
        return "fitted"

    def to_pipeline_config(self) -> pipeline.PipelineConfig:
        return config_from_dict(json.loads(self.config_json))


# ================================================================================ the grid
@dataclass(frozen=True)
class Sweep:
    """One knob swept around a base configuration (the default unless ``base`` overrides)."""

    knob: str
    values: tuple
    base: tuple[tuple[str, object], ...] = ()
    title: str = ""

    def configs(self) -> list[dict[str, object]]:
        return [{**dict(self.base), self.knob: v} for v in self.values]

    @property
    def base_knobs(self) -> dict[str, object]:
        return {**DEFAULT_POINT.knobs, **dict(self.base)}


SMALL_SWEEPS: tuple[Sweep, ...] = (
    Sweep("rom_addr_bits", (6, 8, 10, 12, 14), title="ROM-12 address bits"),
    Sweep("rom_data_bits", (8, 10, 12, 16), title="ROM-12 data bits"),
    Sweep("z_frac_bits", (6, 8, 10, 12, 16, 20, 26, 30), title="angle fraction bits"),
    Sweep("k_set", tuple(K_SETS), title="k-set (cos^k tables)"),
    Sweep("alpha", ("taylor", "inflection"), title="alpha mode (how a is chosen)"),
    Sweep("recip_bits", (10, 12, 14, 16, 18, 20), title="divider reciprocal bits N"),
    Sweep("p", (2, 4, 8, 16), title="Gouraud segment size P"),
    Sweep("specular_mode", ("unit", "adaptive", "vertex"), title="specular path"),
    Sweep(
        "highlight_levels",
        (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0),
        base=(("specular_mode", "adaptive"),),
        title="adaptive highlight threshold (levels)",
    ),
    Sweep("diffuse_mode", ("gouraud", "unit", "adaptive"), title="diffuse path"),
    Sweep("brdf", BRDF_CHOICES, title="BRDF family (the highlight's unit)"),
)
"""One knob at a time around the default (each knob's effect isolated); the named alternatives
(the prototype's cos^2, a single cos^16, {1, 2, 16}, inflection, Gouraud only, adaptive, the
diffuse term through the specular unit) are values of these sweeps."""

NAMED: dict[str, dict[str, object]] = {
    "free": {"alpha": "inflection", "specular_mode": "adaptive"},
    "scene-sized": {
        "alpha": "inflection",
        "specular_mode": "adaptive",
        "rom_addr_bits": 10,
        "rom_data_bits": 12,
        "recip_bits": 14,
    },
}
"""Knob combinations: the two changes that cost nothing ("free"), and a unit sized for what the
built-in scenes need rather than for the worst case (2047-pixel lines, every n)."""

FULL_PRODUCT: dict[str, tuple] = {
    "rom_addr_bits": (8, 10, 12),
    "rom_data_bits": (10, 12, 16),
    "z_frac_bits": (18, 22, 26),
    "k_set": tuple(K_SETS),
    "alpha": ("taylor", "inflection"),
    "recip_bits": (14, 20),
}
"""The full grid adds this cross product (432 configurations: interactions of the knobs)."""
FULL_BRDF_PRODUCT: dict[str, tuple] = {
    "brdf": brdf.RTL_FORMS,
    "z_frac_bits": (18, 22, 26),
    "recip_bits": (14, 20),
}
"""And this one: each BRDF form with the knobs of the product that reach it (``BRDF_KNOBS``;
6 configurations per form)."""

GRIDS = ("small", "full")


def grid_configs(grid: str = "small") -> list[dict[str, object]]:
    """Knob overrides of every configuration of the grid, in order, without repeats."""
    scene.check_choice("grid", grid, GRIDS)
    configs = [{}] + [c for s in SMALL_SWEEPS for c in s.configs()] + list(NAMED.values())
    if grid == "full":
        for product in (FULL_PRODUCT, FULL_BRDF_PRODUCT):
            names = list(product)
            configs += [
                dict(zip(names, vals, strict=True)) for vals in itertools.product(*product.values())
            ]
    seen: set[str] = set()
    unique = []
    for c in configs:
        key = DEFAULT_POINT.with_knobs(**c).config_key
        if key not in seen:
            seen.add(key)
            unique.append(c)
    return unique


def grid_points(
    grid: str = "small", scenes: Sequence[str] = scenefile.SCENE_NAMES, size: int = DEFAULT_SIZE
) -> list[TradePoint]:
    """Every (configuration, scene) of the grid; each configuration is validated here."""
    points = []
    for c in grid_configs(grid):
        for s in scenes:
            p = TradePoint(scene=s, size=size, **c)
            p.to_pipeline_config()  # a bad configuration fails before anything is submitted
            points.append(p)
    return points


def point_scene(
    point: TradePoint, sources: Mapping[str, scenefile.SceneSource] | None = None
) -> scene.Scene:
    """The scene the point names, at its size: a built-in scene, or ``sources[point.scene]``
    (a scene file, or a mesh file framed by ``meshes.scene_from_mesh`` with its defaults).

    The files must still be the ones the key names: one edited since (another sha1) is refused
    with ``ValueError``, so that no result is cached under the key of other content."""
    if not FILE_KEY.fullmatch(point.scene):
        return scenefile.builtin_scene(point.scene, point.size, point.size)
    source = (sources or {}).get(point.scene)
    if source is None:
        raise ValueError(
            f"scene = {point.scene!r} names a file and no file was given for it: legal is "
            "sources = {key: SceneSource} (trade.main makes it from its scenes and meshes)"
        )
    try:
        key = source.key()
    except OSError as exc:
        raise ValueError(f"file '{exc.filename}' cannot be read: {exc.strerror or exc}") from None
    if key != point.scene:
        raise ValueError(
            f"{source.kind} file '{source.ref}' is now {key!r}, not {point.scene!r}: it changed "
            "after the sweep started"
        )
    return source.scene(point.size, point.size)
