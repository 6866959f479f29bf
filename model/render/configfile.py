# SPDX-License-Identifier: Apache-2.0
"""Pipeline configuration files (TOML): the three units' configurations and the shading modes.

Owns ``write_config`` (a ``PipelineConfig`` to a file), ``read_config`` (a file to a
``PipelineConfig``) and ``config_dict`` (the plain dictionary both go through).  ``shading fit``
writes such a file into its bundle; ``shading demo --config FILE`` and ``read_config`` read it.
May import the standard library's ``tomllib`` (``tomli`` before Python 3.11), ``tomli_w``,
``model.render.pipeline`` and ``model.units.brdf``.

The file has one table per unit plus ``[pipeline]`` for the modes; every field may be left out
(it then takes the default of ``PipelineConfig`` and the unit configurations), every field given
is checked: an unknown table or field, a value of the wrong type, or a value the configuration
refuses raises ``ValueError`` naming the file, the field, the value and what is allowed::

    [pipeline]
    specular_mode = "unit"          # "unit" | "vertex" | "adaptive"

    [divider]
    recip_bits = 14

    [gouraud]
    p = 2
    i_frac = 9

    [specular]
    k_ranges = [[1, 1000, 16]]      # (n_lo, n_hi, k) covering n = 1..1000
    rom_addr_bits = 9

An optional ``[brdf]`` table (``form = "quadratic"``, widths) puts a BRDF family unit in place
of the specular unit for the highlight (``PipelineConfig.brdf``); its angle formats are the
``[specular]`` table's.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import tomli_w

from model.render.pipeline import PipelineConfig
from model.units.brdf import FixedConfig

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

UNIT_TABLES = ("divider", "gouraud", "specular")
"""The tables holding a unit configuration (the ``PipelineConfig`` fields of those names)."""
BRDF_TABLE = "brdf"
"""The optional table of ``PipelineConfig.brdf`` (a BRDF family unit for the highlight): its
``FixedConfig`` fields but ``angle``, which is the file's specular configuration."""
TABLES = ("pipeline", *UNIT_TABLES, BRDF_TABLE)
NOT_FIELDS = (*UNIT_TABLES, BRDF_TABLE, "angle")
"""Fields no table sets directly: tables of their own, or (``angle``) taken from another."""
HEADER = "# Shading pipeline configuration (model.render.configfile; docs/fit.md)\n"


def _plain(value: object) -> object:
    """Tuples (k_ranges) as lists, the way TOML holds them."""
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    return value


def config_dict(cfg: PipelineConfig) -> dict[str, dict[str, object]]:
    """``cfg`` as ``{table: {field: value}}``, every field written out (TOML types only)."""
    out: dict[str, dict[str, object]] = {"pipeline": {}}
    for f in dataclasses.fields(cfg):
        value = getattr(cfg, f.name)
        if f.name in UNIT_TABLES:
            out[f.name] = {
                g.name: _plain(getattr(value, g.name)) for g in dataclasses.fields(value)
            }
        elif f.name == BRDF_TABLE:
            if value is not None:
                out[f.name] = {
                    g.name: _plain(getattr(value, g.name))
                    for g in dataclasses.fields(value)
                    if g.name not in NOT_FIELDS
                }
        else:
            out["pipeline"][f.name] = _plain(value)
    return out


def write_config(cfg: PipelineConfig, path: str | Path) -> Path:
    """Write ``cfg`` to ``path`` (every field, so the file says everything the model uses)."""
    path = Path(path)
    path.write_text(HEADER + tomli_w.dumps(config_dict(cfg)))
    return path


def _legal_type(default: object, value: object) -> bool:
    if isinstance(default, bool) or isinstance(value, bool):
        return isinstance(default, bool) and isinstance(value, bool)
    if isinstance(default, float):
        return isinstance(value, int | float)
    if isinstance(default, int):
        return isinstance(value, int)
    if isinstance(default, tuple):
        return isinstance(value, list)
    return isinstance(value, type(default))


def _type_name(default: object) -> str:
    if isinstance(default, tuple):
        return "a list"
    return {bool: "true or false", int: "an integer", float: "a number", str: "a string"}.get(
        type(default), type(default).__name__
    )


def _build(path: Path, table: str, cls: type, given: object, extra: dict | None = None) -> object:
    """An instance of ``cls`` (a frozen dataclass) from the file's table ``table`` (and the
    fields ``extra`` gives)."""
    if not isinstance(given, dict):
        raise ValueError(f"{path}: {table} = {given!r} is not legal: legal is a table")
    defaults = cls()
    names = [f.name for f in dataclasses.fields(cls) if f.name not in NOT_FIELDS]
    kwargs: dict[str, object] = {}
    for key, value in given.items():
        if key not in names:
            raise ValueError(
                f"{path}: {table}.{key} is not a field here: legal fields are {', '.join(names)}"
            )
        default = getattr(defaults, key)
        if not _legal_type(default, value):
            raise ValueError(
                f"{path}: {table}.{key} = {value!r} is not legal: legal is {_type_name(default)}"
            )
        kwargs[key] = float(value) if isinstance(default, float) else value
    if cls is PipelineConfig:
        return kwargs
    return _construct(path, table, cls, {**kwargs, **(extra or {})})


def _construct(path: Path, table: str, cls: type, kwargs: dict[str, object]) -> object:
    try:
        return cls(**kwargs)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"{path}: [{table}] {exc}") from None


def read_config(path: str | Path) -> PipelineConfig:
    """The ``PipelineConfig`` a configuration file describes (fields left out: the defaults)."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"path = '{path}' does not exist: legal value is an existing .toml file")
    try:
        with path.open("rb") as fh:
            doc = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot be read: {exc}") from None
    for key in doc:
        if key not in TABLES:
            raise ValueError(
                f"{path}: {key} is not a table here: legal tables are {', '.join(TABLES)}"
            )
    kwargs = _build(path, "pipeline", PipelineConfig, doc.get("pipeline", {}))
    assert isinstance(kwargs, dict)
    units = {f.name: f.default for f in dataclasses.fields(PipelineConfig) if f.name in UNIT_TABLES}
    for table in UNIT_TABLES:
        if table in doc:
            kwargs[table] = _build(path, table, type(units[table]), doc[table])
    if BRDF_TABLE in doc:
        angle = {"angle": kwargs.get("specular", units["specular"])}
        kwargs[BRDF_TABLE] = _build(path, BRDF_TABLE, FixedConfig, doc[BRDF_TABLE], angle)
    return _construct(path, "pipeline", PipelineConfig, kwargs)
