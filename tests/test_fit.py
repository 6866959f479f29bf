# SPDX-License-Identifier: Apache-2.0
"""``shading fit``: the scene analysis, the decoder ranges it builds, a small fit end to end (the
model meets the target on a fresh render, the bundle reads back, a second run comes from the
cache), an unreachable target said plainly, and the fitted top level's range guard under Icarus
(with a probe: the same check fails on a top whose guard is cut)."""

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
from model.hw import wrapper
from model.render import configfile, meshes, pipeline, raster, reference, scenefile, shade
from model.study import metrics
from model.units import specular
from tests.conftest import record_sim

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
    assert {"shading_fit.core", "rtl/divider_shift.v", "rtl/gouraud_segment.v"} <= names
    roms = {n for n in names if n.startswith("rom/")}
    assert roms == {f"rom/{r}" for r in verilog.rom_images(found.result.config, found.units)}
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
# the range guard of shading_fit_top, under Icarus


def _guard_bench(top_text: str) -> str:
    """A testbench driving every input of ``shading_fit_top`` (0 unless written) that prints
    ``range_err`` after each case: ``<case> <range_err>``."""
    ports = [
        wrapper.Port(m.group(3), m.group(1), int(m.group(2) or 0) + 1)
        for m in re.finditer(
            r"^\s+(input|output)\s+wire\s+(?:\[(\d+):0\]\s+)?(\w+)", top_text, re.M
        )
    ]
    assert len(ports) > 20
    decl = []
    for p in ports:
        rng = f"[{p.width - 1}:0] " if p.width > 1 else ""
        kind = "reg " if p.direction == "input" else "wire"
        decl.append(f"{kind} {rng}{p.name}{' = 0' if p.direction == 'input' else ''};")
    conns = ", ".join(f".{p.name}({p.name})" for p in ports)
    widths = {p.name: p.width for p in ports}
    lens = [("div_k", "div_k_in"), ("gou_len", "gou_len_in"), ("spec_len", "spec_len_in")]
    return (
        "`timescale 1ns/1ps\nmodule tb;\n"
        + "\n".join(decl)
        + f"\n{verilog.TOP} dut ({conns});\n"
        + "always #5 clk = ~clk;\n"
        + "task write_len(input integer which, input integer value); begin\n"
        + "".join(
            f"  if (which == {i}) begin {name} = value; {name[:-3]}_we = 1; end\n"
            for i, (_, name) in enumerate(lens)
            if name in widths
        )
        + "  @(posedge clk); #1;\n"
        + "".join(f"  {name[:-3]}_we = 0;\n" for _, name in lens if name in widths)
        + "end endtask\n"
        + "task write_n(input integer value); begin\n"
        + "  spec_n_in = value; spec_n_we = 1; @(posedge clk); #1; spec_n_we = 0;\n"
        + "end endtask\n"
        + "task report(input [8*16-1:0] name); begin\n"
        + '  @(posedge clk); #1; $display("%0s %0d", name, range_err);\n'
        + "end endtask\n"
        + "task reset; begin rst_n = 0; @(posedge clk); @(posedge clk); #1; rst_n = 1; end "
        + "endtask\n"
        + 'initial begin\n  reset; report("idle");\n'
        + "  `CASES\n  $finish;\nend\nendmodule\n"
    )


def _run_guard(tmp_path: Path, bundle: Path, top_text: str, cases: str) -> dict[str, list[int]]:
    if shutil.which("iverilog") is None:  # make test installs it (scripts/ensure-tools.sh)
        pytest.fail("iverilog is not installed: run `make tools`")
    work = tmp_path / "guard"
    shutil.copytree(bundle / "rom", work / "rom")
    (work / "top.v").write_text(top_text)
    (work / "tb.v").write_text(_guard_bench(top_text).replace("`CASES", cases))
    rtl = sorted(str(p) for p in (bundle / "rtl").glob("*.v"))
    subprocess.run(
        ["iverilog", "-g2005", "-o", "tb.vvp", "-s", "tb", *rtl, "top.v", "tb.v"],
        cwd=work,
        check=True,
        capture_output=True,
        text=True,
    )
    sim = subprocess.run(["vvp", "-n", "tb.vvp"], cwd=work, capture_output=True, text=True)
    assert sim.returncode == 0, sim.stdout + sim.stderr
    seen: dict[str, list[int]] = {}
    for line in sim.stdout.splitlines():
        m = re.fullmatch(r"\s*(\w+) (\d)", line)
        if m:
            seen.setdefault(m.group(1), []).append(int(m.group(2)))
    return seen


def _guard_cases(cfg: pipeline.PipelineConfig) -> tuple[str, dict[str, list[int]]]:
    """Verilog for every guard case, and the ``range_err`` each must print."""
    s = cfg.specular
    cases, want = [], {}

    def case(name: str, body: str, expect: int) -> None:
        cases.append(f'reset; {body} report("{name}"); report("{name}");')
        want[name] = [expect, expect]

    for i, (name, top) in enumerate(
        [("div", cfg.divider.k_max), ("gou", cfg.gouraud.len_max), ("spec", s.len_max)]
    ):
        case(f"{name}_max", f"write_len({i}, {top});", 0)
        case(f"{name}_over", f"write_len({i}, {top + 1});", 1)
        case(f"{name}_top", f"write_len({i}, 2047);", 1)
    case("n_first", f"write_n({s.n_first});", 0)
    case("n_last", f"write_n({s.n_last});", 0)
    case("n_below", f"write_n({s.n_first - 1});", 1)
    case("n_above", f"write_n({s.n_last + 1});", 1)
    case("n_zero", "write_n(0);", 1)
    cases.append('reset; write_len(1, 2047); reset; report("cleared");')
    want["cleared"] = [0]
    want["idle"] = [0]
    return "\n  ".join(cases), want


def test_range_guard_flags_what_the_fit_did_not_see(sphere_fit, tmp_path: Path) -> None:
    found, out = sphere_fit
    cfg = found.result.config
    assert "specular" in found.units
    cases, want = _guard_cases(cfg)
    top = (out / f"{verilog.TOP}.v").read_text()
    assert _run_guard(tmp_path, out, top, cases) == want
    # The probe: with the guard cut, the same check sees the difference.
    cut = re.sub(r"wire range_bad = [^;]*;", "wire range_bad = 1'b0;", top)
    assert cut != top
    assert _run_guard(tmp_path / "cut", out, cut, cases) != want


def test_fitted_top_is_lint_clean(sphere_fit) -> None:
    _, out = sphere_fit
    if shutil.which("verilator") is None:
        pytest.fail("verilator is not installed: run `make tools`")
    rtl = sorted(str(p) for p in (out / "rtl").glob("*.v"))
    lint = subprocess.run(
        ["verilator", "--lint-only", "-Wall", "--top-module", verilog.TOP, *rtl,
         f"{verilog.TOP}.v"],
        cwd=out, capture_output=True, text=True,
    )  # fmt: skip
    assert lint.returncode == 0, lint.stderr


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
def test_fitted_rtl_equals_the_model_byte_for_byte(sphere_fit, request) -> None:
    from sim.scene_cosim import cosimulate

    found, _ = sphere_fit
    cfg = found.result.config
    result = cosimulate("sphere", SIZE, cfg, tag="fit_test")
    diff = (result.rtl_rgb != result.model_rgb).any(axis=2)
    assert not diff.any(), f"{int(diff.sum())} pixels differ"
    assert result.pixels == found.needs.pixels
    assert result.results["divider_shift"] == result.jobs["divider_shift"] > 100
    assert result.results["gouraud_segment"] >= 3 * found.needs.spans
    record_sim(
        request,
        [result.sim_record("fitted design co-simulation (image equal byte for byte)", "fit_cosim")],
    )


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
    assert len(gouraud_modes) == 3
    for step in gouraud_modes:  # each Gouraud-diffuse mode was rendered and missed the target
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
    assert len([s for s in found.result.steps if s.startswith("mode ")]) == len(search.modes())


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
