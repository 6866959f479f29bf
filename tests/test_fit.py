# SPDX-License-Identifier: Apache-2.0
"""``shading fit``: the scene analysis, the decoder ranges it builds, a small fit end to end (the
model meets the target on a fresh render, the bundle reads back, a second run comes from the
cache), an unreachable target said plainly, the fitted core's RTL against the model on the scene,
and the fitted top level's range guard on span beats under Icarus (with a probe: the same check
fails on a top whose guard is cut)."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from model.cli import main
from model.fit import analyse, cost, parallel, report, run, search, verilog
from model.render import configfile, core, meshes, pipeline, raster, reference, scenefile, shade
from model.study import metrics
from model.units import brdf, specular

SIZE = 48


@pytest.fixture(scope="module")
def sphere_fit(tmp_path_factory: pytest.TempPathFactory) -> tuple[report.FitReport, Path]:
    out = tmp_path_factory.mktemp("fit") / "sphere"
    cache = out.parent / "cache"
    found = run.fit(
        scenefile.SceneSource("builtin", "sphere"),
        SIZE,
        out,
        synthesise=False,
        cache_dir=cache,
        say=lambda line: None,
    )
    return found, out


def test_k_ranges_give_every_used_n_its_patent_k() -> None:
    for n in range(1, specular.N_MAX + 1):
        ranges = search.k_ranges_for((n,))
        assert ranges == ((1, specular.N_MAX, specular.decode_k(n)),)
    for used in [(1, 50), (2, 3, 7), (1, 2, 5, 999), (6, 7), (40, 200, 1000)]:
        ranges = search.k_ranges_for(used)
        cfg = specular.SpecularConfig(k_ranges=ranges)  # a legal configuration
        assert len(ranges) == len({specular.decode_k(n) for n in used})
        for n in used:
            (k,) = [k for lo, hi, k in cfg.k_ranges if lo <= n <= hi]
            assert k == specular.decode_k(n), (used, n)


def test_analysis_equals_what_the_renderer_sends(sphere_fit) -> None:
    found, _ = sphere_fit
    frame_raster = raster.rasterise(scenefile.builtin_scene("sphere", SIZE, SIZE))
    frame = shade.shade(frame_raster, reference.exact_blinn)
    needs = found.needs
    assert needs == analyse.analyse(frame_raster)
    assert needs.n_values == frame.stats.n_values
    assert needs.longest_span == frame.stats.longest_span
    assert needs.pixels == frame.stats.pixels_shaded
    assert sum(c for _, c in needs.span_histogram) == needs.spans == frame.stats.spans_shaded
    # The fitted units hold every operand the scene sends.
    cfg = found.result.config
    assert cfg.gouraud.len_max >= needs.longest_span
    assert cfg.divider.k_max >= needs.divisor_max
    assert cfg.specular.len_max >= needs.longest_span - 1
    assert all(cfg.specular.n_first <= n <= cfg.specular.n_last for n in needs.n_values)


def test_fitted_design_meets_the_target_on_a_fresh_render(sphere_fit) -> None:
    found, out = sphere_fit
    assert found.result.met
    cfg = configfile.read_config(out / "config.toml")
    assert cfg == found.result.config
    the_scene = scenefile.builtin_scene("sphere", SIZE, SIZE)
    ref = shade.render(the_scene, reference.exact_blinn).rgb
    img = shade.render(the_scene, pipeline.unit_shader(cfg)).rgb
    value = metrics.nmse(img, ref)
    assert value <= found.target.nmse
    assert value == pytest.approx(found.result.comparison.nmse, rel=0, abs=0)
    # ... and it is much smaller than the default design (the point of fitting).
    default = pipeline.PipelineConfig()
    assert cfg.specular.rom_bits < default.specular.rom_bits / 100
    assert cfg.gouraud.p == 2 and cfg.divider.rom_bits < default.divider.rom_bits / 50


def test_bundle_files_and_report(sphere_fit) -> None:
    found, out = sphere_fit
    names = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert {"config.toml", "report.md", "fit.json", "error.png", "shading_fit_top.v"} <= names
    assert {"shading_fit.core", "shading_fit.f", verilog.LINT_WAIVER} <= names
    rtl = [f"rtl/{p.name}" for p in verilog.core_sources()]
    assert "rtl/shading_core.v" in rtl and set(rtl) <= names
    for name in rtl:  # the core's RTL as the repository holds it
        assert (out / name).read_bytes() == (verilog.RTL_DIR / name[4:]).read_bytes()
    listed = [ln for ln in (out / "shading_fit.f").read_text().splitlines() if "//" not in ln]
    assert listed == [*rtl, f"{verilog.TOP}.v"]
    roms = {n for n in names if n.startswith("rom/")}
    assert roms == {f"rom/{r}" for r in verilog.rom_images(found.result.config)}
    top = (out / f"{verilog.TOP}.v").read_text()
    for name, value in verilog.core_parameters(found.result.config).items():
        assert f".{name}(" in top and str(value if isinstance(value, str) else int(value)) in top
    text = (out / "report.md").read_text()
    assert f"meets {found.target.describe()}" in text
    assert f"NMSE {found.result.comparison.nmse:.6f}" in text
    assert "(not synthesised: --no-synth)" in text


def test_second_fit_renders_nothing(sphere_fit, tmp_path: Path) -> None:
    found, out = sphere_fit
    again = run.fit(
        scenefile.SceneSource("builtin", "sphere"),
        SIZE,
        tmp_path / "again",
        synthesise=False,
        cache_dir=out.parent / "cache",
        say=lambda line: None,
    )
    assert again.renders == 0 and again.cache_hits > 0
    assert again.result.config == found.result.config


def test_unreachable_target_is_said_plainly(tmp_path: Path, capsys) -> None:
    status = main(
        ["fit", "--scene", "sphere", "--size", "24", "--nmse", "1e-12", "--no-synth",
         "--out", str(tmp_path / "o")]
    )  # fmt: skip
    out = capsys.readouterr().out
    assert status == 1
    assert "CANNOT meet NMSE <= 1e-12: no shading mode meets" in out
    assert "the closest is" in out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--nmse", "0"], "argument --nmse: 0 is not allowed: must be a number > 0"),
        (["--nmse", "x"], "argument --nmse: 'x' is not allowed: must be a number > 0"),
        (["--lanes", "3"], "argument --lanes: invalid choice: 3"),
        (["--part", "vu9p"], "argument --part: invalid choice: 'vu9p'"),
        (["--max-error", "300"], "target max_error = 300.0 is out of range: legal is 0..255"),
        (["--min-fmax", "-5"], "argument --min-fmax: -5 is not allowed: must be a number > 0"),
        (
            ["--min-fmax", "100", "--no-synth"],
            "argument --min-fmax: 100 is not allowed with --no-synth: an Fmax comes from synthesis",
        ),
        (["--workers", "0"], "argument --workers: 0 is not allowed: must be an integer >= 1"),
    ],
)
def test_bad_arguments_are_refused(args: list[str], message: str, capsys) -> None:
    with pytest.raises(SystemExit) as info:
        main(["fit", *args])
    assert info.value.code == 2
    assert message in capsys.readouterr().err


# ------------------------------------------------------------------------------------------------
# the range guard of shading_fit_top on span beats, under Icarus

GUARD_BENCH = """`timescale 1ns/1ps
module tb;
reg clk = 0, rst_n = 0, s_axis_tvalid = 0;
reg [WIDTH-1:0] s_axis_tdata = 0;
wire s_axis_tready, m_axis_tlast, m_axis_tuser, m_axis_tvalid, range_err;
wire [PIX-1:0] m_axis_tdata;
reg [WIDTH-1:0] beats [0:CASES-1];
integer i;
shading_fit_top dut (.clk(clk), .rst_n(rst_n), .s_axis_tdata(s_axis_tdata),
    .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready), .m_axis_tdata(m_axis_tdata),
    .m_axis_tlast(m_axis_tlast), .m_axis_tuser(m_axis_tuser), .m_axis_tvalid(m_axis_tvalid),
    .m_axis_tready(1'b1), .range_err(range_err));
always #5 clk = ~clk;
initial begin
    $readmemh("beats.hex", beats);
    for (i = 0; i < CASES; i = i + 1) begin
        rst_n = 0; @(posedge clk); @(posedge clk); #1; rst_n = 1; @(posedge clk); #1;
        $display("before %0d %0d", i, range_err);
        s_axis_tdata = beats[i]; s_axis_tvalid = 1;
        @(posedge clk); while (!s_axis_tready) @(posedge clk);
        #1; s_axis_tvalid = 0; s_axis_tdata = 0;
        @(posedge clk); #1; $display("after %0d %0d", i, range_err);
        @(posedge clk); #1; $display("after %0d %0d", i, range_err);
    end
    $finish;
end
endmodule
"""


def _guard_cases(cfg: pipeline.PipelineConfig) -> list[tuple[str, dict[str, int], int]]:
    """(name, span fields, whether the guard must flag it) of every guard case."""
    lim = verilog.guard_limits(cfg)
    l_field = dict((n, w) for n, _, w in core.SpanFormat(cfg).layout())["l"]
    lo, hi = lim["n_first"], lim["n_last"]
    cases = [
        ("plain", {"l": 3}, 0),
        ("l_max", {"l": lim["l_max"]}, 0),
        ("n_first", {"spec": 1, "n": lo}, 0),
        ("n_last", {"spec": 1, "n": hi}, 0),
        ("n_below", {"spec": 1, "n": lo - 1}, 1),
        ("n_above", {"spec": 1, "n": hi + 1}, 1),
        ("n_top", {"spec": 1, "n": (1 << core.N_WIDTH) - 1}, 1),
        ("n_no_spec", {"n": hi + 1}, 0),  # n is read only on a highlight span
        ("diff", {"diff": 1}, 0 if lim["diffuse"] else 1),
    ]
    if lim["l_max"] < (1 << l_field) - 1:
        cases += [("l_over", {"l": lim["l_max"] + 1}, 1), ("l_top", {"l": (1 << l_field) - 1}, 1)]
    return cases


def _run_guard(tmp_path: Path, bundle: Path, top_text: str, words: list[int]) -> list[int]:
    """``range_err`` after each beat (each after a reset, which must have cleared it)."""
    if shutil.which("iverilog") is None:  # make test installs it (scripts/ensure-tools.sh)
        pytest.fail("iverilog is not installed: run `make tools`")
    cfg = configfile.read_config(bundle / "config.toml")
    fmt = core.SpanFormat(cfg)
    work = tmp_path / "guard"
    shutil.copytree(bundle / "rom", work / "rom")
    shutil.copytree(bundle / "rtl", work / "rtl")
    (work / f"{verilog.TOP}.v").write_text(top_text)
    (work / "beats.hex").write_text("".join(f"{w:x}\n" for w in words))
    bench = GUARD_BENCH.replace("WIDTH-1", str(fmt.width - 1)).replace("CASES", str(len(words)))
    (work / "tb.v").write_text(bench.replace("PIX-1", str(core.PixelFormat().width - 1)))
    (work / "shading_fit.f").write_text((bundle / "shading_fit.f").read_text())
    subprocess.run(
        ["iverilog", "-g2005", "-o", "tb.vvp", "-s", "tb", "-c", "shading_fit.f", "tb.v"],
        cwd=work, check=True, capture_output=True, text=True,
    )  # fmt: skip
    sim = subprocess.run(["vvp", "-n", "tb.vvp"], cwd=work, capture_output=True, text=True)
    assert sim.returncode == 0, sim.stdout + sim.stderr
    seen = re.findall(r"^(before|after) (\d+) (\d)$", sim.stdout, re.M)
    assert len(seen) == 3 * len(words), sim.stdout
    assert all(v == "0" for kind, _, v in seen if kind == "before"), "reset must clear range_err"
    after = [int(v) for kind, _, v in seen if kind == "after"]
    assert after[0::2] == after[1::2], "range_err must stay up"
    return after[0::2]


def test_range_guard_flags_what_the_fit_did_not_build(sphere_fit, tmp_path: Path) -> None:
    found, out = sphere_fit
    cfg = found.result.config
    cases = _guard_cases(cfg)
    layout = core.SpanFormat(cfg).layout()
    words = [core.pack(layout, fields) for _, fields, _ in cases]
    want = [flag for *_, flag in cases]
    # the guard's model says the same
    flagged = {int(line.split()[2].rstrip(":")) for line in verilog.guard_flags(words, cfg)}
    assert [int(i in flagged) for i in range(len(words))] == want
    top = (out / f"{verilog.TOP}.v").read_text()
    assert _run_guard(tmp_path, out, top, words) == want, [c[0] for c in cases]
    # The probe: with the guard cut, the same check sees the difference.
    cut = re.sub(r"wire range_bad = [^;]*;", "wire range_bad = 1'b0;", top)
    assert cut != top
    assert _run_guard(tmp_path / "cut", out, cut, words) != want


def test_the_scene_never_trips_the_guard(sphere_fit) -> None:
    found, _ = sphere_fit
    cfg = found.result.config
    frame_raster = raster.rasterise(scenefile.builtin_scene("sphere", SIZE, SIZE))
    words = core.frame_stream(frame_raster, cfg).words
    assert len(words) == found.needs.spans and verilog.guard_flags(words, cfg) == []


def test_fitted_top_is_lint_clean(sphere_fit) -> None:
    _, out = sphere_fit
    if shutil.which("verilator") is None:
        pytest.fail("verilator is not installed: run `make tools`")
    lint = subprocess.run(
        ["verilator", "--lint-only", "-Wall", verilog.LINT_WAIVER, "-F", "shading_fit.f",
         "--top-module", verilog.TOP],
        cwd=out, capture_output=True, text=True,
    )  # fmt: skip
    assert lint.returncode == 0, lint.stderr


def test_the_synthesised_parameters_are_the_benches(sphere_fit, tmp_path: Path) -> None:
    """``cost.synth_parameters`` (what the fit places) is ``sim.core_run.parameters`` (what the
    core's benches build), for the fitted and the default configuration."""
    from sim import core_run

    found, _ = sphere_fit
    for cfg in (found.result.config, cost.DEFAULT_DESIGN):
        assert cost.synth_parameters(cfg, tmp_path) == core_run.parameters(cfg, tmp_path)


# ------------------------------------------------------------------------------------------------
# the model's guard, and the fitted RTL against the model on the fitted scene


def test_model_refuses_an_n_the_fit_dropped(sphere_fit) -> None:
    found, _ = sphere_fit
    cfg = found.result.config
    the_scene = scenefile.builtin_scene("sphere", SIZE, SIZE)
    obj = the_scene.objects[0]
    n = cfg.specular.n_last + 1
    other = dataclasses.replace(
        the_scene,
        objects=(dataclasses.replace(obj, material=dataclasses.replace(obj.material, n=n)),),
    )
    with pytest.raises(ValueError) as info:
        shade.render(other, pipeline.unit_shader(cfg))
    assert str(info.value).startswith(
        f"material n = {n} (object 0) is out of range for this specular unit: legal range is "
        f"{cfg.specular.n_first}..{cfg.specular.n_last}"
    )


def test_model_refuses_a_longer_span(sphere_fit) -> None:
    found, _ = sphere_fit
    cfg = found.result.config
    bigger = scenefile.builtin_scene("sphere", 4 * SIZE, 4 * SIZE)
    with pytest.raises(ValueError, match=r"span of \d+ pixels is out of range: the units take"):
        shade.render(bigger, pipeline.unit_shader(cfg))


@pytest.mark.sim
def test_fitted_rtl_equals_the_model_byte_for_byte(sphere_fit) -> None:
    """The fitted core's RTL (Icarus) on every span of the scene: the frame equals the model's
    byte for byte, in the clocks the model gives (what ``shading fit`` proves, in-process)."""
    from sim.core_run import cosimulate

    found, _ = sphere_fit
    cfg = found.result.config
    result = cosimulate("sphere", SIZE, cfg, sim="icarus", tag="fit_test")
    diff = (result.rtl_rgb != result.model_rgb).any(axis=2)
    assert not diff.any(), f"{int(diff.sum())} pixels differ"
    assert result.equal and result.run.pixels == found.needs.pixels
    assert result.run.spans == found.needs.spans and result.run.cycles == result.model_cycles


def test_the_fit_proves_the_core_through_the_bench_command(sphere_fit) -> None:
    """``run.prove_rtl``: ``python -m sim bench --config --core-only`` on the bundle's
    configuration, the frame equal, its lines kept."""
    found, out = sphere_fit
    source = scenefile.SceneSource("builtin", "sphere")
    proof = run.prove_rtl(source, SIZE, out / "config.toml")
    assert proof["equal"], proof
    assert proof["command"].endswith("--core-only")
    row = [line.split() for line in proof["lines"] if line.endswith("equal")]
    assert row and row[0][:3] == ["sphere", "config", str(found.needs.pixels)], proof["lines"]


# ------------------------------------------------------------------------------------------------
# coarse meshes: method (h) where the fit needs it, or a plain "cannot"


def _coarse_fit(tmp_path: Path, subdivisions: int) -> report.FitReport:
    size = 64
    the_scene = meshes.scene_from_mesh(
        meshes.sphere_mesh(subdivisions=subdivisions), width=size, height=size
    )
    return run.fit(
        the_scene, size, tmp_path / "bundle", synthesise=False, cache_dir=None, say=lambda _: None
    )


def test_coarse_mesh_is_fitted_through_method_h(tmp_path: Path) -> None:
    """An 80-triangle icosphere: the Gouraud diffuse term misses NMSE <= 0.00025 in every
    specular mode; the diffuse term through the specular unit (h) meets it."""
    found = _coarse_fit(tmp_path, 1)
    r = found.result
    assert r.met and r.config.diffuse_mode != "gouraud"
    gouraud_modes = [s for s in r.steps if s.startswith("mode ") and "diffuse" not in s]
    tried = [search.mode_families(m, search.FAMILIES) for m in search.modes()]
    # vertex, then the adaptive and the unit mode with each family (cos^k and the five forms)
    assert len(gouraud_modes) == sum(len(f) for m, f in zip(search.modes(), tried, strict=True)
                                     if "diffuse_mode" not in m) == 1 + 2 * 6 == 13  # fmt: skip
    for step in gouraud_modes:  # each Gouraud-diffuse design was rendered and missed the target
        assert float(step.split("NMSE ")[1].split(",")[0]) > found.target.nmse
    assert 1 in range(r.config.specular.n_first, r.config.specular.n_last + 1)
    assert r.config.specular.k_ranges[0] == (1, 1, 1)  # the k = 1 table for the diffuse jobs


def test_too_coarse_mesh_is_said_plainly(tmp_path: Path) -> None:
    """A 20-triangle icosphere: no mode meets the target even at the widest widths."""
    found = _coarse_fit(tmp_path, 0)
    assert not found.result.met
    text = (tmp_path / "bundle" / "report.md").read_text()
    assert "CANNOT meet NMSE <= 0.00025: no shading mode meets" in text
    assert "The closest design (the target is not met)" in text
    every = sum(len(search.mode_families(m, search.FAMILIES)) for m in search.modes())
    assert len([s for s in found.result.steps if s.startswith("mode ")]) == every


def test_bundle_core_lints_and_synthesises_under_fusesoc(sphere_fit, tmp_path: Path) -> None:
    """The bundle's FuseSoC core: listed, its lint target (Verilator -Wall) clean, its synth
    target (Yosys for iCE40, through the repository's Tcl shim as for the unit cores) a netlist
    of iCE40 cells."""
    from tests.test_fusesoc import shim_path

    _, out = sphere_fit
    exe = shutil.which("fusesoc", path=str(Path(sys.executable).parent)) or shutil.which("fusesoc")
    assert exe, "fusesoc is not installed: pip install -e '.[dev]' (make setup)"

    def fusesoc(*args: str, path: str | None = None) -> subprocess.CompletedProcess:
        env = {**os.environ, "PATH": path or f"{Path(sys.executable).parent}:{os.environ['PATH']}"}
        return subprocess.run(
            [exe, "--cores-root", str(out), *args],
            capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300,
        )  # fmt: skip

    listed = fusesoc("core", "list")
    assert listed.returncode == 0 and "shading:fit:sphere" in listed.stdout, listed.stderr
    build = tmp_path / "build"
    for target, path in (("lint", None), ("synth", shim_path(tmp_path))):
        ran = fusesoc("run", "--build-root", str(build), "--target", target, "shading:fit:sphere",
                      path=path)  # fmt: skip
        assert ran.returncode == 0, f"{target}:\n{ran.stdout[-2000:]}{ran.stderr[-2000:]}"
    work = build / "shading_fit_sphere_0.1" / "synth-yosys"
    netlist = json.loads((work / "shading_fit_sphere_0.1.json").read_text())
    cells = {c["type"] for m in netlist["modules"].values() for c in m["cells"].values()}
    assert "SB_LUT4" in cells and verilog.TOP in netlist["modules"], sorted(netlist["modules"])


def test_descents_on_dask_find_the_same_designs(sphere_fit, tmp_path: Path) -> None:
    found, _ = sphere_fit
    the_scene = scenefile.builtin_scene("sphere", SIZE, SIZE)
    frame_raster = raster.rasterise(the_scene)
    here = search.search_candidates(
        search.Evaluator(frame_raster, "here"), found.needs, search.Target()
    )
    evaluate = search.Evaluator(frame_raster, "dask", tmp_path / "cache.json")
    there, rendered = parallel.search_candidates_dask(
        the_scene, evaluate, found.needs, search.Target(), workers=2
    )
    assert [r.config for r in there] == [r.config for r in here]
    assert [r.steps for r in there] == [r.steps for r in here]
    assert rendered > 0 and evaluate.renders < rendered  # the descents rendered on the workers
    # ... and their figures came back: the cache file holds them, a second search renders nothing
    again = search.Evaluator(frame_raster, "dask", tmp_path / "cache.json")
    search.search_candidates(again, found.needs, search.Target())
    assert again.renders == 0


def test_candidates_are_placed_and_routed_and_the_fmax_floor_holds(
    tmp_path: Path, monkeypatch
) -> None:
    """With synthesis, every candidate is placed and routed on the first part and the cheapest
    reaching ``min_mhz`` is kept; a floor no candidate reaches is said plainly."""
    monkeypatch.setenv("SYNTH_CACHE", str(tmp_path / "synth"))
    source = scenefile.SceneSource("builtin", "sphere")

    def fit(min_mhz: float, out: str) -> report.FitReport:
        return run.fit(
            source,
            32,
            tmp_path / out,
            parts=("up5k",),
            compare_default=False,
            min_mhz=min_mhz,
            cache_dir=tmp_path / "cache",
            say=lambda _: None,
        )

    low = fit(1.0, "low")
    assert len(low.candidates) >= 2 and low.fmax_met
    shares = {c.policy: cost.part_share(r, "up5k") for c, r in low.candidates}
    assert shares[low.result.policy] == min(shares.values())
    assert low.costs["up5k"].key in {r.key for _, r in low.candidates}  # the same design
    high = fit(1000.0, "high")
    assert not high.fmax_met and high.result.met
    text = (tmp_path / "high" / "report.md").read_text()
    assert "NO candidate reaches 1000 MHz on up5k: the cheapest is kept, and the fit fails" in text


# ------------------------------------------------------------------------------------------------
# the highlight's unit as a knob: the patent's cos^k unit or a BRDF family unit

GALLERY = Path(__file__).resolve().parents[1] / "examples" / "gallery.toml"


@pytest.fixture(scope="module")
def gallery() -> tuple[search.Evaluator, analyse.SceneNeeds]:
    """The four-material example scene (n = 3, 12, 60, 400) at 64 x 64."""
    frame_raster = raster.rasterise(scenefile.scene_source(str(GALLERY)).scene(64, 64))
    return search.Evaluator(frame_raster, "gallery-64"), analyse.analyse(frame_raster)


def _step_nmse(step: str) -> float:
    return float(step.split("NMSE ")[1].split(",")[0])


def test_every_family_is_tried_and_each_that_meets_starts_a_descent(gallery) -> None:
    evaluate, needs = gallery
    target = search.Target()
    starts = search.choose_starts(evaluate, needs, target)
    assert all(s.met for s in starts)
    mode = starts[0].config.specular_mode  # the first mode where a family meets the target
    assert all(s.config.specular_mode == mode for s in starts)
    tried = {
        step.split("family ")[1].split(":")[0]: _step_nmse(step)
        for step in starts[0].steps
        if f"specular_mode = {mode}, family" in step
    }
    assert tuple(tried) == search.FAMILIES  # every family, in order, in that mode
    meeting = [f for f in search.FAMILIES if tried[f] <= target.nmse]
    assert [search.family(s.config) for s in starts] == meeting
    assert len(meeting) >= 2 and meeting[0] == search.COS_K  # BRDF families among them
    for s in starts:  # each start is its family's scene-sized design, with the shared formats
        if s.config.brdf is not None:
            assert s.config.brdf == dataclasses.replace(
                brdf.UNIT_CONFIGS[s.config.brdf.form],
                angle=dataclasses.replace(
                    brdf.UNIT_CONFIGS[s.config.brdf.form].angle,
                    **{f: getattr(s.config.specular, f) for f in brdf.ANGLE_FIELDS},
                ),
            )


def test_a_brdf_descent_moves_only_the_widths_its_design_reads(gallery) -> None:
    evaluate, needs = gallery
    target = search.Target()
    (start,) = search.choose_starts(evaluate, needs, target, families=("log2",))
    found = search.descend(evaluate, start, target, "bits")
    cfg = found.config
    assert found.met and search.family(cfg) == "log2" and target.met(found.comparison)
    moved = {step.split(":")[0] for step in found.steps if not step.startswith("mode ")}
    readable = {f"brdf.{name}" for name in cfg.brdf.widths_read} | {
        f"{k.table}.{k.name}" for k in search.KNOBS if k.name not in search.COS_K_ONLY
    }
    assert moved and moved <= readable, moved - readable
    assert any(m.startswith("brdf.") for m in moved)
    for name in brdf.ANGLE_FIELDS:  # the BRDF unit's formats follow the shared registers
        assert getattr(cfg.brdf.angle, name) == getattr(cfg.specular, name), name
    assert search.design_bits(cfg) < search.design_bits(start.config)


def test_a_family_is_checked_by_name(capsys) -> None:
    with pytest.raises(ValueError, match=r"family 'phong' is out of range: legal are cos\^k, "):
        search.check_family("phong")
    with pytest.raises(SystemExit) as exc:
        main(["fit", "--scene", "sphere", "--family", "phong", "--no-synth"])
    assert exc.value.code == 2
    assert "family 'phong' is out of range: legal are cos^k, cosine_quadratic" in (
        capsys.readouterr().err
    )


def test_the_units_a_brdf_design_uses_are_named() -> None:
    """A design whose highlight goes through a BRDF unit names that unit's field (the report's
    and fit.json's "units"), in place of the patent's specular unit."""
    for form, cfg in pipeline.BRDF_METHODS.items():
        assert cost.units_used(cfg) == ("divider", "gouraud", "brdf"), form
    assert cost.units_used(pipeline.METHODS["hybrid"]) == ("divider", "gouraud", "specular")
