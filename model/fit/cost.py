# SPDX-License-Identifier: Apache-2.0
"""What a pipeline design costs on a part: the shading core at its parameters, placed and routed.

Owns ``units_used`` (the units whose datapaths the design's core builds), ``design_files`` (the
bundle's design as files: ``shading_fit_top.v``, the core's RTL under ``rtl/``, the ROM images
under ``rom/``, the ``.f`` list, the Verilator waiver), ``synth_parameters`` (the core's
parameters with every ROM image on disk) and ``design_cost`` (the core through
``model.hw.synthesise_top``, the flow of ``make synth``, cached).  A design is one shading
core (``rtl/shading_core.f``) at the configuration's widths, its highlight and diffuse paths as
the configuration's modes use them;
the figures count every cell under it (LUT, FF, BRAM, DSP), whether it fits the part, and its
Fmax.  The range guard of ``shading_fit_top`` (a comparison or two on the span beat and one
flip-flop) is not in the placed figures.  May import ``model.hw``, ``model.study.trade`` (which
units a configuration uses), ``model.render`` and ``model.fit.verilog``.
"""

from __future__ import annotations

from pathlib import Path

from model.fit import verilog
from model.hw import synth
from model.hw.parts import part as get_part
from model.render import pipeline
from model.study.trade import unit_configs

DEFAULT_DESIGN = pipeline.METHODS["diffuse"]
"""The default design: the core at its default widths with both paths (the highlight and the
diffuse term through the specular unit), as ``make synth`` places it (``sim.synth_tops``'s
``default``): it serves every scene and method."""
DEFAULT_NAME = "default"
FIT_NAME = "fit"
_FIELD = {
    "divider_shift": "divider",
    "gouraud_segment": "gouraud",
    "specular_unit": "specular",
    "brdf_unit": "brdf",
}


def units_used(cfg: pipeline.PipelineConfig) -> tuple[str, ...]:
    """The units (``PipelineConfig`` field names) whose datapaths the core builds at ``cfg``:
    the trade study's ``unit_configs``, named by field."""
    return tuple(_FIELD[module] for module, _ in unit_configs(cfg))


def design_files(cfg: pipeline.PipelineConfig, note: str = "") -> dict[str, bytes]:
    """{relative file name: bytes} of the bundle's design: its top level, ``rtl/*`` (the core's
    sources), ``rom/*``, ``shading_fit.f``."""
    files = {f"{verilog.TOP}.v": verilog.fit_top(cfg, note).encode()}
    rtl = []
    for path in verilog.core_sources():
        rtl.append(f"rtl/{path.name}")
        files[rtl[-1]] = path.read_bytes()
    for name, text in verilog.rom_images(cfg).items():
        files[f"rom/{name}"] = text.encode()
    files["shading_fit.f"] = verilog.source_list(rtl).encode()
    files[verilog.LINT_WAIVER] = verilog.lint_waiver().encode()
    return files


def synth_parameters(cfg: pipeline.PipelineConfig, rom_dir: Path | None = None) -> dict:
    """The core's Verilog parameters at ``cfg`` with every ROM image a file on disk (a fitted
    configuration's images are generated into ``rom_dir``, as ``model.hw.synth`` does per unit;
    the same parameters as ``sim.core_run.parameters``)."""
    params = dict(verilog.core_parameters(cfg))
    div = synth.synth_parameters("divider_shift", cfg.divider, rom_dir)
    spec = synth.synth_parameters("specular_unit", cfg.specular, rom_dir)
    params["RECIP_ROM_FILE"] = div["ROM_FILE"]
    params["A_ROM_FILE"], params["COS_ROM_FILE"] = spec["A_ROM_FILE"], spec["COS_ROM_FILE"]
    if cfg.brdf is not None:  # the BRDF highlight's tables
        own = synth.synth_parameters("brdf_unit", cfg.brdf, rom_dir)
        for name in verilog.BRDF_ROM_PARAMS.values():
            if name in params:
                params[name] = own[name]
    return params


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
    cfg: pipeline.PipelineConfig, part: str, *, name: str = FIT_NAME, seed: int = 1
) -> synth.SynthResult:
    """The core at ``cfg`` synthesised, placed and routed on ``part`` (``synthesise_top``
    under the configuration name ``name``)."""
    return synth.synthesise_top(verilog.CORE, synth_parameters(cfg), part, config=name, seed=seed)


def default_cost(part: str, *, seed: int = 1) -> synth.SynthResult:
    """The default design (``DEFAULT_DESIGN``) on ``part``, as ``make synth`` places it."""
    return design_cost(DEFAULT_DESIGN, part, name=DEFAULT_NAME, seed=seed)
