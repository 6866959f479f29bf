# SPDX-License-Identifier: Apache-2.0
"""What the units cost and buy: image metrics, pictures, scene reports, the accuracy figures
(``python -m model accuracy``) and the speed/accuracy trade study (Dask).

May import ``model.render`` and ``model.units`` (public names only); never ``model.cli`` or
``sim``.
"""
