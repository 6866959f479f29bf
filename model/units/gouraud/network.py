# SPDX-License-Identifier: Apache-2.0
"""Segment Gouraud unit: the increment network, derived from the segment size P.

Owns how the multiples i*dI (i = 1..P) are made from wired shifts and a few adders
(``increment_network``, ``Adder``, ``IncrementNetwork``), the article's count of increments one
adder reaches (``increment_count``), the unit's adder budget (``adder_counts``), the README's
table (``format_network_table``), ``log2_exact`` (the check that P is a power of two) and
``network_arrays`` (the network as the datapath kernel's arrays).  May import numpy and the
standard library only: ``config`` and ``datapath`` build on it.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import NamedTuple

import numpy as np

NETWORK_MAX_P = 64  # increment_count / increment_network enumerate up to this segment size


def log2_exact(p: int, name: str, hi: int) -> int:
    """log2 of ``p``, or ``ValueError`` naming ``name`` unless p is a power of two in 2..hi."""
    if not isinstance(p, int | np.integer) or p < 2 or p > hi or p & (p - 1):
        powers = ", ".join(str(1 << w) for w in range(1, hi.bit_length()))
        raise ValueError(f"{name} = {p!r} is out of range: legal values are {powers}")
    return int(p).bit_length() - 1


class Adder(NamedTuple):
    """One adder of the increment network: ``target*dI = a*dI +- b*dI``."""

    target: int
    a: int
    b: int
    subtract: bool
    level: int

    def describe(self) -> str:
        return f"{self.target}dI = {self.a}dI {'-' if self.subtract else '+'} {self.b}dI"


@dataclass(frozen=True)
class IncrementNetwork:
    """How the multiples i*dI, i = 1..P, are made: wired shifts and adders, level by level."""

    p: int
    shifts: tuple[int, ...]  # the multiples that are plain wired shifts 2**w (w = 0..log2 P)
    adders: tuple[Adder, ...]  # in level order: an adder only uses shifts and earlier levels

    @property
    def adder_count(self) -> int:
        return len(self.adders)

    @property
    def levels(self) -> int:
        """Adders in series on the longest path (0 when every multiple is a wired shift)."""
        return max((a.level for a in self.adders), default=0)

    def per_level(self) -> list[int]:
        return [sum(1 for a in self.adders if a.level == lv) for lv in range(1, self.levels + 1)]


@cache
def increment_network(p: int) -> IncrementNetwork:
    """Derive the increment network for segment size p (a power of two up to 64).

    Level 0 are the wired shifts ``2**w * dI``, w = 0..log2 p (P*dI included: the next start
    needs it).  Every other multiple i = 1..p gets the lowest level L at which it is
    ``x + y`` or ``x - y`` of two multiples of levels below L; among those, an addition is
    preferred, then the smallest second operand y (and x >= y for an addition).  For p = 8 this
    gives exactly the article's four adders 3 = 2+1, 5 = 4+1, 6 = 4+2, 7 = 8-1 (the one
    subtraction, in two's complement); p = 16 needs a second level for 11 = 10+1 and 13 = 12+1.
    The RTL's constant functions (rtl/gouraud_segment.v) make the same choice.
    """
    log2p = log2_exact(p, "p", NETWORK_MAX_P)
    shifts = tuple(1 << w for w in range(log2p + 1))
    known = dict.fromkeys(shifts, 0)  # multiple -> level
    need = [i for i in range(1, p + 1) if i not in known]
    adders: list[Adder] = []
    level = 0
    while need:
        level += 1
        below = sorted(known)  # everything of a level < this one
        found: dict[int, Adder] = {}
        for i in need:
            choice = None
            for y in below:  # an addition x + y, x >= y
                if i - y >= y and (i - y) in known:
                    choice = Adder(i, i - y, y, False, level)
                    break
            if choice is None:
                for y in below:  # a subtraction x - y, x <= p
                    if (i + y) in known:
                        choice = Adder(i, i + y, y, True, level)
                        break
            if choice is not None:
                found[i] = choice
        for i, adder in found.items():
            known[i] = level
            adders.append(adder)
        need = [i for i in need if i not in found]
    return IncrementNetwork(p=p, shifts=shifts, adders=tuple(adders))


def increment_count(p: int) -> int:
    """How many of the p increments i*dI (i = 0..p-1) one add or subtract of two shifted
    operands 2**w*dI (w = 0..log2 p) reaches: the article's table, by enumeration.

    Both operands may be the same shift (0 = x - x, 2**(w+1) = 2**w + 2**w), so the plain
    shifts count too.  p = 2, 4, 8, 16, 32, 64 give 2, 4, 8, 14, 22, 32.
    """
    log2p = log2_exact(p, "p", NETWORK_MAX_P)
    ops = [1 << w for w in range(log2p + 1)]
    reach = {x + y for x in ops for y in ops} | {x - y for x in ops for y in ops}
    return sum(1 for i in range(p) if i in reach)


def adder_counts(p: int) -> dict[str, int]:
    """The unit's adders for segment size p: network, segment block, rounding bias."""
    net = increment_network(p)
    return {
        "network": net.adder_count,
        "network_levels": net.levels,
        # lanes 1..P-1 (lane 0 is the start register itself) + the next start I0 + P*dI
        "segment": p,
        "bias": 1,
        "total": net.adder_count + p + 1,
    }


def format_network_table(ps: tuple[int, ...] = (2, 4, 8, 16, 32, 64)) -> str:
    """Markdown table of the derived network per P (the README's table)."""
    lines = [
        "| P | increments by one add/sub (article) | network adders | adder levels "
        "| adders per level | segment adders | total adders (+1 bias) |",
        "|---|---|---|---|---|---|---|",
    ]
    for p in ps:
        net = increment_network(p)
        cnt = adder_counts(p)
        per_level = " + ".join(str(n) for n in net.per_level()) or "-"
        lines.append(
            f"| {p} | {increment_count(p)} | {net.adder_count} | {net.levels} | {per_level} "
            f"| {cnt['segment']} | {cnt['total']} |"
        )
    return "\n".join(lines)


def network_arrays(net: IncrementNetwork) -> tuple[np.ndarray, ...]:
    """(shift exponents, adder targets, first operands, second operands, subtract flags): the
    network as int64 arrays, in level order, for the datapath's segment kernel."""
    shift_w = np.array([s.bit_length() - 1 for s in net.shifts], dtype=np.int64)
    tgt = np.array([a.target for a in net.adders], dtype=np.int64)
    opa = np.array([a.a for a in net.adders], dtype=np.int64)
    opb = np.array([a.b for a in net.adders], dtype=np.int64)
    sub = np.array([int(a.subtract) for a in net.adders], dtype=np.int64)
    return shift_w, tgt, opa, opb, sub
