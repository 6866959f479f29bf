# SPDX-License-Identifier: Apache-2.0
"""A unit configuration -> the Verilog parameters of its RTL (docs/architecture.md).

Shared by simulation (``sim.runner`` re-exports both calls) and synthesis (``model.hw.synth``):
the parameters are the configuration's fields in UPPER_CASE, the ROM images absolute paths.
"""

from __future__ import annotations

from dataclasses import asdict, is_dataclass
from pathlib import Path

from model.units import brdf, divider


def hdl_parameters(config: object, **extra: object) -> dict[str, object]:
    """Verilog parameters of a unit: its config fields in UPPER_CASE, plus ``extra``
    (docs/architecture.md).

    Only int and bool fields become parameters; ``extra`` adds e.g. ``ROM_FILE``.  A config
    whose parameters are not just its fields (the specular unit's k-set, ROM files) says so
    with its own ``hdl_parameters()`` method, which is used instead; the BRDF unit's
    (``model.units.brdf.FixedConfig``: its form as text) comes from
    ``model.units.brdf.hdl_parameters``.
    """
    if isinstance(config, brdf.FixedConfig):
        params = brdf.hdl_parameters(config)
    elif hasattr(config, "hdl_parameters"):
        params = dict(config.hdl_parameters())
    else:
        fields = asdict(config) if is_dataclass(config) else dict(config)
        params = {k.upper(): int(v) for k, v in fields.items() if isinstance(v, int | bool)}
    params.update({k: (str(v) if isinstance(v, Path) else v) for k, v in extra.items()})
    return params


def unit_parameters(config: object) -> dict[str, object]:
    """The Verilog parameters of the unit built for ``config``, ROM images included (the BRDF
    unit's from ``model.units.brdf.hdl_parameters``, as ``hdl_parameters`` gives them: its form,
    widths and table images)."""
    if isinstance(config, divider.DividerConfig):
        return hdl_parameters(config, ROM_FILE=divider.rom_path(config))
    return hdl_parameters(config)
