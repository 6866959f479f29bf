# SPDX-License-Identifier: Apache-2.0
"""The golden model proper: every unit's bit-exact arithmetic, its configuration and its ROMs.

Owns ``fixed`` (named rounding and saturation steps, operand checks), ``rom`` (the ``$readmemh``
image format and its checks), ``batch`` (``LineBatch``, the result of the batched calls),
``divider``, and the packages ``gouraud`` and ``specular`` (each a few modules behind an
``__init__`` that re-exports the unit's public names).  May import numpy, numba and the
standard library only — nothing else of the project; the RTL's ROM folder is reached as package
data (``model.rtl``).  Public calls only cross this package's border: per line (``divide``,
``shade_line``, ``setup_line``) and batched (``divide_many``, ``shade_lines``, ``setup_lines``).
"""
