# SPDX-License-Identifier: Apache-2.0
"""Scene description for the renderer: camera, light, viewer, materials and meshes as arrays.

Owns the checks every scene value goes through (``check_range``, ``check_int``, ``check_choice``,
``vector3``, ``unit3``), the frozen dataclasses ``Camera``, ``Light``, ``Material``, ``Mesh``,
``SceneObject`` and ``Scene``, and the limits (``N_MIN``..``N_MAX``, ``MAX_RESOLUTION``,
``MAX_LIGHT_INTENSITY``, ``DEFAULT_WIDTH`` x ``DEFAULT_HEIGHT``).  May import numpy (and trimesh
inside ``Mesh.to_trimesh``), nothing of the project: loading, building and framing meshes, and the
built-in scenes, are ``model.render.meshes``.

Everything is a frozen dataclass checked on construction: a bad value raises ``ValueError`` naming
the field, its value and the legal range (``"n = 0 is out of range: legal range is 1..1000"``), the
project's convention (``model.units.fixed.check_operand``).  Direction vectors that are not unit
length are normalised; a zero or non-finite vector, which cannot be normalised, is refused.

Conventions used by the rasteriser and the shaders (``model.render.raster``,
``model.render.reference``):

* World space is right-handed; the built-in scenes are z-up.
* ``Light.direction`` (directional light) points from the surface **towards** the light, i.e. it
  is the vector L itself.  A point light sits at ``Light.position``; L = normalise(position - P).
* Viewer "infinite": V = normalise(eye - target) everywhere (the usual hardware assumption that
  makes H constant with a directional light); "local": V = normalise(eye - P) per point.
* Lighting, in 8-bit levels (0..255 floats) per colour channel c:
  ``I_c = 255 * ( colour_c * (ambient + k_d * I_l * max(0, N.L)) + k_s * I_l * max(0, N.H)**n )``.
  Ambient and diffuse take the material colour, the specular highlight is white (the colour of
  the light).  The specular term is not gated by N.L (the patent's unit has no such gate).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

N_MIN, N_MAX = 1, 1000
MAX_RESOLUTION = 4096
"""Largest image side in pixels the scene accepts (an 'absurd' resolution is refused)."""
MAX_LIGHT_INTENSITY = 16.0
DEFAULT_WIDTH = 256
DEFAULT_HEIGHT = 256


# ------------------------------------------------------------------------------------------------
# checks


def _fmt(value) -> str:
    if isinstance(value, float | np.floating):
        return f"{float(value):g}"
    return repr(value)


def check_range(name: str, value, lo, hi) -> float:
    """Return ``value`` as a float, or raise ``ValueError`` unless it is finite and in [lo, hi]."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r} is not a number: legal range is {lo}..{hi}") from None
    if not math.isfinite(x) or not lo <= x <= hi:
        raise ValueError(f"{name} = {_fmt(value)} is out of range: legal range is {lo}..{hi}")
    return x


def check_int(name: str, value, lo: int, hi: int) -> int:
    """Return ``value`` as an int, or raise ``ValueError`` unless it is an integer in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        if isinstance(value, float | np.floating) and float(value).is_integer():
            value = int(value)
        else:
            raise ValueError(f"{name} = {value!r} must be an integer: legal range is {lo}..{hi}")
    if not lo <= int(value) <= hi:
        raise ValueError(f"{name} = {int(value)} is out of range: legal range is {lo}..{hi}")
    return int(value)


def check_choice(name: str, value, choices: Sequence[str]) -> str:
    if value not in choices:
        legal = " | ".join(repr(c) for c in choices)
        raise ValueError(f"{name} = {value!r} is not legal: legal values are {legal}")
    return value


def vector3(name: str, value) -> tuple[float, float, float]:
    """A finite 3-vector as a tuple of floats, or ``ValueError``."""
    arr = np.asarray(value, dtype=np.float64) if _is_numeric(value) else None
    if arr is None or arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} = {value!r} is not legal: legal value is a finite 3-vector")
    return (float(arr[0]), float(arr[1]), float(arr[2]))


def unit3(name: str, value) -> tuple[float, float, float]:
    """A 3-vector normalised to unit length; a zero (or tiny) vector cannot be and is refused."""
    v = np.asarray(vector3(name, value))
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(v))
    if math.isinf(norm):  # (0, 0, 1e300): scale first, then it normalises like any other
        v = v / np.abs(v).max()
        norm = float(np.linalg.norm(v))
    if norm < 1e-12:
        raise ValueError(
            f"{name} = {value!r} cannot be normalised: legal value is a finite non-zero 3-vector"
        )
    v = v / norm
    return (float(v[0]), float(v[1]), float(v[2]))


def _scaled_rows(arr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows, their lengths): a finite row whose length overflows (a normal (0, 0, 1e300)) is
    first divided by its largest component, so it normalises like any other; other rows are
    untouched (the same floats as a plain ``arr / norm``)."""
    with np.errstate(over="ignore", invalid="ignore"):
        norm = np.linalg.norm(arr, axis=1)
    big = np.isinf(norm) & np.all(np.isfinite(arr), axis=1)
    if big.any():
        arr = arr.copy()
        arr[big] /= np.abs(arr[big]).max(axis=1, keepdims=True)
        norm[big] = np.linalg.norm(arr[big], axis=1)
    return arr, norm


def _is_numeric(value) -> bool:
    try:
        np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        return False
    return True


def _set(obj, name: str, value) -> None:
    object.__setattr__(obj, name, value)


# ------------------------------------------------------------------------------------------------
# scene description


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: ``eye`` looks at ``target``; ``fov_y`` is the vertical field of view in
    degrees; the image is ``width`` x ``height`` square pixels (1..MAX_RESOLUTION each)."""

    eye: tuple[float, float, float] = (0.0, -4.0, 2.0)
    target: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    fov_y: float = 40.0
    width: int = DEFAULT_WIDTH
    height: int = DEFAULT_HEIGHT

    def __post_init__(self) -> None:
        _set(self, "eye", vector3("eye", self.eye))
        _set(self, "target", vector3("target", self.target))
        _set(self, "up", unit3("up", self.up))
        _set(self, "fov_y", check_range("fov_y", self.fov_y, 1.0, 170.0))
        _set(self, "width", check_int("width", self.width, 1, MAX_RESOLUTION))
        _set(self, "height", check_int("height", self.height, 1, MAX_RESOLUTION))
        d = np.subtract(self.target, self.eye)
        if np.linalg.norm(d) < 1e-12:
            raise ValueError(
                f"target - eye = {tuple(d.tolist())} cannot be normalised: legal is a camera "
                f"with eye != target"
            )
        f = d / np.linalg.norm(d)
        if np.linalg.norm(np.cross(f, self.up)) < 1e-9:
            raise ValueError(
                f"up = {self.up} is parallel to the view direction {tuple(f.tolist())}: "
                f"legal up is any vector not parallel to target - eye"
            )

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, forward) orthonormal camera axes in world space."""
        f = np.subtract(self.target, self.eye)
        f = f / np.linalg.norm(f)
        r = np.cross(f, self.up)
        r = r / np.linalg.norm(r)
        u = np.cross(r, f)
        return r, u, f

    def with_resolution(self, width: int, height: int) -> Camera:
        return Camera(self.eye, self.target, self.up, self.fov_y, width, height)


@dataclass(frozen=True)
class Light:
    """A white light of intensity ``intensity`` (I_l, 0..16).

    kind "directional": ``direction`` is L, the unit vector from the surface towards the light.
    kind "point": the light sits at ``position``.
    """

    kind: str = "directional"
    direction: tuple[float, float, float] = (0.0, 0.0, 1.0)
    position: tuple[float, float, float] = (0.0, 0.0, 10.0)
    intensity: float = 1.0

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, ("directional", "point"))
        _set(self, "direction", unit3("direction", self.direction))
        _set(self, "position", vector3("position", self.position))
        _set(self, "intensity", check_range("intensity", self.intensity, 0.0, MAX_LIGHT_INTENSITY))


VIEWER_MODES = ("infinite", "local")


@dataclass(frozen=True)
class Material:
    """Blinn-Phong material.  ``ambient``, ``k_d``, ``k_s`` and the RGB ``colour`` in 0..1;
    the specular exponent ``n`` is an integer 1..1000 (the patent's range)."""

    ambient: float = 0.08
    k_d: float = 0.55
    k_s: float = 0.4
    n: int = 50
    colour: tuple[float, float, float] = (0.8, 0.2, 0.1)

    def __post_init__(self) -> None:
        _set(self, "ambient", check_range("ambient", self.ambient, 0.0, 1.0))
        _set(self, "k_d", check_range("k_d", self.k_d, 0.0, 1.0))
        _set(self, "k_s", check_range("k_s", self.k_s, 0.0, 1.0))
        _set(self, "n", check_int("n", self.n, N_MIN, N_MAX))
        c = vector3("colour", self.colour)
        for name, v in zip(("colour[0]", "colour[1]", "colour[2]"), c, strict=True):
            check_range(name, v, 0.0, 1.0)
        _set(self, "colour", c)


@dataclass(frozen=True, eq=False)
class Mesh:
    """A triangle mesh: ``vertices`` (V, 3) float64, ``triangles`` (T, 3) int64 indices with
    counter-clockwise winding seen from the front, ``normals`` (V, 3) unit vertex normals.

    The arrays are copied, checked and made read-only.  Non-unit normals are normalised; a zero
    or non-finite normal is refused.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    normals: np.ndarray
    name: str = "mesh"

    def __post_init__(self) -> None:
        v = np.array(self.vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] < 3:
            raise ValueError(
                f"vertices shape = {v.shape} is not legal: legal shape is (V, 3) with V >= 3"
            )
        if not np.all(np.isfinite(v)):
            raise ValueError("vertices hold a non-finite value: legal values are finite floats")
        t = np.asarray(self.triangles)
        if t.dtype.kind not in "iu" or t.ndim != 2 or t.shape[1] != 3 or t.shape[0] < 1:
            raise ValueError(
                f"triangles shape = {t.shape} (dtype {t.dtype}) is not legal: legal is an integer "
                f"(T, 3) array with T >= 1"
            )
        t = t.astype(np.int64)
        if t.min() < 0 or t.max() >= v.shape[0]:
            bad = int(t.min()) if t.min() < 0 else int(t.max())
            raise ValueError(
                f"triangle index = {bad} is out of range: legal range is 0..{v.shape[0] - 1}"
            )
        nrm = np.array(self.normals, dtype=np.float64)
        if nrm.shape != v.shape:
            raise ValueError(
                f"normals shape = {nrm.shape} is not legal: legal shape is {v.shape} "
                f"(one per vertex)"
            )
        nrm, length = _scaled_rows(nrm)
        bad = ~np.isfinite(length) | (length < 1e-12)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"normals[{i}] = {nrm[i].tolist()} cannot be normalised: legal normals are finite "
                f"non-zero 3-vectors"
            )
        nrm = nrm / length[:, None]
        for arr in (v, t, nrm):
            arr.flags.writeable = False
        _set(self, "vertices", v)
        _set(self, "triangles", t)
        _set(self, "normals", nrm)

    @property
    def n_vertices(self) -> int:
        return int(self.vertices.shape[0])

    @property
    def n_triangles(self) -> int:
        return int(self.triangles.shape[0])

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def to_trimesh(self):
        import trimesh

        return trimesh.Trimesh(
            vertices=self.vertices,
            faces=self.triangles,
            vertex_normals=self.normals,
            process=False,
        )


@dataclass(frozen=True, eq=False)
class SceneObject:
    """One mesh with its material."""

    mesh: Mesh
    material: Material

    def __post_init__(self) -> None:
        if not isinstance(self.mesh, Mesh):
            raise ValueError(f"mesh = {self.mesh!r} is not legal: legal value is a Mesh")
        if not isinstance(self.material, Material):
            raise ValueError(
                f"material = {self.material!r} is not legal: legal value is a Material"
            )


@dataclass(frozen=True, eq=False)
class Scene:
    """Meshes with materials, drawn in order, seen by ``camera`` under one ``light``.

    ``viewer`` is "infinite" (V constant, the direction towards the eye) or "local" (V from the
    eye to every point).  ``background`` is the RGB 8-bit colour of uncovered pixels.
    """

    objects: tuple[SceneObject, ...]
    camera: Camera = field(default_factory=Camera)
    light: Light = field(default_factory=Light)
    viewer: str = "infinite"
    background: tuple[int, int, int] = (0, 0, 0)
    name: str = "scene"

    def __post_init__(self) -> None:
        objs = tuple(self.objects)
        if not objs:
            raise ValueError("objects = () is not legal: a scene needs at least one object")
        for o in objs:
            if not isinstance(o, SceneObject):
                raise ValueError(f"object = {o!r} is not legal: legal value is a SceneObject")
        _set(self, "objects", objs)
        check_choice("viewer", self.viewer, VIEWER_MODES)
        bg = tuple(check_int(f"background[{i}]", c, 0, 255) for i, c in enumerate(self.background))
        if len(bg) != 3:
            raise ValueError(f"background = {self.background!r} is not legal: legal is RGB 0..255")
        _set(self, "background", bg)

    @property
    def n_values(self) -> tuple[int, ...]:
        """The distinct specular exponents of the scene's materials, sorted."""
        return tuple(sorted({o.material.n for o in self.objects}))

    @property
    def n_triangles(self) -> int:
        return sum(o.mesh.n_triangles for o in self.objects)

    def with_resolution(self, width: int, height: int) -> Scene:
        return Scene(
            self.objects,
            self.camera.with_resolution(width, height),
            self.light,
            self.viewer,
            self.background,
            self.name,
        )
