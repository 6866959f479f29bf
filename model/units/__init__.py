"""The golden model proper: every unit's bit-exact arithmetic, its configuration and its ROMs.

Owns ``fixed`` (named rounding and saturation steps, operand checks), ``rom`` (the ``$readmemh``
image format and its checks), ``divider``, ``gouraud`` and ``specular``.  May import numpy,
numba and the standard library only — nothing else of the project; the RTL's ROM folder is
reached as package data (``model.rtl``).  Public calls only cross this package's border.
"""
