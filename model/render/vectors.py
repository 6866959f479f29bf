# SPDX-License-Identifier: Apache-2.0
"""Vector kernels and the lighting set-up shared by the rasteriser and the shaders.

Owns the numba kernels on unit 3-vectors (``norm3``, ``slerp3``, ``light_view``, ``half``, their
batched ``slerp``), the light and viewer as the kernels take them (``LightingParams``,
``LIGHT_DIRECTIONAL``, ``LIGHT_POINT``) and the per-point lighting (``lighting_vectors``,
``vertex_lighting``).  May import numpy, numba and ``model.render.scene``.  The kernels are public
because the rasteriser (``model.render.raster``) and the float reference shaders
(``model.render.reference``) call them from their own kernels: one definition of slerp and of H.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from model.render.scene import Material, Scene

LIGHT_DIRECTIONAL, LIGHT_POINT = 0, 1


# ------------------------------------------------------------------------------------------------
# vector kernels (numba; also usable un-jitted)


@njit(cache=True)
def norm3(x: float, y: float, z: float) -> tuple[float, float, float]:
    length = np.sqrt(x * x + y * y + z * z)
    if length < 1e-300:
        return 0.0, 0.0, 0.0
    return x / length, y / length, z / length


@njit(cache=True)
def slerp3(
    ax: float, ay: float, az: float, bx: float, by: float, bz: float, t: float
) -> tuple[float, float, float]:
    """Spherical interpolation of unit vectors a -> b at t in [0, 1] (constant angular speed).

    t = 0 and t = 1 return a and b exactly.  Nearly identical vectors (angle < 1e-9) are lerped
    and normalised.  Antipodal vectors (angle within 1e-9 of pi, the great circle undefined) turn
    about a fixed axis: a x e, e the coordinate axis least aligned with a.
    """
    if t == 0.0:
        return ax, ay, az
    if t == 1.0:
        return bx, by, bz
    cx = ay * bz - az * by
    cy = az * bx - ax * bz
    cz = ax * by - ay * bx
    sin_w = np.sqrt(cx * cx + cy * cy + cz * cz)
    cos_w = ax * bx + ay * by + az * bz
    w = np.arctan2(sin_w, cos_w)
    if w < 1e-9:
        return norm3(ax + t * (bx - ax), ay + t * (by - ay), az + t * (bz - az))
    if np.pi - w < 1e-9:
        # Antipodal: rotate a by t*pi about an axis perpendicular to a.
        aax, aay, aaz = abs(ax), abs(ay), abs(az)
        if aax <= aay and aax <= aaz:
            px, py, pz = 0.0, az, -ay  # a x (1,0,0)
        elif aay <= aaz:
            px, py, pz = -az, 0.0, ax  # a x (0,1,0)
        else:
            px, py, pz = ay, -ax, 0.0  # a x (0,0,1)
        px, py, pz = norm3(px, py, pz)
        c = np.cos(np.pi * t)
        s = np.sin(np.pi * t)
        return norm3(c * ax + s * px, c * ay + s * py, c * az + s * pz)
    s = np.sin(w)
    fa = np.sin((1.0 - t) * w) / s
    fb = np.sin(t * w) / s
    return norm3(fa * ax + fb * bx, fa * ay + fb * by, fa * az + fb * bz)


@njit(cache=True)
def _slerp_rows(a: np.ndarray, b: np.ndarray, t: np.ndarray, out: np.ndarray) -> None:
    for i in range(t.size):
        out[i, 0], out[i, 1], out[i, 2] = slerp3(
            a[i, 0], a[i, 1], a[i, 2], b[i, 0], b[i, 1], b[i, 2], t[i]
        )


def slerp(a, b, t) -> np.ndarray:
    """Spherical interpolation of unit 3-vectors, broadcasting ``a`` (..., 3), ``b`` (..., 3) and
    ``t`` (...).  The same kernel the rasteriser and the reference shaders use."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1], t.shape)
    aa = np.ascontiguousarray(np.broadcast_to(a, (*shape, 3)).reshape(-1, 3))
    bb = np.ascontiguousarray(np.broadcast_to(b, (*shape, 3)).reshape(-1, 3))
    tt = np.ascontiguousarray(np.broadcast_to(t, shape).reshape(-1))
    out = np.empty((tt.size, 3))
    _slerp_rows(aa, bb, tt, out)
    return out.reshape((*shape, 3))


@njit(cache=True)
def light_view(
    px: float,
    py: float,
    pz: float,
    light_kind: int,
    lvec: np.ndarray,
    viewer_local: int,
    vvec: np.ndarray,
) -> tuple[float, float, float, float, float, float]:
    """(L, V) at world point P.  ``lvec``: L (directional) or the light position (point);
    ``vvec``: V (viewer at infinity) or the eye (local viewer)."""
    if light_kind == LIGHT_DIRECTIONAL:
        lx, ly, lz = lvec[0], lvec[1], lvec[2]
    else:
        lx, ly, lz = norm3(lvec[0] - px, lvec[1] - py, lvec[2] - pz)
    if viewer_local == 0:
        vx, vy, vz = vvec[0], vvec[1], vvec[2]
    else:
        vx, vy, vz = norm3(vvec[0] - px, vvec[1] - py, vvec[2] - pz)
    return lx, ly, lz, vx, vy, vz


@njit(cache=True)
def half(
    lx: float, ly: float, lz: float, vx: float, vy: float, vz: float
) -> tuple[float, float, float]:
    """H = (L + V) / |L + V|; when L = -V (undefined) H = V."""
    hx, hy, hz = norm3(lx + vx, ly + vy, lz + vz)
    if hx == 0.0 and hy == 0.0 and hz == 0.0:
        return vx, vy, vz
    return hx, hy, hz


# ------------------------------------------------------------------------------------------------
# lighting set-up shared by the rasteriser and the shaders


@dataclass(frozen=True, eq=False)
class LightingParams:
    """The light and viewer as the kernels take them."""

    light_kind: int  # LIGHT_DIRECTIONAL | LIGHT_POINT
    lvec: np.ndarray  # L (directional) or light position (point)
    viewer_local: int  # 0: viewer at infinity, 1: local viewer
    vvec: np.ndarray  # V (infinite) or the eye position (local)
    intensity: float  # I_l

    @staticmethod
    def of(scene: Scene) -> LightingParams:
        light = scene.light
        cam = scene.camera
        if light.kind == "directional":
            kind, lvec = LIGHT_DIRECTIONAL, np.array(light.direction)
        else:
            kind, lvec = LIGHT_POINT, np.array(light.position)
        if scene.viewer == "infinite":
            local = 0
            v = np.subtract(cam.eye, cam.target)
            vvec = v / np.linalg.norm(v)
        else:
            local, vvec = 1, np.array(cam.eye, dtype=np.float64)
        return LightingParams(kind, lvec.astype(np.float64), local, vvec, float(light.intensity))

    @property
    def constant_half_vector(self) -> bool:
        """True when H is the same everywhere (directional light, viewer at infinity)."""
        return self.light_kind == LIGHT_DIRECTIONAL and self.viewer_local == 0


@njit(cache=True)
def _vectors_kernel(p: np.ndarray, kind: int, lvec, local: int, vvec, out: np.ndarray) -> None:
    for i in range(p.shape[0]):
        lx, ly, lz, vx, vy, vz = light_view(p[i, 0], p[i, 1], p[i, 2], kind, lvec, local, vvec)
        hx, hy, hz = half(lx, ly, lz, vx, vy, vz)
        out[i, 0], out[i, 1], out[i, 2] = lx, ly, lz
        out[i, 3], out[i, 4], out[i, 5] = vx, vy, vz
        out[i, 6], out[i, 7], out[i, 8] = hx, hy, hz


def lighting_vectors(
    points: np.ndarray, params: LightingParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(L, V, H) unit vectors at world points (..., 3)."""
    pts = np.asarray(points, dtype=np.float64)
    # C-contiguous and writable: a read-only view (a broadcast, a frozen mesh's array) would
    # make numba compile the kernel a second time for its read-only type
    flat = np.require(pts.reshape(-1, 3), requirements=("C", "W"))
    out = np.empty((flat.shape[0], 9))
    _vectors_kernel(flat, params.light_kind, params.lvec, params.viewer_local, params.vvec, out)
    out = out.reshape((*pts.shape[:-1], 9))
    return out[..., 0:3], out[..., 3:6], out[..., 6:9]


def vertex_lighting(
    normals: np.ndarray, points: np.ndarray, material: Material, params: LightingParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per vertex: the Gouraud ambient + diffuse colour (..., 3) in 8-bit levels, the specular
    term (...) in levels, and H (..., 3)."""
    lv, _, hv = lighting_vectors(points, params)
    ndl = np.maximum(0.0, np.einsum("...k,...k->...", normals, lv))
    ndh = np.maximum(0.0, np.einsum("...k,...k->...", normals, hv))
    col = np.asarray(material.colour)
    gour = 255.0 * col * (material.ambient + material.k_d * params.intensity * ndl)[..., None]
    spec = 255.0 * material.k_s * params.intensity * ndh**material.n
    return gour, spec, hv
