# SPDX-License-Identifier: Apache-2.0
"""How the shading speed scales: Mpx/s against the image size and against the triangle count.

Owns ``scaling`` (the measurements: the teapot at every size of ``SIZES``, and icospheres of
20 to 81920 triangles at one size, each method the best of ``repeats`` timed shadings after a
warm-up, as ``report.run_methods`` times them), ``format_scaling`` (the markdown table) and
``plot_scaling`` (the two panels ``make bench`` writes to out/bench_scaling.png).  Speeds are
shown, not asserted: they are this machine's.  May import ``model.render`` and ``model.study``.
"""

from __future__ import annotations

from pathlib import Path

from tqdm import tqdm

from model.render import meshes
from model.study import report

SIZES = (64, 128, 256, 512, 1024, 2048)
SUBDIVISIONS = (0, 1, 2, 3, 4, 5, 6)  # icospheres of 20 * 4**k triangles
METHODS = ("exact", "hybrid", "adaptive")


def scaling(
    sizes=SIZES,
    subdivisions=SUBDIVISIONS,
    mesh_size: int = 512,
    methods=METHODS,
    repeats: int = 3,
    progress: bool = True,
) -> list[dict]:
    """One row per (axis, point, method): ``axis`` "size" (the teapot at ``size`` x ``size``)
    or "triangles" (an icosphere at ``mesh_size``), with the triangles, the pixels shaded and
    the Mpx/s."""
    jobs = [("size", s, None) for s in sizes] + [("triangles", mesh_size, k) for k in subdivisions]
    rows = []
    for axis, size, k in tqdm(jobs, desc="scaling", unit=" scenes", disable=not progress):
        if k is None:
            the_scene = "teapot"
        else:
            mesh = meshes.sphere_mesh(subdivisions=k)
            the_scene = meshes.scene_from_mesh(mesh, width=size, height=size)
        run = report.run_methods(the_scene, size, methods=list(methods), repeats=repeats)
        triangles = sum(o.triangles for o in run.raster.objects)
        for name, r in run.results.items():
            rows.append(
                {
                    "axis": axis,
                    "size": size,
                    "triangles": int(triangles),
                    "method": name,
                    "pixels": int(r.frame.stats.pixels_shaded),
                    "mpx_per_s": r.pixels_per_second / 1e6,
                }
            )
    return rows


def format_scaling(rows: list[dict]) -> str:
    """Both axes as markdown tables, one column per method."""
    out = []
    for axis, key, title in (
        ("size", "size", "teapot, image side"),
        ("triangles", "triangles", "icosphere, triangles"),
    ):
        mine = [r for r in rows if r["axis"] == axis]
        methods = list(dict.fromkeys(r["method"] for r in mine))
        points = list(dict.fromkeys(r[key] for r in mine))
        out.append(f"| {title} | " + " | ".join(f"{m} Mpx/s" for m in methods) + " |")
        out.append("|---|" + "---|" * len(methods))
        for p in points:
            speed = {r["method"]: r["mpx_per_s"] for r in mine if r[key] == p}
            out.append(f"| {p} | " + " | ".join(f"{speed[m]:.2f}" for m in methods) + " |")
        out.append("")
    return "\n".join(out).rstrip()


def plot_scaling(rows: list[dict], path: str | Path) -> Path:
    """Two panels: Mpx/s against the image side, and against the triangle count (log axes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), dpi=100)
    for ax, (axis, key, label) in zip(
        axes,
        (("size", "size", "image side (teapot), pixels"),
         ("triangles", "triangles", "triangles (icosphere, 512 x 512)")),
        strict=True,
    ):  # fmt: skip
        mine = [r for r in rows if r["axis"] == axis]
        for method in dict.fromkeys(r["method"] for r in mine):
            pts = [(r[key], r["mpx_per_s"]) for r in mine if r["method"] == method]
            ax.plot(*zip(*pts, strict=True), marker="o", label=report.METHOD_LABELS[method])
        ax.set_xscale("log", base=2 if axis == "size" else 10)
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel("Mpx/s (shading only, best of the timed runs)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Shading speed against image size and triangle count (this machine)")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path
