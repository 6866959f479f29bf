# SPDX-License-Identifier: Apache-2.0
"""Scene files (TOML), the built-in scenes written as such files, and where a scene comes from.

Owns ``read_scene`` (a TOML file to a ``Scene``), ``builtin_scene`` with ``SCENE_NAMES`` and
``SCENE_DIR`` (the built-in scenes are the files ``model/render/scenes/<name>.toml``: the examples
to copy), ``SHAPES`` (the built-in shapes a file may name) and ``SceneSource`` with
``scene_source`` and ``mesh_source`` (a built-in name, a scene file or a mesh file, as the command
line names them, with the key a cache files results under).  May import the standard library's
``tomllib`` (``tomli`` before Python 3.11), numpy and ``model.render.scene``, ``.meshes`` and
``.meshfile``.

A scene file (every table and field optional except one ``[[mesh]]``; see the shipped ones and
docs/meshes.md)::

    name = "bunny"                      # default: the file's stem
    viewer = "infinite"                 # "infinite" | "local"
    background = [0, 0, 0]              # RGB 0..255

    [camera]                            # either a pinhole ...
    eye = [0.0, -4.0, 2.0]
    target = [0.0, 0.0, 0.0]
    up = [0.0, 0.0, 1.0]
    fov_y = 40.0                        # degrees, 1..170
    # ... or framed: frame = true, direction = [0.6, -1.0, 0.7], fill = 0.9, fov_y = 35.0

    [light]                             # one light: the units shade one light per pass
    kind = "directional"                # or "point", with position = [x, y, z]
    direction = [1.0, -0.6, 1.4]        # towards the light
    intensity = 1.0                     # 0..16

    [[mesh]]                            # one or more, drawn in order
    file = "bunny.ply"                  # relative to this file; or shape = "sphere" | "torus" |
    up = "auto"                         #   "quad" | "teapot" with the shape's parameters
    normalise = true                    # files: centred, largest side 2
    scale = 1.0                         # then scale, rotate (degrees about x, then y, then z),
    rotate = [0.0, 0.0, 0.0]            #   translate
    translate = [0.0, 0.0, 0.0]
    [mesh.material]
    colour = [0.8, 0.2, 0.1]
    ambient = 0.08
    k_d = 0.55
    k_s = 0.4
    n = 50                              # 1..1000

The image size is not part of the file: the command line's ``--size`` (``read_scene``'s
``width``, ``height``) sets it.  Every field is checked; a bad one raises ``ValueError`` naming the
file, the field, the value and what is allowed (``"sc.toml: camera.fov_y = 500 is out of range:
legal range is 1.0..170.0"``).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import math
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from model.render import meshes, meshfile
from model.render.scene import (
    DEFAULT_HEIGHT,
    DEFAULT_WIDTH,
    MAX_RESOLUTION,
    VIEWER_MODES,
    Camera,
    Light,
    Material,
    Mesh,
    Scene,
    SceneObject,
    check_choice,
    check_int,
    check_range,
    unit3,
    vector3,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - the CI runs 3.11
    import tomli as tomllib

SCENE_DIR = Path(__file__).resolve().parent / "scenes"
SCENE_NAMES = ("sphere", "torus", "teapot", "quad")
"""The built-in scenes: ``SCENE_DIR / f"{name}.toml"``."""

SHAPES: dict[str, tuple[Callable[..., Mesh], tuple[str, ...]]] = {
    "sphere": (meshes.sphere_mesh, ("radius", "subdivisions")),
    "torus": (meshes.torus_mesh, ("major", "minor", "segments", "rings")),
    "quad": (meshes.domed_quad_mesh, ("size", "bulge", "cells")),
    "teapot": (meshes.teapot_mesh, ("steps",)),
}
"""Shape name -> (builder in ``model.render.meshes``, the parameters a file may give it)."""

FRAME_DIRECTION = (0.6, -1.0, 0.7)
"""A framed camera's default direction from the scene's centre (``meshes.scene_from_mesh``'s)."""
DEFAULT_LIGHT = {"kind": "directional", "direction": [1.0, -0.6, 1.4], "intensity": 1.0}

_TOP = ("name", "viewer", "background", "camera", "light", "mesh")
_CAMERA = ("eye", "target", "up", "fov_y", "frame", "direction", "fill")
_LIGHT = ("kind", "direction", "position", "intensity")
_MATERIAL = ("colour", "ambient", "k_d", "k_s", "n")
_PLACE = ("scale", "rotate", "translate", "material")
_FILE = ("file", "up", "normalise")


@contextlib.contextmanager
def _field(file: Path, where: str) -> Iterator[None]:
    """Re-raise a check's ``ValueError`` ("n = 0 is out of range ...") as
    "<file>: <where>n = 0 is out of range ..."."""
    try:
        yield
    except ValueError as exc:
        raise ValueError(f"{file}: {where}{exc}") from None


def _table(file: Path, where: str, value: object, legal: tuple[str, ...]) -> dict:
    if not isinstance(value, dict):
        raise ValueError(
            f"{file}: {where.rstrip('.')} = {value!r} is not legal: legal is a table with "
            f"fields {', '.join(legal)}"
        )
    for key in value:
        if key not in legal:
            raise ValueError(
                f"{file}: {where}{key} is not a field here: legal fields are {', '.join(legal)}"
            )
    return value


def _number(file: Path, where: str, name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{file}: {where}{name} = {value!r} is not legal: legal is a number")
    return float(value)


def _vector(file: Path, where: str, name: str, value: object) -> tuple[float, float, float]:
    if not isinstance(value, list) or any(
        isinstance(x, bool) or not isinstance(x, int | float) for x in value
    ):
        raise ValueError(
            f"{file}: {where}{name} = {value!r} is not legal: legal is a list of three numbers"
        )
    with _field(file, where):
        return vector3(name, value)


# ------------------------------------------------------------------------------------------------
# reading a scene file


def _read_toml(path: Path) -> dict:
    if not path.is_file():
        raise ValueError(f"path = '{path}' does not exist: legal value is an existing .toml file")
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot be read: {exc}") from None


def _mesh_entries(path: Path, doc: dict) -> list[dict]:
    entries = doc.get("mesh")
    if isinstance(entries, dict):
        entries = [entries]
    if not isinstance(entries, list) or not entries:
        raise ValueError(
            f"{path}: mesh = {entries!r} is not legal: legal is one or more [[mesh]] tables, "
            'each with file = "..." or shape = "..."'
        )
    return entries


def mesh_files(path: str | Path) -> list[Path]:
    """The mesh files a scene file names (resolved), in order: what its results depend on."""
    p = Path(path)
    doc = _read_toml(p)
    return [
        (p.parent / Path(e["file"]).expanduser()).resolve()
        for e in _mesh_entries(p, doc)
        if isinstance(e, dict) and isinstance(e.get("file"), str)
    ]


def _rotation(degrees: tuple[float, float, float]) -> np.ndarray:
    """Rotation about x, then y, then z (extrinsic), angles in degrees."""
    ax, ay, az = (math.radians(d) for d in degrees)
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    return rz @ ry @ rx


def _placed(file: Path, where: str, entry: dict, mesh: Mesh) -> Mesh:
    scale = _number(file, where, "scale", entry.get("scale", 1.0))
    with _field(file, where):
        check_range("scale", scale, 1e-9, 1e9)
    rotate = _vector(file, where, "rotate", entry.get("rotate", [0.0, 0.0, 0.0]))
    translate = _vector(file, where, "translate", entry.get("translate", [0.0, 0.0, 0.0]))
    if scale == 1.0 and rotate == (0.0, 0.0, 0.0) and translate == (0.0, 0.0, 0.0):
        return mesh  # the shape exactly as built (the built-in scenes)
    r = _rotation(rotate)
    return Mesh(
        mesh.vertices @ r.T * scale + np.asarray(translate),
        mesh.triangles,
        mesh.normals @ r.T,
        name=mesh.name,
    )


def _mesh(file: Path, index: int, entry: object) -> tuple[Mesh, Material]:
    where = f"mesh[{index}]."
    if not isinstance(entry, dict):
        raise ValueError(f"{file}: mesh[{index}] = {entry!r} is not legal: legal is a table")
    if ("file" in entry) == ("shape" in entry):
        raise ValueError(
            f"{file}: mesh[{index}] has {'both' if 'file' in entry else 'neither'} file and "
            f"shape: legal is one of them (shape: {', '.join(SHAPES)})"
        )
    if "file" in entry:
        _table(file, where, entry, (*_FILE, *_PLACE))
        name = entry["file"]
        if not isinstance(name, str):
            raise ValueError(f"{file}: {where}file = {name!r} is not legal: legal is a path")
        up = entry.get("up", "auto")
        normalise = entry.get("normalise", True)
        if not isinstance(normalise, bool):
            raise ValueError(
                f"{file}: {where}normalise = {normalise!r} is not legal: legal is true or false"
            )
        with _field(file, where):
            check_choice("up", up, meshfile.UP_AXES)
        mesh_path = file.parent / Path(name).expanduser()
        with _field(file, where):
            mesh = meshfile.read_mesh(mesh_path, up, normalise).mesh
    else:
        shape = entry["shape"]
        with _field(file, where):
            check_choice("shape", shape, tuple(SHAPES))
        build, params = SHAPES[shape]
        _table(file, where, entry, ("shape", *params, *_PLACE))
        kwargs = {k: entry[k] for k in params if k in entry}
        for k, v in kwargs.items():
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise ValueError(f"{file}: {where}{k} = {v!r} is not legal: legal is a number")
        with _field(file, where):
            mesh = build(**kwargs)
    material = _table(file, f"{where}material.", entry.get("material", {}), _MATERIAL)
    kw: dict[str, object] = {}
    for k, v in material.items():
        kw[k] = _vector(file, f"{where}material.", k, v) if k == "colour" else v
        if k != "colour":
            _number(file, f"{where}material.", k, v)
    with _field(file, f"{where}material."):
        mat = Material(**kw)
    return _placed(file, where, entry, mesh), mat


def _camera(file: Path, doc: dict, objects: list[SceneObject], width: int, height: int) -> Camera:
    cam = _table(file, "camera.", doc.get("camera", {"frame": True}), _CAMERA)
    frame = cam.get("frame", False)
    if not isinstance(frame, bool):
        raise ValueError(f"{file}: camera.frame = {frame!r} is not legal: legal is true or false")
    fov = _number(file, "camera.", "fov_y", cam.get("fov_y", 35.0 if frame else 40.0))
    if frame:
        for k in ("eye", "target", "up"):
            if k in cam:
                raise ValueError(
                    f"{file}: camera.{k} is not legal with frame = true: a framed camera takes "
                    "direction, fill and fov_y"
                )
        direction = _vector(
            file, "camera.", "direction", cam.get("direction", list(FRAME_DIRECTION))
        )
        fill = _number(file, "camera.", "fill", cam.get("fill", 0.9))
        with _field(file, "camera."):
            unit3("direction", direction)
            check_range("fill", fill, 0.05, 1.0)
            check_range("fov_y", fov, 1.0, 170.0)
            points = np.concatenate([o.mesh.vertices for o in objects])
            return meshes.frame_camera(points, direction, width, height, fov, fill)
    for k in ("direction", "fill"):
        if k in cam:
            raise ValueError(f"{file}: camera.{k} is not legal without frame = true")
    given = {k: _vector(file, "camera.", k, cam[k]) for k in ("eye", "target", "up") if k in cam}
    missing = [k for k in ("eye", "target") if k not in given]
    if missing:
        raise ValueError(
            f"{file}: camera.{missing[0]} is missing: legal is eye, target (up, fov_y optional) "
            "or frame = true"
        )
    eye, target, up = given["eye"], given["target"], given.get("up", (0.0, 0.0, 1.0))
    with _field(file, "camera."):
        return Camera(eye, target, up, fov, width, height)


def _light(file: Path, doc: dict) -> Light:
    value = doc.get("light", DEFAULT_LIGHT)
    if isinstance(value, list):
        if len(value) != 1:
            raise ValueError(
                f"{file}: light has {len(value)} entries: legal is one light (the units shade "
                "one light per pass)"
            )
        value = value[0]
    light = _table(file, "light.", value, _LIGHT)
    kw: dict[str, object] = {}
    for k, v in light.items():
        if k in ("direction", "position"):
            kw[k] = _vector(file, "light.", k, v)
        elif k == "intensity":
            kw[k] = _number(file, "light.", k, v)
        else:
            kw[k] = v
    with _field(file, "light."):
        return Light(**kw)


def read_scene(path: str | Path, width: int = DEFAULT_WIDTH, height: int = DEFAULT_HEIGHT) -> Scene:
    """The scene a TOML file describes (the module's docstring), ``width`` x ``height``."""
    file = Path(path)
    check_int("width", width, 1, MAX_RESOLUTION)
    check_int("height", height, 1, MAX_RESOLUTION)
    doc = _table(file, "", _read_toml(file), _TOP)
    objects = [SceneObject(*_mesh(file, i, e)) for i, e in enumerate(_mesh_entries(file, doc))]
    name = doc.get("name", file.stem)
    if not isinstance(name, str) or not name:
        raise ValueError(f"{file}: name = {name!r} is not legal: legal is a non-empty string")
    viewer = doc.get("viewer", "infinite")
    with _field(file, ""):
        check_choice("viewer", viewer, VIEWER_MODES)
    background = doc.get("background", [0, 0, 0])
    if not isinstance(background, list) or len(background) != 3:
        raise ValueError(
            f"{file}: background = {background!r} is not legal: legal is [r, g, b], 0..255 each"
        )
    with _field(file, ""):
        bg = tuple(check_int(f"background[{i}]", c, 0, 255) for i, c in enumerate(background))
    camera = _camera(file, doc, objects, width, height)
    return Scene(tuple(objects), camera, _light(file, doc), viewer, bg, name=name)


def builtin_scene(name: str, width: int = DEFAULT_WIDTH, height: int = DEFAULT_HEIGHT) -> Scene:
    """A built-in scene (``SCENE_NAMES``), read from its file in ``SCENE_DIR``.

    * "sphere": icosphere (1280 triangles), n = 60, directional light, viewer at infinity.
    * "torus": 48 x 24 torus, n = 20, point light, local viewer.
    * "teapot": the Utah teapot (28 Bezier patches, 10 x 10 cells each), n = 40, directional
      light, viewer at infinity, a framed camera.
    * "quad": a 4 x 4 domed quad (32 x 32 cells, normals tilting up to 14 degrees), n = 1000,
      a nearby point light and a local viewer: one tight highlight.
    """
    check_choice("name", name, SCENE_NAMES)
    return read_scene(SCENE_DIR / f"{name}.toml", width, height)


# ------------------------------------------------------------------------------------------------
# where a scene comes from: the command line's --scene and --mesh


@functools.lru_cache(maxsize=4)
def _read_mesh_once(ref: str, up: str, stamp: tuple[int, int] | None) -> meshfile.LoadedMesh:
    return meshfile.read_mesh(ref, up, normalise_size=True)


@dataclass(frozen=True)
class SceneSource:
    """A scene as the command line names it: ``kind`` "builtin" (``ref`` a name in
    ``SCENE_NAMES``), "file" (``ref`` a scene file) or "mesh" (``ref`` a mesh file framed by
    ``meshes.scene_from_mesh`` with its defaults, turned by ``up`` and normalised)."""

    kind: str
    ref: str
    up: str = "auto"

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, ("builtin", "file", "mesh"))
        check_choice("up", self.up, meshfile.UP_AXES)

    @property
    def label(self) -> str:
        return self.ref if self.kind == "builtin" else f"{self.kind} {self.ref}"

    def read(self) -> meshfile.LoadedMesh:
        """A mesh source's file, read (repairs and up axis in its ``summary()``); read once
        while the file is unchanged (its size and modification time)."""
        p = Path(self.ref)
        stamp = (p.stat().st_mtime_ns, p.stat().st_size) if p.is_file() else None
        return _read_mesh_once(self.ref, self.up, stamp)

    def scene(self, width: int, height: int) -> Scene:
        if self.kind == "builtin":
            return builtin_scene(self.ref, width, height)
        if self.kind == "file":
            return read_scene(self.ref, width, height)
        return meshes.scene_from_mesh(self.read().mesh, width=width, height=height)

    def files(self) -> list[Path]:
        """The files the scene is made from (none for a built-in one)."""
        if self.kind == "builtin":
            return []
        if self.kind == "mesh":
            return [Path(self.ref)]
        return [Path(self.ref), *mesh_files(self.ref)]

    def key(self) -> str:
        """A name a cache can file results under: the built-in's name, or
        ``<kind>:<file name>@<12 hex>`` with the sha1 of every file's bytes (and of ``up`` for a
        mesh), so the key follows the content.  ``OSError`` when a file cannot be read."""
        if self.kind == "builtin":
            return self.ref
        digest = hashlib.sha1(usedforsecurity=False)
        for f in self.files():
            digest.update(f.read_bytes())
        if self.kind == "mesh":
            digest.update(f"up={self.up}".encode())
        return (
            f"{'scene' if self.kind == 'file' else 'mesh'}:{Path(self.ref).name}@"
            + (digest.hexdigest()[:12])
        )


def scene_source(text: str) -> SceneSource:
    """``--scene``: a built-in scene's name or a ``.toml`` scene file (checked: it must read)."""
    if text in SCENE_NAMES:
        return SceneSource("builtin", text)
    if Path(text).suffix.lower() != ".toml":
        raise ValueError(
            f"scene = {text!r} is not legal: legal is a built-in scene "
            f"({', '.join(SCENE_NAMES)}) or a .toml scene file"
        )
    read_scene(text, 8, 8)
    return SceneSource("file", text)


def mesh_source(text: str | Path, up: str = "auto") -> SceneSource:
    """``--mesh FILE --up AXIS``: a mesh file, checked (it must read and frame)."""
    source = SceneSource("mesh", str(text), up)
    source.scene(8, 8)
    return source
