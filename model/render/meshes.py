# SPDX-License-Identifier: Apache-2.0
"""Meshes the renderer builds: the sphere, torus and domed quad, the Utah teapot, and a camera and
light that frame any mesh.

Owns the shape builders (``sphere_mesh``, ``torus_mesh``, ``domed_quad_mesh``, ``weld``), the
teapot (``read_bezier_patches``, ``tessellate_patches``, ``teapot_mesh``, ``TEAPOT_*`` and the
folder of the fetched data, ``DATA_DIR``), ``frame_camera`` and ``scene_from_mesh``.  May import
numpy, trimesh and ``model.render.scene``.  Mesh files are ``model.render.meshfile``; the
built-in scenes, files themselves, are ``model.render.scenefile``.

The teapot is the Utah teapot's 28 bicubic Bezier patches from Debian's geomview package,
fetched by ``scripts/fetch-teapot.sh`` into ``data/teapot.bez`` and tessellated here.  The
geomview teapot has no bottom patches: its base is open (invisible from the default camera, which
looks from above); the tessellation is manifold, consistently wound and oriented outwards.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from model.render.scene import (
    DEFAULT_HEIGHT,
    DEFAULT_WIDTH,
    Camera,
    Light,
    Material,
    Mesh,
    Scene,
    SceneObject,
    check_int,
    check_range,
    unit3,
)

REPO_ROOT = Path(__file__).resolve().parents[2]
# The fetched (not shipped) teapot: $SHADING_DATA/teapot.bez if set, else the checkout's data/.
DATA_DIR = Path(os.environ.get("SHADING_DATA", REPO_ROOT / "data"))
TEAPOT_PATH = DATA_DIR / "teapot.bez"
TEAPOT_FETCH = "scripts/fetch-teapot.sh"
TEAPOT_PATCHES = 28

# ------------------------------------------------------------------------------------------------
# meshes from files (trimesh) and from shapes


def sphere_mesh(radius: float = 1.0, subdivisions: int = 3) -> Mesh:
    """An icosphere (trimesh); the exact normals are the unit position vectors."""
    import trimesh

    check_range("radius", radius, 1e-6, 1e6)
    check_int("subdivisions", subdivisions, 0, 6)
    ico = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    unit = np.asarray(ico.vertices, dtype=np.float64)
    unit /= np.linalg.norm(unit, axis=1, keepdims=True)
    return Mesh(unit * radius, np.asarray(ico.faces), unit, name="sphere")


def _grid_triangles(rows: int, cols: int) -> np.ndarray:
    """Two triangles per cell of a (rows+1) x (cols+1) grid of vertices indexed i*(cols+1)+j,
    wound (i,j) -> (i+1,j) -> (i+1,j+1) so the face normal follows dP/du x dP/dv."""
    i, j = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    i, j = i.ravel(), j.ravel()
    stride = cols + 1
    a = i * stride + j
    b = (i + 1) * stride + j
    c = (i + 1) * stride + j + 1
    d = i * stride + j + 1
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int64)


def weld(
    points: np.ndarray, normals: np.ndarray, triangles: np.ndarray, tol: float = 1e-9
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge coincident vertices (within ``tol``), average their normals, drop triangles that
    became degenerate (two corners on one vertex, e.g. next to a Bezier patch pole)."""
    key = np.round(points / tol).astype(np.int64) if tol > 0 else points
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    # Keep the vertices in order of first appearance (a deterministic, readable numbering).
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    inverse = rank[inverse]
    merged_p = points[first[order]]
    summed = np.zeros_like(merged_p)
    np.add.at(summed, inverse, normals)
    length = np.linalg.norm(summed, axis=1, keepdims=True)
    # Normals of coincident samples that cancel exactly would be a bug in the surface: fall back.
    merged_n = np.where(length > 1e-12, summed / np.maximum(length, 1e-300), normals[first[order]])
    tri = inverse[triangles]
    ok = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])
    return merged_p, merged_n, tri[ok]


def torus_mesh(major: float = 1.0, minor: float = 0.4, segments: int = 48, rings: int = 24) -> Mesh:
    """A torus around the z axis with analytic normals; ``segments`` around the axis,
    ``rings`` around the tube."""
    check_range("major", major, 1e-6, 1e6)
    check_range("minor", minor, 1e-6, major)
    check_int("segments", segments, 3, 1024)
    check_int("rings", rings, 3, 1024)
    u = np.linspace(0.0, 2 * np.pi, segments + 1)
    v = np.linspace(0.0, 2 * np.pi, rings + 1)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    nrm = np.stack([np.cos(vv) * np.cos(uu), np.cos(vv) * np.sin(uu), np.sin(vv)], -1)
    ctr = np.stack([major * np.cos(uu), major * np.sin(uu), np.zeros_like(uu)], -1)
    pts = ctr + minor * nrm
    tri = _grid_triangles(segments, rings)  # the seam is closed by welding
    p, n, t = weld(pts.reshape(-1, 3), nrm.reshape(-1, 3), tri, tol=1e-9)
    return Mesh(p, t, n, name="torus")


def domed_quad_mesh(size: float = 4.0, bulge: float = 0.25, cells: int = 32) -> Mesh:
    """A large, gently domed square in the xy plane: z = bulge * (1 - (x^2 + y^2) / (size/2)^2),
    ``cells`` x ``cells`` cells, analytic normals (tilting up to ~atan(4*bulge/size) at the
    edges), facing +z."""
    check_range("size", size, 1e-6, 1e6)
    check_range("bulge", bulge, 0.0, size)
    check_int("cells", cells, 1, 1024)
    h = size / 2
    s = np.linspace(-h, h, cells + 1)
    x, y = np.meshgrid(s, s, indexing="ij")
    z = bulge * (1.0 - (x * x + y * y) / (h * h))
    pts = np.stack([x, y, z], -1).reshape(-1, 3)
    dzdx = -2 * bulge * x / (h * h)
    dzdy = -2 * bulge * y / (h * h)
    nrm = np.stack([-dzdx, -dzdy, np.ones_like(x)], -1).reshape(-1, 3)
    tri = _grid_triangles(cells, cells)  # (x, y) grid: winding faces +z
    return Mesh(pts, tri, nrm, name="quad")


# ------------------------------------------------------------------------------------------------
# the Utah teapot from geomview's Bezier patches


def read_bezier_patches(path: str | Path = TEAPOT_PATH) -> np.ndarray:
    """Read a geomview "BBP" file (bicubic Bezier patches): returns (P, 4, 4, 3) control points.

    The format: a first line "BBP", then 16 lines "x y z" per patch (row-major 4 x 4), patches
    separated by blank lines.  A file that breaks it raises ``ValueError`` naming the file, the
    line and what was expected there.
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(
            f"path = '{p}' does not exist: the teapot patches come from Debian's geomview package; "
            f"run `{TEAPOT_FETCH}` (or `make setup`) to fetch them"
        )
    try:
        text = p.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(
            f"{p}: cannot be read as a text file ({exc}): expected a BBP file"
        ) from None
    numbered = [(i, line.strip()) for i, line in enumerate(text.splitlines(), 1) if line.strip()]
    if not numbered or numbered[0][1] != "BBP":
        where, head = numbered[0] if numbered else (1, "")
        raise ValueError(f"{p}, line {where}: {head[:40]!r} is not legal: expected 'BBP'")
    points, first_line = [], []
    for i, line in numbered[1:]:
        fields = line.split()
        try:
            xyz = [float(f) for f in fields]
        except ValueError:
            xyz = []
        if len(xyz) != 3 or not all(map(math.isfinite, xyz)):
            raise ValueError(
                f"{p}, line {i}: {line[:60]!r} is not legal: expected three finite numbers "
                f"'x y z' (one control point; 16 per patch)"
            )
        if len(points) % 16 == 0:
            first_line.append(i)
        points.append(xyz)
    if not points:
        raise ValueError(
            f"{p}, line {numbered[0][0]}: 'BBP' and no control point after it: expected 16 "
            f"lines 'x y z' per patch"
        )
    if len(points) % 16:
        raise ValueError(
            f"{p}: {3 * len(points)} numbers is not legal: expected a multiple of 48 (16 points "
            f"x 3 per patch); the last patch, from line {first_line[-1]}, has "
            f"{len(points) % 16} of its 16 points"
        )
    return np.array(points, dtype=np.float64).reshape(-1, 4, 4, 3)


def _bernstein(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cubic Bernstein basis and its derivative at ``t``: two (len(t), 4) arrays."""
    s = 1.0 - t
    b = np.stack([s**3, 3 * t * s * s, 3 * t * t * s, t**3], -1)
    db = np.stack([-3 * s * s, 3 * s * s - 6 * t * s, 6 * t * s - 3 * t * t, 3 * t * t], -1)
    return b, db


def _patch_normals(ctrl: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    bu, dbu = _bernstein(u)
    bv, dbv = _bernstein(v)
    su = np.einsum("ui,ijk,vj->uvk", dbu, ctrl, bv)
    sv = np.einsum("ui,ijk,vj->uvk", bu, ctrl, dbv)
    return np.cross(su, sv)


def tessellate_patches(patches: np.ndarray, steps: int = 10) -> Mesh:
    """Tessellate bicubic Bezier patches ((P, 4, 4, 3) control points) into one welded mesh.

    Each patch is sampled on a (steps+1)^2 grid by Bernstein evaluation; the normal is the
    analytic ``dS/du x dS/dv``.  Where that cross product vanishes (a degenerate patch edge, such
    as the teapot's lid pole where a whole row of control points coincides) the normal is taken
    as the limit from inside the patch: it is evaluated at parameters moved 1e-4 towards the
    patch centre.  Triangles are wound to agree with the analytic normal, coincident vertices of
    neighbouring patches are welded (their normals averaged) and the triangles that collapse at a
    pole are dropped.  The teapot data's patches are all oriented outwards (dS/du x dS/dv points
    out of the body), which the tests check; no patch is flipped.
    """
    check_int("steps", steps, 1, 256)
    t = np.linspace(0.0, 1.0, steps + 1)
    bu, _ = _bernstein(t)
    pts_all, nrm_all, tri_all = [], [], []
    base = 0
    scale = float(np.ptp(patches.reshape(-1, 3), axis=0).max()) or 1.0
    for ctrl in patches:
        pts = np.einsum("ui,ijk,vj->uvk", bu, ctrl, bu)
        nrm = _patch_normals(ctrl, t, t)
        length = np.linalg.norm(nrm, axis=-1)
        bad = length < 1e-10 * scale * scale
        if bad.any():
            iu, iv = np.nonzero(bad)
            eps = 1e-4
            uu = np.clip(t[iu] + np.where(t[iu] < 0.5, eps, -eps), 0.0, 1.0)
            vv = np.clip(t[iv] + np.where(t[iv] < 0.5, eps, -eps), 0.0, 1.0)
            for k in range(iu.size):
                nrm[iu[k], iv[k]] = _patch_normals(ctrl, uu[k : k + 1], vv[k : k + 1])[0, 0]
        nrm = nrm / np.linalg.norm(nrm, axis=-1, keepdims=True)
        pts_all.append(pts.reshape(-1, 3))
        nrm_all.append(nrm.reshape(-1, 3))
        tri_all.append(_grid_triangles(steps, steps) + base)
        base += (steps + 1) ** 2
    p, n, tri = weld(
        np.concatenate(pts_all), np.concatenate(nrm_all), np.concatenate(tri_all), tol=1e-6
    )
    return Mesh(p, tri, n, name="teapot")


def teapot_mesh(steps: int = 10, path: str | Path = TEAPOT_PATH) -> Mesh:
    """The Utah teapot (geomview's 28 patches, z-up, no bottom patches) tessellated with
    ``steps`` x ``steps`` cells per patch."""
    patches = read_bezier_patches(path)
    if patches.shape[0] != TEAPOT_PATCHES:
        raise ValueError(
            f"{path}: patches = {patches.shape[0]} is not legal: the teapot has {TEAPOT_PATCHES}"
        )
    return tessellate_patches(patches, steps)


# ------------------------------------------------------------------------------------------------
# framing


def frame_camera(
    points: np.ndarray, direction, width: int, height: int, fov_y: float = 35.0, fill: float = 0.9
) -> Camera:
    """A camera on ``direction`` from the centre of the points' bounding box, at the distance
    where the points fill ``fill`` of the narrower image extent (found by bisection)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo)) / 2 or 1.0
    d = np.asarray(unit3("direction", direction))
    up = np.array([0.0, 0.0, 1.0])
    f = -d
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    tan_v = math.tan(math.radians(fov_y) / 2) * fill
    tan_h = tan_v * width / height
    rel = points - centre

    def fits(dist: float) -> bool:
        zc = dist - rel @ d
        return bool(np.all(np.abs(rel @ r) <= tan_h * zc) and np.all(np.abs(rel @ u) <= tan_v * zc))

    near, far = radius * 1.001, radius / math.sin(math.atan(min(tan_h, tan_v))) * 1.01
    for _ in range(50):
        mid = (near + far) / 2
        near, far = (near, mid) if fits(mid) else (mid, far)
    eye = centre + d * far
    return Camera(tuple(eye), tuple(centre), (0.0, 0.0, 1.0), fov_y, width, height)


def scene_from_mesh(
    mesh: Mesh,
    material: Material | None = None,
    width: int = DEFAULT_WIDTH,
    height: int = DEFAULT_HEIGHT,
    light: Light | None = None,
    viewer: str = "infinite",
) -> Scene:
    """A scene that frames one mesh: camera from the front-right-above, a light over the
    viewer's shoulder."""
    cam = frame_camera(mesh.vertices, (0.6, -1.0, 0.7), width, height)
    light = light or Light("directional", direction=(1.0, -0.6, 1.4))
    return Scene((SceneObject(mesh, material or Material()),), cam, light, viewer, name=mesh.name)
