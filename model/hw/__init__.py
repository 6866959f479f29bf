# SPDX-License-Identifier: Apache-2.0
"""The units on real FPGA parts: synthesis, place and route, resources and Fmax (make synth).

``synthesise(unit, config, part)`` runs Yosys and nextpnr (the yowasp packages) on one unit
behind a six-pin wrapper and returns a ``SynthResult`` (``synthesise_design``: the same for a
design of several modules, such as the top level ``shading fit`` writes; ``synthesise_top``:
a top's ``.f`` source list at a parameter set, such as the shading core); ``parts`` names the
devices and the Fmax targets, ``params`` the Verilog parameters of a configuration (shared with
``sim``), ``parse`` reads the tools' output, ``report`` makes the table and the JSON record.
Layer 2: imports ``model.units`` only.
"""

from model.hw.params import hdl_parameters, unit_parameters
from model.hw.parts import PARTS, TARGETS, Part
from model.hw.synth import (
    UNITS,
    SynthError,
    SynthResult,
    config_named,
    default_runs,
    synthesise,
    synthesise_design,
    synthesise_top,
)

__all__ = [
    "PARTS",
    "TARGETS",
    "UNITS",
    "Part",
    "SynthError",
    "SynthResult",
    "config_named",
    "default_runs",
    "hdl_parameters",
    "synthesise",
    "synthesise_design",
    "synthesise_top",
    "unit_parameters",
]
