# SPDX-License-Identifier: Apache-2.0
"""The tops beside the units that ``make synth`` places and routes (``scripts/synth.py``), each
with its named configurations: the streaming shading core (``rtl/shading_core.f``) at pipeline
configurations of ``model.render.pipeline.METHODS`` and ``BRDF_METHODS``.

``model.hw`` sits beside ``model.render`` and cannot import it, so a top's Verilog parameters
are made here, one layer up, by ``sim.core_run.parameters`` (``core.core_parameters`` with every
ROM image on disk, as the core's benches build it) and handed to
``model.hw.synth.synthesise_top`` as a dict.  The core's Fmax targets are in
``model.hw.parts.TARGETS`` under the names used here.
"""

from __future__ import annotations

from pathlib import Path

from model.hw import SynthResult, synthesise_top
from sim import core_run

# top -> configuration name -> the METHODS or BRDF_METHODS entry it is built from (a name
# ``core_run.method_config`` takes).  "default": both the highlight and the diffuse path
# (METHODS["diffuse"]); "hybrid": the highlight path only; "brdf_<form>": the highlight path
# through that BRDF form (its pipe, rtl/shading_brdf_pipe.v), the two small forms.
TOPS: dict[str, dict[str, str]] = {
    "shading_core": {
        "default": "diffuse",
        "hybrid": "hybrid",
        "brdf_cosine_quadratic": "cosine_quadratic",
        "brdf_log2": "log2",
    },
}


def configs(top: str) -> dict[str, str]:
    """The named configurations of ``top``; ValueError naming the tops there are otherwise."""
    if top not in TOPS:
        raise ValueError(f"top {top!r} is unknown: known tops are {', '.join(TOPS)}")
    return TOPS[top]


def parameters(top: str, config: str = "default", rom_dir: Path | None = None) -> dict:
    """The Verilog parameters of ``top`` at ``config``, ROM images as paths of files on disk."""
    named = configs(top)
    if config not in named:
        raise ValueError(
            f"config {config!r} is unknown for {top}: named configurations are {', '.join(named)}"
        )
    return core_run.parameters(core_run.method_config(named[config]), rom_dir)


def synthesise(
    top: str, config: str = "default", part: str = "hx8k", *, seed: int = 1
) -> SynthResult:
    """``model.hw.synthesise_top`` of ``top`` at the named ``config`` on ``part``."""
    return synthesise_top(top, parameters(top, config), part, config=config, seed=seed)
