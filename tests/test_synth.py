# SPDX-License-Identifier: Apache-2.0
"""make synth: one real synthesis + place and route, the parsers on its files, the refusals,
and docs/synth.json recorded from the current RTL, ROM images and parameters.

The real run is the divider at its article configuration (9-bit dividend, 5-bit divisor) on the
iCE40 HX8K: a few seconds with the yowasp tools, into a fresh cache folder; a narrow BRDF unit
(a configuration of its own, its ROM images generated) runs on the ECP5-25F.  The shading core (a
top of several files, its parameters from sim.synth_tops) is placed and routed in the slow tier;
the quick tier checks its wrapper, its cell count and its refusals.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from model.hw import PARTS, TARGETS, UNITS, SynthResult, default_runs, parse, report, synthesise
from model.hw import synth as hw_synth
from model.hw.sources import source_list
from model.hw.wrapper import ports, wrapper_verilog
from model.render.core import PixelFormat, SpanFormat
from model.render.pipeline import METHODS
from model.units import brdf, divider
from sim import synth_tops

ROOT = Path(__file__).resolve().parent.parent
RECORD = ROOT / "docs" / "synth.json"

# The lines of a real nextpnr-ice40 log (specular_unit, default configuration, on the HX8K)
# that say the design does not fit.
HX8K_OVERFLOW_LOG = """\
Info: Device utilisation:
Info: \t         ICESTORM_LC:    3156/   7680    41%
Info: \t        ICESTORM_RAM:      69/     32   215%
Info: \t               SB_IO:       6/    206     2%
ERROR: Unable to place cell 'u_unit.a_rom.0.3_RAM', no BELs remaining to implement cell type \
'ICESTORM_RAM'
"""


@pytest.fixture(scope="module")
def small(tmp_path_factory: pytest.TempPathFactory) -> tuple[SynthResult, float, Path]:
    """A real run into an empty cache: (result, seconds it took, its run folder)."""
    cache = tmp_path_factory.mktemp("synth") / "cache"
    mp = pytest.MonkeyPatch()
    mp.setenv("SYNTH_CACHE", str(cache))
    start = time.monotonic()
    result = synthesise("divider_shift", divider.ARTICLE, "hx8k", seed=1)
    took = time.monotonic() - start
    yield result, took, hw_synth.run_dir(result)
    mp.undo()


def test_small_run_gives_sane_figures(small: tuple[SynthResult, float, Path]) -> None:
    r, _, _ = small
    assert (r.unit, r.config, r.part, r.seed) == ("divider_shift", "article", "hx8k", 1)
    # the unit's own cells: operand registers (9 + 5), shift register, accumulator, control
    assert 40 <= r.lut <= 400 and 50 <= r.ff <= 200
    assert (r.bram, r.dsp) == (0, 0)  # a 32-word ROM stays in LUTs
    assert dict(r.other).get("SB_CARRY", 0) > 0
    assert r.fits and r.overflow == ""
    assert 50 <= r.fmax_mhz <= 400
    assert r.path_ns == pytest.approx(1000 / r.fmax_mhz, rel=0.15)
    assert r.path_from.startswith("u_unit.") or r.path_to.startswith("u_unit.")
    util = {k: (u, a) for k, u, a in r.utilisation}
    # the design (wrapper included) uses more logic cells than the unit alone, six IOs
    assert util["ICESTORM_LC"][0] > r.lut and util["SB_IO"] == (6, 206)
    assert r.target_mhz is None and r.meets_target is None and r.ok
    assert dict(r.tools)["yosys"].startswith("Yosys ")


def test_cache_hit_returns_the_same_result_at_once(small: tuple[SynthResult, float, Path]) -> None:
    r, _, _ = small

    def no_tool(*args: object, **kwargs: object) -> None:
        raise AssertionError(f"a cache hit ran a tool: {args}")

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hw_synth.subprocess, "run", no_tool)
        again = synthesise("divider_shift", "article", "hx8k", seed=1)
    assert again == r
    assert (Path(hw_synth.cache_dir()) / f"{r.key}.json").is_file()


def test_parsers_on_the_real_run(small: tuple[SynthResult, float, Path]) -> None:
    r, _, folder = small
    stat = (folder / "stat.json").read_text()
    modules = parse.stat_modules(stat)
    assert set(modules) == {"divider_shift", "synth_top"}
    cells = parse.classify(modules["divider_shift"], "ice40")
    assert (cells.lut, cells.ff, cells.bram, cells.dsp, cells.other) == (
        r.lut, r.ff, r.bram, r.dsp, r.other,
    )  # fmt: skip
    # the wrapper: two flip-flops per input bit (17) and one per output bit (20)
    top = parse.classify(modules["synth_top"], "ice40")
    assert top.ff == 2 * 17 + 20
    assert parse.yosys_version(stat) == dict(r.tools)["yosys"]
    rep = (folder / "report.json").read_text()
    timing = parse.report_timing(rep)
    assert (timing.fmax_mhz, timing.path_ns) == (r.fmax_mhz, r.path_ns)
    assert parse.report_utilisation(rep) == r.utilisation
    assert parse.log_overflow((folder / "nextpnr.log").read_text()) is None


def test_overflow_is_read_from_the_log() -> None:
    assert parse.log_overflow(HX8K_OVERFLOW_LOG) == "ICESTORM_RAM 69/32"
    last = HX8K_OVERFLOW_LOG.splitlines()[-1]
    assert parse.log_overflow(last) is None or "ICESTORM_RAM" in parse.log_overflow(last)
    assert parse.log_overflow("Info: Program finished normally.\n") is None


def test_wrapper_reads_the_ports_from_the_rtl() -> None:
    params = hw_synth.synth_parameters("divider_shift", divider.DEFAULT)
    got = {
        p.name: (p.direction, p.width)
        for p in ports(hw_synth.RTL_DIR / "divider_shift.v", "divider_shift", params)
    }
    assert got["a_in"] == ("input", 21) and got["k_in"] == ("input", 11)
    assert got["q"] == ("output", 41) and got["valid"] == ("output", 1)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("adder", None, "hx8k"), ["'adder'", "divider_shift", "specular_unit"]),
        (("divider_shift", None, "xc9"), ["'xc9'", "up5k", "ecp5-25f"]),
        (("divider_shift", "up5k", "hx8k"), ["'up5k'", "default", "article"]),
        (("gouraud_segment", divider.DEFAULT, "hx8k"), ["DividerConfig", "GouraudConfig"]),
        (("brdf_unit", "default", "hx8k"), ["'default'", "cosine_quadratic, quadratic"]),
        (("brdf_unit", divider.DEFAULT, "hx8k"), ["DividerConfig", "FixedConfig"]),
        (
            ("brdf_unit", brdf.FixedConfig("piecewise", coef_bits=22), "hx8k"),
            ["coef_bits = 22", "11..21"],
        ),
    ],
)
def test_bad_input_is_refused(args: tuple, words: list[str]) -> None:
    with pytest.raises(ValueError) as err:
        synthesise(*args)
    for word in words:
        assert word in str(err.value)
    with pytest.raises(ValueError, match="seed"):
        synthesise("divider_shift", None, "hx8k", seed=-1)


def test_cli_refuses_an_unknown_part() -> None:
    proc = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "synth.py"), "--parts", "xc9"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert proc.returncode == 2 and "'xc9'" in proc.stderr and "hx8k" in proc.stderr


def test_a_missed_target_fails_the_run(small: tuple[SynthResult, float, Path]) -> None:
    r, _, _ = small
    missed = SynthResult(**{**r.to_json(), "target_mhz": 1000.0, "meets_target": False})
    unfit = SynthResult(**{**r.to_json(), "target_mhz": 10.0, "fits": False, "overflow": "X 2/1"})
    assert report.failures([r]) == []
    assert "misses the target 1000 MHz" in report.failures([missed])[0]
    assert "does not fit hx8k: X 2/1" in report.failures([unfit])[0]
    assert "**NO**" in report.table([missed]) and "**no** (X 2/1)" in report.table([unfit])


def test_every_target_is_in_the_default_runs() -> None:
    runs = default_runs(tuple(synth_tops.TOPS))
    assert set(TARGETS) <= set(runs)
    assert {p for _, _, p in runs} == set(PARTS)
    assert {u for u, _, _ in runs} == set(UNITS) | set(synth_tops.TOPS)
    # without the tops: the units' runs only, as before the core
    assert {u for u, _, _ in default_runs()} == set(UNITS)
    assert ("shading_core", "hybrid", "ecp5-25f") in runs
    # the BRDF unit has no "default": each form on every part
    brdf_runs = {(c, p) for u, c, p in runs if u == "brdf_unit"}
    assert brdf_runs == {(c, p) for c in brdf.UNIT_CONFIGS for p in PARTS}
    assert hw_synth.config_named("brdf_unit", None) == (
        "cosine_quadratic", brdf.UNIT_CONFIGS["cosine_quadratic"],
    )  # fmt: skip


def test_the_record_is_current(teapot_file) -> None:
    """docs/synth.json was made from the RTL, ROM images and parameters there are now, and holds
    every run of make synth (remake it: make synth SYNTH_ARGS='--record docs/synth.json')."""
    data = json.loads(RECORD.read_text())
    results = [SynthResult.from_json(r) for r in data["results"]]
    missing = set(default_runs(tuple(synth_tops.TOPS))) - {
        (r.unit, r.config, r.part) for r in results
    }
    assert not missing, f"docs/synth.json lacks the runs {sorted(missing)}"
    stale = []
    for r in results:
        params = None if r.unit in UNITS else synth_tops.parameters(r.unit, r.config)
        now = hw_synth.run_inputs(r.unit, r.config, params)
        if dict(r.inputs) != now:
            changed = [k for k in now if dict(r.inputs).get(k) != now[k]]
            stale.append(f"{r.unit} ({r.config}) on {r.part}: {', '.join(changed)} changed")
    assert not stale, "docs/synth.json is stale:\n" + "\n".join(stale)


@pytest.mark.parametrize("unit", list(UNITS))
def test_every_unit_gets_a_wrapper(unit: str) -> None:
    """Every port of the unit's RTL is wired: inputs from the hold register, outputs captured."""
    _, cfg = hw_synth.config_named(unit, "up5k" if unit == "specular_unit" else None)
    params = hw_synth.synth_parameters(unit, cfg)
    found = ports(hw_synth.RTL_DIR / f"{unit}.v", unit, params)
    text = wrapper_verilog(unit, found, params)
    for p in found:
        assert f".{p.name}(" in text
    assert text.count("\n    input  wire ") == 5 and text.count("\n    output wire ") == 1


def test_the_units_synthesise_their_listed_files() -> None:
    """A unit's rtl/<unit>.f names its own file first, then its submodules (the BRDF unit's form
    datapaths and rounding) and the ROM module the divider, the specular unit and the BRDF unit
    instantiate; the run reads exactly those files and hashes their bytes."""
    below = {
        "gouraud_segment": [],
        "brdf_unit": [
            "brdf_front.v", "brdf_cosine_quadratic.v", "brdf_quadratic.v", "brdf_cubic.v",
            "brdf_log2.v", "brdf_piecewise.v", "brdf_div.v", "brdf_delay.v", "brdf_mul.v",
            "brdf_round.v", "shading_rom.v",
        ],
    }  # fmt: skip
    for unit in UNITS:
        files = [f"{unit}.v", *below.get(unit, ["shading_rom.v"])]
        listed = [(hw_synth.RTL_DIR / name).resolve() for name in files]
        assert source_list(unit) == listed
        assert list(hw_synth.rtl_sources(unit)) == [p.name for p in listed]
        params = hw_synth.synth_parameters(unit, hw_synth.config_named(unit, None)[1])
        got = hw_synth.inputs_of(unit, params)["rtl"]
        assert (
            got == hw_synth.inputs_of(unit, params, b"".join(p.read_bytes() for p in listed))["rtl"]
        )


@pytest.mark.parametrize("config", ["default", "hybrid", "brdf_log2"])
def test_the_core_gets_a_wrapper(config: str) -> None:
    """The core's ports from its source list, the derived widths evaluated (s_axis_tdata is
    SpanFormat.width bits, m_axis_tdata PixelFormat.width), every port wired; a BRDF
    highlight's configuration names its form and its tables."""
    params = synth_tops.parameters("shading_core", config)
    method = synth_tops.TOPS["shading_core"][config]
    assert params == synth_tops.core_run.parameters(synth_tops.core_run.method_config(method))
    assert params["HIGHLIGHT"] == ("log2" if config == "brdf_log2" else "specular")
    text = "\n".join(d.decode() for d in hw_synth.rtl_sources("shading_core").values())
    local = {k: v for k, v in params.items() if not k.endswith("ROM_FILE")}
    found = {p.name: (p.direction, p.width) for p in ports(text, "shading_core", local)}
    fmt = SpanFormat(METHODS["diffuse"])
    assert found["s_axis_tdata"] == ("input", fmt.width) == ("input", 352)
    assert found["m_axis_tdata"] == ("output", PixelFormat().width)
    wrapped = wrapper_verilog("shading_core", ports(text, "shading_core", local), local)
    for name in found:
        assert f".{name}(" in wrapped
    assert f"reg [{fmt.width + 1}:0] in_hold" in wrapped  # tdata, tvalid and tready


def test_the_core_is_refused_where_it_is_not_a_unit() -> None:
    params = synth_tops.parameters("shading_core")
    with pytest.raises(ValueError, match="'shading_core' is unknown"):
        synthesise("shading_core", None, "ecp5-25f")
    with pytest.raises(ValueError, match="is a unit"):
        hw_synth.synthesise_top("divider_shift", {}, "ecp5-25f")
    with pytest.raises(ValueError, match=r"A_ROM_FILE = 'nowhere\.hex' does not exist"):
        hw_synth.synthesise_top("shading_core", {**params, "A_ROM_FILE": "nowhere.hex"})
    with pytest.raises(ValueError, match="has no source list"):
        hw_synth.synthesise_top("no_such_top", {}, "ecp5-25f")
    with pytest.raises(ValueError, match="'up5k' is unknown for shading_core"):
        synth_tops.parameters("shading_core", "up5k")
    with pytest.raises(ValueError, match="known tops are shading_core"):
        synth_tops.parameters("adder")


def test_cells_under_a_top_count_every_instance() -> None:
    """stat_tree: a submodule's cells once per instance (the core has three increments)."""
    stat = {
        "modules": {
            "$paramod$1\\inc": {"num_cells_by_type": {"MULT18X18D": 4, "TRELLIS_FF": 22}},
            "$paramod$2\\top": {
                "num_cells_by_type": {"LUT4": 10, "$paramod$1\\inc": 3, "TRELLIS_FF": 1}
            },
            "\\synth_top": {"num_cells_by_type": {"TRELLIS_FF": 9, "$paramod$2\\top": 1}},
        }
    }
    assert parse.stat_tree(stat, "top") == {"LUT4": 10, "MULT18X18D": 12, "TRELLIS_FF": 67}
    assert parse.stat_tree(stat, "synth_top")["TRELLIS_FF"] == 76
    with pytest.raises(ValueError, match="names 0 modules"):
        parse.stat_tree(stat, "nothing")


def test_cells_are_counted_per_family() -> None:
    """Cell names as the real runs of make synth give them (docs/synth.json)."""
    ecp5 = parse.classify(
        {"LUT4": 10, "CCU2C": 3, "PFUMX": 2, "TRELLIS_FF": 5, "DP16KD": 2, "MULT18X18D": 1}, "ecp5"
    )
    assert (ecp5.lut, ecp5.ff, ecp5.bram, ecp5.dsp) == (16, 5, 2, 1)
    gowin = parse.classify({"LUT4": 4, "LUT2": 1, "ALU": 3, "DFFRE": 2, "SDPB": 1}, "gowin")
    assert (gowin.lut, gowin.ff, gowin.bram) == (8, 2, 1)
    xc7 = parse.classify({"LUT6": 2, "CARRY4": 1, "FDRE": 3, "RAMB36E1": 1, "DSP48E1": 2}, "xilinx")
    assert (xc7.lut, xc7.ff, xc7.bram, xc7.dsp) == (2, 3, 2, 2)


def test_the_fpga_page_carries_the_recorded_table() -> None:
    """docs/fpga.md's synthesis table is report.table() of docs/synth.json, row for row (paste
    out/synth/synth.md after a --record run)."""
    data = json.loads(RECORD.read_text())
    results = [SynthResult.from_json(r) for r in data["results"]]
    page = (ROOT / "docs" / "fpga.md").read_text()
    missing = [line for line in report.table(results).splitlines() if line and line not in page]
    assert not missing, "docs/fpga.md lacks these lines of the recorded table:\n" + "\n".join(
        missing
    )


@pytest.mark.parametrize(
    ("row", "config", "part"), [("`DEFAULT`", "default", "ecp5-25f"), ("`UP5K`", "up5k", "up5k")]
)
def test_the_specular_page_quotes_the_record(row: str, config: str, part: str) -> None:
    """docs/specular.md's FPGA table: Fmax, target, LUT, FF, block RAM and DSP as recorded."""
    data = json.loads(RECORD.read_text())
    (r,) = [
        SynthResult.from_json(x)
        for x in data["results"]
        if (x["unit"], x["config"], x["part"]) == ("specular_unit", config, part)
    ]
    page = (ROOT / "docs" / "specular.md").read_text()
    (line,) = [ln for ln in page.splitlines() if ln.startswith(f"| {row} (")]
    cells = [c.strip() for c in line.strip("|").split("|")]
    assert cells[2] == f"{r.fmax_mhz:.1f} MHz" and cells[3] == f"{r.target_mhz:g} MHz"
    assert (cells[4], cells[5]) == (str(r.lut), str(r.ff))
    assert cells[6].startswith(f"{r.bram} ") and cells[7].startswith(f"{r.dsp} ")


def _brdf_script():
    spec = importlib.util.spec_from_file_location("brdf_unit_script", ROOT / "scripts/brdf_unit.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_brdf_page_carries_the_recorded_resources() -> None:
    """docs/brdf_unit.md's Resources table is what python scripts/brdf_unit.py --resources prints
    from docs/synth.json, and each statement of its list holds in the record."""
    script = _brdf_script()
    page = (ROOT / "docs" / "brdf_unit.md").read_text()
    begin = "<!-- resources: python scripts/brdf_unit.py --resources -->\n"
    shown = page[page.index(begin) + len(begin) : page.index("<!-- end of resources -->")]
    assert shown == script.resources(RECORD), "stale: python scripts/brdf_unit.py --resources"
    results = report.load(RECORD)
    row = {(r.unit, r.config, r.part): r for r in results}
    forms = list(brdf.UNIT_CONFIGS)
    for part in PARTS:
        spec = row["specular_unit", "default", part]
        placed = [x for x in (spec, row.get(("specular_unit", "up5k", part))) if x and x.fmax_mhz]
        cq, q, cubic, log2, pw = (row["brdf_unit", form, part] for form in forms)
        for r in (cq, q, cubic, log2, pw):
            assert r.bram < spec.bram and r.ff > spec.ff  # fewer block RAMs, more flip-flops
            if PARTS[part].dsp and part != "gw1nr-9":
                assert r.dsp > spec.dsp  # more DSP blocks where the part has them
            if PARTS[part].dsp == 0:
                assert r.dsp == 0
            if not r.fits:
                continue
            assert r.ok, r
            if part in ("up5k", "gw1nr-9"):  # slower there than the specular unit, but log2
                # and the Gowin's cubic and piecewise form
                faster = r is log2 or (part == "gw1nr-9" and r in (cubic, pw))
                assert all((r.fmax_mhz > o.fmax_mhz) == faster for o in placed), (r, placed)
            if part == "ecp5-25f":  # faster there than the specular unit's default
                assert r.fmax_mhz > spec.fmax_mhz, (r, spec)
        assert cq.fits and q.fits  # both fit every part, targets met
        assert cq.lut < q.lut and cq.ff < q.ff and cq.bram < q.bram  # the cheaper form
        # the cubic: more of everything than the quadratic; no iCE40 holds it
        assert cubic.lut > q.lut and cubic.ff > q.ff and cubic.bram > q.bram
        assert cubic.dsp > q.dsp if PARTS[part].dsp else cubic.dsp == 0
        assert cubic.fits == (part not in ("up5k", "hx8k")), cubic
        if PARTS[part].dsp:
            assert cubic.dsp == 17
        # the log2 form: fits every part, the fewest DSP blocks of the forms, the fastest, one
        # block RAM more than the cosine-quadratic (its second table), the fewest LUTs where
        # its products are not on LUT-rich paths (ECP5, Gowin) or all LUTs (HX8K)
        others = (cq, q, cubic)
        assert log2.fits and all(log2.fmax_mhz > r.fmax_mhz for r in others if r.fmax_mhz)
        if PARTS[part].dsp:
            assert all(log2.dsp < r.dsp for r in others)
        if part in ("ecp5-25f", "gw1nr-9", "hx8k"):
            assert all(log2.lut < r.lut for r in others)
        one_bram = {"up5k": 4, "hx8k": 4}.get(part, 1)
        assert log2.bram == cq.bram + one_bram
        # the piecewise form: more LUTs, flip-flops and block RAMs than the cubic everywhere,
        # more DSP blocks (two more where beta's 18 bits are one block's operand); no iCE40
        # holds it; no target on the ECP5-25F, where its placement moves it across 100 MHz
        assert pw.lut > cubic.lut and pw.ff > cubic.ff and pw.bram > cubic.bram
        assert pw.dsp > cubic.dsp if PARTS[part].dsp else pw.dsp == 0
        if part in ("ecp5-25f", "gw1nr-9"):
            assert pw.dsp == cubic.dsp + 2 == 19 <= PARTS[part].dsp
        assert pw.fits == (part not in ("up5k", "hx8k")), pw
        if part == "ecp5-25f":
            assert pw.target_mhz is None
    for part in ("up5k", "hx8k"):
        assert not row["specular_unit", "default", part].fits
        assert row["brdf_unit", "cubic", part].bram == 38 > PARTS[part].bram
        assert row["brdf_unit", "piecewise", part].bram == 47 > PARTS[part].bram
    assert "ICESTORM_DSP 17/8" in row["brdf_unit", "cubic", "up5k"].overflow
    assert "ICESTORM_LC" in row["brdf_unit", "cubic", "hx8k"].overflow
    spec_target = {k[2]: v for k, v in TARGETS.items() if k[0] == "specular_unit"}
    for form in forms[:-1]:  # the specular unit's 100 MHz on the ECP5 (the piecewise: none)
        ecp5 = row["brdf_unit", form, "ecp5-25f"]
        assert ecp5.target_mhz == spec_target["ecp5-25f"] <= ecp5.fmax_mhz
    # 35 MHz on the UP5K: the quadratic under 40, the cosine-quadratic at its edge; the cubic
    # has no target there; the log2 form the specular unit's 40
    log2_up5k = row["brdf_unit", "log2", "up5k"]
    assert log2_up5k.target_mhz == spec_target["up5k"] <= log2_up5k.fmax_mhz
    cq_up5k, q_up5k = (row["brdf_unit", form, "up5k"] for form in ("cosine_quadratic", "quadratic"))
    assert cq_up5k.target_mhz == q_up5k.target_mhz == 35 <= q_up5k.fmax_mhz < spec_target["up5k"]
    assert 35 <= cq_up5k.fmax_mhz < 42 and row["brdf_unit", "cubic", "up5k"].target_mhz is None
    hardware = brdf.format_hardware()  # the cost table the list cites: 3 multipliers against 2
    assert "base x base (25 x 25)" in hardware and "c x (1 - a w) (21 x 25)" in hardware
    counts = {f"brdf_unit, {f}": n for f, n in zip(forms, (3, 3, 5, 2, 6), strict=True)}
    for unit, count in [*counts.items(), ("specular_unit (the", 2)]:
        (line,) = [ln for ln in hardware.splitlines() if ln.startswith(f"| {unit}")]
        assert line.split(" | ")[1].startswith(f"{count}: "), line


def test_the_brdf_resources_refuse_a_bad_record(tmp_path: Path) -> None:
    script = _brdf_script()
    with pytest.raises(ValueError, match="does not exist"):
        script.resources(tmp_path / "none.json")
    results = report.load(RECORD)
    with pytest.raises(ValueError, match=r"unit 'brdf_unit' has no row in the record: it holds"):
        report.beside([r for r in results if r.unit != "brdf_unit"], "brdf_unit", script.BASE)
    with pytest.raises(ValueError, match=r"base \('specular_unit', 'default'\) has no row on up5k"):
        report.beside(
            [r for r in results if r.part != "up5k" or r.unit != "specular_unit"],
            "brdf_unit",
            script.BASE,
        )


def test_a_small_brdf_unit_places_and_routes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The BRDF unit through the whole flow, cheaply: the quadratic form at narrow widths (a
    64-word angle table, 10-bit coefficients: a configuration of its own, so both ROM images are
    generated into the cache's folder) on the ECP5-25F, a few seconds."""
    monkeypatch.setenv("SYNTH_CACHE", str(tmp_path / "cache"))
    cfg = brdf.FixedConfig("quadratic", cos_addr_bits=6, cos_data_bits=8, coef_bits=10,
                           work_bits=8, out_bits=6)  # fmt: skip
    r = synthesise("brdf_unit", cfg, "ecp5-25f", seed=1)
    params = dict(r.params)
    assert (r.unit, r.config, r.part) == ("brdf_unit", "custom", "ecp5-25f")
    assert params["FORM"] == "quadratic" and params["COS_ADDR_BITS"] == 6
    for name in ("ANGLE_ROM_FILE", "COEF_ROM_FILE"):
        assert (tmp_path / "roms" / params[name]).is_file(), params[name]
    assert (tmp_path / "roms" / params["COEF_ROM_FILE"]).read_text() == brdf.rom_text(cfg, "coef")
    util = {k: (u, a) for k, u, a in r.utilisation}
    assert r.fits and r.overflow == "" and r.target_mhz is None and r.ok
    assert util["DP16KD"][0] == r.bram >= 1 and util["MULT18X18D"][0] == r.dsp >= 3
    assert util["TRELLIS_IO"][0] == 6 and 100 <= r.lut <= 2000 and 100 <= r.ff <= 1000
    assert 50 <= r.fmax_mhz <= 400 and r.path_ns == pytest.approx(1000 / r.fmax_mhz, rel=0.15)


def test_the_slowest_clock_gives_the_critical_path() -> None:
    """nextpnr-ice40 reports a second clock for a DSP whose clock pin is tied to ground (the
    BRDF unit's UP5K runs): Fmax and the path are the slower, real clock's."""

    def path(cell_from: str, cell_to: str, ns: float) -> list[dict]:
        return [{"from": {"cell": cell_from}, "to": {"cell": cell_to}, "delay": ns}]

    rep = {
        "fmax": {"gnd": {"achieved": 317.0}, "clk": {"achieved": 41.5}},
        "critical_paths": [
            {"from": "posedge gnd", "to": "posedge gnd", "path": path("u_unit.a", "u_unit.b", 3)},
            {"from": "posedge clk", "to": "posedge clk", "path": path("u_unit.c", "u_unit.d", 24)},
        ],
    }
    timing = parse.report_timing(rep)
    assert (timing.fmax_mhz, timing.path_from, timing.path_to, timing.path_ns) == (
        41.5, "u_unit.c", "u_unit.d", 24,
    )  # fmt: skip


def test_the_cli_runs_every_brdf_form_without_a_config() -> None:
    spec = importlib.util.spec_from_file_location("synth_script", ROOT / "scripts/synth.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    parser_args = module.argparse.Namespace(units=["brdf_unit"], parts=["xc7"], config=None)
    assert module.runs_of(parser_args) == [
        ("brdf_unit", "cosine_quadratic", "xc7"), ("brdf_unit", "quadratic", "xc7"),
        ("brdf_unit", "cubic", "xc7"), ("brdf_unit", "log2", "xc7"),
        ("brdf_unit", "piecewise", "xc7"),
    ]  # fmt: skip
    parser_args.config = ["quadratic"]
    assert module.runs_of(parser_args) == [("brdf_unit", "quadratic", "xc7")]
    parser_args.config = ["default"]
    with pytest.raises(ValueError, match="'default' is unknown for brdf_unit"):
        module.runs_of(parser_args)


def test_the_up5k_specular_configuration_places_and_routes_on_the_up5k(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The UP5K target row, placed and routed here (a fresh cache, so in every CI run) through
    the six-pin wrapper: it fits the UP5K (block RAMs within its 30) and meets 40 MHz."""
    monkeypatch.setenv("SYNTH_CACHE", str(tmp_path / "cache"))
    r = synthesise("specular_unit", "up5k", "up5k", seed=1)
    util = {k: (u, a) for k, u, a in r.utilisation}
    assert r.fits and r.overflow == "", r.overflow
    assert util["ICESTORM_RAM"][0] == r.bram <= util["ICESTORM_RAM"][1] == 30
    assert util["SB_IO"][0] == 6 <= util["SB_IO"][1]
    assert r.target_mhz == 40 and r.meets_target and r.fmax_mhz >= 40, r.fmax_mhz


# "default" holds both paths; "hybrid" (the highlight path alone, a subset of its hardware) is
# placed and routed by make synth, whose record row (docs/synth.json) it fails on a missed target
@pytest.mark.parametrize("config", ["default"])
def test_the_core_places_and_routes_on_the_ecp5(
    config: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The shading core from rtl/shading_core.f behind the six-pin wrapper on the ECP5-25F: it
    fits, every instance's cells are counted (three increments' DSPs), and the run holds its
    target (>= 100 MHz: make synth fails while it misses it, as it does for a unit)."""
    monkeypatch.setenv("SYNTH_CACHE", str(tmp_path / "cache"))
    r = synth_tops.synthesise("shading_core", config, "ecp5-25f", seed=1)
    assert (r.unit, r.config, r.part) == ("shading_core", config, "ecp5-25f")
    assert r.fits and r.overflow == "", r.overflow
    util = {k: (u, a) for k, u, a in r.utilisation}
    assert util["MULT18X18D"][0] == r.dsp and util["DP16KD"][0] == r.bram
    assert util["TRELLIS_IO"][0] == 6 and util["TRELLIS_FF"][0] > r.ff > 0
    assert r.target_mhz == 100 and r.meets_target == (r.fmax_mhz >= 100)
    stat = (hw_synth.run_dir(r) / "stat.json").read_text()
    assert parse.classify(parse.stat_tree(stat, "shading_core"), "ecp5").dsp == r.dsp
    assert r.ok, f"Fmax {r.fmax_mhz} MHz, critical path {r.path_from} -> {r.path_to}"
