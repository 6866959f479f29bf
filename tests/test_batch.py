# SPDX-License-Identifier: Apache-2.0
"""The batched unit calls equal the per-line public calls, row by row.

``divider.divide_many``, ``gouraud.shade_lines`` and ``specular.shade_lines`` are what the
renderer runs; every row must be what ``divide``/``cycles``, ``gouraud.shade_line`` and
``specular.shade_line`` give for that row alone: random lines including the shortest (l = 0,
length 1) and the longest, the empty batch, writing into the caller's array (``out``/``at``)
and bad input, refused with the per-line call's message plus the row.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from model.units import divider, gouraud, specular
from model.units.batch import LineBatch

SPECULAR_CONFIGS = [("default", specular.DEFAULT), ("narrow", specular.NARROW)]
GOURAUD_CONFIGS = [
    ("default", gouraud.DEFAULT),
    ("p2", gouraud.GouraudConfig(p=2, len_width=6)),
    ("p16", gouraud.GouraudConfig(p=16, i_frac=8)),
]
DIVIDER_CONFIGS = [("default", divider.DEFAULT), ("article", divider.ARTICLE)]


# ------------------------------------------------------------------------ operands
def specular_lines(cfg: specular.SpecularConfig, count: int, seed: int) -> dict[str, np.ndarray]:
    """Random lines whose angles sweep through the highlight (most pixels neither 0 nor full),
    with the shortest and the longest line and the extreme n among them."""
    rng = np.random.default_rng(seed)
    one = 1 << cfg.z_frac_bits  # pi/2
    length = rng.integers(0, min(cfg.len_max, 300) + 1, count)
    length[:3] = [0, cfg.len_max, 1]
    z0 = rng.integers(-one, one, count)
    sweep = rng.uniform(-2.0, 2.0, count) * one  # how far the line's angle moves
    dz = np.round(sweep / np.maximum(length, 1)).astype(np.int64)
    dz[rng.random(count) < 0.1] = 0
    n = rng.integers(1, specular.N_MAX + 1, count)
    n[:4] = [1, specular.N_MAX, 2, 16]
    c = rng.integers(0, cfg.c_format.hi + 1, count)
    c[3] = cfg.c_format.hi
    return {"c": c, "dz": dz, "z0": z0, "n": n, "length": length}


def gouraud_lines(cfg: gouraud.GouraudConfig, count: int, channels: int | None, seed: int):
    rng = np.random.default_rng(seed)
    shape = (count,) if channels is None else (count, channels)
    length = rng.integers(1, cfg.len_max + 1, count)
    length[:3] = [1, cfg.len_max, cfg.p + 1]
    i0 = rng.integers(*cfg.i0_range, shape, endpoint=True)
    # Mostly the increments a line between two intensities needs, some anywhere in range.
    end = rng.integers(*cfg.i0_range, shape, endpoint=True)
    steps = np.maximum(length - 1, 1).reshape((count,) + (1,) * (len(shape) - 1))
    di = np.round((end - i0) / steps).astype(np.int64)
    wild = rng.random(shape) < 0.2
    di[wild] = rng.integers(*cfg.di_range, shape, endpoint=True)[wild]
    return {"i0": i0, "di": di, "length": length}


# ------------------------------------------------------------------------ every row
@pytest.mark.parametrize(("name", "cfg"), SPECULAR_CONFIGS, ids=[n for n, _ in SPECULAR_CONFIGS])
def test_specular_rows_equal_shade_line(name: str, cfg: specular.SpecularConfig) -> None:
    ops = specular_lines(cfg, 120, seed=12)
    res = specular.shade_lines(**ops, cfg=cfg)
    assert isinstance(res, LineBatch) and len(res) == 120
    assert res.pixels.dtype == np.int64 and res.pixels.shape == (int((ops["length"] + 1).sum()),)
    np.testing.assert_array_equal(res.offsets[1:] - res.offsets[:-1], ops["length"] + 1)
    lit = 0
    for j in range(120):
        row = {key: int(v[j]) for key, v in ops.items()}
        line = specular.shade_line(**row, cfg=cfg)
        np.testing.assert_array_equal(res.line(j), line, err_msg=f"row {j}: {row}")
        assert res.cycles[j] == specular.cycles(row["length"], cfg)
        lit += int(((line > 0) & (line < cfg.out_max)).sum())
    assert lit > res.pixels.size // 20  # the lines are not all dark or saturated


@pytest.mark.parametrize(("name", "cfg"), GOURAUD_CONFIGS, ids=[n for n, _ in GOURAUD_CONFIGS])
@pytest.mark.parametrize("channels", [None, 3])
def test_gouraud_rows_equal_shade_line(
    name: str, cfg: gouraud.GouraudConfig, channels: int | None
) -> None:
    ops = gouraud_lines(cfg, 60, channels, seed=13)
    res = gouraud.shade_lines(**ops, cfg=cfg)
    total = int(ops["length"].sum())
    assert res.pixels.shape == ((total,) if channels is None else (total, channels))
    assert res.pixels.dtype == np.int64
    for j in range(60):
        got = res.line(j).reshape(ops["length"][j], -1)
        i0, di = ops["i0"][j].reshape(-1), ops["di"][j].reshape(-1)
        for c in range(i0.size):
            line = gouraud.shade_line(int(i0[c]), int(di[c]), int(ops["length"][j]), cfg)
            np.testing.assert_array_equal(got[:, c], line, err_msg=f"row {j} channel {c}")
        assert res.cycles[j] == gouraud.cycles(int(ops["length"][j]), cfg)


@pytest.mark.parametrize(("name", "cfg"), DIVIDER_CONFIGS, ids=[n for n, _ in DIVIDER_CONFIGS])
def test_divide_many_equals_divide_and_cycles(name: str, cfg: divider.DividerConfig) -> None:
    rng = np.random.default_rng(14)
    a = rng.integers(*cfg.a_range, (40, 3), endpoint=True)
    k = rng.integers(1, cfg.k_max + 1, (40, 3))
    a[0, :] = [cfg.a_range[0], cfg.a_range[1], 0]
    k[0, :] = [1, cfg.k_max, 2]
    q, cyc = divider.divide_many(a, k, cfg)
    assert q.shape == cyc.shape == a.shape and q.dtype == cyc.dtype == np.int64
    for i in np.ndindex(a.shape):
        assert q[i] == divider.divide(int(a[i]), int(k[i]), cfg), i
        assert cyc[i] == divider.cycles(int(k[i]), cfg), i


# ------------------------------------------------------------------------ empty batches
def test_empty_batches() -> None:
    none = np.zeros(0, dtype=np.int64)
    res = specular.shade_lines(none, none, none, none, none)
    assert res.pixels.shape == (0,) and res.cycles.shape == (0,) and len(res) == 0
    np.testing.assert_array_equal(res.offsets, [0])
    for shape in [(0,), (0, 3)]:
        res = gouraud.shade_lines(np.zeros(shape, int), np.zeros(shape, int), none)
        assert res.pixels.shape == (0, *shape[1:]) and res.cycles.shape == (0,)
        np.testing.assert_array_equal(res.offsets, [0])
    q, cyc = divider.divide_many(none, none)
    assert q.shape == cyc.shape == (0,)
    # An empty batch written into an array leaves it alone.
    out = np.full(5, -1, dtype=np.int64)
    assert specular.shade_lines(none, none, none, none, none, out=out, at=none).pixels is out
    assert (out == -1).all()


# ------------------------------------------------------------------------ out / at
def scattered(counts: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, int]:
    """Start rows for lines of ``counts`` pixels in a random order with gaps: (at, size)."""
    order = rng.permutation(counts.size)
    gaps = rng.integers(0, 4, counts.size)
    at = np.zeros(counts.size, dtype=np.int64)
    row = 0
    for j in order:
        row += gaps[j]
        at[j] = row
        row += counts[j]
    return at, row + 2


def test_specular_writes_into_out_at_rows() -> None:
    cfg = specular.DEFAULT
    ops = specular_lines(cfg, 50, seed=15)
    rng = np.random.default_rng(15)
    at, size = scattered(ops["length"] + 1, rng)
    out = np.full(size, -1, dtype=np.int64)
    res = specular.shade_lines(**ops, cfg=cfg, out=out, at=at)
    assert res.pixels is out
    packed = specular.shade_lines(**ops, cfg=cfg)
    written = np.zeros(size, dtype=bool)
    for j in range(50):
        rows = slice(at[j], at[j] + ops["length"][j] + 1)
        np.testing.assert_array_equal(out[rows], packed.line(j))
        written[rows] = True
    assert (out[~written] == -1).all()  # nothing outside the lines is touched
    np.testing.assert_array_equal(res.offsets, packed.offsets)
    np.testing.assert_array_equal(res.cycles, packed.cycles)


@pytest.mark.parametrize("channels", [None, 3])
def test_gouraud_writes_into_out_at_rows(channels: int | None) -> None:
    cfg = gouraud.DEFAULT
    ops = gouraud_lines(cfg, 40, channels, seed=16)
    rng = np.random.default_rng(16)
    at, size = scattered(ops["length"], rng)
    out = np.full((size,) if channels is None else (size, channels), -1, dtype=np.int64)
    res = gouraud.shade_lines(**ops, cfg=cfg, out=out, at=at)
    assert res.pixels is out
    packed = gouraud.shade_lines(**ops, cfg=cfg)
    written = np.zeros(size, dtype=bool)
    for j in range(40):
        rows = slice(at[j], at[j] + ops["length"][j])
        np.testing.assert_array_equal(out[rows], packed.line(j))
        written[rows] = True
    assert (out[~written] == -1).all()
    # A strided view of a larger array is written through, not copied.
    big = np.full((2 * size, *out.shape[1:]), -1, dtype=np.int64)
    gouraud.shade_lines(**ops, cfg=cfg, out=big[::2], at=at)
    np.testing.assert_array_equal(big[::2], out)
    assert (big[1::2] == -1).all()


def test_out_and_at_are_checked() -> None:
    ops = specular_lines(specular.DEFAULT, 4, seed=17)
    counts = ops["length"] + 1
    size = int(counts.sum())
    good = np.zeros(size, dtype=np.int64)
    at = np.concatenate([[0], np.cumsum(counts)[:-1]])
    cases = [
        ({"out": good}, r"^out and at go together: give both or neither$"),
        ({"at": at}, r"^out and at go together: give both or neither$"),
        ({"out": good.astype(np.int32), "at": at}, r"^out is out of range: got ndarray int32"),
        ({"out": np.zeros((size, 1), np.int64), "at": at}, r"legal is a writeable int64 \(N,\)"),
        ({"out": good, "at": at[:3]}, r"^at is out of range: got shape \(3,\); legal is \(4,\)"),
        ({"out": good, "at": at - 1}, r"^at\[0\] = -1 is out of range: legal range is 0\.\."),
        (
            {"out": good, "at": at + 1},
            rf"^at\[3\] = {at[3] + 1} is out of range: line 3 has {counts[3]} pixels and out "
            rf"{size} rows, legal range is 0\.\.{size - counts[3]}$",
        ),
    ]
    read_only = good.copy()
    read_only.flags.writeable = False
    cases.append(({"out": read_only, "at": at}, r"legal is a writeable int64"))
    for kwargs, match in cases:
        with pytest.raises(ValueError, match=match) as err:
            specular.shade_lines(**ops, **kwargs)
        assert "\n" not in str(err.value)
    lengths, starts = np.array([3, 1, 4, 2]), np.array([0, 3, 4, 8])
    wide = np.zeros((10, 3), dtype=np.int64)
    with pytest.raises(ValueError, match=r"legal is a writeable int64 \(N, 3\) array"):
        gouraud.shade_lines(
            np.zeros((4, 3), int), np.zeros((4, 3), int), lengths, out=wide[:, :2], at=starts
        )
    with pytest.raises(ValueError, match=r"^at\[3\] = 9 is out of range: line 3 has 2 pixels"):
        gouraud.shade_lines(
            np.zeros((4, 3), int), np.zeros((4, 3), int), lengths, out=wide, at=starts + 1
        )


# ------------------------------------------------------------------------ bad input
def per_line_message(call, *args, **kwargs) -> str:
    with pytest.raises(ValueError) as err:
        call(*args, **kwargs)
    return str(err.value)


def with_row(message: str, name: str, index: str) -> str:
    """The per-line message with the operand named at its row: ``c = 7`` -> ``c[3] = 7``."""
    out, count = re.subn(rf"^{name} (=|must)", rf"{name}[{index}] \1", message)
    assert count == 1, message
    return out


SPECULAR_BAD = [
    ("c", 1 << 16),
    ("c", -1),
    ("dz", 1 << 28),
    ("z0", -(1 << 28) - 1),
    ("length", 2048),
    ("length", -1),
    ("n", 0),
    ("n", 1001),
    ("c", 2.5),
    ("n", 1e30),
    ("dz", 2**70),
]


@pytest.mark.parametrize(("operand", "value"), SPECULAR_BAD)
def test_specular_bad_row_gives_the_per_line_message_and_the_row(operand: str, value) -> None:
    cfg = specular.DEFAULT
    # As the per-line call sees them: a float array for a float, Python ints beyond int64.
    kind = float if isinstance(value, float) else object
    ops = {k: v.astype(kind) for k, v in specular_lines(cfg, 6, seed=18).items()}
    row = {k: int(v[3]) for k, v in ops.items()}
    row[operand] = value
    ops[operand][3] = value
    expect = with_row(per_line_message(specular.shade_line, **row, cfg=cfg), operand, "3")
    got = per_line_message(specular.shade_lines, **ops, cfg=cfg)
    assert got == expect and "\n" not in got


GOURAUD_BAD = [("i0", 1 << 20), ("i0", -1), ("di", 1 << 20), ("di", -(1 << 20) - 1)]
GOURAUD_BAD += [("length", 0), ("length", 2048), ("di", 0.5)]


@pytest.mark.parametrize(("operand", "value"), GOURAUD_BAD)
def test_gouraud_bad_row_gives_the_per_line_message_and_the_row(operand: str, value) -> None:
    cfg = gouraud.DEFAULT
    ops = gouraud_lines(cfg, 5, 3, seed=19)
    row = {k: int(np.asarray(v[3]).reshape(-1)[-1]) for k, v in ops.items()}
    row[operand] = value
    ops = {
        k: v.astype(np.float64 if isinstance(value, float) else np.int64) for k, v in ops.items()
    }
    if operand == "length":
        ops[operand][3] = value
        index = "3"
    else:
        ops[operand][3, 2] = value
        index = "3, 2"
    expect = with_row(per_line_message(gouraud.shade_line, **row, cfg=cfg), operand, index)
    got = per_line_message(gouraud.shade_lines, **ops, cfg=cfg)
    assert got == expect and "\n" not in got


@pytest.mark.parametrize(("operand", "value"), [("a", 1 << 20), ("k", 0), ("k", 2048)])
def test_divide_many_bad_element_gives_the_divide_message_and_the_index(operand, value) -> None:
    a = np.array([[5, 6], [7, 8]])
    k = np.array([[1, 2], [3, 4]])
    ops = {"a": a, "k": k}
    single = {"a": 8, "k": 4, operand: value}
    ops[operand][1, 1] = value
    expect = with_row(per_line_message(divider.divide, **single), operand, "1, 1")
    assert per_line_message(divider.divide_many, **ops) == expect


def test_shapes_are_checked() -> None:
    two = np.zeros(2, dtype=np.int64)
    with pytest.raises(ValueError, match=r"^operand shapes are out of range: got c \(2,\), dz \("):
        specular.shade_lines(two, two, two, two, np.zeros(3, np.int64))
    with pytest.raises(ValueError, match=r"operand shapes are out of range"):
        specular.shade_lines(5, 0, 0, 1, 0)  # a single line is shade_line's job
    with pytest.raises(ValueError, match=r"i0, di may be \(L, C\), alike"):
        gouraud.shade_lines(np.zeros((2, 3), int), np.zeros((2, 2), int), two + 1)
    with pytest.raises(ValueError, match=r"i0, di may be \(L, C\), alike"):
        gouraud.shade_lines(np.zeros((2, 3), int), two, two + 1)
    with pytest.raises(ValueError, match=r"got a \(2,\), k \(3,\); legal are arrays of one shape"):
        divider.divide_many(two, np.ones(3, np.int64))
