# SPDX-License-Identifier: Apache-2.0
"""A combinational and-inverter graph (binary AIGER, as ABC and Yosys write it) decided by
evaluating it on every assignment of the inputs an output depends on: the window proof of
``make mutants`` (sim/mutation_window.py, ``prove_window``) unrolls its miter in ABC to one
output whose cone reads a few dozen inputs at most, where a SAT solver stalls on the
multipliers but a bit-parallel sweep of all 2^k assignments takes seconds.

``read_aiger`` reads the file, ``support`` finds the inputs an output's cone reads and
``first_one`` sweeps them (a numba kernel, 64 assignments a word): the first assignment that
sets the output, or None when none does.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit


@dataclass(frozen=True)
class Aig:
    """A combinational AIG: ``inputs`` inputs (variables 1..inputs), ``outputs`` as literals
    (2 x variable, + 1 when inverted) and ``ands``, one row (rhs0, rhs1) per and gate, gate k
    being variable inputs + k + 1 (AIGER's order: each reads only lower variables)."""

    inputs: int
    outputs: np.ndarray
    ands: np.ndarray


def read_aiger(path: Path) -> Aig:
    """The binary AIGER file ``path`` (``aig M I L O A``, latches refused: the graph must be
    combinational)."""
    data = path.read_bytes()
    end = data.index(b"\n")
    head = data[:end].split()
    if len(head) < 6 or head[0] != b"aig":
        raise ValueError(f"{path}: not a binary AIGER file (header {data[:end]!r})")
    _, inputs, latches, n_out, n_and = (int(x) for x in head[1:6])
    if latches:
        raise ValueError(f"{path}: {latches} latches; only a combinational AIG is evaluated")
    pos = end + 1
    outputs = []
    for _ in range(n_out):
        end = data.index(b"\n", pos)
        outputs.append(int(data[pos:end].split()[0]))
        pos = end + 1
    ands = np.empty((n_and, 2), dtype=np.int64)
    buf = np.frombuffer(data, dtype=np.uint8)
    pos = _deltas(buf, pos, inputs, ands)
    return Aig(inputs, np.array(outputs, dtype=np.int64), ands)


@njit(cache=True)
def _deltas(buf: np.ndarray, pos: int, inputs: int, ands: np.ndarray) -> int:
    """AIGER's and section: per gate two LEB128 deltas, lhs - rhs0 and rhs0 - rhs1."""
    for k in range(ands.shape[0]):
        lhs = 2 * (inputs + k + 1)
        for j in range(2):
            delta = np.int64(0)
            shift = 0
            while True:
                byte = np.int64(buf[pos])
                pos += 1
                delta |= (byte & 0x7F) << shift
                shift += 7
                if byte < 0x80:
                    break
            ands[k, j] = (lhs if j == 0 else ands[k, 0]) - delta
    return pos


def _cone(aig: Aig, output: int) -> np.ndarray:
    """Per variable (0..inputs + gates): whether the cone of output ``output`` reads it."""
    need = np.zeros(aig.inputs + len(aig.ands) + 1, dtype=np.bool_)
    need[aig.outputs[output] >> 1] = True
    _mark(aig.ands, aig.inputs, need)
    return need


def _inputs(aig: Aig, need: np.ndarray) -> list[int]:
    return [int(v) for v in np.flatnonzero(need[1 : aig.inputs + 1]) + 1]


def support(aig: Aig, output: int = 0) -> list[int]:
    """The inputs (variables 1..inputs) the cone of output ``output`` reads, ascending."""
    return _inputs(aig, _cone(aig, output))


@njit(cache=True)
def _mark(ands: np.ndarray, inputs: int, need: np.ndarray) -> None:
    for k in range(ands.shape[0] - 1, -1, -1):
        if need[inputs + k + 1]:
            need[ands[k, 0] >> 1] = True
            need[ands[k, 1] >> 1] = True


# 64-bit words per sweep step (4096 assignments)
_WORDS = 64
# The six lowest assignment bits within a word: input j is 1 where bit j of the position is
_LANES = np.array(
    [0xAAAAAAAAAAAAAAAA, 0xCCCCCCCCCCCCCCCC, 0xF0F0F0F0F0F0F0F0, 0xFF00FF00FF00FF00,
     0xFFFF0000FFFF0000, 0xFFFFFFFF00000000],
    dtype=np.uint64,
)  # fmt: skip


def first_one(aig: Aig, output: int = 0, limit: int = 28) -> dict[int, int] | None:
    """Output ``output`` of ``aig`` evaluated on every assignment of its ``support``: None if
    it is 0 on all of them, else the first assignment (by the binary count over the support,
    its lowest input first) that makes it 1, as {input variable: bit}.  A support wider than
    ``limit`` inputs (2^limit assignments) is refused with ValueError."""
    need = _cone(aig, output)
    inputs = _inputs(aig, need)
    if len(inputs) > limit:
        raise ValueError(
            f"output {output} reads {len(inputs)} inputs; at most {limit} are swept (2^{limit} "
            "assignments)"
        )
    # the cone's gates, renumbered: 0 false, 1..k the support, then the gates in order
    place = np.full(len(need), -1, dtype=np.int64)
    place[0] = 0
    place[np.array(inputs, dtype=np.int64)] = np.arange(1, len(inputs) + 1)
    gates = np.flatnonzero(need[aig.inputs + 1 :])
    place[aig.inputs + 1 + gates] = np.arange(len(inputs) + 1, len(inputs) + 1 + len(gates))
    rows = aig.ands[gates]
    operands = (place[rows >> 1] << 1) | (rows & 1)
    out = aig.outputs[output]
    found = _sweep(len(inputs), operands, (place[out >> 1] << 1) | (out & 1))
    if found < 0:
        return None
    return {v: (found >> j) & 1 for j, v in enumerate(inputs)}


@njit(cache=True)
def _sweep(k: int, operands: np.ndarray, out: int) -> int:
    """The first of the 2^k assignments of inputs 1..k that sets literal ``out``, or -1."""
    total = np.int64(1) << k
    words = min(_WORDS, max(np.int64(1), total >> 6))
    nodes = k + 1 + operands.shape[0]
    val = np.zeros((nodes, words), dtype=np.uint64)
    ones = ~np.uint64(0)
    lanes = _LANES
    valid = ones if total >= 64 else (np.uint64(1) << np.uint64(total)) - np.uint64(1)
    step = words * 64
    for base in range(0, total, step):
        for j in range(k):
            for w in range(words):
                if j < 6:
                    val[j + 1, w] = lanes[j]
                else:
                    position = (base >> 6) + w
                    val[j + 1, w] = ones if (position >> (j - 6)) & 1 else np.uint64(0)
        for g in range(operands.shape[0]):
            a = operands[g, 0]
            b = operands[g, 1]
            ia = a >> 1
            ib = b >> 1
            fa = ones if a & 1 else np.uint64(0)
            fb = ones if b & 1 else np.uint64(0)
            row = k + 1 + g
            for w in range(words):
                val[row, w] = (val[ia, w] ^ fa) & (val[ib, w] ^ fb)
        flip = ones if out & 1 else np.uint64(0)
        for w in range(words):
            hit = (val[out >> 1, w] ^ flip) & valid
            if hit:
                bit = 0
                while not (hit >> np.uint64(bit)) & np.uint64(1):
                    bit += 1
                return base + w * 64 + bit
    return -1
