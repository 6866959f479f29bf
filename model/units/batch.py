# SPDX-License-Identifier: Apache-2.0
"""Batched unit calls: their result ``LineBatch`` and the placement checks they share.

``gouraud.shade_lines`` and ``specular.shade_lines`` run many lines through a unit in one call
(the renderer's path) and return a ``LineBatch``; ``divider.divide_many`` returns quotients and
cycles.  This module owns the result type and ``place_lines``: where each line's pixels go,
either a fresh packed array or the caller's ``out`` at rows ``at`` (checked, since the numba
kernels write without bounds checks).  May import numpy and ``model.units.fixed`` only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from model.units import fixed


@dataclass(frozen=True)
class LineBatch:
    """The results of L lines, in input order.

    ``pixels``: every line's pixels one after the other, (P,) or (P, C) int64 with P the total
    (or, when the call was given ``out`` and ``at``, that ``out`` array: line j then sits at
    rows ``at[j] : at[j] + counts[j]``).  ``offsets``: (L + 1,) where each line starts in the
    packed layout, ``offsets[0] = 0``, ``offsets[L] = P``; ``counts`` = their differences.
    ``cycles``: (L,) the cycles ``busy`` is high for each line, as the unit's ``cycles`` call
    gives them (a new start is accepted one cycle later).
    """

    pixels: np.ndarray
    offsets: np.ndarray
    cycles: np.ndarray

    def __len__(self) -> int:
        return int(self.cycles.size)

    @property
    def counts(self) -> np.ndarray:
        """(L,) pixels per line."""
        return np.diff(self.offsets)

    def line(self, j: int) -> np.ndarray:
        """The pixels of line j in the packed layout (a batch made without ``out``)."""
        return self.pixels[self.offsets[j] : self.offsets[j + 1]]


def check_rows(operands: dict[str, object], channels: tuple[str, ...] = ()) -> int:
    """The common row count L of the batched operands, or ``ValueError`` naming the shapes.

    Every operand must be an (L,) array; those named in ``channels`` may instead be (L, C),
    all with the same C.  Returns L (the values are checked by the caller, operand by operand).
    """
    shapes = {name: np.shape(value) for name, value in operands.items()}
    ok = all(len(s) == 1 or (len(s) == 2 and name in channels) for name, s in shapes.items())
    ok = ok and len({s[0] for s in shapes.values() if s}) == 1
    ok = ok and len({shapes[name] for name in channels}) <= 1
    if not ok:
        legal = "(L,) arrays of one length"
        if channels:
            legal += f" ({', '.join(channels)} may be (L, C), alike)"
        got = ", ".join(f"{name} {shape}" for name, shape in shapes.items())
        raise ValueError(f"operand shapes are out of range: got {got}; legal are {legal}")
    return int(next(iter(shapes.values()))[0])


def place_lines(
    counts: np.ndarray, out, at, channels: int | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(out, starts, offsets): where the kernels write line j (``out[starts[j]:][:counts[j]]``).

    Without ``out`` and ``at``: a new packed (P,) or (P, ``channels``) int64 array, starts =
    offsets[:-1].  With both: the caller's ``out`` (int64, (N,) or (N, channels), writeable),
    every line inside it; anything else raises ``ValueError``.
    """
    counts = np.asarray(counts, dtype=np.int64)
    offsets = np.zeros(counts.size + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    shape = (int(offsets[-1]),) if channels is None else (int(offsets[-1]), channels)
    if out is None and at is None:
        return np.empty(shape, dtype=np.int64), offsets[:-1], offsets
    if out is None or at is None:
        raise ValueError("out and at go together: give both or neither")
    want = "(N,)" if channels is None else f"(N, {channels})"
    if (
        not isinstance(out, np.ndarray)
        or out.dtype != np.int64
        or out.ndim != len(shape)
        or out.shape[1:] != shape[1:]
        or not out.flags.writeable
    ):
        got = f"{type(out).__name__} {getattr(out, 'dtype', '')} {np.shape(out)}".strip()
        raise ValueError(f"out is out of range: got {got}; legal is a writeable int64 {want} array")
    size = out.shape[0]
    if np.ndim(at) != 1 or np.shape(at)[0] != counts.size:
        raise ValueError(
            f"at is out of range: got shape {np.shape(at)}; legal is ({counts.size},), one row "
            "per line"
        )
    starts = fixed.check_operand("at", at, 0, size, rows=True)
    past = starts + counts > size
    if past.any():
        j = int(np.argmax(past))
        raise ValueError(
            f"at[{j}] = {int(starts[j])} is out of range: line {j} has {int(counts[j])} pixels "
            f"and out {size} rows, legal range is 0..{size - int(counts[j])}"
        )
    return out, starts, offsets
