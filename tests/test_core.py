# SPDX-License-Identifier: Apache-2.0
"""The shading core (rtl/shading_core.v, docs/core.md): its stream formats and model, and its
RTL through the stream bench (sim/core_run.py) against the model, byte for byte and clock for
clock."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from model.hw.sources import source_list
from model.render import core
from model.render.pipeline import BRDF_METHODS, METHODS, PipelineConfig
from model.units import brdf, gouraud, specular
from sim import core_run

pytestmark = pytest.mark.sim

DEFAULT = METHODS["diffuse"]  # both paths: the highlight and the diffuse jobs


def random_words(
    fmt: core.SpanFormat, count: int, seed: int, lengths=None, lit: float = 0.0
) -> list[int]:
    """Span beats with every field random in its range (``lengths``: the pixels of each; by
    default 1..23; ``lit``: the share of spans with a lit highlight), from
    ``core_run.random_spans``."""
    if lengths is None:
        lengths = np.random.default_rng(seed + 1).integers(1, 24, count)
    return core_run.random_spans(fmt, lengths, seed, lit)


# ------------------------------------------------------------------------------ the formats


def test_span_beat_round_trips_every_field_at_both_ends():
    fmt = core.SpanFormat(DEFAULT)
    layout = fmt.layout()
    assert fmt.width % 8 == 0 and fmt.bits <= fmt.width < fmt.bits + 8
    assert layout[-1][1] + layout[-1][2] == fmt.bits
    for end in (0, 1):
        row = {}
        for name, _, w in layout:
            lo, hi = (
                (-(1 << (w - 1)), (1 << (w - 1)) - 1) if name in core.SIGNED else (0, (1 << w) - 1)
            )
            row[name] = hi if end else lo
        assert core.unpack(layout, core.pack(layout, row)) == row


def test_a_field_out_of_range_is_refused_by_name():
    layout = core.SpanFormat(DEFAULT).layout()
    with pytest.raises(
        ValueError, match=r"span field n = 1024 is out of range: legal range is 0\.\.1023"
    ):
        core.pack(layout, {"n": 1024})
    with pytest.raises(ValueError, match=r"span field dz = .* signed"):
        core.pack(layout, {"dz": 1 << 40})


def test_diffuse_jobs_must_share_their_angle():
    from model.render.pipeline import UnitJobs

    one = np.zeros(1, dtype=np.int64)
    jobs = UnitJobs(
        intervals=one, i_start=np.zeros((1, 3), np.int64), i_end=np.zeros((1, 3), np.int64),
        spec_span=one[:0], spec_c=one[:0], spec_dz=one[:0], spec_z0=one[:0], spec_n=one[:0],
        diff_span=np.zeros(3, np.int64), diff_channel=np.arange(3),
        diff_c=np.ones(3, np.int64), diff_dz=np.array([5, 5, 6]), diff_z0=np.zeros(3, np.int64),
    )  # fmt: skip
    with pytest.raises(ValueError, match="span 0: the diffuse jobs' dz, z0 differ between"):
        core.span_beats(jobs, one, one, core.SpanFormat(DEFAULT))


def test_bad_formats_and_timing_are_refused():
    with pytest.raises(ValueError, match=r"x_width = 17 is out of range: legal range is 1\.\.16"):
        core.SpanFormat(DEFAULT, x_width=17)
    with pytest.raises(ValueError, match="pixels = 0 is out of range"):
        core.core_cycles(0)
    kept = PipelineConfig(
        gouraud=gouraud.GouraudConfig(len_width=specular.KEPT.len_width), specular=specular.KEPT
    )
    with pytest.raises(ValueError, match="n_first = 17 is out of range for diffuse spans"):
        core.core_parameters(kept, diffuse_path=True)


def test_the_core_model_gives_the_pipeline_image_on_a_scene():
    """core_pixels (the units' per-line calls on the unpacked beats) = pipeline.unit_shader's
    image (the fused kernels), every method: the packer loses nothing."""
    from model.render import pipeline, raster, scenefile, shade

    frame = raster.rasterise(scenefile.builtin_scene("torus", 40, 40))
    for name, cfg in METHODS.items():
        fmt = core.SpanFormat(cfg)
        stream = core.frame_stream(frame, cfg, fmt)
        pixels = core.core_pixels(stream.words, fmt)
        rgb = np.array([[p["r"], p["g"], p["b"]] for p in pixels], dtype=np.uint8)
        per, at = {}, 0
        for obj, n in zip(stream.objects, stream.pixels, strict=True):
            per[obj] = rgb[at : at + n]
            at += n
        got = shade.shade(frame, lambda spans, ctx, per=per: per[ctx.obj]).rgb
        want = shade.shade(frame, pipeline.unit_shader(cfg)).rgb
        assert np.array_equal(got, want), name


def test_the_core_model_of_a_brdf_highlight_gives_the_pipeline_image():
    """core_pixels with the highlight through a BRDF unit (brdf.unit.unit_line per span) = the
    pipeline's image with ``PipelineConfig.brdf`` (brdf.lines.shade_lines), every form."""
    from model.render import pipeline, raster, scenefile, shade

    frame = raster.rasterise(scenefile.builtin_scene("sphere", 40, 40))
    for name, cfg in BRDF_METHODS.items():
        fmt = core.SpanFormat(cfg)
        stream = core.frame_stream(frame, cfg, fmt)
        pixels = core.core_pixels(stream.words, fmt)
        rgb = np.array([[p["r"], p["g"], p["b"]] for p in pixels], dtype=np.uint8)
        per, at = {}, 0
        for obj, n in zip(stream.objects, stream.pixels, strict=True):
            per[obj] = rgb[at : at + n]
            at += n
        got = shade.shade(frame, lambda spans, ctx, per=per: per[ctx.obj]).rgb
        want = shade.shade(frame, pipeline.unit_shader(cfg)).rgb
        assert np.array_equal(got, want), name
        assert not np.array_equal(want, shade.shade(frame, pipeline.unit_shader(METHODS[
            "hybrid"])).rgb), name  # fmt: skip


def test_the_latency_follows_the_highlight_path():
    """18 clocks with the patent's highlight path (and without one); with a BRDF form the
    span pipe, its front and back (7) and the form's stages (brdf.FORM_LATENCY), the FIFO."""
    assert core.latency() == core.LATENCY == 18
    assert core.latency(METHODS["gouraud"]) == core.LATENCY
    for form, cfg in BRDF_METHODS.items():
        stages = core.BRDF_FRONT_BACK + brdf.FORM_LATENCY[form]
        assert core.highlight_stages(cfg) == stages
        assert core.latency(cfg) == core.SPAN_PIPE + stages + 2
        assert core.latency(cfg, specular_path=False) == core.LATENCY
        assert core.core_cycles(100, cfg) == core.latency(cfg) + 100
    assert {f: core.latency(c) for f, c in BRDF_METHODS.items()} == {
        "cosine_quadratic": 20, "quadratic": 21, "cubic": 28, "log2": 22,
        "piecewise": 39}  # fmt: skip
    assert set(core.CORE_FORMS) <= set(brdf.RTL_FORMS)
    # docs/core.md's table, "Timing", is these
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "core.md").read_text()
    section = text.split("## Timing\n", 1)[1].split("\n## ", 1)[0]
    for name, cfg in (("specular", METHODS["hybrid"]), *BRDF_METHODS.items()):
        row = (f"| `{name}` | {core.highlight_stages(cfg)} | {core.pixel_pipe(cfg)} | "
               f"{core.latency(cfg)} |")  # fmt: skip
        assert row in section, row


def test_a_configuration_the_core_cannot_build_is_refused_by_name(monkeypatch):
    """A BRDF form without a pipe in the core (here: the cubic, taken out of CORE_FORMS as a
    form with RTL but no core pipe would be), and an output FIFO that the pixels in flight
    would fill: ValueError naming the field, its value and what is legal."""
    cfg = BRDF_METHODS["cubic"]
    with pytest.raises(ValueError, match=r"fifo_depth = 16 is out of range: legal is a power "
                       r"of two from 16 to 4096 above the 22 pixels in flight"):  # fmt: skip
        core.core_parameters(cfg, fifo_depth=16)
    with pytest.raises(ValueError, match="fifo_depth = 48 is out of range"):
        core.core_parameters(METHODS["hybrid"], fifo_depth=48)
    assert core.core_parameters(METHODS["hybrid"], fifo_depth=16)["FIFO_DEPTH"] == 16
    monkeypatch.setattr(core, "CORE_FORMS", ("cosine_quadratic", "quadratic", "log2"))
    says = r"brdf form = 'cubic' is out of range for the shading core: its highlight path takes"
    fmt = core.SpanFormat(cfg)
    for call in (
        lambda: core.core_parameters(cfg),
        lambda: core.core_pixels([0], fmt),
        lambda: core.core_cycles(10, cfg),
    ):
        with pytest.raises(ValueError, match=says):
            call()


def test_the_diffuse_pipe_shifts_exactly_where_rom_9_holds_one_for_n_1():
    """The core derives from K0 and ALPHA that the diffuse jobs' a (ROM 9's word of n = 1) is
    1.0 and then shifts instead of multiplying (rtl/shading_core.v DIFF_A_ONE): the model's
    word agrees for the patent's, the thesis's and the prototype's a, at every width."""
    from dataclasses import replace

    from model.units.specular import config as spec_config

    for cfg in (specular.DEFAULT, specular.INFLECTION, specular.PROTOTYPE, specular.NARROW,
                specular.UP5K, replace(specular.PROTOTYPE, alpha="inflection")):  # fmt: skip
        one = cfg.k_ranges[0][2] == 1 or cfg.alpha == "inflection"
        word = int(spec_config.a_words(cfg)[1])
        assert one == (word == 1 << cfg.a_frac_bits), cfg
    rtl = (core_run.vector_run.RTL_DIR / "shading_core.v").read_text()
    assert "localparam DIFF_A_ONE = (K0 == 1) || (ALPHA == ALPHA_INFLECTION);" in rtl


# ------------------------------------------------------------------------------ the RTL


@pytest.mark.parametrize("method", ["hybrid", "diffuse"])
def test_teapot_256_through_the_core_is_the_model_frame_at_one_pixel_per_clock(
    method, request, teapot_file
):
    r = core_run.cosimulate("teapot", 256, method)
    assert r.equal
    assert r.run.cycles == r.model_cycles == core.LATENCY + r.run.pixels
    assert r.run.px_per_clock >= 0.9
    # the figures README.md and docs/core.md give are these
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    for page in ("README.md", "docs/core.md"):
        text = " ".join((root / page).read_text().split())
        m = re.search(r"([\d ]+) pixels in ([\d ]+) clocks[ :(]+(\d\.\d+) p", text)
        assert m, page
        said = (int(m[1].replace(" ", "")), int(m[2].replace(" ", "")), float(m[3]))
        assert said == (r.run.pixels, r.run.cycles, round(r.run.px_per_clock, 4)), page
    from tests.conftest import record_sim

    record = {"unit": "shading_core", "test": method, "jobs": r.run.spans, "errors": 0}
    record_sim(request, [{**record, "compared": r.run.pixels, "cycles": r.run.cycles}])


@pytest.mark.parametrize("form", list(BRDF_METHODS))
def test_teapot_256_through_a_brdf_highlight_is_the_model_frame_at_one_pixel_per_clock(
    form, request, teapot_file
):
    """The teapot with the highlight through each BRDF form's pipe (BRDF_METHODS): the frame
    from the pixel beats equals the model's byte for byte, in the clocks the model gives
    (core.latency of the form + pixels); docs/core.md's table gives these figures."""
    cfg = BRDF_METHODS[form]
    r = core_run.cosimulate("teapot", 256, form, tag=f"core_teapot_{form}")
    assert r.equal
    assert r.run.cycles == r.model_cycles == core.latency(cfg) + r.run.pixels
    assert r.run.px_per_clock >= 0.9
    from pathlib import Path

    from tests.conftest import record_sim

    text = (Path(__file__).resolve().parents[1] / "docs" / "core.md").read_text()
    row = f"| `{form}` | {core.latency(cfg)} | {r.run.pixels} | {r.run.cycles} | " \
          f"{r.run.px_per_clock:.4f} |"  # fmt: skip
    assert row in text, row
    record = {"unit": "shading_core", "test": f"teapot_{form}", "jobs": r.run.spans, "errors": 0}
    record_sim(request, [{**record, "compared": r.run.pixels, "cycles": r.run.cycles}])


@pytest.mark.parametrize("form", list(BRDF_METHODS))
def test_random_spans_through_a_brdf_highlight_are_scoreboarded(form):
    """Random span beats, most with a lit highlight (back-to-back spans of different n, one
    pixel or the longest, n refused among them: tuser), random idles and stalls: every pixel
    beat equals the model's (the form's word of n travels with its pixels); with the diffuse
    path built beside it (DIFFUSE = 1, the diffuse terms waiting for the longer highlight) for
    the log2 form."""
    cfg = BRDF_METHODS[form]
    fmt = core.SpanFormat(cfg)
    longest = cfg.gouraud.len_max
    lengths = [1] * 40 + [longest, 2, 1, 5] + [3] * 30 + [1, 2] * 15
    if form == "piecewise":  # spans as far as its bloom part shines (core_run.random_spans)
        lengths += [6] * 40
    words = random_words(fmt, len(lengths), seed=17, lengths=lengths, lit=0.7)
    layout = fmt.layout()
    for at, n in ((5, 0), (6, 1001), (7, 1023)):  # refused n between lit spans: tuser
        words[at] = core.pack(layout, {**core.unpack(layout, words[at]), "spec": 1, "n": n})
    diffuse = form == "log2"
    params = core_run.parameters(cfg, diffuse_path=diffuse)
    r = core_run.run_words(words, fmt, params, idle_pct=30, stall_pct=40, seed=3,
                           tag=f"core_rand_{form}")  # fmt: skip
    assert r.mismatches == []
    assert r.pixels == sum(lengths) and r.stalls > 0
    want = core.core_pixels(words, fmt, diffuse_path=diffuse)
    dark = core.core_pixels(words, fmt, specular_path=False, diffuse_path=diffuse)
    lit_spans, at = 0, 0
    for n_px in lengths:
        got, off = want[at : at + n_px], dark[at : at + n_px]
        lit_spans += any((p["r"], p["g"], p["b"]) != (q["r"], q["g"], q["b"])
                         for p, q in zip(got, off, strict=True))  # fmt: skip
        at += n_px
    assert lit_spans > len(lengths) // 2 and any(p["n_err"] for p in want)
    if form == "piecewise":  # both parts lit: the cubic's, the divider's, spans across both
        seen = _piecewise_parts(words, fmt, want, dark)
        assert seen["cubic"] > 100 and seen["bloom"] > 100 and seen["across"] > 5, seen


def _piecewise_parts(words, fmt, want, dark) -> dict[str, int]:
    """Lit pixels of the piecewise form's cubic part (cos above its junction s = 0.5^(1/n)) and
    of its bloom part (below), and the spans lit in both, by each pixel's angle z0 + x dz."""
    import math

    layout, zf = fmt.layout(), fmt.cfg.specular.z_frac_bits
    seen, at = {"cubic": 0, "bloom": 0, "across": 0}, 0
    for word in words:
        f = core.unpack(layout, word)
        parts = set()
        for x in range(f["l"] + 1):
            p, q = want[at + x], dark[at + x]
            angle = abs(f["z0"] + x * f["dz"]) / (1 << zf) * math.pi / 2
            lit = (p["r"], p["g"], p["b"]) != (q["r"], q["g"], q["b"])
            if f["spec"] and 1 <= f["n"] <= 1000 and lit and angle < math.pi / 2:
                part = "cubic" if math.cos(angle) > 0.5 ** (1 / f["n"]) else "bloom"
                seen[part] += 1
                parts.add(part)
        seen["across"] += len(parts) == 2
        at += f["l"] + 1
    return seen


@pytest.mark.parametrize(
    ("form", "name"),
    [
        ("cubic", "shading_brdf_pipe_cubic_b1_early"),
        ("piecewise", "shading_brdf_pipe_piecewise_beta_early"),
    ],
)
def test_a_coefficient_a_stage_off_is_caught_with_the_span_that_shows_it(tmp_path, form, name):
    """The saved mutants (tests/mutants) that hand the form a coefficient of the pixel a stage
    behind: the cubic's b1, the piecewise form's beta.  Unlit spans leave them unseen; lit spans
    of random n back to back (with the piecewise form half of them reaching into its bloom
    part) show them, naming the pixel and its span beat."""
    from tests import mutants

    mutant = mutants.build(name, tmp_path)
    rtl = [mutant if p.name == "shading_brdf_pipe.v" else p for p in source_list("shading_core")]
    cfg = BRDF_METHODS[form]
    fmt = core.SpanFormat(cfg)
    params = core_run.parameters(cfg)
    unlit = random_words(fmt, 60, seed=3)
    r = core_run.run_words(unlit, fmt, params, tag=f"core_mutant_{form}", rtl=rtl)
    assert r.mismatches == []
    lit = random_words(fmt, 60, seed=3, lit=0.8)
    r = core_run.run_words(lit, fmt, params, tag=f"core_mutant_{form}", rtl=rtl)
    assert r.mismatches and "span beat 0x" in r.mismatches[0]


def test_a_pixel_beat_after_the_last_expected_one_fails_the_bench(tmp_path):
    """The saved mutant shading_core_issues_on (tests/mutants): after a run's last span the core
    goes on sending pixels.  Every expected beat is right, so only the bench's watch after the
    last expected pixel (TAIL_CYCLES, m_axis_tready high) sees the extra ones, and it fails."""
    from tests import mutants

    mutant = mutants.build("shading_core_issues_on", tmp_path)
    rtl = [mutant if p.name == "shading_core.v" else p for p in source_list("shading_core")]
    fmt = core.SpanFormat(DEFAULT)
    words = random_words(fmt, 1, seed=5)
    with pytest.raises(AssertionError, match="a pixel beat after the last expected one"):
        core_run.run_words(words, fmt, core_run.parameters(DEFAULT), tag="core_mutant_on",
                           rtl=rtl)  # fmt: skip
    r = core_run.run_words(words, fmt, core_run.parameters(DEFAULT), tag="core_mutant_on")
    assert r.mismatches == [] and r.pixels == len(core.core_pixels(words, fmt))


def test_the_diffuse_path_keeps_multiplier_11_where_a_of_n_1_is_not_one():
    """The prototype's one cos^2 table gives n = 1 the a sqrt(1/2): the diffuse pipe keeps its
    multiplier and ROM 9's second port (DIFF_A_ONE = 0); every pixel compared."""
    cfg = PipelineConfig(specular=specular.PROTOTYPE, diffuse_mode="unit")
    fmt = core.SpanFormat(cfg)
    words = random_words(fmt, 80, seed=21)
    params = core_run.parameters(cfg, core_run.SIM_BUILD / "core_prototype_roms")
    r = core_run.run_words(words, fmt, params, idle_pct=20, stall_pct=30, seed=2,
                           tag="core_prototype")  # fmt: skip
    assert r.mismatches == []
    assert any(p["diff"] for p in (core.unpack(fmt.layout(), w) for w in words))


@pytest.mark.parametrize("scene", ["sphere", "torus", "teapot", "quad"])
@pytest.mark.parametrize("method", list(METHODS))
def test_every_scene_and_method_at_64_is_the_model_frame(scene, method, teapot_file):
    r = core_run.cosimulate(scene, 64, method, tag=f"core_{scene}_{method}")
    assert r.equal
    assert r.run.cycles == r.model_cycles


def test_random_spans_under_random_idles_and_stalls_are_scoreboarded():
    """Random fields (invalid n included: tuser), spans of 1 pixel and of the longest length,
    sums that saturate; random idle cycles on s_axis and random tready on m_axis: every pixel
    beat equals the model's, none lost or reordered, the AXI4-Stream rules hold."""
    fmt = core.SpanFormat(DEFAULT)
    longest = DEFAULT.gouraud.len_max
    lengths = [1] * 40 + [longest, 2, 1, longest - 1] + [3] * 20
    words = random_words(fmt, len(lengths), seed=7, lengths=lengths)
    params = core_run.parameters(DEFAULT)
    r = core_run.run_words(words, fmt, params, idle_pct=30, stall_pct=40, seed=11, tag="core_rand")
    assert r.mismatches == []
    assert r.pixels == sum(lengths) and r.stalls > 0
    want = core.core_pixels(words, fmt)
    assert any(p["n_err"] for p in want) and any(255 in (p["r"], p["g"], p["b"]) for p in want)


def test_a_broken_core_is_caught_with_the_span_that_shows_it(tmp_path):
    """A one-line defect in the Gouraud rounding bias: the scoreboard names the pixel and the
    span beat that reproduces it."""
    rtl = []
    for path in source_list("shading_core"):
        copy = tmp_path / path.name
        shutil.copy(path, copy)
        rtl.append(copy)
    text = (tmp_path / "shading_core.v").read_text()
    assert text.count("G_BIAS = 1 << (I_FRAC - 1)") == 1
    (tmp_path / "shading_core.v").write_text(
        text.replace("G_BIAS = 1 << (I_FRAC - 1)", "G_BIAS = 0")
    )
    fmt = core.SpanFormat(DEFAULT)
    words = random_words(fmt, 30, seed=3)
    r = core_run.run_words(words, fmt, core_run.parameters(DEFAULT), tag="core_mutant", rtl=rtl)
    assert r.mismatches and "span beat 0x" in r.mismatches[0]


@pytest.mark.parametrize(
    ("override", "rule"),
    [
        ({"FIFO_DEPTH": 24}, "FIFO_DEPTH_must_be_a_power_of_2_from_16_to_4096"),
        ({"N_FIRST": 2, "DIFFUSE": 1}, "DIFFUSE_needs_N_FIRST_1"),
        ({"K_WIDTH": 9}, "K_WIDTH_must_reach_the_longest_span_s_intervals"),
        # the units' own rules, by the units' own names
        ({"MAG_INT_BITS": 2}, "specular_unit_PARAMETER_ERROR_MAG_INT_BITS_must_equal_the_model"),
        ({"K3": 65}, "specular_unit_PARAMETER_ERROR_K_of_a_table_must_be_1_to_64"),
        ({"ALPHA": "cubic"}, "specular_unit_PARAMETER_ERROR_ALPHA_must_be_taylor_or_inflection"),
        ({"RECIP_BITS": 9}, "K_WIDTH_must_be_1_to_RECIP_BITS_plus_1"),
        # the highlight's unit: a name that is no form; a BRDF form's pixels in flight
        ({"HIGHLIGHT": "phong"}, "HIGHLIGHT_must_be_specular_or_a_BRDF_form"),
        ({"HIGHLIGHT": "log"}, "HIGHLIGHT_must_be_specular_or_a_BRDF_form"),
        ({"HIGHLIGHT": "cubic", "FIFO_DEPTH": 16}, "FIFO_DEPTH_must_exceed_the_pixels_in_flight"),
        ({"HIGHLIGHT": "piecewise"}, "FIFO_DEPTH_must_exceed_the_pixels_in_flight"),  # 33 of 32
        (
            {"HIGHLIGHT": "piecewise", "FIFO_DEPTH": 64, "COEF_BITS": 22},
            "brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_11_to_21_for_the_piecewise_form",
        ),
        # the BRDF unit's own rules, by its own names
        (
            {"HIGHLIGHT": "quadratic", "COEF_BITS": 9},
            "brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_10_to_32_for_the_quadratic_form",
        ),
        (
            {"HIGHLIGHT": "log2", "COS_ADDR_BITS": 27},
            "brdf_unit_PARAMETER_ERROR_COS_ADDR_BITS_must_be_2_to_16_and_at_most_Z_FRAC_BITS",
        ),
    ],
)
def test_a_bad_parameter_stops_elaboration_naming_the_rule(override, rule):
    params = {**core_run.parameters(DEFAULT), **override}
    with pytest.raises(RuntimeError, match=rule):
        core_run.build(params, "icarus")


def _doc_table(heading: str) -> list[tuple[str, str, int]]:
    """(field, bits, width) rows of the table under ``## heading`` in docs/core.md."""
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "core.md").read_text()
    section = text.split(f"## {heading}\n", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and cells[2].isdigit():
            rows.append((cells[0], cells[1], int(cells[2])))
    return rows


def test_the_data_sheet_gives_every_field_bit_by_bit_as_the_packer_packs_it():
    fmt = core.SpanFormat(METHODS["hybrid"])
    for heading, layout in (
        ("Span beat", fmt.layout()),
        ("Pixel beat", core.PixelFormat().layout()),
    ):
        want = [(name, f"{lo + w - 1}:{lo}", w) for name, lo, w in layout]
        assert _doc_table(heading) == want, heading


def test_sim_bench_prints_every_scene_and_method_through_the_core(capsys, teapot_file):
    """``python -m sim bench``'s core table: every built-in scene and method (the BRDF methods
    among them), the frame equal to the model's and the clocks the model gives, the (c) and (h)
    targets on the scene."""
    from model.render import scenefile
    from sim.__main__ import core_bench

    assert core_bench(scenefile.SceneSource("builtin", "teapot"), 24, "icarus") == 0
    out = capsys.readouterr().out
    rows = [line.split() for line in out.splitlines() if line.startswith("  ") and "equal" in line]
    methods = [*METHODS, *BRDF_METHODS]
    assert len(rows) == len(scenefile.SCENE_NAMES) * len(methods)
    assert {(r[0], r[1]) for r in rows} == {(s, m) for s in scenefile.SCENE_NAMES for m in methods}
    for r in rows:
        assert r[3] == r[4] and float(r[5]) == pytest.approx(int(r[2]) / int(r[3]), abs=1e-4)
    assert out.count("px/clk: ") == 2  # the (c) and (h) target lines (met at 256, not at 24)


def test_the_teapot_s_fitted_configuration_through_the_core_is_the_model_frame(
    tmp_path, teapot_file
):
    """The configuration ``shading fit`` chose for the teapot (docs/fit_teapot.json): its core
    (narrow widths, one cos^16 table, the kept n = 40 only) gives the model's frame."""
    import json
    from pathlib import Path

    import tomli_w

    from model.render import configfile

    record = json.loads((Path(__file__).resolve().parents[1] / "docs/fit_teapot.json").read_text())
    path = tmp_path / "config.toml"
    path.write_bytes(tomli_w.dumps(record["config"]).encode())
    cfg = configfile.read_config(path)
    r = core_run.cosimulate("teapot", 256, cfg, tag="core_fitted")
    assert r.equal and r.run.cycles == r.model_cycles
    assert r.run.px_per_clock >= 0.9


def test_a_mesh_file_through_the_core_is_the_model_frame(tmp_path):
    import trimesh

    from model.render import scenefile

    path = tmp_path / "ball.obj"
    trimesh.creation.icosphere(subdivisions=2).export(path)
    target = scenefile.mesh_source(str(path), "auto").scene(48, 48)
    for method in ("hybrid", "diffuse"):
        r = core_run.cosimulate(target, 48, method, tag=f"core_mesh_{method}")
        assert r.equal and r.run.cycles == r.model_cycles, method


def test_a_soak_under_verilator_binary_scoreboards_every_pixel(request):
    """The vector soak: random span beats (every field at random, invalid n and the longest
    span included) with random idles and stalls through the core under ``verilator --binary``,
    every pixel compared; SOAK_SEED=N replays a run (the seed is printed in the summary)."""
    import random

    from sim.runner import env_seed
    from tests.conftest import record_sim

    seed = env_seed("SOAK_SEED")
    seed = random.randrange(1 << 30) if seed is None else seed
    fmt = core.SpanFormat(DEFAULT)
    rng = np.random.default_rng(seed)
    lengths = rng.integers(1, 24, 3000)
    lengths[rng.integers(0, lengths.size, 3)] = DEFAULT.gouraud.len_max
    words = random_words(fmt, lengths.size, seed, lengths=lengths)
    params = core_run.parameters(DEFAULT)
    r = core_run.run_words(
        words, fmt, params, sim="verilator", idle_pct=20, stall_pct=30, seed=seed, tag="soak"
    )
    assert r.mismatches == [], f"SOAK_SEED={seed}"
    assert r.pixels == int(lengths.sum())
    record = {"unit": "shading_core", "test": "soak", "jobs": r.spans, "errors": 0}
    record_sim(request, [{**record, "compared": r.pixels, "cycles": r.cycles, "seed": seed}])


# The divider's own check (its instance u_divider_rules: "ROM_FILE") or the core's reciprocal
# ROM ("RECIP_ROM_FILE"), whichever reads the image first, names the file and the field
ROM_DAMAGE = {
    "missing": r'ROM_FILE ".*missing\.hex": word 0 is undefined',
    "other": r'ROM_FILE ".*": check field (magic|width|depth) is',
    "short": r"ROM_FILE .*: word \d+ is undefined",
    "long": r"ROM_FILE .*: the file has \d+ words, more than the \d+ of this image",
    "data": r"ROM_FILE .*: check field checksum is .*a data word differs",
}


@pytest.mark.parametrize(
    ("sim", "damage"),
    [*(("icarus", d) for d in ROM_DAMAGE), ("verilator", "other"), ("verilator", "long")],
)
def test_a_bad_rom_image_stops_the_core_naming_file_and_field(sim, damage, tmp_path):
    """A missing, foreign, short, long or altered image stops the run at time 0 with one
    message naming the file and the field, under either simulator (Verilator: the two images
    its own $readmemh could not have reported)."""
    import re

    from model.units import divider

    says = ROM_DAMAGE[damage]
    params = core_run.parameters(DEFAULT)
    good = divider.rom_path(DEFAULT.divider).read_text().splitlines()
    path = tmp_path / f"{damage}.hex"
    if damage == "other":
        path = divider.rom_path(divider.ROM_CONFIGS["n16"])
    elif damage == "short":
        path.write_text("\n".join(good[:-5]) + "\n")
    elif damage == "long":
        path.write_text("\n".join([*good, good[-1]]) + "\n")
    elif damage == "data":
        first = next(i for i, line in enumerate(good) if not line.startswith("//"))
        good[first + 1] = "0" * len(good[first + 1])  # k = 1: 2^N
        path.write_text("\n".join(good) + "\n")
    fmt = core.SpanFormat(DEFAULT)
    words = random_words(fmt, 2, seed=1)
    with pytest.raises(AssertionError) as err:
        core_run.run_words(words, fmt, {**params, "RECIP_ROM_FILE": str(path)}, sim=sim,
                           tag=f"core_rom_{sim}_{damage}")  # fmt: skip
    assert re.search(says, str(err.value)), str(err.value)


def test_the_committed_vector_set_is_the_model_s_and_replays_without_python(tmp_path):
    """sim/vectors/core_default/ (make vectors): the span beats and the model's pixel beats as
    the generator writes them now; the bench alone (+EXPECT_FILE) passes on them and fails on a
    pixel changed."""
    import subprocess

    spans, pixels = core_run.vector_set_text()
    assert (core_run.VECTOR_SET / "spans.hex").read_text() == spans
    assert (core_run.VECTOR_SET / "pixels.hex").read_text() == pixels
    command, folder, _ = core_run.build(core_run.parameters(DEFAULT), "icarus")
    n_spans, n_pixels = spans.count("\n"), pixels.count("\n")
    bad = tmp_path / "bad.hex"
    lines = pixels.splitlines()
    lines[7] = ("0" if lines[7][0] != "0" else "1") + lines[7][1:]
    bad.write_text("\n".join(lines) + "\n")
    for expect, ok in ((core_run.VECTOR_SET / "pixels.hex", True), (bad, False)):
        ran = subprocess.run(
            [*command, f"+SPAN_FILE={core_run.VECTOR_SET / 'spans.hex'}", f"+EXPECT_FILE={expect}",
             f"+OUT_FILE={tmp_path / 'out.hex'}", f"+SPANS={n_spans}", f"+PIXELS={n_pixels}",
             "+STALL_PCT=25", "+IDLE_PCT=25"],
            capture_output=True, text=True, cwd=folder, timeout=600,
        )  # fmt: skip
        assert (ran.returncode == 0) == ok, ran.stdout + ran.stderr
        if not ok:
            assert "tb_shading_core: pixel 7: RTL" in ran.stdout


def _waves(text: str) -> dict[str, str]:
    """Each signal's wave of the WaveDrom diagram in ``text``, one character a cycle, '.'
    replaced by the value it repeats."""
    import json

    block = text.split("```wavedrom\n", 1)[1].split("```", 1)[0]
    out = {}
    for sig in json.loads(block)["signal"]:
        chars, last = [], "x"
        for ch in sig["wave"]:
            last = last if ch == "." else ch
            chars.append(last)
        out[sig["name"]] = "".join(chars)
    return out


def test_the_timing_diagram_is_the_core_s_timing():
    """docs/core.md's diagram: two span beats (two pixels, one pixel) taken in cycles 1 and 2,
    the pixel beats from cycle 1 + LATENCY, tlast on each span's last; and the stream bench
    measures the same clocks for the same beats."""
    from pathlib import Path

    w = _waves((Path(__file__).resolve().parents[1] / "docs" / "core.md").read_text())
    taken = [i for i, (v, r) in enumerate(zip(w["s_axis_tvalid"], w["s_axis_tready"],
                                               strict=True)) if v == r == "1"]  # fmt: skip
    out = [i for i, (v, r) in enumerate(zip(w["m_axis_tvalid"], w["m_axis_tready"],
                                             strict=True)) if v == r == "1"]  # fmt: skip
    assert taken == [1, 2] and out == [1 + core.LATENCY + k for k in range(3)]
    assert [i for i in out if w["m_axis_tlast"][i] == "1"] == [out[1], out[2]]
    fmt = core.SpanFormat(DEFAULT)
    words = random_words(fmt, 2, seed=4, lengths=[2, 1])
    r = core_run.run_words(words, fmt, core_run.parameters(DEFAULT), tag="core_wave")
    assert r.mismatches == [] and r.cycles == out[-1] - taken[0] + 1


def test_the_data_sheet_s_resources_are_the_synthesis_record():
    """docs/core.md's resource table is docs/synth.json's shading_core rows (make synth)."""
    import json
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    record = json.loads((root / "docs" / "synth.json").read_text())["results"]
    want = []
    for r in record:
        if r["unit"] == "shading_core":
            fmax = f"{r['fmax_mhz']:.1f}" if r["fmax_mhz"] else "-"
            want.append(f"| {r['config']} | {r['part']} | {r['lut']} | {r['ff']} | {r['bram']} | "
                        f"{r['dsp']} | {'yes' if r['fits'] else 'no'} | {fmax} |")  # fmt: skip
    text = (root / "docs" / "core.md").read_text()
    section = text.split("## Resources\n", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| ") and "---" not in line]
    assert rows[1:] == want
    # what the prose says of the BRDF highlights' cores on the ECP5-25F
    ecp5 = {r["config"]: r for r in record if r["unit"] == "shading_core" and r["part"] ==
            "ecp5-25f"}  # fmt: skip
    for name in ("brdf_cosine_quadratic", "brdf_log2"):
        r = ecp5[name]
        assert r["fits"] and r["fmax_mhz"] >= 100 and r["bram"] < ecp5["hybrid"]["bram"]
        assert r["dsp"] > ecp5["hybrid"]["dsp"], name
    assert ecp5["default"]["dsp"] == 18 and "18 DSP blocks on the ECP5-25F" in section


@pytest.mark.parametrize("name", sorted(core_run.shipped_configs()))
def test_the_configurations_users_ship_through_the_core(name):
    """Narrow widths (4-bit Gouraud levels and 4-bit highlights: the sum's width at its
    smallest), the kept range of n (N_FIRST > 1, as shading fit emits; no diffuse path), the
    UP5K tables and each BRDF form's highlight: random span beats (half of them lit), idles
    and stalls, every pixel compared."""
    cfg = core_run.shipped_configs()[name]
    fmt = core.SpanFormat(cfg)
    words = random_words(fmt, 120, seed=9, lit=0.5 if cfg.brdf is not None else 0.0)
    params = core_run.parameters(cfg, core_run.SIM_BUILD / f"core_{name}_roms")
    r = core_run.run_words(words, fmt, params, idle_pct=20, stall_pct=30, seed=5,
                           tag=f"core_{name}")  # fmt: skip
    assert r.mismatches == []
