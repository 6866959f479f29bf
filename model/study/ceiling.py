# SPDX-License-Identifier: Apache-2.0
"""The fastest any bit-exact hybrid pipeline with this set-up could be: the bench's ceiling row.

The hybrid (c) sets up every span on the host in float arithmetic (``specular.setup_row``, the
patent's "external device"): the registers the units receive are those bits, so a bit-exact
pipeline cannot skip or approximate it.  Its transcendental calls alone, per span, are two
``arctan2`` (the path angle gamma and the phase lambda), a ``hypot`` (the amplitude A) and a
power (``A**n`` in C).  ``setup_floor`` is a shader that does exactly those four calls per span
on the span's own end vectors and nothing else (no geometry, no units, no pixels: its image is
black), so ``shade.shade`` with it costs the frame's fill and scatter plus that floor.  Any
(c) costs at least as much, so (a)'s time over the floor's is an upper bound on (c)'s ratio to
(a): the bench prints it beside each ratio target.  May import numpy, numba and
``model.render``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from model.render.shade import ShadeContext, ShadeResult
from model.render.spans import Spans


@njit(cache=True)
def floor_kernel(n0: np.ndarray, h0: np.ndarray, h1: np.ndarray, n_exp: int) -> float:
    """Per span: arctan2, arctan2, hypot and a power of the span's vectors; their sum (kept, so
    that the compiler cannot drop the calls)."""
    total = 0.0
    for s in range(n0.shape[0]):
        cg = h0[s, 0] * h1[s, 0] + h0[s, 1] * h1[s, 1] + h0[s, 2] * h1[s, 2]
        gamma = np.arctan2(abs(h0[s, 1] - h1[s, 1]) + 1e-3, cg)
        cos1 = n0[s, 0] * h0[s, 0] + n0[s, 1] * h0[s, 1] + n0[s, 2] * h0[s, 2]
        nw = n0[s, 0] * h1[s, 0] + n0[s, 1] * h1[s, 1] + n0[s, 2] * h1[s, 2]
        lam = np.arctan2(nw, cos1)
        amp = min(1.0, np.hypot(cos1, nw))
        total += gamma + lam + amp**n_exp
    return total


def setup_floor(spans: Spans, ctx: ShadeContext) -> ShadeResult:
    """The set-up's transcendental calls for every span, and a black image: the floor under
    any bit-exact (c) (see the module's text)."""
    floor_kernel(spans.n_start, spans.h_start, spans.h_end, ctx.material.n)
    return ShadeResult(np.zeros((spans.n_pixels, 3), dtype=np.uint8))


def ceiling_lines(runs, goals=((512, 10.0), (1024, 10.0), (64, 3.0))) -> list[str]:
    """Per scene and size of ``runs`` (``bench.Measurement`` with a ``floor`` row): the best
    ratio to (a) any bit-exact (c) with this set-up could reach, against the target at that
    size; then whether every target is within reach."""
    goal_at = dict(goals)
    out, blocked = [], []
    for m in runs:
        if "floor" not in m.seconds or m.size not in goal_at:
            continue
        best = m.ratio("floor", "exact")
        goal = goal_at[m.size]
        reach = "within reach" if best >= goal else "out of reach"
        out.append(
            f"ceiling: {m.scene} {m.size} x {m.size}: (c) <= {best:.2f}x (a) "
            f"(the set-up's arctan2, arctan2, hypot, power per span alone; target {goal:g}x: "
            f"{reach})"
        )
        if best < goal:
            blocked.append(f"{m.scene} {m.size}")
    if blocked:
        out.append(
            "ceiling: the (c) >= 10x / 3x (a) targets cannot be met at "
            + ", ".join(blocked)
            + " by any pipeline bit-exact to this set-up"
        )
    return out
