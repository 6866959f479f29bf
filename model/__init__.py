# SPDX-License-Identifier: Apache-2.0
"""Bit-exact golden models of three shading units, the renderer above them and the studies.

Packages, arrows pointing down only (``tests/test_layers.py`` checks them):

* ``model.units``  — the golden model proper (numpy + numba): fixed-point helpers, ROM images,
  the divider, the Gouraud unit, the specular unit; imports nothing else of the project;
* ``model.render`` — scenes and meshes, the float rasteriser, float reference shaders and the
  pipeline that pushes a scene's spans through the units; imports ``units``;
* ``model.study``  — metrics, images, reports, accuracy figures, the trade study; imports
  ``render`` and ``units``;
* ``model.hw``     — synthesis, place and route, formal proofs of the RTL; imports ``units``;
* ``model.fit``    — fitting the units to a scene (``shading fit``): analysis, knob search,
  synthesised cost, the bundle; imports ``study``, ``hw``, ``render`` and ``units``;
* ``model.cli``    — the command line on top (``python -m model``, ``shading``).

``from model import divider, gouraud, specular`` and ``from model.specular import ...`` keep
working: the three units are re-exported here and aliased under their old module names.
"""

from __future__ import annotations

import sys

from model.units import divider, gouraud, specular

__all__ = ["divider", "gouraud", "specular"]

for _name, _module in (("divider", divider), ("gouraud", gouraud), ("specular", specular)):
    sys.modules.setdefault(f"{__name__}.{_name}", _module)
