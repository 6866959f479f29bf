# SPDX-License-Identifier: Apache-2.0
"""Colour tables for the pictures, stored so that drawing them needs no matplotlib.

``INFERNO``: matplotlib's "inferno" colour map as 256 RGB rows, ``(cmap(i)[:3] * 255)``
truncated to uint8 for i = 0..255 (what ``Colormap(..., bytes=True)`` gives), the colour of the
error heat-maps; ``TAB10``: matplotlib's "tab10" cycle, the curves of the error chart.
``python -m model.study.palette`` recomputes both from the installed matplotlib and rewrites
this file; ``tests/test_pictures.py`` checks that the stored tables equal matplotlib's.
May import numpy (matplotlib only in ``from_matplotlib``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

# fmt: off
_INFERNO_HEX = (
    "00000300000400000601000701010901010b02010e02021003021204031404031605041806041b07051d08061f090621"
    "0a07230b07260d08280e082a0f092d10092f120a32130a34140b36160b39170b3b190b3e1a0b401c0c431d0c451f0c47"
    "200c4a220b4c240b4e260b50270b52290b542b0a562d0a582e0a5a300a5c32095d34095f3509603709613909623b0964"
    "3c09653e0966400966410967430a68450a69460a69480b6a4a0b6a4b0c6b4d0c6b4f0d6c500d6c520e6c530e6d550f6d"
    "570f6d58106d5a116d5b116e5d126e5f126e60136e62146e63146e65156e66156e68166e6a176e6b176e6d186e6e186e"
    "70196e72196d731a6d751b6d761b6d781c6d7a1c6d7b1d6c7d1d6c7e1e6c801f6b811f6b83206b85206a86216a88216a"
    "8922698b22698d23698e24689024689125679325679526669626669827659928649b28649c29639e2963a02a62a12b61"
    "a32b61a42c60a62c5fa72d5fa92e5eab2e5dac2f5cae305baf315bb1315ab23259b43358b53357b73456b83556ba3655"
    "bb3754bd3753be3852bf3951c13a50c23b4fc43c4ec53d4dc73e4cc83e4bc93f4acb4049cc4148cd4247cf4446d04544"
    "d14643d24742d44841d54940d64a3fd74b3ed94d3dda4e3bdb4f3adc5039dd5238de5337df5436e05634e25733e35832"
    "e45a31e55b30e65c2ee65e2de75f2ce8612be9622aea6428eb6527ec6726ed6825ed6a23ee6c22ef6d21f06f1ff0701e"
    "f1721df2741cf2751af37719f37918f47a16f57c15f57e14f68012f68111f78310f7850ef8870df8880cf88a0bf98c09"
    "f98e08f99008fa9107fa9306fa9506fa9706fb9906fb9b06fb9d06fb9e07fba007fba208fba40afba60bfba80dfbaa0e"
    "fbac10fbae12fbb014fbb116fbb318fbb51afbb71cfbb91efabb21fabd23fabf25fac128f9c32af9c52cf9c72ff8c931"
    "f8cb34f8cd37f7cf3af7d13cf6d33ff6d542f5d745f5d948f4db4bf4dc4ff3de52f3e056f3e259f2e45df2e660f1e864"
    "f1e968f1eb6cf1ed70f1ee74f1f079f1f27df2f381f2f485f3f689f4f78df5f891f6fa95f7fb99f9fc9dfafda0fcfea4"
)
TAB10: tuple[tuple[int, int, int], ...] = (
    (31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
    (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207),
)
# fmt: on

INFERNO: np.ndarray = np.frombuffer(bytes.fromhex("".join(_INFERNO_HEX)), np.uint8).reshape(256, 3)
INFERNO.flags.writeable = False


def from_matplotlib(name: str) -> np.ndarray:
    """(256, 3) uint8: matplotlib's colour map ``name`` as ``INFERNO`` is stored (imports
    matplotlib: for a map other than the stored ones, and for the check)."""
    from matplotlib import colormaps

    cmap = colormaps[name].resampled(256)
    return (cmap(np.arange(256))[:, :3] * 255).astype(np.uint8)


def tab10_from_matplotlib() -> tuple[tuple[int, int, int], ...]:
    from matplotlib import colormaps

    return tuple(tuple(round(255 * c) for c in rgb[:3]) for rgb in colormaps["tab10"].colors)


def table(name: str) -> np.ndarray:
    """The (256, 3) uint8 table of colour map ``name``: stored for "inferno", else matplotlib's."""
    return INFERNO if name == "inferno" else from_matplotlib(name)


def main() -> int:
    """Rewrite the stored tables of this file from the installed matplotlib."""
    path = Path(__file__)
    text = path.read_text()
    hexed = from_matplotlib("inferno").tobytes().hex()
    rows = "".join(f'    "{hexed[i : i + 96]}"\n' for i in range(0, len(hexed), 96))
    head, rest = text.split("_INFERNO_HEX = (\n", 1)
    rest = rest.split(")\nTAB10", 1)[1]
    tab = tab10_from_matplotlib()
    rows_tab = "".join(
        f"    {', '.join(map(str, tab[i : i + 5]))},\n".replace("), (", "), (")
        for i in range(0, 10, 5)
    )
    rest = rest.split("(\n", 1)[0] + "(\n" + rows_tab + ")\n" + rest.split("\n)\n", 1)[1]
    path.write_text(f"{head}_INFERNO_HEX = (\n{rows})\nTAB10{rest}")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":  # python -m model.study.palette
    sys.exit(main())
