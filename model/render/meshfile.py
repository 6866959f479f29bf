# SPDX-License-Identifier: Apache-2.0
"""Mesh files as people have them: every triangle format trimesh reads, repaired, oriented, framed.

Owns ``read_mesh`` (a file to a ``LoadedMesh``: the ``Mesh``, what was repaired, which way is
up), ``load_mesh`` (just the mesh), ``repair`` (the repairs on plain arrays, with their
``Repairs`` tally), ``orient`` and ``up_rotation`` (an up axis to the renderer's +z),
``auto_up`` (the up axis a file implies) and ``normalise`` (centred, unit size).  May import numpy,
trimesh (with scipy, its fast paths) and ``model.render.scene``.

The formats (``MESH_FORMATS``): whatever trimesh reads as triangles — OBJ, PLY, OFF, STL (binary
and ASCII), GLB and glTF; polygons are triangulated by trimesh, a file of several meshes (an
OBJ's objects, a glTF's nodes) becomes one mesh with each node's transform applied.  An OFF file
is first cleaned into what trimesh's OFF reader handles (``_off_text``: comments out, polygons
fanned into triangles, face colours dropped; a 4-D ``4OFF`` refused).

Repairs (``repair``): a broken file is refused with its name and what was expected, but messy
geometry never is on its own.  In order:

1. a non-finite coordinate is refused (``ValueError`` naming the file and the vertex index);
2. degenerate faces are dropped: a repeated corner, or an area below 1e-12 of the bounding box's
   diagonal squared;
3. duplicate faces are dropped: the same three corners in the same cyclic order (a face and its
   reverse are the two sides of a sheet, both kept);
4. vertices no face uses are removed;
5. normals: the file's where it has them; a zero or non-finite one is recomputed from the faces
   around its vertex (area-weighted), or is the normal of one of its faces when those cancel.  A
   file without normals gets trimesh's smooth normals, split at edges sharper than
   ``CREASE_DEGREES`` (``trimesh.Trimesh.smooth_shaded``) so a box stays a box; coincident
   vertices are welded first (an STL stores every triangle's corners apart).

``Repairs.summary()`` is the one line the command line prints.

Orientation (``UP_AXES``): the renderer's world is z-up.  ``up`` names the file's up axis
(``x``, ``y``, ``z`` or negated) and ``orient`` turns it to +z by a proper rotation (for ``y``:
(x, y, z) -> (x, -z, y), the usual y-up to z-up turn: the model's front, +z, faces the default
camera at -y).  ``auto`` takes the format's own convention where it has one (glTF: +y up), else
the signed axis whose lowest slab holds a clearly flat base (``auto_up``), else z: a heuristic for
scanned and modelled objects that stand on something, printed with its reason, and overridden by
naming the axis.
``normalise`` centres the bounding box on the origin and scales its largest side to 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.render.scene import Mesh, check_choice

UP_AXES = ("auto", "x", "y", "z", "-x", "-y", "-z")
MESH_FORMATS = (".obj", ".ply", ".off", ".stl", ".glb", ".gltf")
"""File suffixes read (trimesh's triangle formats)."""
Y_UP_FORMATS = (".glb", ".gltf")
"""Formats whose specification fixes the up axis: glTF 2.0 is +y up."""
CREASE_DEGREES = 30.0
"""Computed normals are split at edges whose faces turn more than this (trimesh's default)."""
DEGENERATE_AREA = 1e-12
"""A face is degenerate below this fraction of the bounding box's diagonal squared."""
BASE_SLAB = 0.01
"""``auto_up``: a base face lies within this fraction of the extent above the lowest point ..."""
BASE_COS = math.cos(math.radians(25.0))
"""... and faces down within 25 degrees ..."""
BASE_MIN_FILL, BASE_MARGIN = 0.05, 2.0
"""... and the winning base covers at least 5 % of the bounding box's footprint across the axis and
twice what the best base on another axis covers of its own (a tie between +a and -a, a shape with
two flat ends, is +a; a box, flat every way, has no clear base)."""


@dataclass
class Repairs:
    """What ``repair`` changed, counted."""

    degenerate_faces: int = 0
    duplicate_faces: int = 0
    unreferenced_vertices: int = 0
    normals_recomputed: int = 0
    welded_vertices: int = 0
    crease_splits: int = 0
    normals_from: str = "file"  # "file" | "computed"

    def summary(self) -> str:
        parts = []
        if self.degenerate_faces:
            parts.append(f"{self.degenerate_faces} degenerate faces dropped")
        if self.duplicate_faces:
            parts.append(f"{self.duplicate_faces} duplicate faces dropped")
        if self.unreferenced_vertices:
            parts.append(f"{self.unreferenced_vertices} unreferenced vertices removed")
        if self.normals_recomputed:
            parts.append(f"{self.normals_recomputed} zero or non-finite normals recomputed")
        fixes = "; ".join(parts) if parts else "nothing to repair"
        if self.normals_from == "computed":
            how = f"normals computed (smooth, split at edges over {CREASE_DEGREES:g} degrees"
            if self.welded_vertices:
                how += f"; {self.welded_vertices} coincident vertices welded first"
            if self.crease_splits:
                how += f"; {self.crease_splits} vertices split at sharp edges"
            fixes += f"; {how})"
        return fixes


@dataclass(frozen=True, eq=False)
class LoadedMesh:
    """A mesh file read by ``read_mesh``: the mesh, its repairs, the up axis used and how it was
    chosen, and the scale ``normalise`` applied (1.0 when not normalised)."""

    mesh: Mesh
    path: Path
    repairs: Repairs = field(default_factory=Repairs)
    up: str = "z"
    up_reason: str = "given"
    scale: float = 1.0

    def summary(self) -> str:
        """One line: the file, its size, what was repaired, the up axis."""
        m = self.mesh
        return (
            f"{self.path.name}: {m.n_triangles} triangles, {m.n_vertices} vertices; "
            f"{self.repairs.summary()}; up {_signed(self.up)} ({self.up_reason})"
        )


def _signed(axis: str) -> str:
    return axis if axis.startswith("-") else f"+{axis}"


# ------------------------------------------------------------------------------------------------
# reading


def _check_path(p: Path) -> None:
    legal = ", ".join(MESH_FORMATS)
    if p.suffix.lower() not in MESH_FORMATS:
        raise ValueError(
            f"path = '{p}' is not a mesh file this program reads: legal suffixes are {legal}"
        )
    if not p.is_file():
        raise ValueError(f"path = '{p}' does not exist: legal value is an existing mesh file")


def _quiet_trimesh() -> None:
    import logging

    logging.getLogger("trimesh").setLevel(logging.ERROR)


def _file_normals(tm) -> np.ndarray | None:
    """The vertex normals the file carried (trimesh keeps loaded ones in its cache), or None."""
    cached = tm._cache.cache.get("vertex_normals")  # trimesh: loaded normals live in the cache
    if cached is None or np.shape(cached) != np.shape(tm.vertices):
        return None
    return np.asarray(cached, dtype=np.float64)


def _off_text(p: Path):
    """An OFF file as trimesh's OFF reader wants it: no comments (it takes a ``#`` and what
    follows as numbers: geomview's own files, with comments after the header or after a vertex,
    come out wrong or not at all) and triangles only (``_off_triangles``); a 4-D or n-D OFF
    (header ``4OFF``, ``nOFF``) is refused, its vertices are not points in space."""
    import io

    try:
        text = p.read_text(errors="strict")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"path = '{p}' could not be read as OFF: {exc}") from None
    lines = [line.split("#", 1)[0] for line in text.splitlines()]
    header = next((line.split()[0] for line in lines if line.split()), "")
    if header.endswith("OFF") and ("4" in header or header.lstrip("CNST").startswith("n")):
        raise ValueError(
            f"path = '{p}' is a {header} file (4-D or n-D vertices): legal is a 3-D OFF file "
            "(header OFF, COFF, NOFF, CNOFF, STOFF)"
        )
    return io.StringIO("\n".join(_off_triangles(lines)) + "\n")


def _off_triangles(lines: list[str]) -> list[str]:
    """The OFF lines with every face a triangle: an n-gon becomes the fan of its n - 2 triangles,
    a face's colour after its corners is dropped (trimesh's reader fails on polygons of mixed
    sizes); unchanged when the counts cannot be read (trimesh then says what is wrong)."""
    rows = [line.split() for line in lines if line.split()]
    try:
        inline = len(rows[0]) > 1  # "OFF 8 6 12" on one line
        head = rows[0][1:] if inline else rows[1]
        start = 1 if inline else 2
        n_vertices, n_faces = int(head[0]), int(head[1])
        faces = rows[start + n_vertices : start + n_vertices + n_faces]
        triangles = [
            f"3 {row[1]} {row[k]} {row[k + 1]}" for row in faces for k in range(2, int(row[0]))
        ]
    except (IndexError, ValueError):
        return lines
    vertices = [" ".join(row) for row in rows[start : start + n_vertices]]
    return [rows[0][0], f"{n_vertices} {len(triangles)} 0", *vertices, *triangles]


def _read_arrays(p: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """(vertices, faces, normals or None) of every triangle mesh in the file, node transforms
    applied; ``ValueError`` naming the file when it cannot be read or holds no triangles."""
    import trimesh

    _quiet_trimesh()
    try:
        if p.suffix.lower() == ".off":
            loaded = trimesh.load(_off_text(p), file_type="off", process=False)
        else:
            loaded = trimesh.load(str(p), process=False)
    except ValueError as exc:
        if str(p) in str(exc):
            raise
        raise ValueError(
            f"path = '{p}' could not be read as {p.suffix.lower()[1:].upper()}: "
            + (" ".join(str(exc).split()) or type(exc).__name__)
        ) from None
    except Exception as exc:  # trimesh raises many types for a broken file
        why = " ".join(str(exc).split()) or type(exc).__name__
        raise ValueError(
            f"path = '{p}' could not be read as {p.suffix.lower()[1:].upper()}: {why}"
        ) from None
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray | None]] = []
    if isinstance(loaded, trimesh.Scene):
        for node in loaded.graph.nodes_geometry:
            matrix, name = loaded.graph[node]
            g = loaded.geometry.get(name)
            if not isinstance(g, trimesh.Trimesh) or len(g.faces) == 0:
                continue
            v = trimesh.transform_points(np.asarray(g.vertices, dtype=np.float64), matrix)
            n = _file_normals(g)
            if n is not None:
                n = n @ np.linalg.inv(np.asarray(matrix)[:3, :3])  # normals: inverse transpose
            parts.append((v, np.asarray(g.faces, dtype=np.int64), n))
    elif isinstance(loaded, trimesh.Trimesh) and len(loaded.faces):
        parts.append(
            (
                np.asarray(loaded.vertices, dtype=np.float64),
                np.asarray(loaded.faces, dtype=np.int64),
                _file_normals(loaded),
            )
        )
    if not parts:
        raise ValueError(f"path = '{p}' holds no triangle mesh: legal is a file with faces")
    offsets = np.cumsum([0] + [len(v) for v, _, _ in parts])
    vertices = np.concatenate([v for v, _, _ in parts])
    faces = np.concatenate([f + o for (_, f, _), o in zip(parts, offsets, strict=False)])
    if all(n is not None for _, _, n in parts):
        normals = np.concatenate([n for _, _, n in parts])
    else:
        normals = None
    return vertices, faces, normals


def read_mesh(
    path: str | Path, up: str = "z", normalise_size: bool = False, name: str | None = None
) -> LoadedMesh:
    """Read, repair and orient a mesh file (the module's docstring says how).

    ``up`` is the file's up axis (``UP_AXES``; ``auto`` infers it), turned to +z;
    ``normalise_size`` centres the mesh and scales its largest side to 2.  The defaults keep the
    file's coordinates.  ``ValueError`` for a file that cannot be used, naming it."""
    check_choice("up", up, UP_AXES)
    p = Path(path)
    _check_path(p)
    vertices, faces, normals = _read_arrays(p)
    try:
        vertices, faces, normals, repairs = repair(vertices, faces, normals)
    except ValueError as exc:
        raise ValueError(f"{p}: {exc}") from None
    reason = "given"
    if up == "auto":
        up, reason = auto_up(vertices, faces, p.suffix.lower())
    vertices, normals = orient(vertices, normals, up)
    scale = 1.0
    if normalise_size:
        vertices, scale = normalise(vertices)
    mesh = Mesh(vertices, faces, normals, name=name or p.stem)
    return LoadedMesh(mesh, p, repairs, up, reason, scale)


def load_mesh(path: str | Path, up: str = "z", normalise_size: bool = False) -> Mesh:
    """``read_mesh(...).mesh``: the repaired, oriented mesh of a file."""
    return read_mesh(path, up, normalise_size).mesh


# ------------------------------------------------------------------------------------------------
# repairs


def _face_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    p = vertices[faces]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])


def _area_weighted_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Per vertex, the sum of its faces' cross products (twice their area times their normal)."""
    cross = _face_cross(vertices, faces)
    out = np.zeros_like(vertices)
    for corner in range(3):
        for axis in range(3):
            out[:, axis] += np.bincount(
                faces[:, corner], weights=cross[:, axis], minlength=len(vertices)
            )
    return out


def repair(
    vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, Repairs]:
    """The repairs of the module's docstring on plain arrays: returns (vertices, faces, unit
    normals, ``Repairs``).  ``ValueError`` for a non-finite coordinate, a face index out of range,
    or no face left."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    fixes = Repairs(normals_from="file" if normals is not None else "computed")
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices shape = {v.shape} is not legal: legal shape is (V, 3)")
    if f.ndim != 2 or f.shape[1] != 3 or f.dtype.kind not in "iu":
        raise ValueError(f"faces shape = {f.shape} is not legal: legal is an integer (F, 3) array")
    f = f.astype(np.int64)
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"vertex {i} = {v[i].tolist()} is not finite ({int(bad.sum())} such vertices): "
            "legal coordinates are finite numbers"
        )
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        j = int(np.flatnonzero((f < 0).any(axis=1) | (f >= len(v)).any(axis=1))[0])
        raise ValueError(
            f"face {j} = {f[j].tolist()} refers to a vertex that does not exist: legal indices "
            f"are 0..{len(v) - 1}"
        )
    # 2. degenerate faces: a repeated corner, or (almost) no area
    diag = float(np.linalg.norm(np.ptp(v, axis=0))) if len(v) else 0.0
    area2 = np.linalg.norm(_face_cross(v, f), axis=1)
    repeated = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 0] == f[:, 2])
    degenerate = repeated | (area2 <= 2 * DEGENERATE_AREA * diag * diag)
    fixes.degenerate_faces = int(degenerate.sum())
    f = f[~degenerate]
    # 3. duplicate faces: the same corners in the same cyclic order
    if len(f):
        start = np.argmin(f, axis=1)
        rolled = np.stack([f[np.arange(len(f)), (start + k) % 3] for k in range(3)], axis=1)
        _, first = np.unique(rolled, axis=0, return_index=True)
        keep = np.zeros(len(f), dtype=bool)
        keep[first] = True
        fixes.duplicate_faces = int((~keep).sum())
        f = f[keep]  # order kept: first occurrences in file order
    if not len(f):
        dropped = f"{fixes.degenerate_faces} degenerate faces dropped"
        raise ValueError(
            f"no face is left after the repairs ({dropped}): legal is a mesh with at least one "
            "face of non-zero area"
        )
    # 4. unreferenced vertices
    used = np.zeros(len(v), dtype=bool)
    used[f.ravel()] = True
    fixes.unreferenced_vertices = int((~used).sum())
    new_index = np.cumsum(used) - 1
    v, f = v[used], new_index[f]
    if normals is not None:
        n = np.asarray(normals, dtype=np.float64)[used]
        n = _fix_normals(v, f, n, fixes)
    else:
        v, f, n = _computed_normals(v, f, fixes)
    return v, f, n, fixes


def _unit_rows(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    with np.errstate(over="ignore", invalid="ignore"):
        length = np.linalg.norm(n, axis=1)
    ok = np.isfinite(length) & (length > 1e-12)
    out = np.zeros_like(n)
    out[ok] = n[ok] / length[ok, None]
    return out, ok


def _fix_normals(v: np.ndarray, f: np.ndarray, n: np.ndarray, fixes: Repairs) -> np.ndarray:
    """The file's normals, made unit; the zero or non-finite ones recomputed from their faces."""
    finite = np.isfinite(n).all(axis=1)
    n, ok = _unit_rows(np.where(finite[:, None], n, 0.0))
    fixes.normals_recomputed = int((~ok).sum())
    if ok.all():
        return n
    around, ok_around = _unit_rows(_area_weighted_normals(v, f))
    n[~ok] = around[~ok]
    left = ~ok & ~ok_around  # faces that cancel around the vertex: take one face's normal
    if left.any():
        face_n, _ = _unit_rows(_face_cross(v, f))
        owner = np.full(len(v), -1)
        owner[f.ravel()] = np.repeat(np.arange(len(f)), 3)  # any face of the vertex
        n[left] = face_n[owner[left]]
    return n


def _computed_normals(
    v: np.ndarray, f: np.ndarray, fixes: Repairs
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weld coincident vertices, then trimesh's smooth normals split at sharp edges."""
    import trimesh

    _quiet_trimesh()
    _, first, inverse = np.unique(v, axis=0, return_index=True, return_inverse=True)
    if len(first) < len(v):
        order = np.argsort(first)  # keep the vertices in order of first appearance
        rank = np.empty_like(order)
        rank[order] = np.arange(order.size)
        fixes.welded_vertices = len(v) - len(first)
        v, f = v[first[order]], rank[inverse.ravel()][f]
    tm = trimesh.Trimesh(v, f, process=False)
    smooth = trimesh.graph.smooth_shade(tm, angle=np.radians(CREASE_DEGREES))
    fixes.crease_splits = len(smooth.vertices) - len(v)
    vn, ok = _unit_rows(np.asarray(smooth.vertex_normals, dtype=np.float64))
    if not ok.all():  # a vertex whose faces cancel: recompute like a bad file normal
        vn = _fix_normals(np.asarray(smooth.vertices), np.asarray(smooth.faces), vn, Repairs())
    return (
        np.asarray(smooth.vertices, dtype=np.float64),
        np.asarray(smooth.faces, dtype=np.int64),
        vn,
    )


# ------------------------------------------------------------------------------------------------
# orientation and size

_UP_ROTATIONS = {
    # rows: new x, y, z in old coordinates; each a proper rotation taking the axis to +z
    "z": ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    "-z": ((1, 0, 0), (0, -1, 0), (0, 0, -1)),
    "y": ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    "-y": ((1, 0, 0), (0, 0, 1), (0, -1, 0)),
    "x": ((0, 1, 0), (0, 0, 1), (1, 0, 0)),
    "-x": ((0, -1, 0), (0, 0, 1), (-1, 0, 0)),
}


def up_rotation(up: str) -> np.ndarray:
    """The 3 x 3 rotation taking the axis ``up`` (not ``auto``) to +z."""
    check_choice("up", up, UP_AXES[1:])
    return np.array(_UP_ROTATIONS[up], dtype=np.float64)


def orient(
    vertices: np.ndarray, normals: np.ndarray | None, up: str
) -> tuple[np.ndarray, np.ndarray | None]:
    """Vertices and normals turned so that ``up`` becomes +z (a copy; ``z`` changes nothing)."""
    if up == "z":
        return vertices, normals
    r = up_rotation(up)
    return vertices @ r.T, None if normals is None else normals @ r.T


def auto_up(vertices: np.ndarray, faces: np.ndarray, suffix: str = "") -> tuple[str, str]:
    """The up axis a mesh file implies, and why: the format's convention (glTF: +y), else the
    signed axis with a clearly flat base (``BASE_*``), else z."""
    if suffix in Y_UP_FORMATS:
        return "y", f"auto: {suffix[1:]} is +y up by its specification"
    cross = _face_cross(vertices, faces)
    area2 = np.linalg.norm(cross, axis=1)
    unit = cross / np.maximum(area2, 1e-300)[:, None]
    extents = np.ptp(vertices, axis=0)
    bases = {}
    for axis, name in enumerate("xyz"):
        coord = vertices[:, axis]
        extent = float(extents[axis]) or 1.0
        footprint = float(np.prod(np.delete(extents, axis))) or 1.0
        for sign in (1, -1):
            height = sign * coord[faces]  # along the candidate up
            low = height.min()
            flat = (height.max(axis=1) <= low + BASE_SLAB * extent) & (
                -sign * unit[:, axis] >= BASE_COS
            )
            fill = float(area2[flat].sum()) / 2 / footprint
            bases[name if sign > 0 else f"-{name}"] = fill
    ranked = sorted(bases.items(), key=lambda kv: kv[1], reverse=True)
    best, share = ranked[0]
    # The runner-up on another axis: a cylinder's two ends tie between +y and -y, both upright.
    second = max(s for name, s in ranked if name.lstrip("-") != best.lstrip("-"))
    if share >= BASE_MIN_FILL and share >= BASE_MARGIN * second:
        if bases[best.lstrip("-")] >= share:
            best = best.lstrip("-")  # two flat ends: the positive axis
        faces_down = best[1:] if best.startswith("-") else f"-{best}"
        return (
            best,
            f"auto: a flat base faces {faces_down}, covering {100 * share:.0f} % of the footprint",
        )
    return "z", "auto: no convention and no clear flat base, so z"


def normalise(vertices: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre the bounding box on the origin and scale its largest side to 2: (vertices, scale)."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    side = float((hi - lo).max())
    scale = 2.0 / side if side > 0 else 1.0
    return (vertices - (lo + hi) / 2) * scale, scale
