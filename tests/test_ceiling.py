# SPDX-License-Identifier: Apache-2.0
"""The bench's ceiling row (model/study/ceiling.py): the floor shader does the set-up's
transcendental calls and nothing else, and the ceiling lines say which targets are in reach."""

from __future__ import annotations

import inspect

import numpy as np

from model.render import raster, scenefile, shade
from model.study import bench, ceiling
from model.units.specular import setup


def test_the_floor_makes_the_set_ups_transcendental_calls() -> None:
    """The set-up (``setup_row`` and the path it follows) calls arctan2 twice, hypot once and
    one power per span; the floor kernel makes the same calls, so no bit-exact (c) costs less."""
    module = inspect.getsource(setup)
    used = module[module.index("def _path(") : module.index("def rotation_onto(")]
    floor = inspect.getsource(ceiling.floor_kernel)
    for call, times in (("np.arctan2(", 2), ("np.hypot(", 1), ("**n", 1)):
        assert used.count(call) == times, call
        assert floor.count(call) == times, call


def test_the_floor_shader_gives_a_black_image_of_the_spans() -> None:
    scene = scenefile.scene_source("sphere").scene(48, 48)
    frame = shade.shade(raster.rasterise(scene), ceiling.setup_floor)
    covered = frame.obj_id >= 0
    assert covered.sum() == frame.stats.pixels_covered > 0
    assert not frame.rgb[covered].any()


def _run(size: int, floor: float) -> bench.Measurement:
    return bench.Measurement("s", size, 100, {"exact": 1.0, "floor": floor})


def test_ceiling_lines_say_what_is_in_reach() -> None:
    lines = ceiling.ceiling_lines([_run(512, 0.05), _run(64, 0.5)])
    assert "(c) <= 20.00x (a)" in lines[0] and "within reach" in lines[0]
    assert "(c) <= 2.00x (a)" in lines[1] and "out of reach" in lines[1]
    assert lines[2].endswith("s 64 by any pipeline bit-exact to this set-up")
    assert len(ceiling.ceiling_lines([_run(1024, 0.01)])) == 1
    assert ceiling.ceiling_lines([bench.Measurement("s", 512, 1, {"exact": np.float64(1)})]) == []
