# SPDX-License-Identifier: Apache-2.0
"""What a pipeline design costs on a part: its top level synthesised, placed and routed.

Owns ``units_used`` (the units a design instantiates), ``design_files`` (the design as files:
``shading_fit_top.v``, the units' RTL, the ROM images) and ``design_cost`` (those files through
``model.hw.synthesise_design``, the flow of ``make synth``, cached).  A design is one divider, one
Gouraud unit (time-shared by the three colour channels) and, where its shading modes use it, one
specular unit, behind the range guard of ``model.fit.verilog``; the figures count every cell of
it (LUT, FF, BRAM, DSP), whether it fits the part, and its Fmax.  May import ``model.hw``,
``model.study.trade`` (which units a configuration uses),
``model.render`` and ``model.fit.verilog``.
"""

from __future__ import annotations

from model.fit import verilog
from model.hw import synth
from model.hw.parts import part as get_part
from model.render import pipeline
from model.study.trade import unit_configs


def units_used(cfg: pipeline.PipelineConfig) -> tuple[str, ...]:
    """The units (``PipelineConfig`` field names) the design instantiates: the trade study's
    ``unit_configs``, named by field."""
    field = {module: name for name, module in verilog.MODULE.items()}
    return tuple(field[module] for module, _ in unit_configs(cfg))


def design_files(cfg: pipeline.PipelineConfig, note: str = "") -> dict[str, bytes]:
    """{relative file name: bytes} of the design: its top level, the units' RTL, ``rom/*``."""
    units = units_used(cfg)
    files = {f"{verilog.TOP}.v": verilog.fit_top(cfg, units, note).encode()}
    for unit in units:
        name = f"{verilog.MODULE[unit]}.v"
        files[name] = (verilog.RTL_DIR / name).read_bytes()
    for name, text in verilog.rom_images(cfg, units).items():
        files[f"rom/{name}"] = text.encode()
    return files


def part_share(result: synth.SynthResult, part: str) -> float:
    """How much of ``part`` the design takes: the sum over LUT, FF, BRAM and DSP of used /
    available (a design that does not fit counts as infinitely dear).  The fit keeps the
    candidate with the smallest share."""
    if not result.fits:
        return float("inf")
    cap = get_part(part).capacity()
    used = {"LUT": result.lut, "FF": result.ff, "BRAM": result.bram, "DSP": result.dsp}
    return sum(used[k] / cap[k] for k in used if cap[k] > 0)


def design_cost(
    cfg: pipeline.PipelineConfig, part: str, note: str = "", *, seed: int = 1
) -> synth.SynthResult:
    """The whole design (``design_files``) synthesised, placed and routed on ``part``."""
    return synth.synthesise_design(verilog.TOP, design_files(cfg, note), part, seed=seed)
