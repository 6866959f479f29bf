# SPDX-License-Identifier: Apache-2.0
"""docs/fit_teapot.json (``make fit``) is current and docs/fit.md shows it: the block is the
record's, the search finds the recorded configuration again, that configuration gives the
recorded accuracy on a fresh render, and the synthesised design is made of today's files."""

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
RECORD = ROOT / "docs" / "fit_teapot.json"
PAGE = ROOT / "docs" / "fit.md"
STALE = "stale: rerun `make fit` (it rewrites docs/fit_teapot.json and docs/fit.md)"


@pytest.fixture(scope="module")
def record() -> dict:
    return json.loads(RECORD.read_text())


def _config(record: dict, tmp_path: Path) -> pipeline.PipelineConfig:
    path = tmp_path / "config.toml"
    path.write_text(tomli_w.dumps(record["config"]))
    return configfile.read_config(path)


def test_page_shows_the_record(record: dict) -> None:
    text = PAGE.read_text()
    block = report.docs_block(record, "docs/fit_teapot.json")
    assert block in text, STALE
    assert record["met"] and record["rtl_proof"]["equal"]


def test_readme_quotes_the_record(record: dict) -> None:
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert report.readme_sentence(record) in readme, STALE


def test_search_finds_the_recorded_design(teapot_file, record: dict, tmp_path: Path) -> None:
    the_scene = scenefile.builtin_scene(record["scene"], record["size"], record["size"])
    frame_raster = raster.rasterise(the_scene)
    needs = analyse.analyse(frame_raster)
    assert json.loads(json.dumps(needs.as_dict())) == record["needs"], STALE
    evaluate = search.Evaluator(frame_raster, "record")
    found = search.search(evaluate, needs, search.Target(), policy=record["policy"])
    assert found.met
    assert configfile.config_dict(found.config) == record["config"], STALE
    assert found.steps == record["steps"], STALE


def test_recorded_design_gives_the_recorded_accuracy(
    teapot_file, record: dict, tmp_path: Path
) -> None:
    cfg = _config(record, tmp_path)
    the_scene = scenefile.builtin_scene(record["scene"], record["size"], record["size"])
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
    part = next(iter(record["cost"]))
    assert kept["cost"] == record["cost"][part]
    for c in cands:  # the share is the sum of used / available, from the recorded figures
        cap = PARTS[part].capacity()
        assert c["share"] == pytest.approx(
            sum(c["cost"][k] / cap[k] for k in ("LUT", "FF", "BRAM", "DSP")), rel=1e-12
        )


def test_record_meets_the_size_targets(record: dict) -> None:
    """Teapot fitted to NMSE <= 0.00025: the fitted core fits an iCE40 UP5K (the default core
    does not); on ECP5-25F at most half the default core's LUTs and a third of its BRAM.  (How
    long the fit took is a figure of docs/fit.md, measured once, not a test.)"""
    assert record["cost"]["up5k"]["fits"] and not record["default_cost"]["up5k"]["fits"]
    ecp5, default = record["cost"]["ecp5-25f"], record["default_cost"]["ecp5-25f"]
    assert 2 * ecp5["LUT"] <= default["LUT"]
    assert 3 * ecp5["BRAM"] <= default["BRAM"]
