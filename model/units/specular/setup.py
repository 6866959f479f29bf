# SPDX-License-Identifier: Apache-2.0
"""Specular unit: the float set-up of the patent's "external device", from end vectors to registers.

Owns ``setup_line`` / ``setup_lines`` (N, H at the line's ends -> the registers C, dz, z0 of
``C cos^n(z0 + t dz)``), the geometry they rest on (``half_vector_path``, ``rotation_onto`` and
their numba kernels), the results ``LineSetup`` / ``LineSetups`` and the float reference
``blinn_line``.  Float arithmetic only; the register words come from ``SpecularConfig``'s
formats.  May import numpy, numba, ``model.units.fixed`` and ``config``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from model.units import fixed
from model.units.specular.config import DEFAULT, N_MAX, SpecularConfig

_EPS = 1e-12
MIN_NORM = _EPS
"""The shortest end vector the set-up takes (``setup_line`` refuses shorter ones)."""


@dataclass(frozen=True)
class LineSetup:
    """The external device's result for one line: float values and the register words."""

    gamma: float  # angle between H1 and H2' (rad)
    lam: float  # lambda (rad), chosen so the line's angles lie in [-3pi/2, 3pi/2]
    amp: float  # A = max of N1.H on the great circle (>= 0)
    c: float  # C = light * (2**out_width - 1) * A**n, output LSBs
    dz: float  # gamma / l in units of pi/2 (0 for l = 0)
    z0: float  # -lambda in units of pi/2
    c_reg: int
    dz_reg: int
    z0_reg: int
    n: int
    length: int

    def registers(self) -> dict[str, int]:
        """The operand registers of the unit: c, dz, z0, n, len."""
        return {
            "c": self.c_reg,
            "dz": self.dz_reg,
            "z0": self.z0_reg,
            "n": self.n,
            "len": self.length,
        }


def _unit_vector(name: str, v) -> np.ndarray:
    arr = np.asarray(v, dtype=np.float64)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} = {v!r} is out of range: legal is a finite 3-vector")
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(arr))
    if math.isinf(norm):  # (0, 0, 1e300): scale first, then it normalises like any other
        arr = arr / np.abs(arr).max()
        norm = float(np.linalg.norm(arr))
    if norm < _EPS:
        raise ValueError(
            f"{name} = {v!r} is out of range: legal is a non-zero 3-vector (length >= {_EPS:g})"
        )
    return arr / norm


def _scaled_rows(arr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows, their lengths), rows whose length overflows (a normal (0, 0, 1e300)) first
    divided by their largest component, so that they normalise like any other; the other rows
    are untouched (the same float values as a plain ``arr / norm``)."""
    with np.errstate(over="ignore"):
        norm = np.linalg.norm(arr, axis=1)
    big = np.isinf(norm)
    if big.any():
        arr = arr.copy()
        arr[big] /= np.abs(arr[big]).max(axis=1, keepdims=True)
        norm[big] = np.linalg.norm(arr[big], axis=1)
    return arr, norm


# The geometry works on scalars (x, y, z tuples, no arrays): a numba kernel then allocates
# nothing per line, and each step is the same float operation in the same order as the vector
# formula its docstring gives, so the bits are those of that formula.


@njit(cache=True, inline="always")
def _dot(ax: float, ay: float, az: float, bx: float, by: float, bz: float) -> float:
    return ax * bx + ay * by + az * bz


@njit(cache=True, inline="always")
def _cross(ax: float, ay: float, az: float, bx: float, by: float, bz: float):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@njit(cache=True)
def _perp(vx: float, vy: float, vz: float):
    """A fixed unit vector perpendicular to v: v x e, e the coordinate axis least aligned with v
    (the first of them on a tie)."""
    ex, ey, ez = 1.0, 0.0, 0.0
    if abs(vy) < abs(vx) and abs(vy) <= abs(vz):
        ex, ey = 0.0, 1.0
    elif abs(vz) < abs(vx) and abs(vz) < abs(vy):
        ex, ez = 0.0, 1.0
    px, py, pz = _cross(vx, vy, vz, ex, ey, ez)
    norm = np.sqrt(_dot(px, py, pz, px, py, pz))
    return px / norm, py / norm, pz / norm


@njit(cache=True)
def _rotate(sx, sy, sz, dx, dy, dz, vx, vy, vz):
    """v rotated by the rotation taking unit vector src onto dst (Rodrigues, axis src x dst).

    R v = c v + s (k x v) + (1 - c) k (k . v).  src = dst: identity.  src = -dst (axis
    undefined): the half turn about the fixed perpendicular ``_perp(dst)``.
    """
    ax, ay, az = _cross(sx, sy, sz, dx, dy, dz)
    s = np.sqrt(_dot(ax, ay, az, ax, ay, az))
    c = _dot(sx, sy, sz, dx, dy, dz)
    if s < _EPS:
        if c > 0:
            return vx, vy, vz
        ux, uy, uz = _perp(dx, dy, dz)
        f = 2.0 * _dot(ux, uy, uz, vx, vy, vz)
        return f * ux - vx, f * uy - vy, f * uz - vz
    kx, ky, kz = ax / s, ay / s, az / s
    cx, cy, cz = _cross(kx, ky, kz, vx, vy, vz)
    f = (1.0 - c) * _dot(kx, ky, kz, vx, vy, vz)
    return c * vx + s * cx + f * kx, c * vy + s * cy + f * ky, c * vz + s * cz + f * kz


@njit(cache=True)
def _path(n1: np.ndarray, n2: np.ndarray, h1: np.ndarray, h2: np.ndarray):
    """(Wx, Wy, Wz, gamma) of ``half_vector_path`` for unit (3,) vectors."""
    rx, ry, rz = _rotate(n2[0], n2[1], n2[2], n1[0], n1[1], n1[2], h2[0], h2[1], h2[2])
    cg = _dot(h1[0], h1[1], h1[2], rx, ry, rz)
    wx, wy, wz = rx - cg * h1[0], ry - cg * h1[1], rz - cg * h1[2]
    sg = np.sqrt(_dot(wx, wy, wz, wx, wy, wz))
    if sg >= 1e-9:
        return wx / sg, wy / sg, wz / sg, np.arctan2(sg, cg)
    if cg > 0:
        return 0.0, 0.0, 0.0, 0.0
    d = _dot(n1[0], n1[1], n1[2], h1[0], h1[1], h1[2])
    wx, wy, wz = n1[0] - d * h1[0], n1[1] - d * h1[1], n1[2] - d * h1[2]
    wn = np.sqrt(_dot(wx, wy, wz, wx, wy, wz))
    if wn >= 1e-9:
        return wx / wn, wy / wn, wz / wn, np.pi
    px, py, pz = _perp(h1[0], h1[1], h1[2])
    return px, py, pz, np.pi


@njit(cache=True)
def _setup_kernel(
    n1: np.ndarray,
    n2: np.ndarray,
    h1: np.ndarray,
    h2: np.ndarray,
    n: np.ndarray,
    light: np.ndarray,
    length: np.ndarray,
    out_max: int,
    out: np.ndarray,
) -> None:
    """The external device for each row (unit vectors): out[i] = gamma, lambda, A, C, dz, z0.

    See ``setup_line`` for the formulas and the degenerate cases.
    """
    for i in range(n.size):
        setup_row(n1[i], n2[i], h1[i], h2[i], n[i], light[i], length[i], out_max, out[i])


@njit(cache=True)
def setup_row(
    n1: np.ndarray,
    n2: np.ndarray,
    h1: np.ndarray,
    h2: np.ndarray,
    n: int,
    light: float,
    length: int,
    out_max: int,
    out: np.ndarray,
) -> None:
    """One row of ``setup_lines``' kernel (unit (3,) vectors, checked operands): ``out[:6]`` =
    gamma, lambda, A, C, dz, z0; public for fused renderers (the same code, so the same bits).
    Before the registers, C, dz and z0 take ``c_format.quantise`` and ``z_format.quantise``."""
    wx, wy, wz, gamma = _path(n1, n2, h1, h2)
    cos1 = _dot(n1[0], n1[1], n1[2], h1[0], h1[1], h1[2])
    nw = _dot(n1[0], n1[1], n1[2], wx, wy, wz)
    amp = min(1.0, np.hypot(cos1, nw))
    lam = np.arctan2(nw, cos1)
    if gamma / 2 - lam > np.pi:
        lam += 2 * np.pi
    out[0] = gamma
    out[1] = lam
    out[2] = amp
    out[3] = light * out_max * amp**n
    out[4] = (gamma / length) / (np.pi / 2) if length > 0 else 0.0
    out[5] = -lam / (np.pi / 2)


def rotation_onto(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """The rotation matrix taking unit vector src onto dst (Rodrigues, axis src x dst).

    src = dst: identity.  src = -dst (axis undefined): the half turn about the fixed
    perpendicular ``_perp(dst)``.  Its columns are ``_rotate`` of the basis.
    """
    src, dst = np.asarray(src, dtype=np.float64), np.asarray(dst, dtype=np.float64)
    return np.array([_rotate(*src, *dst, *e) for e in np.eye(3)]).T


def half_vector_path(n1, n2, h1, h2) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(N1, H1, W, gamma): along the line H(t) = H1 cos(t gamma) + W sin(t gamma), N = N1.

    H2' = H2 rotated by the rotation taking N2 onto N1; gamma = angle(H1, H2'); W the unit vector
    perpendicular to H1 towards H2'.  gamma -> 0: W = 0 (H is constant).  gamma -> pi (H2' =
    -H1, the great circle undefined): W = the part of N1 perpendicular to H1 (the path passes the
    highlight's peak), or a fixed perpendicular if N1 is parallel to H1.
    """
    n1u, n2u = _unit_vector("n1", n1), _unit_vector("n2", n2)
    h1u, h2u = _unit_vector("h1", h1), _unit_vector("h2", h2)
    wx, wy, wz, gamma = _path(n1u, n2u, h1u, h2u)
    return n1u, h1u, np.array([wx, wy, wz]), float(gamma)


@dataclass(frozen=True)
class LineSetups:
    """``setup_lines``' result: one row per line, float values and register words."""

    gamma: np.ndarray
    lam: np.ndarray
    amp: np.ndarray
    c: np.ndarray
    dz: np.ndarray
    z0: np.ndarray
    c_reg: np.ndarray
    dz_reg: np.ndarray
    z0_reg: np.ndarray


def _unit_rows(name: str, v) -> np.ndarray:
    arr = np.asarray(v, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 3 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} is out of range: legal is an (S, 3) array of finite vectors")
    scaled, norm = _scaled_rows(arr)
    if arr.shape[0] and norm.min() < _EPS:
        bad = int(np.argmin(norm))
        raise ValueError(
            f"{name}[{bad}] = {arr[bad].tolist()} is out of range: legal is a non-zero 3-vector "
            f"(length >= {_EPS:g})"
        )
    return scaled / norm[:, None]


def setup_lines(n1, n2, h1, h2, n, light, length, cfg: SpecularConfig = DEFAULT) -> LineSetups:
    """``setup_line`` for S lines at once: (S, 3) end vectors, (S,) n, light and l."""
    vecs = [_unit_rows(name, v) for name, v in (("n1", n1), ("n2", n2), ("h1", h1), ("h2", h2))]
    rows = vecs[0].shape[0]
    if any(v.shape[0] != rows for v in vecs):
        raise ValueError("n1, n2, h1, h2 must have the same number of rows")
    n_arr = np.broadcast_to(fixed.check_operand("n", n, 1, N_MAX), (rows,))
    len_arr = np.broadcast_to(fixed.check_operand("length", length, 0, cfg.len_max), (rows,))
    light_arr = np.broadcast_to(np.asarray(light, dtype=np.float64), (rows,))
    if not np.all(np.isfinite(light_arr)) or (rows and light_arr.min() < 0):
        raise ValueError(f"light = {light!r} is out of range: legal is a finite value >= 0")
    out = np.empty((rows, 6))
    # Contiguous, writeable copies whatever the caller passed (a broadcast view is read-only,
    # and a read-only array is another numba signature: compiled once more on a cold start)
    _setup_kernel(
        *vecs,
        np.require(n_arr, np.int64, ("C", "W")),
        np.require(light_arr, np.float64, ("C", "W")),
        np.require(len_arr, np.int64, ("C", "W")),
        cfg.out_max,
        out,
    )
    gamma, lam, amp, c, dz, z0 = out.T
    return LineSetups(
        gamma=gamma,
        lam=lam,
        amp=amp,
        c=c,
        dz=dz,
        z0=z0,
        c_reg=np.asarray(cfg.c_format.quantise(c), dtype=np.int64).reshape(rows),
        dz_reg=np.asarray(cfg.z_format.quantise(dz), dtype=np.int64).reshape(rows),
        z0_reg=np.asarray(cfg.z_format.quantise(z0), dtype=np.int64).reshape(rows),
    )


def setup_line(
    n1, n2, h1, h2, n: int, light: float, length: int, cfg: SpecularConfig = DEFAULT
) -> LineSetup:
    """The float "external device": register values of one line from its end vectors.

    ``n1``, ``h1``: normal and half-vector at the start pixel; ``n2``, ``h2`` at the end pixel
    (normalised here); ``n`` the specular exponent; ``light`` = I_l * k_s (1 = full scale);
    ``length`` the number of intervals l.  N.H(t) = A cos(t gamma - lambda) along the line, so
    I = C cos^n(zeta) with C = light * (2**out_width - 1) * A**n, zeta(0) = -lambda and
    dz = gamma / l.

    With N.W the component of N1 along the path's direction W, A = hypot(cos theta1, N.W) and
    lambda = atan2(N.W, cos theta1): the patent's lambda = arctan P and A = cos theta1 / cos lambda
    whenever cos theta1 > 0, and still defined when cos theta1 <= 0.  lambda is then moved by
    2 pi so that the middle of the line's angles lies in (-pi, pi]: every angle of the line is
    in [-3pi/2, 3pi/2], where cos > 0 exactly for |zeta| < pi/2, the range the unit lights.
    Degenerate cases (each gives finite registers, never NaN): gamma -> 0 (constant H: dz = 0),
    gamma -> pi and N1 = -N2 (see ``half_vector_path`` and ``rotation_onto``), cos theta1 <= 0
    (A, lambda from atan2; A = 0 gives C = 0), l = 0 (dz = 0, one pixel).  C beyond the C
    register saturates.  One implementation with ``setup_lines`` (a one-row batch).
    """
    n_i = int(fixed.check_operand("n", n, 1, N_MAX))
    len_i = int(fixed.check_operand("length", length, 0, cfg.len_max))
    if not isinstance(light, int | float | np.floating) or not math.isfinite(light) or light < 0:
        raise ValueError(f"light = {light!r} is out of range: legal is a finite value >= 0")
    vecs = [
        _unit_vector(name, v)[None, :]
        for name, v in (("n1", n1), ("n2", n2), ("h1", h1), ("h2", h2))
    ]
    rows = setup_lines(*vecs, n_i, float(light), len_i, cfg)
    return LineSetup(
        gamma=float(rows.gamma[0]),
        lam=float(rows.lam[0]),
        amp=float(rows.amp[0]),
        c=float(rows.c[0]),
        dz=float(rows.dz[0]),
        z0=float(rows.z0[0]),
        c_reg=int(rows.c_reg[0]),
        dz_reg=int(rows.dz_reg[0]),
        z0_reg=int(rows.z0_reg[0]),
        n=n_i,
        length=len_i,
    )


def blinn_line(n1, n2, h1, h2, n: int, light: float, length: int, out_max: int = 255) -> np.ndarray:
    """Float reference: light * out_max * max(0, N1.H(t))**n at the l+1 pixels, H(t) on the
    great circle of ``half_vector_path`` (vector arithmetic, no lambda or A involved)."""
    n1u, h1u, w, gamma = half_vector_path(n1, n2, h1, h2)
    t = np.arange(length + 1) / length if length > 0 else np.zeros(1)
    h = np.outer(np.cos(t * gamma), h1u) + np.outer(np.sin(t * gamma), w)
    return light * out_max * np.maximum(h @ n1u, 0.0) ** n
