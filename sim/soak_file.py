# SPDX-License-Identifier: Apache-2.0
"""The soak's binary vector file as a numba kernel over the prediction's arrays.

``write_vector_file(cfg, stim, pred, path)`` (and ``vector_bytes``, the same bytes in memory)
writes the file sim/soak.py ``write_vectors`` writes from per-cycle dicts: per record the
stimulus word, then ``{mask, expect}`` of the RESET_ALL = 0 prediction, then of the
RESET_ALL = 1 one, each big-endian and right-aligned in whole bytes (sim/vectors/vector_loop.vh
reads it).  One kernel packs the bits of a chunk of records into a buffer that is reused, so a
long segment never holds its whole file in memory; tests/test_soak_fast.py checks the bytes
against ``write_vectors``.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
from numba import njit

from sim import units
from sim.protocol import UnitSpec
from sim.soak_predict import Column, Prediction, columns, unit_spec
from sim.soak_stimulus import Stimulus

KIND = {"data": 0, "flag": 1, "strobe": 2}


def record_layout(spec: UnitSpec) -> tuple[int, int, int, int]:
    """(stimulus bits, response bits, stimulus bytes, bytes of one {mask, expect} pair)."""
    stim_w = 2 + sum(1 + p.width for p in spec.operands)
    out_w = 2 + sum(p.width for p in spec.outputs)
    return stim_w, out_w, -(-stim_w // 8), -(-2 * out_w // 8)


@njit(cache=True, inline="always")
def _push32(
    buf: np.ndarray, at: int, acc: int, n: int, value: int, bits: int
) -> tuple[int, int, int]:
    """Append ``bits`` (<= 32) of ``value`` to the ``n`` pending bits of ``acc`` and OR every
    whole byte into ``buf[at]``, ``buf[at + 1]``, ...; returns the new (at, acc, n)."""
    acc = (acc << bits) | value
    n += bits
    while n >= 8:
        n -= 8
        buf[at] |= np.uint8((acc >> n) & 0xFF)
        at += 1
    return at, acc & ((np.int64(1) << n) - 1), n


@njit(cache=True, inline="always")
def _push(
    buf: np.ndarray, at: int, acc: int, n: int, value: int, bits: int
) -> tuple[int, int, int]:
    """``_push32`` for up to 62 bits of ``value`` (>= 0)."""
    if bits > 32:
        at, acc, n = _push32(buf, at, acc, n, value >> 32, bits - 32)
        return _push32(buf, at, acc, n, value & 0xFFFFFFFF, 32)
    return _push32(buf, at, acc, n, value, bits)


@njit(cache=True, inline="always")
def _flush(buf: np.ndarray, at: int, acc: int, n: int) -> None:
    if n > 0:
        buf[at] |= np.uint8((acc << (8 - n)) & 0xFF)


@njit(cache=True)
def _write_kernel(
    buf: np.ndarray, first: int, stim_w: int, out_w: int, stim_bytes: int, pair_bytes: int,
    rst_n: np.ndarray, start: np.ndarray, we: np.ndarray, value: np.ndarray,
    op_width: np.ndarray, busy: np.ndarray, valid: np.ndarray, held: np.ndarray,
    seq: np.ndarray, base: np.ndarray, table: np.ndarray, col_width: np.ndarray,
    col_kind: np.ndarray, mask_all: np.ndarray, mask_reset: np.ndarray,
) -> None:  # fmt: skip
    """The records of the cycles from ``first`` on into the zeroed ``buf`` (as many as it
    holds): the stimulus word, then per RESET_ALL mode its
    ``{mask, expect}``.  The mask is ``mask_all`` (every output defined) or, in RESET_ALL = 0
    mode with no result since reset, ``mask_reset`` (the data outputs undefined); the data
    outputs then read 0 in RESET_ALL = 1 mode, the flags and strobes 0 in both; a strobe is 0
    but with valid.  A cycle whose prediction is the one before's copies its bytes, and a
    result's pair is the same in both modes."""
    record = stim_bytes + 2 * pair_bytes
    for c in range(first, min(rst_n.size, first + buf.size // record)):
        at = (c - first) * record
        at, acc, n = _push(buf, at, 0, stim_bytes * 8 - stim_w, rst_n[c] * 2 + start[c], 2)
        for p in range(op_width.size):
            w = op_width[p]
            at, acc, n = _push(buf, at, acc, n, we[c, p], 1)
            at, acc, n = _push(buf, at, acc, n, value[c, p] & ((np.int64(1) << w) - 1), w)
        _flush(buf, at, acc, n)
        if busy[c] < 0:
            continue
        pairs = (c - first) * record + stim_bytes
        if (
            c > first
            and busy[c] == busy[c - 1]
            and valid[c] == valid[c - 1]
            and held[c] == held[c - 1]
            and seq[c] == seq[c - 1]
        ):
            buf[pairs : pairs + 2 * pair_bytes] = buf[
                pairs - record : pairs - record + 2 * pair_bytes
            ]
            continue
        row = base[held[c]] + seq[c] if held[c] >= 0 else -1
        for mode in range(2):
            pair = pairs + mode * pair_bytes
            if mode == 1 and row >= 0:  # a result: RESET_ALL makes no difference
                buf[pair : pair + pair_bytes] = buf[pairs : pairs + pair_bytes]
                break
            buf[pair : pair + pair_bytes] = mask_all if row >= 0 or mode == 1 else mask_reset
            e = (pair + pair_bytes) * 8 - out_w
            at, acc, n = _push(buf, e >> 3, 0, e & 7, busy[c] * 2 + valid[c], 2)
            for k in range(col_width.size):
                w = col_width[k]
                v = 0
                if row >= 0 and (col_kind[k] != 2 or valid[c] == 1):
                    v = table[row, k] & ((np.int64(1) << w) - 1)
                at, acc, n = _push(buf, at, acc, n, v, w)
            _flush(buf, at, acc, n)


def _mask_pair(out_w: int, pair_bytes: int, cols: tuple[Column, ...], data: bool) -> np.ndarray:
    """The bytes of ``{mask, 0}``: busy, valid and every column defined (``data`` False: not
    the data columns)."""
    mask = 3
    for c in cols:
        mask = (mask << c.width) | (((1 << c.width) - 1) if data or c.kind != "data" else 0)
    word = mask << out_w
    return np.frombuffer(word.to_bytes(pair_bytes, "big"), dtype=np.uint8).copy()


def _records(
    cfg: units.UnitConfig, stim: Stimulus, pred: Prediction, chunk: int
) -> Iterator[np.ndarray]:
    """The vector file's records, ``chunk`` cycles at a time, each chunk in one reused buffer
    (a view valid until the next one)."""
    spec = unit_spec(cfg)
    stim_w, out_w, stim_bytes, pair_bytes = record_layout(spec)
    record = stim_bytes + 2 * pair_bytes
    cols = columns(cfg)
    widths = np.array([p.width for p in spec.operands], dtype=np.int64)
    col_width = np.array([c.width for c in cols], dtype=np.int64)
    col_kind = np.array([KIND[c.kind] for c in cols], dtype=np.int64)
    masks = _mask_pair(out_w, pair_bytes, cols, True), _mask_pair(out_w, pair_bytes, cols, False)
    buf = np.zeros(min(chunk, len(stim)) * record, dtype=np.uint8)
    for first in range(0, len(stim), chunk):
        n = min(chunk, len(stim) - first)
        buf[:] = 0
        _write_kernel(
            buf[: n * record], first, stim_w, out_w, stim_bytes, pair_bytes, stim.rst_n,
            stim.start, stim.we, stim.value, widths, pred.busy, pred.valid, pred.held,
            pred.seq, pred.base, pred.table, col_width, col_kind, *masks,
        )  # fmt: skip
        yield buf[: n * record]


def vector_bytes(cfg: units.UnitConfig, stim: Stimulus, pred: Prediction) -> np.ndarray:
    """The vector file of ``stim`` and ``pred`` (uint8; sim/soak.py ``write_vectors``)."""
    if not len(stim):
        return np.zeros(0, dtype=np.uint8)
    return next(_records(cfg, stim, pred, len(stim)))


def write_vector_file(
    cfg: units.UnitConfig, stim: Stimulus, pred: Prediction, path: Path, chunk: int = 1 << 16
) -> None:
    """``vector_bytes`` into the file ``path``, ``chunk`` cycles at a time (a buffer that stays
    in the cache, not the whole file in memory)."""
    with open(path, "wb") as out:
        for records in _records(cfg, stim, pred, chunk):
            records.tofile(out)
