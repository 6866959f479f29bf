# SPDX-License-Identifier: Apache-2.0
"""The soak's constrained-random stimulus as a numba kernel over numpy integer arrays.

``stimulus(cfg, cycles, seed)`` draws what a careless host could do to a unit, cycle by cycle
(``Stimulus``: per cycle rst_n, start, every write strobe and operand value): each strobe and
``start`` at random, operand values from the extremes, values next to 0 (so a register crosses 0
from one job to the next, e.g. the divider's k), powers of two of either sign and uniform ones,
line lengths mostly short and now and then up to the maximum, the specular unit's n at its
table and kept-range edges and inside the kept range, writes in the start cycle and in every
busy cycle, and a short random reset now and then; the first three cycles hold reset.  The
random numbers are a splitmix64 stream seeded from the unit, the seed and the segment
(``seed_state``), so the arrays are the same on every machine and numba version.  The
prediction and the vector file are sim/soak_predict.py's; sim/soak.py puts them together.
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np
from numba import njit

from model.units.brdf import FixedConfig
from model.units.specular import N_MAX, SpecularConfig
from sim import units
from sim.protocol import Port, UnitSpec

# Per cycle: chance of a reset (held 1..3 cycles), of start, of each write strobe.
P_RESET = 0.0015
P_START = 0.35
P_WRITE = 0.3
# Longest line the soak draws often (a long line now and then is drawn up to the maximum).
SHORT_LINE = 24
P_LONG_LINE = 0.02
# How an operand's values are drawn (``_pick``).
DRAW_PLAIN, DRAW_LENGTH, DRAW_N = 0, 1, 2
# Operand widths the kernel draws in one int64.
MAX_BITS = 62

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


# ---------------------------------------------------------------------- random numbers
@njit(cache=True)
def _next(state: np.ndarray) -> np.uint64:
    """splitmix64: the next 64 random bits of ``state`` (one uint64)."""
    z = state[0] + _GOLDEN
    state[0] = z
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    return z ^ (z >> np.uint64(31))


@njit(cache=True)
def _uniform(state: np.ndarray) -> float:
    """A float in [0, 1) with 53 random bits."""
    return float(_next(state) >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@njit(cache=True)
def _between(state: np.ndarray, lo: int, hi: int) -> int:
    """An integer in lo..hi (both included; hi - lo < 2**62): a span under 2**32 from the top
    32 bits by a multiply (Lemire's method, no division), a wider one by a remainder."""
    span = hi - lo + 1
    if span <= 0xFFFFFFFF:
        return lo + np.int64(((_next(state) >> np.uint64(32)) * np.uint64(span)) >> np.uint64(32))
    return lo + np.int64(_next(state) % np.uint64(span))


def seed_state(toplevel: str, seed: int, segment: int = 0) -> np.ndarray:
    """The generator state of a unit's soak for ``seed`` and ``segment`` (sim/soak.py runs a long
    soak in segments of its own stimulus, each starting with a reset)."""
    text = f"soak-{toplevel}-{seed}" + (f"-{segment}" if segment else "")
    return np.frombuffer(hashlib.sha256(text.encode()).digest()[:8], dtype=np.uint64).copy()


# ---------------------------------------------------------------------- the stimulus
@dataclass(frozen=True)
class Stimulus:
    """Per cycle: ``rst_n``, ``start`` (uint8), and per operand (``names``) its write strobe
    ``we`` (uint8) and the value on its input ``value`` (int64, signed for signed operands)."""

    names: tuple[str, ...]
    rst_n: np.ndarray
    start: np.ndarray
    we: np.ndarray
    value: np.ndarray

    def __len__(self) -> int:
        return int(self.rst_n.size)

    def inputs(self, cycle: int) -> dict[str, int]:
        """The inputs of one cycle as ``ProtocolModel.step`` takes them."""
        out = {"rst_n": int(self.rst_n[cycle]), "start": int(self.start[cycle])}
        for i, name in enumerate(self.names):
            out[f"{name}_we"] = int(self.we[cycle, i])
            out[f"{name}_in"] = int(self.value[cycle, i])
        return out

    def as_inputs(self) -> list[dict[str, int]]:
        """Every cycle's inputs (``inputs``), built from whole columns at once."""
        cols = {"rst_n": self.rst_n.tolist(), "start": self.start.tolist()}
        for i, name in enumerate(self.names):
            cols[f"{name}_we"] = self.we[:, i].tolist()
            cols[f"{name}_in"] = self.value[:, i].tolist()
        keys = list(cols)
        return [dict(zip(keys, row, strict=True)) for row in zip(*cols.values(), strict=True)]

    def tail(self, first: int) -> Stimulus:
        """The cycles from ``first`` on (a stimulus that need not begin with a reset)."""
        return Stimulus(
            self.names,
            self.rst_n[first:].copy(),
            self.start[first:].copy(),
            self.we[first:].copy(),
            self.value[first:].copy(),
        )


def port_range(port: Port) -> tuple[int, int]:
    if port.signed:
        return -(1 << (port.width - 1)), (1 << (port.width - 1)) - 1
    return 0, (1 << port.width) - 1


def extremes(port: Port) -> list[int]:
    """The operand values a soak favours: both ends, 0 and its neighbours, the ends' neighbours."""
    lo, hi = port_range(port)
    return sorted({v for v in (lo, lo + 1, -1, 0, 1, 2, hi - 1, hi) if lo <= v <= hi})


@dataclass(frozen=True)
class DrawPlan:
    """How the stimulus kernel draws each operand: ``kind`` (``DRAW_*``), range, signedness,
    width, the favoured values ``ext`` (row per operand, ``n_ext`` used), and for the specular
    unit's n its edges and kept range."""

    kind: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    signed: np.ndarray
    width: np.ndarray
    ext: np.ndarray
    n_ext: np.ndarray
    n_edges: np.ndarray
    n_kept: tuple[int, int, int]  # (1 if a kept range, n_first, n_last)


@functools.cache
def draw_plan(cfg: units.UnitConfig) -> DrawPlan:
    spec = units.spec(cfg)
    ops = spec.operands
    for p in ops:
        if p.width > MAX_BITS:
            raise ValueError(f"operand {p.name} is {p.width} bits: the soak draws up to {MAX_BITS}")
    kind = np.array(
        [
            DRAW_LENGTH
            if p.name == "len"
            else DRAW_N
            if p.name == "n" and isinstance(cfg, SpecularConfig | FixedConfig)
            else DRAW_PLAIN
            for p in ops
        ],
        dtype=np.int64,
    )
    ext = np.zeros((len(ops), 8), dtype=np.int64)
    n_ext = np.zeros(len(ops), dtype=np.int64)
    for i, p in enumerate(ops):
        values = extremes(p)
        ext[i, : len(values)] = values
        n_ext[i] = len(values)
    edges: set[int] = set()
    kept = (0, 0, 0)
    if isinstance(cfg, FixedConfig):  # the BRDF unit: n = 1..1000, no tables by n
        edges = {0, 1, 2, N_MAX, N_MAX + 1, (1 << units.N_WIDTH) - 1}
    if isinstance(cfg, SpecularConfig):
        edges = {0, 1, N_MAX, N_MAX + 1, (1 << units.N_WIDTH) - 1}
        for hi in cfg.n_hi:
            edges.update((hi, hi + 1))
        if cfg.n_first > 1 or cfg.n_last < N_MAX:  # a kept range: its edges, and n inside it
            edges.update((cfg.n_first - 1, cfg.n_first, cfg.n_last, cfg.n_last + 1))
            kept = (1, cfg.n_first, cfg.n_last)
    ranges = [port_range(p) for p in ops]
    return DrawPlan(
        kind=kind,
        lo=np.array([r[0] for r in ranges], dtype=np.int64),
        hi=np.array([r[1] for r in ranges], dtype=np.int64),
        signed=np.array([int(p.signed) for p in ops], dtype=np.int64),
        width=np.array([p.width for p in ops], dtype=np.int64),
        ext=ext,
        n_ext=n_ext,
        n_edges=np.array(sorted(edges) or [0], dtype=np.int64),
        n_kept=kept,
    )


@njit(cache=True)
def _pick(
    state: np.ndarray, kind: int, lo: int, hi: int, signed: int, width: int, ext: np.ndarray,
    n_ext: int, n_edges: np.ndarray, kept: int, n_first: int, n_last: int,
) -> int:  # fmt: skip
    """One operand value: extremes, near 0, a power of two (signed: either sign) or uniform;
    a line length mostly short, now and then up to the maximum; the specular unit's n at the
    table and range edges, inside a kept range, or anywhere in 0..N_MAX + 23."""
    if kind == DRAW_LENGTH:
        if _uniform(state) < P_LONG_LINE:
            return hi if _uniform(state) < 0.5 else _between(state, 0, hi)
        return _between(state, 0, min(SHORT_LINE, hi))
    if kind == DRAW_N:
        if kept and _uniform(state) < 0.3:
            return _between(state, n_first, n_last)
        if _uniform(state) < 0.5:
            return n_edges[_between(state, 0, n_edges.size - 1)]
        return _between(state, 0, N_MAX + 23)
    r = _uniform(state)
    if r < 0.35:
        return ext[_between(state, 0, n_ext - 1)]
    if r < 0.55:
        return _between(state, -2, 2) if signed else _between(state, 0, 2)
    if r < 0.7:
        value = np.int64(1) << _between(state, 0, width - 2 if signed else width - 1)
        return -value if signed and _uniform(state) < 0.5 else value
    return _between(state, lo, hi)


@njit(cache=True)
def _stimulus_kernel(
    state: np.ndarray, kind: np.ndarray, lo: np.ndarray, hi: np.ndarray, signed: np.ndarray,
    width: np.ndarray, ext: np.ndarray, n_ext: np.ndarray, n_edges: np.ndarray, kept: int,
    n_first: int, n_last: int, rst_n: np.ndarray, start: np.ndarray, we: np.ndarray,
    value: np.ndarray,
) -> None:  # fmt: skip
    """Fill the stimulus arrays: the first three cycles hold reset, then a reset of 1..3 cycles
    with chance P_RESET per cycle, start and each strobe at random, a port keeping its value
    when not written."""
    nops = kind.size
    held = np.zeros(nops, dtype=np.int64)
    reset_left = 3
    for c in range(rst_n.size):
        if reset_left == 0 and _uniform(state) < P_RESET:
            reset_left = _between(state, 1, 3)
        rst_n[c] = 0 if reset_left else 1
        start[c] = 1 if _uniform(state) < P_START else 0
        reset_left = max(0, reset_left - 1)
        for p in range(nops):
            if _uniform(state) < P_WRITE:
                held[p] = _pick(
                    state, kind[p], lo[p], hi[p], signed[p], width[p], ext[p], n_ext[p],
                    n_edges, kept, n_first, n_last,
                )  # fmt: skip
                we[c, p] = 1
            value[c, p] = held[p]


def stimulus(cfg: units.UnitConfig, cycles: int, seed: int, segment: int = 0) -> Stimulus:
    """``cycles`` cycles of the soak's random inputs for ``seed`` (and ``segment``)."""
    spec = units.spec(cfg)
    plan = draw_plan(cfg)
    nops = len(spec.operands)
    stim = Stimulus(
        tuple(p.name for p in spec.operands),
        np.zeros(cycles, dtype=np.uint8),
        np.zeros(cycles, dtype=np.uint8),
        np.zeros((cycles, nops), dtype=np.uint8),
        np.zeros((cycles, nops), dtype=np.int64),
    )
    _stimulus_kernel(
        seed_state(spec.toplevel, seed, segment), plan.kind, plan.lo, plan.hi, plan.signed,
        plan.width, plan.ext, plan.n_ext, plan.n_edges, *plan.n_kept,
        stim.rst_n, stim.start, stim.we, stim.value,
    )  # fmt: skip
    return stim


def from_inputs(spec: UnitSpec, inputs: list[dict[str, int]]) -> Stimulus:
    """A ``Stimulus`` of a list of per-cycle inputs (as ``ProtocolModel.step`` takes them)."""
    names = tuple(p.name for p in spec.operands)
    n = len(inputs)
    we = np.array([[row[f"{x}_we"] for x in names] for row in inputs], dtype=np.uint8)
    value = np.array([[row[f"{x}_in"] for x in names] for row in inputs], dtype=np.int64)
    return Stimulus(
        names,
        np.array([row["rst_n"] for row in inputs], dtype=np.uint8),
        np.array([row["start"] for row in inputs], dtype=np.uint8),
        we.reshape(n, len(names)),
        value.reshape(n, len(names)),
    )


def line_rows(
    spec: UnitSpec, jobs: Iterable[dict[str, int]], wait: Callable[[dict[str, int]], int]
) -> list[dict[str, int]]:
    """Three reset cycles, then for each job (its operands by name) a cycle writing every
    operand, the start, and ``wait(job)`` idle cycles (to its last result)."""
    ops = spec.operands

    def row(base: dict[str, int], we: int, held: dict[str, int]) -> dict[str, int]:
        out = dict(base)
        for p in ops:
            out[f"{p.name}_we"] = we
            out[f"{p.name}_in"] = held[p.name]
        return out

    idle = {"rst_n": 1, "start": 0}
    rows = [row({"rst_n": 0, "start": 0}, 0, {p.name: 0 for p in ops})] * 3
    for job in jobs:
        rows.append(row(idle, 1, job))
        rows.append(row({"rst_n": 1, "start": 1}, 0, job))
        rows += [row(idle, 0, job)] * wait(job)
    return rows


def back_to_back(spec: UnitSpec, jobs: np.ndarray, busy: np.ndarray) -> Stimulus:
    """Three reset cycles, a cycle writing the first job's operands (``jobs``: a row per job,
    a column per operand in ``spec``'s order), then per job its start, with the next job's
    operands written in the same cycle (kept for the next line), and ``busy[j]`` + 1 idle
    cycles: the next start comes in the first cycle the unit is free, or one after; then a
    tail to the last result."""
    k, ops = len(jobs), len(spec.operands)
    span = busy.astype(np.int64) + 2  # the start and the idle cycles after it
    starts = 4 + np.concatenate(([0], np.cumsum(span)[:-1]))
    total = 4 + int(span.sum()) + 8
    rst_n = np.ones(total, np.uint8)
    rst_n[:3] = 0
    start = np.zeros(total, np.uint8)
    start[starts] = 1
    we = np.zeros((total, ops), np.uint8)
    value = np.zeros((total, ops), np.int64)
    we[3], value[3] = 1, jobs[0]
    we[starts[:-1]], value[starts[:-1]] = 1, jobs[1:]
    assert k == 0 or starts[-1] + span[-1] + 8 == total
    return Stimulus(tuple(p.name for p in spec.operands), rst_n, start, we, value)
