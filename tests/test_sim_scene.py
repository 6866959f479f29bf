# SPDX-License-Identifier: Apache-2.0
"""Scene co-simulation: a 64 x 64 sphere with a highlight rendered through the three RTL units."""

from __future__ import annotations

import numpy as np
import pytest

from model.render import raster, reference, scenefile
from model.render.shade import render
from model.units import divider
from sim.scene_cosim import cosimulate, job_stream
from tests.conftest import record_sim

pytestmark = pytest.mark.sim


def test_rtl_scene_equals_model_scene_byte_for_byte(request) -> None:
    result = cosimulate("sphere", 64, method="hybrid", tag="scene_test")
    diff = (result.rtl_rgb != result.model_rgb).any(axis=2)
    ys, xs = np.nonzero(diff)
    assert not diff.any(), (
        f"{diff.sum()} pixels differ, first at (x={xs[0]}, y={ys[0]}): "
        f"RTL {result.rtl_rgb[ys[0], xs[0]]} model {result.model_rgb[ys[0], xs[0]]}"
    )
    assert result.pixels > 1000
    # Every pixel went through the specular unit, every channel of every span through Gouraud.
    assert result.results["specular_unit"] == result.pixels
    # The scene has a visible highlight: the reference specular term passes a quarter of full scale.
    ref = render(scenefile.builtin_scene("sphere", 64, 64), reference.exact_blinn)
    assert ref.specular is not None and ref.specular.max() > 64
    record_sim(
        request,
        [
            result.sim_record(
                "scene co-simulation (3 RTL units, image equal byte for byte)", "scene_cosim"
            )
        ],
    )
    print(
        f"scene co-simulation ({result.sim}): {result.pixels} pixels in {result.wall_s:.1f} s "
        f"= {result.pixels_per_second:.0f} pixels/s; RTL cycles {result.cycles}"
    )


def test_one_mesh_of_each_format_through_the_rtl(tmp_path) -> None:
    """A small mesh written as OBJ, PLY, OFF, STL and GLB, the five placed side by side by a scene
    file, each with another n (every cos^k table): the RTL's image equals the hybrid pipeline's
    byte for byte, and every mesh is in the picture."""
    import trimesh

    formats = ("obj", "ply", "off", "stl", "glb")
    shininess = (1, 5, 20, 200, 1000)
    text = "[camera]\neye = [0.0, -2.7, 0.5]\ntarget = [0.0, 0.0, 0.0]\nfov_y = 40.0\n"
    for i, (ext, n) in enumerate(zip(formats, shininess, strict=True)):
        trimesh.creation.icosphere(subdivisions=1).export(tmp_path / f"ball.{ext}")
        text += (
            f'[[mesh]]\nfile = "ball.{ext}"\nup = "z"\nscale = 0.45\n'
            f"translate = [{(i - 2) * 1.0}, 0.0, 0.0]\n[mesh.material]\nn = {n}\n"
        )
    path = tmp_path / "formats.toml"
    path.write_text(text)
    sc = scenefile.read_scene(path, 64, 24)
    result = cosimulate(sc, tag="formats_test")
    diff = (result.rtl_rgb != result.model_rgb).any(axis=2)
    assert not diff.any(), f"{diff.sum()} pixels differ"
    winner = raster.rasterise(sc).winner
    per_mesh = sc.objects[0].mesh.n_triangles
    seen = {int(t) // per_mesh for t in np.unique(winner[winner >= 0])}
    assert seen == set(range(len(formats))), seen
    assert result.results["specular_unit"] == result.pixels > 100


def test_rtl_scene_with_the_diffuse_term_through_the_specular_unit() -> None:
    """Method (h) on a small frame: the diffuse jobs (n = 1, one per span and channel) run on
    the RTL specular unit after the highlight jobs; the image equals the model's byte for byte."""
    result = cosimulate("sphere", 24, method="diffuse", tag="scene_diffuse_test")
    diff = (result.rtl_rgb != result.model_rgb).any(axis=2)
    assert not diff.any(), f"{diff.sum()} pixels differ"
    # Every pixel through the unit once for the highlight and once per channel for the diffuse.
    assert result.results["specular_unit"] == 4 * result.pixels > 100
    print(f"diffuse co-simulation: {result.pixels} pixels, RTL cycles {result.cycles}")


def test_job_stream_runs_the_jobs_back_to_back() -> None:
    """The scene's stimulus: three reset cycles, the first job's operands, then each start in
    the first cycle busy is 0 with the next job's operands written beside it (no simulator)."""
    jobs = [{"a": 100, "k": 4}, {"a": -7, "k": 0}, {"a": 5, "k": 2047}]
    stim, pred, started = job_stream(divider.DEFAULT, jobs)
    assert [job.operands for job in started] == jobs
    s = pred.stats
    assert s.jobs_completed == 3 and s.back_to_back == 2 and s.results_compared == 3, s
    assert s.writes_ignored == 0 and s.starts_ignored == 0, s
    assert [c["rst_n"] for c in stim[:4]] == [0, 0, 0, 1]
    assert sum(c["start"] for c in stim) == 3
    assert pred.outputs[-1]["busy"] == 0 and pred.outputs[-2]["busy"] == 1
