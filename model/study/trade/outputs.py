# SPDX-License-Identifier: Apache-2.0
"""What a trade run writes: the CSV of every point, the markdown tables and the Pareto plots.

Owns ``write_outputs`` (``results.csv``, ``results.md``, ``pareto_cycles.png``,
``pareto_bits.png`` and the README's ``trade_pareto.png``), the tables (``CSV_FIELDS``,
``table_row``, ``sweep_rows``, ``knob_summary``, ``format_markdown``) and the plots
(``plot_pareto``, ``plot_figure``, ``place_labels``).  May import numpy, matplotlib,
``model.study.metrics`` and ``model.study.trade`` ``points`` and ``analysis``.
"""

from __future__ import annotations

import csv
import itertools
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from model.study import metrics
from model.study.trade.analysis import NEAR, aggregate, default_position, default_row
from model.study.trade.points import DEFAULT_POINT, KNOBS, SMALL_SWEEPS, Sweep, row_knobs

# ================================================================================ outputs
CSV_FIELDS = (
    "scene",
    "size",
    *KNOBS,
    "label",
    "nmse",
    "psnr",
    "max_abs_error",
    "share_off_by_more_than_1",
    "highlight_max_abs_error",
    "epicentre_rel_error",
    "epicentre_worst_n",
    "epicentre_out_lsb",
    "unit_error_lsb",
    "line_drift_levels",
    "angle_drift_steps",
    "pixels_shaded",
    "divider_cycles",
    "gouraud_cycles",
    "specular_cycles",
    "specular_pixels",
    "cycles",
    "frame_clocks",
    "px_per_clock",
    "px_per_clock_parallel",
    "table_bits",
    "adders",
    "multipliers",
    "mult_bits",
    "shade_seconds",
    "sw_pixels_per_second",
    "key",
    "config_key",
)


def write_csv(results: list[dict], path: Path) -> Path:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        w.writerows(results)
    return path


def _num(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{x:.3f}"


def _pct(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{100 * x:.2f} %"


TABLE_HEAD = (
    "| config | NMSE (mean) | PSNR dB (min) | max err | epicentre err (n) | unit err (LSB) "
    "| line drift "
    "| angle drift | cycles/frame | frame clocks | px/clk | px/clk par. | table bits | adders "
    "| mult (bits) | Mpx/s | front |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
)


def table_row(r: dict) -> str:
    marks = ("C" if r["pareto_cycles"] else "") + ("B" if r["pareto_bits"] else "")
    epi = (
        f"{_pct(r['epicentre_rel_error'])} ({r['epicentre_worst_n']})"
        if np.isfinite(r["epicentre_rel_error"])
        else "-"
    )
    name = "**default**" if r["label"] == "default" else r["label"]
    return (
        f"| {name} | {r['nmse']:.6f} | {r['psnr']:.1f} | {r['max_abs_error']:.0f} | {epi} "
        f"| {_num(r['unit_error_lsb'])} "
        f"| {r['line_drift_levels']:.3f} | {_num(r['angle_drift_steps'])} "
        f"| {r['cycles']:,.0f} | {r['frame_clocks']:,.0f} "
        f"| {r['px_per_clock']:.3f} | {r['px_per_clock_parallel']:.3f} | {r['table_bits']:,} "
        f"| {r['adders']} | {r['multipliers']} ({r['mult_bits']}) "
        f"| {r['sw_pixels_per_second'] / 1e6:.2f} | {marks or '-'} |"
    )


def sweep_rows(sweep: Sweep, rows: list[dict]) -> list[dict]:
    """The aggregated rows of the sweep's configurations, in the sweep's order."""
    by_knobs = {tuple(r[k] for k in KNOBS): r for r in rows}
    out = []
    for c in sweep.configs():
        knobs = {**DEFAULT_POINT.knobs, **c}
        r = by_knobs.get(tuple(knobs[k] for k in KNOBS))
        if r is not None:
            out.append(r)
    return out


def _ratio(a: float, b: float) -> str:
    return f"{a / b:.2f}x" if b else "-"


def knob_summary(sweep: Sweep, rows: list[dict]) -> str:
    """What the knob buys, from its one-knob sweep: accuracy and cost at each end."""
    rs = sweep_rows(sweep, rows)
    if len(rs) < 2:
        return f"* {sweep.title}: not measured"
    base = {**DEFAULT_POINT.knobs, **dict(sweep.base)}
    ref = next((r for r in rs if r[sweep.knob] == base[sweep.knob]), rs[0])
    parts = []
    for r in rs:
        if r is ref:
            continue
        parts.append(
            f"{r[sweep.knob]}: NMSE {_ratio(r['nmse'], ref['nmse'])}, epicentre "
            f"{_pct(r['epicentre_rel_error'])}, cycles {_ratio(r['cycles'], ref['cycles'])}, "
            f"frame clocks {_ratio(r['frame_clocks'], ref['frame_clocks'])}, table bits "
            f"{_ratio(r['table_bits'], ref['table_bits'])}"
        )
    return (
        f"* **{sweep.title}** (`{sweep.knob}`, against {ref[sweep.knob]}: NMSE "
        f"{ref['nmse']:.6f}, epicentre {_pct(ref['epicentre_rel_error'])}): " + "; ".join(parts)
    )


def format_markdown(rows: list[dict], sweeps: Sequence[Sweep] = SMALL_SWEEPS) -> str:
    lines = ["# Speed/accuracy trade", ""]
    if rows:
        lines.append(
            f"Scenes: {rows[0]['scenes']} at {rows[0]['size']} x {rows[0]['size']}; accuracy "
            "against exact Blinn (a): NMSE mean, PSNR and max error worst over the scenes; "
            "cost per frame: mean over the scenes.  front: C = on the NMSE-vs-cycles Pareto "
            "front, B = on the NMSE-vs-table-bits front (over every configuration of the run)."
        )
        lines.append("")
    shown: set[str] = set()
    for sw in sweeps:
        rs = sweep_rows(sw, rows)
        if not rs:
            continue
        lines += [f"## {sw.title} (`{sw.knob}`)", "", TABLE_HEAD]
        lines += [table_row(r) for r in rs]
        lines.append("")
        shown.update(r["config_key"] for r in rs)
    rest = [r for r in rows if r["config_key"] not in shown]
    if rest:
        lines += ["## other configurations", "", TABLE_HEAD, *map(table_row, rest), ""]
    lines += ["## What each knob buys", ""]
    lines += [knob_summary(sw, rows) for sw in sweeps]
    lines += ["", "## Where the default lies", ""]
    for name, labels in default_position(rows).items():
        verdict = "on or near the front" if not labels else "eps-dominated by " + "; ".join(labels)
        lines.append(f"* NMSE vs {name}: {verdict}")
    lines.append(
        f"\n(eps-dominated: another configuration is more than {100 * NEAR:.0f} % better in one "
        f"figure and at most {100 * NEAR:.0f} % worse in every other; all figures: NMSE, the "
        "worst epicentre error, line drift and angle drift, cycles, table bits, adders and "
        "multiplier bits.)"
    )
    return "\n".join(lines) + "\n"


THRESHOLD_LABEL = "visually identical: NMSE ≤ {:g} (thesis)"
"""The label of the thesis's "visually identical" line (``metrics.NMSE_VISUALLY_IDENTICAL``)."""
LABEL_STEPS_PT = (7, 14, 22, 32, 44, 58)
"""Distances (points) from a data point at which ``place_labels`` tries its label."""
LABEL_DIRECTIONS = (  # (dx, dy, horizontal alignment, vertical alignment)
    (1, 0, "left", "center"),
    (1, 1, "left", "bottom"),
    (1, -1, "left", "top"),
    (0, 1, "center", "bottom"),
    (0, -1, "center", "top"),
    (-1, 0, "right", "center"),
    (-1, 1, "right", "bottom"),
    (-1, -1, "right", "top"),
)


def point_label(r: dict) -> str:
    """A row's label on the plots: "default", a named combination, the changed knob of its
    sweep (``p=4``, ``highlight_levels=16``), else every changed knob, one per line."""
    group = DEFAULT_POINT.with_knobs(**row_knobs(r)).group
    if group in KNOBS:
        v = r[group]
        return f"{group}={v:g}" if isinstance(v, float) else f"{group}={v}"
    return r["label"].replace(", ", "\n")


def _overlap(a, b) -> float:
    """Area (pixels²) two display boxes share."""
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return w * h if w > 0 and h > 0 else 0.0


def _outside(box, frame) -> float:
    """Area (pixels²) of ``box`` outside ``frame``."""
    return box.width * box.height - _overlap(box, frame)


def _segment_boxes(p0, p1, skip: float = 0.0, half: float = 1.0) -> list:
    """Small display boxes every 3 pixels along the segment p0 -> p1, from ``skip`` pixels."""
    from matplotlib.transforms import Bbox

    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    length = float(np.hypot(*(p1 - p0)))
    out = []
    for t in np.arange(skip, length, 3.0) / max(length, 1e-9):
        u, v = p0 + t * (p1 - p0)
        out.append(Bbox([[u - half, v - half], [u + half, v + half]]))
    return out


def _distance(point, box) -> float:
    """Pixels from a display point to a display box (0 inside it)."""
    dx = max(box.x0 - point[0], 0.0, point[0] - box.x1)
    dy = max(box.y0 - point[1], 0.0, point[1] - box.y1)
    return float(np.hypot(dx, dy))


def _polyline_boxes(ax, xs, ys) -> list:
    """``_segment_boxes`` along a line through data points (in their order)."""
    pts = ax.transData.transform(np.c_[xs, ys])
    return [b for a, c in itertools.pairwise(pts) for b in _segment_boxes(a, c)]


def place_labels(ax, xy, texts, markers=(), avoid=(), others=(), fontsize: float = 6.0) -> list:
    """Label the data points ``xy`` ((m, 2), data coordinates) with ``texts`` so that no label
    overlaps another label or leader line, a marker or a line (``markers``: display boxes) or a
    box of ``avoid``, and every label stays inside the axes.

    Greedy and deterministic: from left to right, each label takes the first free spot among 8
    directions at the distances ``LABEL_STEPS_PT``, joined to its point by a thin leader line
    that crosses no label; a spot is free when, besides, the label covers no marker or line and
    is nearer its own point than any other labelled point or any of ``others`` (the unlabelled
    data points).  On a plot too crowded for that: the spot that overlaps the labels least,
    then covers and misleads least.  Call it once the axes' limits and the figure's layout are
    final (labels are offsets in points from their data point, so a later change of either can
    move them into each other).
    Returns the annotations.
    """
    renderer = ax.figure.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    scale = ax.figure.dpi / 72
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    px = ax.transData.transform(xy)
    others_px = ax.transData.transform(np.asarray(others, dtype=float).reshape(-1, 2))
    taken = list(avoid)
    placed = []

    def label(i, offset, ha, va, leader=None):
        return ax.annotate(
            texts[i],
            xy[i],
            xytext=offset,
            textcoords="offset points",
            ha=ha,
            va=va,
            fontsize=fontsize,
            arrowprops=leader,
            zorder=6,
        )

    for i in np.lexsort((px[:, 1], px[:, 0])):
        best = None
        for step in LABEL_STEPS_PT:
            for dx, dy, ha, va in LABEL_DIRECTIONS:
                offset = (dx * step, dy * step)
                probe = label(i, offset, ha, va)
                box = probe.get_window_extent(renderer).padded(2)  # a gap between labels
                probe.remove()
                lead = _segment_boxes(px[i], px[i] + np.multiply(offset, scale), skip=10)
                # hard: outside the axes, on a label or a leader
                clash = 10 * _outside(box, frame) + sum(_overlap(box, b) for b in taken)
                clash += sum(_overlap(s, b) for s in lead for b in taken)
                # soft: on a marker or a line, or nearer another point than its own
                own = _distance(px[i], box)
                soft = sum(_overlap(box, b) for b in markers)
                soft += 0.5 * sum(_overlap(s, b) for s in lead for b in markers)
                soft += 300 * sum(_distance(q, box) < own for q in np.delete(px, i, axis=0))
                soft += 60 * sum(_distance(q, box) < own for q in others_px)
                cost = (clash, soft)
                if best is None or cost < best[0]:
                    best = (cost, offset, ha, va, box, lead)
                if cost == (0, 0):
                    break
            if best[0] == (0, 0):
                break
        _, offset, ha, va, box, lead = best
        leader = {"arrowstyle": "-", "lw": 0.6, "color": "0.3", "shrinkA": 1, "shrinkB": 2}
        placed.append(label(i, offset, ha, va, leader))
        taken += [box, *lead]
    return placed


def _marker_boxes(ax, xs, ys, size: float) -> list:
    """Display boxes of scatter markers of area ``size`` (points²) at the data points."""
    from matplotlib.transforms import Bbox

    r = np.sqrt(size) / 2 * ax.figure.dpi / 72
    return [
        Bbox([[u - r, v - r], [u + r, v + r]]) for u, v in ax.transData.transform(np.c_[xs, ys])
    ]


def _threshold_line(ax, markers: list, fontsize: float):
    """The "visually identical" line with its label just above or below it, at its right or
    left end, wherever it keeps clear of the markers (padded by 2 pixels), else where it covers
    least; returns the label's display box."""
    from matplotlib.transforms import blended_transform_factory

    y = metrics.NMSE_VISUALLY_IDENTICAL
    ax.axhline(y, color="0.35", lw=0.9, ls=":", zorder=1)
    trans = blended_transform_factory(ax.transAxes, ax.transData)
    renderer = ax.figure.canvas.get_renderer()
    best = None
    for va in ("bottom", "top"):
        for x, ha in ((0.99, "right"), (0.01, "left")):
            text = ax.text(
                x,
                y,
                THRESHOLD_LABEL.format(y),
                transform=trans,
                ha=ha,
                va=va,
                fontsize=fontsize,
                color="0.3",
                zorder=4,
            )
            box = text.get_window_extent(renderer)
            cost = sum(_overlap(box.padded(2), m) for m in markers)
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, text, box)
            else:
                text.remove()
            if best[0] == 0:
                return best[2]
    return best[2]


def plot_pareto(
    rows: list[dict], x: str, path: Path | None = None, ax=None, legend: bool = True
) -> Path | None:
    """NMSE (log) against ``x`` ("cycles" or "table_bits"): every configuration coloured by its
    sweep, the Pareto front dashed, the default starred, the thesis's "visually identical"
    threshold as a labelled line, and the front points and the default labelled without
    collisions (``place_labels``).  With ``ax``, draws into it (its figure's layout must be
    final) and returns None; otherwise writes ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    front_key = "pareto_cycles" if x == "cycles" else "pareto_bits"
    xlabel = "unit cycles per frame (mean over scenes)" if x == "cycles" else "ROM bits"
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(8.4, 4.8), dpi=100)
        fig.subplots_adjust(left=0.1, right=0.74, bottom=0.11, top=0.97)
    fontsize = 6.5 if own else 6.0
    xs = np.array([r[x] for r in rows], dtype=float)
    ys = np.array([r["nmse"] for r in rows], dtype=float)
    front = np.array([r[front_key] for r in rows])
    knob = [DEFAULT_POINT.with_knobs(**row_knobs(r)).group for r in rows]
    kinds = sorted(set(knob) - {"default"})
    cmap = plt.get_cmap("tab10")
    for i, kname in enumerate(kinds):
        sel = np.array([k == kname for k in knob])
        ax.scatter(xs[sel], ys[sel], s=18, color=cmap(i % 10), label=kname, alpha=0.8)
    order = np.argsort(xs[front])
    ax.plot(xs[front][order], ys[front][order], "k--", lw=1, label="Pareto front")
    ax.scatter(xs[front], ys[front], s=60, facecolors="none", edgecolors="k")
    d = default_row(rows)
    if d is not None:
        ax.scatter([xs[d]], [ys[d]], s=140, marker="*", color="red", zorder=5, label="default")
    ax.axhline(metrics.NMSE_VISUALLY_IDENTICAL, lw=0)  # in the y limits before they freeze
    ax.set_yscale("log")
    if x == "table_bits":
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("NMSE vs exact Blinn (mean over scenes)")
    ax.grid(True, which="both", alpha=0.3)
    if legend:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax.set_xlim(ax.get_xlim())  # freeze the limits: the labels are placed in them
    ax.set_ylim(ax.get_ylim())
    markers = _marker_boxes(ax, xs, ys, 60) + _polyline_boxes(
        ax, xs[front][order], ys[front][order]
    )
    if d is not None:
        markers += _marker_boxes(ax, xs[d : d + 1], ys[d : d + 1], 140)
    avoid = [_threshold_line(ax, markers, fontsize)]
    labelled = sorted(set(np.flatnonzero(front)) | ({d} if d is not None else set()))
    place_labels(
        ax,
        np.c_[xs[labelled], ys[labelled]],
        [point_label(rows[i]) for i in labelled],
        markers=markers,
        avoid=avoid,
        others=np.delete(np.c_[xs, ys], labelled, axis=0),
        fontsize=fontsize,
    )
    if own:
        fig.savefig(path)
        plt.close(fig)
        return path
    return None


def plot_figure(rows: list[dict], path: Path) -> Path:
    """Both fronts side by side, small, one legend below them (the README's committed
    figure)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4), dpi=80)
    fig.subplots_adjust(left=0.07, right=0.99, bottom=0.27, top=0.93, wspace=0.18)
    axes[0].set_title("NMSE against unit cycles per frame", fontsize=10)
    axes[1].set_title("NMSE against ROM bits", fontsize=10)
    plot_pareto(rows, "cycles", ax=axes[0], legend=False)
    plot_pareto(rows, "table_bits", ax=axes[1], legend=False)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=7, fontsize=7, frameon=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def write_outputs(
    results: list[dict], out_dir: Path, figure_dir: Path | None = None
) -> tuple[list[dict], list[Path]]:
    """results.csv, results.md, pareto_cycles.png, pareto_bits.png (+ figure_dir's PNG)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = aggregate(results)
    written = [write_csv(results, out_dir / "results.csv")]
    md = out_dir / "results.md"
    md.write_text(format_markdown(rows))
    written.append(md)
    if rows:
        written.append(plot_pareto(rows, "cycles", out_dir / "pareto_cycles.png"))
        written.append(plot_pareto(rows, "table_bits", out_dir / "pareto_bits.png"))
        if figure_dir is not None:
            written.append(plot_figure(rows, Path(figure_dir) / "trade_pareto.png"))
    return rows, written
