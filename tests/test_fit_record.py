# SPDX-License-Identifier: Apache-2.0
"""The records of ``make fit`` (docs/fit_teapot.json, the teapot; docs/fit_gallery.json, the
four-material example scene) are current and docs/fit.md shows them: each block is its record's,
the search finds the recorded candidates again (every family and policy), the kept
configuration gives the recorded accuracy on a fresh render, the synthesised designs are made
of today's files, and the kept one is the cheapest candidate whatever its family."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import tomli_w

from model.fit import analyse, cost, report, search, verilog
from model.hw import synth
from model.hw.parts import PARTS
from model.render import configfile, pipeline, raster, reference, scenefile, shade
from model.study import metrics

ROOT = Path(__file__).resolve().parent.parent
RECORDS = {"teapot": "docs/fit_teapot.json", "gallery": "docs/fit_gallery.json"}
PAGE = ROOT / "docs" / "fit.md"
STALE = "stale: rerun `make fit` (it rewrites docs/fit_*.json and docs/fit.md)"


@pytest.fixture(scope="module", params=list(RECORDS))
def record(request) -> dict:
    found = json.loads((ROOT / RECORDS[request.param]).read_text())
    found["_path"] = RECORDS[request.param]
    return found


def _source(record: dict) -> scenefile.SceneSource:
    """The recorded scene: its command-line arguments (``--scene NAME|FILE``)."""
    flag, ref = record["source"]
    assert flag == "--scene", record["source"]
    if ref in scenefile.SCENE_NAMES:
        return scenefile.SceneSource("builtin", ref)
    return scenefile.scene_source(str(ROOT / ref))


def _config(record: dict, tmp_path: Path) -> pipeline.PipelineConfig:
    path = tmp_path / "config.toml"
    path.write_text(tomli_w.dumps(record["config"]))
    return configfile.read_config(path)


def test_page_shows_the_record(record: dict) -> None:
    text = PAGE.read_text()
    block = report.docs_block({k: v for k, v in record.items() if k != "_path"}, record["_path"])
    assert block in text, STALE
    assert record["met"] and record["rtl_proof"]["equal"]


def test_readme_quotes_the_teapot_record() -> None:
    record = json.loads((ROOT / RECORDS["teapot"]).read_text())
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert report.readme_sentence(record) in readme, STALE


def test_search_finds_the_recorded_candidates(teapot_file, record: dict) -> None:
    the_scene = _source(record).scene(record["size"], record["size"])
    frame_raster = raster.rasterise(the_scene)
    needs = analyse.analyse(frame_raster)
    assert json.loads(json.dumps(needs.as_dict())) == record["needs"], STALE
    evaluate = search.Evaluator(frame_raster, "record")
    found = search.search_candidates(evaluate, needs, search.Target())
    got = [(search.family(c.config), c.policy, configfile.config_dict(c.config)) for c in found]
    want = [(c["family"], c["policy"], c["config"]) for c in record["candidates"]]
    assert got == want, STALE
    (kept,) = [c for c in found if configfile.config_dict(c.config) == record["config"]]
    assert kept.met and kept.steps == record["steps"], STALE


def test_recorded_design_gives_the_recorded_accuracy(
    teapot_file, record: dict, tmp_path: Path
) -> None:
    cfg = _config(record, tmp_path)
    the_scene = _source(record).scene(record["size"], record["size"])
    ref = shade.render(the_scene, reference.exact_blinn).rgb
    img = shade.render(the_scene, pipeline.unit_shader(cfg)).rgb
    assert metrics.nmse(img, ref) == record["comparison"]["nmse"], STALE
    assert metrics.nmse(img, ref) <= metrics.NMSE_VISUALLY_IDENTICAL


def test_synthesised_design_is_todays_files(teapot_file, record: dict, tmp_path: Path) -> None:
    """The placed designs are the shading core of today's RTL, ROM images and parameters: the
    fitted configuration's, and the default design's."""
    cfg = _config(record, tmp_path)
    want = synth.run_inputs(verilog.CORE, params=cost.synth_parameters(cfg, tmp_path / "roms"))
    for part, row in record["cost"].items():
        assert row["inputs"] == want, f"{part}: {STALE}"
    default = cost.synth_parameters(cost.DEFAULT_DESIGN, tmp_path / "roms")
    want = synth.run_inputs(verilog.CORE, params=default)
    for part, row in record["default_cost"].items():
        assert row["inputs"] == want, f"{part}: {STALE}"


def test_the_kept_candidate_is_the_cheapest_synthesised_one(record: dict) -> None:
    cands = record["candidates"]
    assert len(cands) >= 2 and {c["policy"] for c in cands} <= set(search.POLICIES)
    kept = min(cands, key=lambda c: c["share"])
    assert kept["policy"] == record["policy"] and kept["config"] == record["config"]
    assert kept["family"] == record["family"]
    part = next(iter(record["cost"]))
    assert kept["cost"] == record["cost"][part]
    for c in cands:  # the share is the sum of used / available, from the recorded figures
        cap = PARTS[part].capacity()
        assert c["share"] == pytest.approx(
            sum(c["cost"][k] / cap[k] for k in ("LUT", "FF", "BRAM", "DSP")), rel=1e-12
        )


def test_record_meets_the_size_targets(record: dict) -> None:
    """Each scene fitted to NMSE <= 0.00025: the fitted core fits an iCE40 UP5K (the default core
    does not); on ECP5-25F at most half the default core's LUTs and a third of its BRAM.  (How
    long the fit took is a figure of docs/fit.md, measured once, not a test.)"""
    assert record["cost"]["up5k"]["fits"] and not record["default_cost"]["up5k"]["fits"]
    ecp5, default = record["cost"]["ecp5-25f"], record["default_cost"]["ecp5-25f"]
    assert 2 * ecp5["LUT"] <= default["LUT"]
    assert 3 * ecp5["BRAM"] <= default["BRAM"]
