# SPDX-License-Identifier: Apache-2.0
"""Scenes through the units: meshes and scenes, the float rasteriser, the float reference
shaders and the pipeline that runs a scene's spans through the bit-exact units.

May import ``model.units`` (public names only), numpy, numba, trimesh; never ``model.study``,
``model.cli`` or ``sim``.
"""
