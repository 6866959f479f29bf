# SPDX-License-Identifier: Apache-2.0
"""Shared fixed-point helpers: ranges, operand checks, rounding, saturation, bit patterns.

Every unit states its formats as ``Qm.f`` (m integer bits, f fraction bits, signed or not) and
stores values as plain integers in units of 2**-f.  The helpers here are the only place where
a range is computed, an operand is checked or a value is rounded, so the three units (and the
RTL benches, which need two's-complement bit patterns) agree on every step.

The ``*_shift`` and ``saturate`` kernels are numba ``@njit`` functions so the units' kernels can
call them; they also run un-jitted under ``NUMBA_DISABLE_JIT=1``.
"""

from __future__ import annotations

from dataclasses import dataclass
from decimal import ROUND_CEILING, Decimal

import numpy as np
from numba import njit

# Largest width the int64 kernels handle without overflow in intermediate products.
MAX_KERNEL_WIDTH = 62


@dataclass(frozen=True)
class QFormat:
    """A fixed-point format: ``int_bits`` integer bits, ``frac_bits`` fraction bits.

    For a signed format ``int_bits`` includes the sign bit, so Q1.15 signed spans [-1, 1).
    """

    int_bits: int
    frac_bits: int
    signed: bool

    @property
    def width(self) -> int:
        return self.int_bits + self.frac_bits

    @property
    def lo(self) -> int:
        """Smallest raw integer value."""
        return signed_range(self.width)[0] if self.signed else 0

    @property
    def hi(self) -> int:
        """Largest raw integer value."""
        return signed_range(self.width)[1] if self.signed else unsigned_range(self.width)[1]

    def describe(self) -> str:
        return f"{'signed' if self.signed else 'unsigned'} Q{self.int_bits}.{self.frac_bits}"

    def quantise(self, x: float | np.ndarray) -> int | np.ndarray:
        """Round a real value to the nearest raw integer (half away from zero), saturated."""
        raw = np.sign(x) * np.floor(
            np.abs(np.asarray(x, dtype=np.float64)) * 2.0**self.frac_bits + 0.5
        )
        raw = np.clip(raw, self.lo, self.hi).astype(np.int64)
        return int(raw) if raw.ndim == 0 else raw

    def to_float(self, raw: int | np.ndarray) -> float | np.ndarray:
        return np.asarray(raw, dtype=np.float64) / 2.0**self.frac_bits


def signed_range(width: int) -> tuple[int, int]:
    """(min, max) of a two's-complement integer of ``width`` bits."""
    return -(1 << (width - 1)), (1 << (width - 1)) - 1


def unsigned_range(width: int) -> tuple[int, int]:
    """(min, max) of an unsigned integer of ``width`` bits."""
    return 0, (1 << width) - 1


def check_width(name: str, width: int, lo: int, hi: int) -> None:
    """Raise ``ValueError`` unless the configuration width ``name`` lies in [lo, hi]."""
    if not isinstance(width, int | np.integer) or not lo <= width <= hi:
        raise ValueError(f"{name} = {width!r} is out of range: legal widths are {lo}..{hi}")


def check_operand(
    name: str, value: int | np.ndarray, lo: int, hi: int, *, rows: bool = False
) -> np.ndarray:
    """Return ``value`` as an int64 array, or raise ``ValueError`` naming the first bad element.

    Non-integer input is refused rather than truncated: nothing is lost silently.  With
    ``rows`` (the batched calls) the message also names the bad element's index, ``c[3] = ...``
    or ``i0[3, 1] = ...``; otherwise it is word for word the per-line call's.
    """
    arr = np.asarray(value)
    if arr.dtype == object and arr.size and all(_is_int(x) for x in arr.flat):
        # Python ints beyond int64 (2**70): numpy keeps them as objects; compare them exactly.
        outside = np.array([not lo <= int(x) <= hi for x in arr.flat]).reshape(arr.shape)
        if outside.any():
            label, first = _first(name, arr, outside, rows)
            raise ValueError(f"{label} = {int(first)} is out of range: legal range is {lo}..{hi}")
        arr = arr.astype(np.int64)
    if arr.dtype.kind not in "iu":
        if arr.dtype.kind == "f" and np.all(np.isfinite(arr)) and np.all(arr == np.floor(arr)):
            outside = (arr < lo) | (arr > hi)  # before the cast: 1e30 would wrap in int64
            if outside.any():
                label, first = _first(name, arr, outside, rows)
                raise ValueError(
                    f"{label} = {float(first):g} is out of range: legal range is {lo}..{hi}"
                )
            arr = arr.astype(np.int64)
        else:
            if not rows or arr.ndim == 0:
                raise ValueError(
                    f"{name} must be an integer, got {value!r}: legal range is {lo}..{hi}"
                )
            label, first = _first(name, arr, _not_integer(arr), rows)
            raise ValueError(
                f"{label} must be an integer, got {first!r}: legal range is {lo}..{hi}"
            )
    if arr.dtype.kind == "u" and arr.size and arr.max() > np.iinfo(np.int64).max:
        label, first = _first(name, arr, arr > np.iinfo(np.int64).max, rows)
        first = first if rows else arr.max()
        raise ValueError(f"{label} = {int(first)} is out of range: legal range is {lo}..{hi}")
    arr = arr.astype(np.int64)
    bad = (arr < lo) | (arr > hi)
    if bad.any():
        label, first = _first(name, arr, bad, rows)
        raise ValueError(f"{label} = {int(first)} is out of range: legal range is {lo}..{hi}")
    return arr


def _first(name: str, arr: np.ndarray, bad: np.ndarray, rows: bool) -> tuple[str, object]:
    """(``name`` or ``name[i, ...]``, the value) of the first element ``bad`` marks."""
    index = tuple(int(i) for i in np.argwhere(bad)[0])
    first = arr[index]
    first = first.item() if isinstance(first, np.generic) else first
    if not rows or not index:
        return name, first
    return f"{name}[{', '.join(map(str, index))}]", first


def _not_integer(arr: np.ndarray) -> np.ndarray:
    """Which elements of a non-integer-typed array are not integers (floats with a fraction,
    infinities, NaN, booleans, objects that are not ints)."""
    if arr.dtype.kind == "f":
        finite = np.isfinite(arr)
        return ~finite | (np.where(finite, arr, 0.0) != np.floor(np.where(finite, arr, 0.0)))
    if arr.dtype == object:
        return np.array([not _is_int(x) for x in arr.flat], dtype=bool).reshape(arr.shape)
    return np.ones(arr.shape, dtype=bool)


def _is_int(x) -> bool:
    return isinstance(x, int | np.integer) and not isinstance(x, bool | np.bool_)


@njit(cache=True)
def round_shift(x: int, shift: int) -> int:
    """x / 2**shift rounded to nearest, ties toward +infinity (add half, arithmetic shift).

    This is what the RTL does: add the constant 2**(shift-1), then drop ``shift`` bits.
    """
    if shift <= 0:
        return x << (-shift)
    return (x + (1 << (shift - 1))) >> shift


@njit(cache=True)
def trunc_shift(x: int, shift: int) -> int:
    """x / 2**shift rounded toward -infinity (a plain arithmetic shift: drop the low bits)."""
    if shift <= 0:
        return x << (-shift)
    return x >> shift


@njit(cache=True)
def saturate(x: int, lo: int, hi: int) -> int:
    """Clamp x to [lo, hi]: the named saturation step every unit output takes."""
    if x < lo:
        return lo
    if x > hi:
        return hi
    return x


def to_bits(value: int, width: int) -> int:
    """The unsigned bit pattern of a (possibly negative) integer in ``width`` bits."""
    lo = signed_range(width)[0]
    if not lo <= value <= (1 << width) - 1:
        raise ValueError(f"value {value} does not fit in {width} bits")
    return value & ((1 << width) - 1)


def from_bits(bits: int, width: int) -> int:
    """The two's-complement integer a ``width``-bit pattern stands for."""
    bits &= (1 << width) - 1
    return bits - (1 << width) if bits >> (width - 1) else bits


def format_up(value: float, digits: int, scale: int = 1) -> str:
    """``value * scale`` with ``digits`` decimals, rounded toward +infinity from the exact float
    value: a worst case printed this way is an upper bound, never a rounded-down miss."""
    exact = Decimal(value) * scale
    return f"{exact.quantize(Decimal(1).scaleb(-digits), rounding=ROUND_CEILING):.{digits}f}"
