# SPDX-License-Identifier: Apache-2.0
"""How fast a mesh file loads (``python -m model bench-load``, part of ``make bench``).

Owns ``load_bench`` (a mesh of about ``triangles`` triangles written in every format of
``meshfile.MESH_FORMATS`` but glTF's text form, each read by ``meshfile.read_mesh`` as the command
line reads it: repaired, ``up = auto``, normalised; best of ``repeats``) and ``format_load_bench``.
May import numpy, trimesh and ``model.render``.

The mesh is a torus (trimesh's ``creation.torus``): smooth, closed, no defects, so the time is the
reading and the normals, the path every file takes.  The files are written without normals, so
the normals are computed (trimesh's smoothing, which needs scipy's sparse matrices for its fast
path: without scipy a 70k-triangle file takes tens of seconds).  The target: under 2 s a file on a
2-core machine.
"""

from __future__ import annotations

import math
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from model.render import meshfile

LOAD_TARGET_SECONDS = 2.0
BENCH_FORMATS = (".obj", ".ply", ".off", ".stl", ".glb")


@dataclass(frozen=True)
class LoadTime:
    suffix: str
    triangles: int
    vertices: int
    seconds: float  # best of the repeats
    summary: str  # read_mesh's one line


def load_bench(triangles: int = 70_000, repeats: int = 3) -> list[LoadTime]:
    """Write a torus of about ``triangles`` triangles in each of ``BENCH_FORMATS`` into a
    temporary folder and time ``meshfile.read_mesh`` on each (best of ``repeats``)."""
    import trimesh

    if triangles < 100 or repeats < 1:
        raise ValueError(
            f"triangles = {triangles}, repeats = {repeats} are not legal: legal is triangles "
            ">= 100 and repeats >= 1"
        )
    minor = max(3, round(math.sqrt(triangles / 2 / 2)))  # 2 * major * minor triangles
    major = max(3, round(triangles / 2 / minor))
    torus = trimesh.creation.torus(1.0, 0.35, major_sections=major, minor_sections=minor)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for suffix in BENCH_FORMATS:
            path = Path(folder) / f"torus{suffix}"
            torus.export(path)
            best, loaded = math.inf, None
            for _ in range(repeats):
                began = time.perf_counter()
                loaded = meshfile.read_mesh(path, up="auto", normalise_size=True)
                best = min(best, time.perf_counter() - began)
            assert loaded is not None
            rows.append(
                LoadTime(
                    suffix,
                    loaded.mesh.n_triangles,
                    loaded.mesh.n_vertices,
                    best,
                    loaded.summary(),
                )
            )
    return rows


def format_load_bench(rows: list[LoadTime]) -> str:
    """The table ``bench-load`` prints, and the target's verdict."""
    lines = ["| format | triangles | vertices | load s (best) |", "|---|---|---|---|"]
    lines += [f"| {r.suffix} | {r.triangles:,} | {r.vertices:,} | {r.seconds:.2f} |" for r in rows]
    worst = max(rows, key=lambda r: r.seconds)
    verdict = "met" if worst.seconds < LOAD_TARGET_SECONDS else "not met"
    lines.append("")
    lines.append(
        f"target: every file under {LOAD_TARGET_SECONDS:g} s: slowest {worst.suffix} "
        f"{worst.seconds:.2f} s ({verdict})"
    )
    return "\n".join(lines)
