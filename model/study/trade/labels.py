# SPDX-License-Identifier: Apache-2.0
"""Labels on the trade plots that do not collide: ``place_labels`` and the display boxes it
avoids (``marker_boxes``, ``polyline_boxes``, ``overlap``).  May import numpy and matplotlib.
"""

from __future__ import annotations

import itertools

import numpy as np

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


def overlap(a, b) -> float:
    """Area (pixels²) two display boxes share."""
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return w * h if w > 0 and h > 0 else 0.0


def _outside(box, frame) -> float:
    """Area (pixels²) of ``box`` outside ``frame``."""
    return box.width * box.height - overlap(box, frame)


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


def polyline_boxes(ax, xs, ys) -> list:
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
                clash = 10 * _outside(box, frame) + sum(overlap(box, b) for b in taken)
                clash += sum(overlap(s, b) for s in lead for b in taken)
                # soft: on a marker or a line, or nearer another point than its own
                own = _distance(px[i], box)
                soft = sum(overlap(box, b) for b in markers)
                soft += 0.5 * sum(overlap(s, b) for s in lead for b in markers)
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


def marker_boxes(ax, xs, ys, size: float) -> list:
    """Display boxes of scatter markers of area ``size`` (points²) at the data points."""
    from matplotlib.transforms import Bbox

    r = np.sqrt(size) / 2 * ax.figure.dpi / 72
    return [
        Bbox([[u - r, v - r], [u + r, v + r]]) for u, v in ax.transData.transform(np.c_[xs, ys])
    ]
