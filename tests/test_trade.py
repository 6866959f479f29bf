# SPDX-License-Identifier: Apache-2.0
"""The trade study's machinery: keys, knob mapping, the Dask sweep with its cache, the fronts.

Size: about 530 lines, one file for the one package ``model.study.trade`` (points, sweep,
synthesised cost, analysis, outputs): its tests share the tiny sweeps and their fixtures.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json

import numpy as np
import pytest

from model.render import core, pipeline, scenefile
from model.study import trade
from model.study.trade import hardware, sweep
from model.units import brdf, divider, gouraud, specular

TINY = 32


def test_key_is_stable_and_canonical():
    p = trade.TradePoint(scene="sphere", size=32)
    # The canonical JSON hash: equal across processes and runs (the cache relies on it).
    assert p.key == trade.TradePoint(scene="sphere", size=np.int64(32)).key
    assert p.key == trade.TradePoint(scene="sphere", size=32, highlight_levels=0.5).key
    assert trade.TradePoint(highlight_levels=1).key == trade.TradePoint(highlight_levels=1.0).key
    assert len(p.key) == 16 and int(p.key, 16) >= 0
    canonical = (
        '{"alpha":"taylor","brdf":"none","diffuse_mode":"gouraud","highlight_levels":0.5,'
        '"k_set":"patent","p":8,"recip_bits":20,'
        '"rom_addr_bits":12,"rom_data_bits":16,"scene":"sphere","size":32,'
        f'"specular_mode":"unit","version":{trade.CACHE_VERSION},"z_frac_bits":26}}'
    )
    assert p.key == hashlib.sha256(canonical.encode()).hexdigest()[:16]
    # Every field is part of the key; the config key ignores the scene and the size.
    keys = {p.key}
    for f, v in [("scene", "quad"), ("size", 64), ("rom_addr_bits", 10), ("alpha", "inflection")]:
        q = dataclasses.replace(p, **{f: v})
        assert q.key not in keys
        keys.add(q.key)
    assert p.config_key == trade.TradePoint(scene="quad", size=64).config_key
    assert p.config_key != p.with_knobs(p=4).config_key


def test_bad_point_is_refused():
    with pytest.raises(ValueError, match="k_set"):
        trade.TradePoint(k_set="k3")
    with pytest.raises(ValueError, match="scene"):
        trade.TradePoint(scene="cube")


def test_default_point_is_the_default_pipeline():
    assert trade.DEFAULT_POINT.to_pipeline_config() == pipeline.METHODS["hybrid"]
    assert trade.DEFAULT_POINT.label == "default"


@pytest.mark.parametrize(
    "knob, value, field",
    [
        ("rom_addr_bits", 10, lambda c: c.specular.rom_addr_bits),
        ("rom_data_bits", 12, lambda c: c.specular.rom_data_bits),
        ("z_frac_bits", 18, lambda c: c.specular.z_frac_bits),
        ("k_set", "k1-2-16", lambda c: c.specular.k_ranges),
        ("alpha", "inflection", lambda c: c.specular.alpha),
        ("recip_bits", 14, lambda c: c.divider.recip_bits),
        ("p", 4, lambda c: c.gouraud.p),
        ("specular_mode", "adaptive", lambda c: c.specular_mode),
        ("highlight_levels", 2.0, lambda c: c.highlight_levels),
        ("diffuse_mode", "unit", lambda c: c.diffuse_mode),
        ("brdf", "quadratic", lambda c: c.brdf and c.brdf.form),
    ],
)
def test_each_knob_maps_to_its_config_field(knob, value, field):
    base = trade.DEFAULT_POINT.to_pipeline_config()
    cfg = trade.DEFAULT_POINT.with_knobs(**{knob: value}).to_pipeline_config()
    expect = trade.K_SETS[value] if knob == "k_set" else value
    assert field(cfg) == expect
    assert field(base) != expect
    # Nothing else moves (a_int_bits follows the k-set and alpha; the same 3 bits here).
    assert cfg == _set(base, field, cfg)


def _set(base: pipeline.PipelineConfig, field, cfg: pipeline.PipelineConfig):
    """base with only the units that ``field`` reads taken from cfg."""
    for unit in ("divider", "gouraud", "specular"):
        if getattr(cfg, unit) != getattr(base, unit):
            base = dataclasses.replace(base, **{unit: getattr(cfg, unit)})
    for top in ("specular_mode", "highlight_levels", "diffuse_mode", "brdf"):
        if getattr(cfg, top) != getattr(base, top):
            base = dataclasses.replace(base, **{top: getattr(cfg, top)})
    return base


def test_prototype_k_set_is_the_prototype_unit():
    cfg = trade.DEFAULT_POINT.with_knobs(k_set="cos2").to_pipeline_config()
    assert cfg.specular == specular.PROTOTYPE  # a_int_bits = 5 follows from a up to 22.4
    assert cfg.divider == divider.DEFAULT and cfg.gouraud == gouraud.DEFAULT


def test_small_grid_isolates_each_knob():
    configs = trade.grid_configs("small")
    points = [trade.DEFAULT_POINT.with_knobs(**c) for c in configs]
    assert len({p.config_key for p in points}) == len(points)
    for p in points:
        changed = p.changed_knobs()
        # one knob, the threshold with adaptive on, or a named combination
        assert (
            len(changed) <= 1
            or set(changed) == {"specular_mode", "highlight_levels"}
            or (changed in trade.NAMED.values())
        )
    assert {k for p in points for k in p.changed_knobs()} == set(trade.KNOBS)
    assert len(trade.grid_points("small", ["sphere", "quad"], 64)) == 2 * len(configs)


# ------------------------------------------------------------------------------ BRDF family
def test_brdf_knob_puts_each_form_in_the_highlight():
    """``brdf``: "none" (the patent's unit, the default) or each form with RTL, never a list of
    its own: the form's default unit with the point's specular configuration as its angle
    format (so the angle knobs reach it), synthesised as the BRDF unit instead of the specular
    unit, in the small grid at the default other knobs, and in every key."""
    assert ("none", *brdf.RTL_FORMS) == trade.BRDF_CHOICES
    assert trade.DEFAULT_POINT.brdf == "none"
    assert trade.DEFAULT_POINT.to_pipeline_config().brdf is None
    small = [trade.DEFAULT_POINT.with_knobs(**c) for c in trade.grid_configs("small")]
    assert {p.brdf for p in small if p.changed_knobs() == {"brdf": p.brdf}} == set(brdf.RTL_FORMS)
    keys = {trade.DEFAULT_POINT.key}
    for form in brdf.RTL_FORMS:
        p = trade.TradePoint(brdf=form)
        cfg = p.to_pipeline_config()
        assert cfg == pipeline.BRDF_METHODS[form]  # the demo's method of that form
        assert cfg.brdf == brdf.UNIT_CONFIGS[form] and cfg.brdf.angle == cfg.specular
        assert p.label == f"brdf={form}" and p.family == form
        assert hardware.unit_configs(cfg) == [
            ("divider_shift", cfg.divider),
            ("gouraud_segment", cfg.gouraud),
            ("brdf_unit", cfg.brdf),
        ]
        narrow = p.with_knobs(z_frac_bits=18, specular_mode="adaptive").to_pipeline_config()
        assert narrow.brdf.angle == narrow.specular and narrow.brdf.angle.z_frac_bits == 18
        keys |= {p.key, p.config_key}
    assert len(keys) == 1 + 2 * len(brdf.RTL_FORMS)  # another key per form, and per config
    full = [trade.DEFAULT_POINT.with_knobs(**c) for c in trade.grid_configs("full")]
    assert {p.brdf for p in full} == set(trade.BRDF_CHOICES)
    for p in full:  # what a BRDF point varies reaches its unit
        if p.brdf != "none":
            assert set(p.changed_knobs()) - {"brdf"} <= set(trade.BRDF_KNOBS)


def test_bad_brdf_knob_is_one_clear_message():
    """A bad value names the knob, the value and every legal value; a combination a BRDF unit
    refuses names the knobs (the grid never holds one: ``grid_points`` checks every point)."""
    legal = " | ".join(repr(v) for v in trade.BRDF_CHOICES)
    with pytest.raises(ValueError) as err:
        trade.TradePoint(brdf="phong")
    assert str(err.value) == f"brdf = 'phong' is not legal: legal values are {legal}"
    form = brdf.RTL_FORMS[0]
    for other in ({"specular_mode": "vertex"}, {"diffuse_mode": "unit"}):
        with pytest.raises(ValueError, match=rf"brdf = '{form}' is out of range with specular_mo"):
            trade.TradePoint(brdf=form, **other)
    with pytest.raises(ValueError, match=rf"brdf = '{form}' is out of range with z_frac_bits = 8"):
        trade.TradePoint(brdf=form, z_frac_bits=8).to_pipeline_config()


def test_brdf_config_file_keeps_its_unit():
    """A configuration file with a ``[brdf]`` table is a point of that family, run as written."""
    from model.render import configfile

    for form, cfg in pipeline.BRDF_METHODS.items():
        point = trade.ConfigPoint.from_config("config:b", cfg, "sphere", 16)
        assert point.brdf == form and point.to_pipeline_config() == cfg
        assert json.loads(point.config_json) == configfile.config_dict(cfg)


def test_brdf_points_figures_and_the_front_across_families(tmp_path):
    """A BRDF point's figures are its unit's: the table bits brdf.table_bits (not ROM 9 + ROM
    12), the epicentre error the unit's own (fixed_accuracy against cos^n, n = 2..1000), its
    highlight cycles its fill latency's, the shading core's clocks with that form's pipe (its
    latency, core.latency) and the hardware Mpx/s from them; the fronts are over every family
    and say which."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.text import Annotation

    forms = brdf.RTL_FORMS
    configs = [{}, {"specular_mode": "vertex"}, *({"brdf": f} for f in forms)]
    points = [trade.TradePoint(scene="sphere", size=TINY, **c) for c in configs]
    out = trade.run_sweep(points, tmp_path / "cache", workers=0, progress=False, repeats=1)
    assert out.failed == {}
    patent, _vertex, *forms_r = out.results
    for form, r in zip(forms, forms_r, strict=True):
        cfg = trade.TradePoint(brdf=form).to_pipeline_config()
        assert r["brdf"] == form and r["label"] == f"brdf={form}"
        assert r["table_bits"] == divider.DEFAULT.rom_bits + brdf.table_bits(cfg.brdf)["total"]
        assert r["table_bits"] != patent["table_bits"]
        worst, n, _ = brdf.fixed_accuracy(cfg.brdf).worst("rel_cos", 2)
        assert (r["epicentre_rel_error"], r["epicentre_worst_n"]) == (worst, n)
        assert np.isnan(r["unit_error_lsb"]) and np.isnan(r["epicentre_out_lsb"])
        # The same highlight jobs, each its unit's fill latency longer or shorter.
        assert r["specular_pixels"] == patent["specular_pixels"] > 0
        fill, fill_p = brdf.cycles(0, cfg.brdf), specular.cycles(0)
        jobs = (patent["specular_cycles"] - patent["specular_pixels"]) // fill_p
        assert r["specular_cycles"] - r["specular_pixels"] == jobs * fill
        # The shading core with the form's highlight pipe: its latency + pixels
        pixels = r["pixels_shaded"]
        assert r["core_clocks"] == core.core_cycles(pixels, cfg) == core.latency(cfg) + pixels
        assert r["core_clocks"] > patent["core_clocks"]
        assert r["px_per_clock_core"] == pytest.approx(pixels / r["core_clocks"])
        assert r["frame_clocks"] == trade.frame_clocks(r)
        # Its arithmetic where its RTL is counted (the accumulator's adder is the patent's too),
        # else NaN: a form given RTL joins the sweep before anyone counts its adders.
        if form in sweep.BRDF_ADDERS:
            assert r["adders"] == patent["adders"] - 1 + sweep.BRDF_ADDERS[form]
        else:
            assert np.isnan(r["adders"])
        try:
            mults = brdf.multipliers(cfg.brdf)
        except KeyError:
            assert np.isnan(r["multipliers"]) and np.isnan(r["mult_bits"])
        else:
            assert r["multipliers"] == len(mults) >= 2  # the log2: 2, the cubic: 5
            assert r["mult_bits"] == sum(a * b for _, a, b in mults)
        assert trade.check_result(trade.TradePoint(scene="sphere", size=TINY, brdf=form), r) is None
    # hw Mpx/s: the core's px/clk x Fmax, for every family
    figures = {r["config_key"]: {k: 1 for k in trade.HW_FIELDS[:-1]} for r in out.results}
    for r in trade.attach(out.results, figures, "ecp5-25f"):
        assert r["hw_mpx_per_s"] == pytest.approx(r["px_per_clock_core"])
    rows, _ = trade.write_outputs(out.results, tmp_path / "trade")
    by = {r["label"]: r for r in rows}
    assert [by[f"brdf={f}"]["family"] for f in forms] == list(forms)
    assert by["default"]["family"] == "cos^k"
    fronts = trade.front_families(rows)
    assert {fam for fam in ("cos^k", *forms)} >= {f for m in fronts.values() for _, f in m}
    bits = fronts["NMSE vs table bits"]
    assert len({f for _, f in bits}) >= 2, bits  # the table-bits front spans the families
    # a BRDF point is less accurate here and its core's latency longer: dominated on throughput
    assert all(f == "cos^k" for _, f in fronts["NMSE vs throughput"])
    md = (tmp_path / "trade" / "results.md").read_text()
    assert "## The fronts across families" in md and "| config | family |" in md
    line = next(x for x in md.splitlines() if x.startswith("* NMSE vs table bits: "))
    assert all(f"{label} ({fam})" in line for label, fam in bits)
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    trade.plot_pareto(rows, "table_bits", ax=ax)
    labels = {t.get_text() for t in ax.texts if isinstance(t, Annotation)}
    on = {r["brdf"] for r in rows if r["pareto_bits"] and r["brdf"] != "none"}
    assert on and on <= labels  # a BRDF point's label is its form
    legend = {h.get_label() for h in ax.collections}
    assert {f"family {f}" for f in ("cos^k", *forms)} <= legend
    plt.close(fig)


def test_a_configuration_the_core_cannot_build_has_no_core_clocks(monkeypatch):
    """A BRDF form with RTL but no pipe in the shading core (here the cubic, taken out of
    core.CORE_FORMS as a new form would be) has NaN core clocks, so no px/clk core, no hw
    Mpx/s and no place on a throughput front; a form with a pipe has its latency's."""
    cfg = trade.TradePoint(brdf="cubic").to_pipeline_config()
    assert sweep.core_clocks(100, cfg) == core.latency(cfg) + 100
    assert sweep.core_clocks(0, cfg) == 0
    monkeypatch.setattr(core, "CORE_FORMS", ("cosine_quadratic", "quadratic", "log2"))
    assert np.isnan(sweep.core_clocks(100, cfg))


def test_old_or_other_family_cache_entries_are_not_read(tmp_path):
    """The knob is in every key and the figures' definitions changed with it (CACHE_VERSION): an
    entry of the patent's point, or one written before the knob, is never read as a BRDF one."""
    p = trade.TradePoint(scene="sphere", size=TINY)
    q = p.with_knobs(brdf=brdf.RTL_FORMS[0])
    assert p.key != q.key and trade.cache_path(tmp_path, p) != trade.cache_path(tmp_path, q)
    result = {
        **dataclasses.asdict(q),
        "key": q.key,
        "config_key": q.config_key,
        "label": q.label,
        **{f: 1 if kind == "int" else 1.0 for f, (kind, *_) in trade.RESULT_RANGES.items()},
    }
    trade.store(tmp_path, q, result)
    assert trade.load_cached(tmp_path, q) == result
    path = trade.cache_path(tmp_path, q)
    old = json.loads(path.read_text())
    old["version"] = trade.CACHE_VERSION - 1
    path.write_text(json.dumps(old))
    assert trade.read_cached(tmp_path, q) == (
        None,
        f"version = {trade.CACHE_VERSION - 1}, expected {trade.CACHE_VERSION}",
    )
    trade.store(tmp_path, p, {**result, **dataclasses.asdict(p), "key": p.key})
    path.write_text(trade.cache_path(tmp_path, p).read_text())  # p's entry under q's name
    assert trade.read_cached(tmp_path, q) == (None, "holds the result of another point")


# ------------------------------------------------------------------------------ the engine
CALLS: list[str] = []


def counting_evaluate(point, repeats):
    """trade.evaluate, counted (module level: an in-process Dask worker calls this very one)."""
    CALLS.append(point.key)
    return trade.evaluate(point, repeats)


def _mtimes(cache_dir):
    return {p.name: p.stat().st_mtime_ns for p in cache_dir.glob("*.json")}


def test_sweep_on_dask_caches_and_resumes(tmp_path):
    from dask.distributed import Client

    cache = tmp_path / "cache"
    points = [
        trade.TradePoint(scene="sphere", size=TINY),
        trade.TradePoint(scene="sphere", size=TINY, recip_bits=14),
    ]
    # The real engine: a LocalCluster of worker processes made by run_sweep itself.
    first = trade.run_sweep(points, cache, workers=2, progress=False)
    assert (first.cached, first.evaluated, first.failed) == (0, 2, {})
    assert sorted(_mtimes(cache)) == sorted(f"{p.key}.json" for p in points)
    assert [r["key"] for r in first.results] == [p.key for p in points]
    r0, r1 = first.results
    assert r0["label"] == "default" and r1["label"] == "recip_bits=14"
    assert 0 < r0["nmse"] < 0.01 and r0["cycles"] == (
        r0["divider_cycles"] + r0["gouraud_cycles"] + r0["specular_cycles"]
    )
    assert r1["divider_cycles"] <= r0["divider_cycles"]
    assert r1["line_drift_levels"] > 10 * r0["line_drift_levels"]
    rom_bits = divider.DEFAULT.rom_bits + specular.DEFAULT.rom_bits  # one copy of every ROM
    assert r0["table_bits"] == rom_bits and r0["epicentre_worst_n"] == 3
    # The throughput is the shading core's: its model's clocks (LATENCY + pixels), whatever
    # the knobs; the parallel-units estimate stays a column.
    for r in (r0, r1):
        pixels = r["pixels_shaded"]
        assert r["core_clocks"] == core.core_cycles(pixels) == core.LATENCY + pixels
        assert r["px_per_clock_core"] == pytest.approx(r["pixels_shaded"] / r["core_clocks"])
        assert r["frame_clocks"] == trade.frame_clocks(r)

    # Resumed: everything from the cache, nothing evaluated or rewritten.
    before = _mtimes(cache)
    calls = CALLS
    calls.clear()
    again = trade.run_sweep(points, cache, workers=2, progress=False, evaluate_fn=counting_evaluate)
    assert (again.cached, again.evaluated, calls) == (2, 0, [])
    assert again.results == first.results
    assert _mtimes(cache) == before

    # Partly cached: only the missing point goes to the (in-process) Dask cluster.
    extra = trade.TradePoint(scene="sphere", size=TINY, p=4)
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as c:
        part = trade.run_sweep(
            [*points, extra], cache, client=c, progress=False, evaluate_fn=counting_evaluate
        )
    assert (part.cached, part.evaluated, calls) == (2, 1, [extra.key])
    assert _mtimes(cache).items() >= before.items()
    assert part.results[:2] == first.results and part.results[2]["p"] == 4


def test_cache_ignores_other_or_broken_files(tmp_path):
    p = trade.TradePoint(scene="sphere", size=TINY)
    q = p.with_knobs(p=4)
    result = {
        **dataclasses.asdict(p),
        "key": p.key,
        "config_key": p.config_key,
        "label": p.label,
        **{f: 1 if kind == "int" else 1.0 for f, (kind, *_) in trade.RESULT_RANGES.items()},
    }
    trade.store(tmp_path, p, result)
    assert trade.load_cached(tmp_path, p) == result
    trade.store(tmp_path, p, {"x": 1})  # not a result (tests/test_bad_input.py: every case)
    assert trade.read_cached(tmp_path, p) == (None, "field 'scene' is missing")
    trade.store(tmp_path, p, result)
    assert not list(tmp_path.glob("*.tmp"))
    # a file under q's name holding p's result (a collision) or half written: not used
    trade.cache_path(tmp_path, p).rename(trade.cache_path(tmp_path, q))
    assert trade.load_cached(tmp_path, q) is None
    trade.cache_path(tmp_path, p).write_text('{"version": ')
    assert trade.load_cached(tmp_path, p) is None
    # An entry written before the core's figures existed is not mixed in: named, evaluated again.
    old = {k: v for k, v in result.items() if k not in ("core_clocks", "px_per_clock_core")}
    trade.store(tmp_path, p, old)
    assert trade.read_cached(tmp_path, p) == (None, "field 'core_clocks' is missing")
    calls = CALLS
    calls.clear()
    swept = trade.run_sweep([p], tmp_path, workers=0, progress=False, evaluate_fn=counting_evaluate)
    assert (swept.cached, swept.evaluated, calls) == (0, 1, [p.key])
    assert swept.recomputed == {p.key: "field 'core_clocks' is missing"}
    assert trade.load_cached(tmp_path, p)["core_clocks"] > core.LATENCY


# ------------------------------------------------------------------------------ analysis
def test_pareto_mask_on_known_points():
    pts = np.array([[1, 9], [2, 5], [3, 5], [4, 1], [5, 5], [2, 5], [6, 0.5]])
    assert trade.pareto_mask(pts).tolist() == [True, True, False, True, False, True, True]
    assert trade.pareto_mask(np.array([[1.0, 1.0]])).tolist() == [True]


def test_eps_dominance_defines_near():
    d = [1.0, 100.0]
    assert trade.eps_dominates([1.04, 50.0], d)  # as accurate within 5 %, half the cost
    assert not trade.eps_dominates([1.2, 50.0], d)  # cheaper but 20 % worse: a trade
    assert not trade.eps_dominates([0.97, 98.0], d)  # better by less than 5 %: near
    objs = np.array([d, [1.2, 50.0], [0.97, 98.0], [0.5, 200.0]])
    assert trade.near_front(objs, 0) == []
    assert trade.near_front(np.vstack([objs, [0.9, 90.0]]), 0) == [4]


def test_default_is_on_the_all_figures_front_but_for_the_free_changes(tmp_path):
    """What docs/trade.md states: over every figure at once (accuracy, exhaustive worst cases and
    costs), the default is eps-dominated only by changes that cost nothing (inflection a,
    adaptive skipping, a smaller P on small scenes) and by 12-bit ROM-12 words (within 5 % on
    every figure, the unit's own error included); its address and angle widths, N and k-set are
    on the front.  On NMSE against cycles alone, smaller N dominates it (the scenes' short spans
    cannot show the drift)."""
    configs = [
        {},
        {"recip_bits": 14},
        {"rom_addr_bits": 10},
        {"rom_data_bits": 12},
        {"z_frac_bits": 10},
        {"k_set": "k1-2-16"},
        {"alpha": "inflection"},
        {"specular_mode": "adaptive"},
        {"specular_mode": "vertex"},
    ]
    points = [trade.TradePoint(scene="sphere", size=48, **c) for c in configs]
    out = trade.run_sweep(points, tmp_path, workers=0, progress=False, repeats=1)
    rows, written = trade.write_outputs(out.results, tmp_path / "trade")
    assert [p.name for p in written] == [
        "results.csv",
        "results.md",
        "pareto_cycles.png",
        "pareto_bits.png",
        "pareto_throughput.png",
    ]
    pos = trade.default_position(rows)
    free = {"alpha", "specular_mode", "highlight_levels", "p", "rom_data_bits"}
    by_label = {r["label"]: r for r in rows}
    for label in pos["all figures"]:
        assert (
            set(trade.DEFAULT_POINT.with_knobs(**trade.row_knobs(by_label[label])).changed_knobs())
            <= free
        )
    assert "alpha=inflection" in pos["all figures"]
    assert "rom_data_bits=12" in pos["all figures"]
    assert by_label["recip_bits=14"]["cycles"] <= by_label["default"]["cycles"]
    vertex = by_label["specular_mode=vertex"]
    assert vertex["pareto_cycles"] and vertex["pareto_bits"]  # the cheapest: on both fronts
    assert vertex["nmse"] > 5 * by_label["default"]["nmse"]

    # The plots: the thesis's threshold is a labelled line; the front and the default labelled,
    # no two labels overlapping.
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.text import Annotation

    for x in ("cycles", "table_bits"):
        fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
        trade.plot_pareto(rows, x, ax=ax, legend=False)
        texts = [t.get_text() for t in ax.texts if not isinstance(t, Annotation)]
        assert texts == ["visually identical: NMSE ≤ 0.00025 (thesis)"]
        labels = [t for t in ax.texts if isinstance(t, Annotation)]
        front = {r["label"] for r in rows if r["pareto_cycles" if x == "cycles" else "pareto_bits"]}
        assert {t.get_text() for t in labels} == front | {"default"}
        _assert_apart(fig, labels)
        plt.close(fig)


def _assert_apart(fig, texts) -> None:
    """No two of the texts overlap and each lies inside its axes (the text itself: an
    annotation's extent would include its leader line)."""
    from matplotlib.text import Text

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = [Text.get_window_extent(t, renderer) for t in texts]
    for i, a in enumerate(boxes):
        frame = texts[i].axes.get_window_extent(renderer)
        assert frame.x0 <= a.x0 and a.x1 <= frame.x1 and frame.y0 <= a.y0 and a.y1 <= frame.y1
        for b in boxes[i + 1 :]:
            assert not a.overlaps(b), (texts[i].get_text(), a, b)


def test_labels_of_crowded_points_do_not_collide():
    """place_labels on a tight cluster (the fronts crowd near their knee): every label finds a
    free spot, inside the axes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(5)
    xy = np.c_[3000 + 60 * rng.random(10), 5e-5 * (1 + 0.3 * rng.random(10))]
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    ax.scatter(xy[:, 0], xy[:, 1])
    ax.set_yscale("log")
    ax.set_xlim(2000, 6000)
    ax.set_ylim(1e-5, 1e-3)
    labels = trade.place_labels(ax, xy, [f"knob_{i}={2**i}" for i in range(10)])
    assert len(labels) == 10
    _assert_apart(fig, labels)
    plt.close(fig)


# ------------------------------------------------------------------------------ meshes
def _write_mesh(path, subdivisions: int = 1, radius: float = 1.0):
    import trimesh

    trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius).export(path)
    return path


def mesh_key(path, up: str = "auto") -> str:
    return scenefile.SceneSource("mesh", str(path), up).key()


def test_mesh_scene_key_follows_the_content(tmp_path):
    mesh = _write_mesh(tmp_path / "ico.obj")
    key = mesh_key(mesh)
    digest = hashlib.sha1(mesh.read_bytes() + b"up=auto").hexdigest()[:12]
    assert key == f"mesh:ico.obj@{digest}"
    assert mesh_key(mesh, "y") != key  # the up axis turns the scene: another key
    p = trade.TradePoint(scene=key, size=16)  # a legal scene, in the key like any other field
    assert p.key != trade.TradePoint(scene="sphere", size=16).key
    other = tmp_path / "other"
    other.mkdir()
    assert mesh_key(_write_mesh(other / "ico.obj")) == key  # same name and content
    assert mesh_key(_write_mesh(other / "ico.obj", radius=2.0)) != key
    sc = trade.point_scene(p, {key: scenefile.SceneSource("mesh", str(mesh))})
    assert (sc.camera.width, sc.camera.height, sc.n_triangles) == (16, 16, 80)
    with pytest.raises(ValueError, match=r"is now 'mesh:ico.obj@.*it changed"):
        trade.point_scene(p, {key: scenefile.SceneSource("mesh", str(other / "ico.obj"))})
    with pytest.raises(ValueError, match="no file was given"):
        trade.point_scene(p)
    with pytest.raises(ValueError, match=r"scene = 'mesh:ico.obj' is not legal.*file key"):
        trade.TradePoint(scene="mesh:ico.obj")


def _one_config(grid, scenes, size):
    """grid_points of the default configuration only (a sweep of one config per scene)."""
    return [trade.TradePoint(scene=s, size=size) for s in scenes]


def test_trade_sweeps_a_mesh_like_a_builtin_scene(tmp_path, monkeypatch, capsys):
    import csv

    mesh = _write_mesh(tmp_path / "ico.obj", subdivisions=2)
    key = mesh_key(mesh)
    monkeypatch.setattr(trade, "grid_points", _one_config)
    out = tmp_path / "out"
    run = {"size": 16, "out_dir": out, "workers": 0, "repeats": 1, "part": "none"}
    assert trade.main(["sphere"], meshes=[mesh], **run) == 0
    assert f"1 configurations x 2 scenes (sphere, {key})" in capsys.readouterr().out
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["scene"] for r in rows] == ["sphere", key]
    result = trade.load_cached(out / "cache", trade.TradePoint(scene=key, size=16))
    assert result is not None and 0 <= result["nmse"] < 0.01 and result["pixels_shaded"] > 50
    # The cache follows the content: a rerun evaluates nothing, an edited mesh is a new scene.
    assert trade.main(["sphere"], meshes=[mesh], **run) == 0
    assert "0 evaluated, 2 from the cache" in capsys.readouterr().out
    _write_mesh(mesh, subdivisions=2, radius=1.5)
    assert trade.main(["sphere"], meshes=[mesh], **run) == 0
    assert "1 evaluated, 1 from the cache" in capsys.readouterr().out


def test_unreadable_mesh_is_refused_before_any_work(tmp_path, monkeypatch):
    def started(*args, **kwargs):
        raise AssertionError("the work started")

    monkeypatch.setattr(trade, "run_sweep", started)
    garbage = tmp_path / "garbage.obj"
    garbage.write_text("this is not a mesh\n")
    folder = tmp_path / "folder.obj"
    folder.mkdir()
    cases = [tmp_path / "missing.obj", garbage, folder, tmp_path / "m.xyz"]
    for bad in cases:
        with pytest.raises(trade.SetupError) as err:
            trade.main(["sphere"], size=16, out_dir=tmp_path / "out", meshes=[bad])
        message = str(err.value)
        assert message.startswith("argument --mesh: ") and str(bad) in message, message
        assert "\n" not in message and err.value.status == 2
    assert not (tmp_path / "out").exists()  # refused before the output folder was made


# ================================================================ synthesised cost, --config
def _vertex_only(grid, scenes, size):
    """One cheap configuration (no specular unit: a divider and a Gouraud unit to synthesise)."""
    return [
        trade.TradePoint(scene=s, size=size, specular_mode="vertex", recip_bits=10, p=2)
        for s in scenes
    ]


def _csv_rows(path):
    import csv

    with open(path) as f:
        return list(csv.DictReader(f))


def test_synthesised_cost_columns(tmp_path, monkeypatch, capsys):
    """--part: every unit the configuration uses synthesised once per part (real runs on the
    iCE40 HX8K and UP5K, a few seconds each); LUT, FF, BRAM, DSP the units' sums, Fmax the
    slowest unit's, Mpx/s = the shading core's px/clk x Fmax; the first part's outputs in --out,
    the second's in --out/<part>/ with its own fronts; --part none synthesises nothing."""
    from model.hw import synthesise
    from model.study.trade import hardware

    monkeypatch.setenv("SYNTH_CACHE", str(tmp_path / "synth"))
    monkeypatch.setattr(trade, "grid_points", _vertex_only)
    run = {"size": 16, "workers": 0, "repeats": 1}
    parts = ["hx8k", "up5k"]
    assert trade.main(["sphere", "quad"], out_dir=tmp_path / "hw", part=parts, **run) == 0
    out = capsys.readouterr().out
    assert out.count("2 unit configurations synthesised") == 2
    assert f"The fronts across families on up5k ({tmp_path / 'hw' / 'up5k' / 'results.md'})" in out
    (second,) = {r["part"] for r in _csv_rows(tmp_path / "hw" / "up5k" / "results.csv")}
    assert second == "up5k"
    up5k_md = (tmp_path / "hw" / "up5k" / "results.md").read_text()
    assert "on up5k" in up5k_md and "## The fronts across families" in up5k_md
    assert (tmp_path / "hw" / "up5k" / "pareto_lut.png").is_file()
    cfg = _vertex_only("small", ["sphere"], 16)[0].to_pipeline_config()
    units = [synthesise(u, c, "hx8k") for u, c in trade.unit_configs(cfg)]  # cache hits now
    assert [r.unit for r in units] == ["divider_shift", "gouraud_segment"]
    rows = _csv_rows(tmp_path / "hw" / "results.csv")
    assert [r["scene"] for r in rows] == ["sphere", "quad"]
    for r in rows:  # per configuration: the same on every scene
        assert r["part"] == "hx8k"
        for k in ("lut", "ff", "bram", "dsp"):
            assert int(r[k]) == sum(getattr(u, k) for u in units)
        assert int(r["lut"]) > 0 and int(r["ff"]) > 0
        assert float(r["fmax_mhz"]) == pytest.approx(min(u.fmax_mhz for u in units))
        assert int(r["core_clocks"]) == core.core_cycles(int(r["pixels_shaded"]))
        expect = float(r["px_per_clock_core"]) * float(r["fmax_mhz"])
        assert float(r["hw_mpx_per_s"]) == pytest.approx(expect)
    md = (tmp_path / "hw" / "results.md").read_text()
    assert "| LUT | FF | BRAM | DSP | Fmax MHz | hw Mpx/s |" in md and "on hx8k" in md
    assert (tmp_path / "hw" / "pareto_lut.png").is_file()
    assert (tmp_path / "hw" / "pareto_throughput.png").is_file()

    def no_synthesis(*args, **kwargs):
        raise AssertionError("synthesised with --part none")

    monkeypatch.setattr(hardware, "synthesise", no_synthesis)
    assert trade.main(["sphere"], out_dir=tmp_path / "sw", part="none", **run) == 0
    (r,) = _csv_rows(tmp_path / "sw" / "results.csv")
    assert r["part"] == "none" and r["lut"] == "nan" and r["hw_mpx_per_s"] == "nan"
    assert not (tmp_path / "sw" / "pareto_lut.png").exists()
    assert (tmp_path / "sw" / "pareto_throughput.png").is_file()  # against the core's px/clk


def _fitted_config(tmp_path):
    """A "fitted" configuration: a smaller unit that keeps only the sphere's n (60)."""
    from model.render import configfile

    base = trade.TradePoint(rom_addr_bits=8, z_frac_bits=16).to_pipeline_config()
    cfg = dataclasses.replace(
        base, specular=dataclasses.replace(base.specular, n_first=60, n_last=60)
    )
    path = tmp_path / "fit" / "sphere" / "config.toml"
    path.parent.mkdir(parents=True)
    return configfile.write_config(cfg, path), cfg


def test_config_file_is_a_point_marked_on_every_plot(teapot_file, tmp_path, monkeypatch, capsys):
    """--config FILE: the file's configuration over the scenes, labelled fit:<folder>, keyed by
    its content; a scene it refuses is reported, not a failure; every plot marks it and the
    default."""
    path, cfg = _fitted_config(tmp_path)
    monkeypatch.setattr(trade, "grid_points", _one_config)
    out = tmp_path / "out"
    run = {"size": 16, "workers": 0, "repeats": 1, "part": "none", "out_dir": out}
    assert trade.main(["sphere", "teapot"], configs=[path], **run) == 0
    text = capsys.readouterr().out
    assert "1 refused by their configuration file" in text
    assert "REFUSED fit:sphere on teapot: ValueError('material n = " in text
    rows = _csv_rows(out / "results.csv")
    assert [(r["label"], r["scene"]) for r in rows] == [
        ("default", "sphere"),
        ("default", "teapot"),
        ("fit:sphere", "sphere"),
    ]
    point = trade.ConfigPoint.from_config("fit:sphere", cfg, "sphere", 16)
    assert point.to_pipeline_config() == cfg
    assert rows[2]["key"] == point.key and rows[2]["config_key"] != rows[0]["config_key"]
    assert trade.load_cached(out / "cache", point) is not None
    md = (out / "results.md").read_text()
    assert "## configuration files (`--config`)" in md and "* refused: fit:sphere on teapot" in md
    # Another content, another key: the cache follows the file.
    other = dataclasses.replace(cfg, gouraud=dataclasses.replace(cfg.gouraud, p=4))
    assert trade.ConfigPoint.from_config("fit:sphere", other, "sphere", 16).key != point.key

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.text import Annotation

    swept = trade.run_sweep(
        [*_one_config("small", ["sphere"], 16), point], out / "cache", workers=0, progress=False
    )
    agg = trade.aggregate(swept.results)
    assert trade.analysis.throughput_axis(agg) == "px_per_clock_core"  # no synthesis
    for x in ("cycles", "table_bits", "px_per_clock_core"):
        fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
        trade.plot_pareto(
            [{**r, **dict.fromkeys(trade.HW_FIELDS[1:], np.nan), "part": "none"} for r in agg],
            x,
            ax=ax,
        )
        legend = {c.get_label(): c for c in ax.collections}
        assert legend["default"].get_paths() and legend["fitted (--config)"].get_paths()
        fitted_xy = legend["fitted (--config)"].get_offsets()
        assert len(fitted_xy) == 1
        labels = {t.get_text() for t in ax.texts if isinstance(t, Annotation)}
        assert {"default", "fit:sphere"} <= labels
        plt.close(fig)


def test_bad_config_or_part_is_one_line_before_any_work(tmp_path, monkeypatch, capsys):
    from model import cli

    def started(*args, **kwargs):
        raise AssertionError("the work started")

    monkeypatch.setattr(trade, "run_sweep", started)
    bad = tmp_path / "bad.toml"
    bad.write_text("[divider]\nrecip_bits = 'many'\n")
    cases = [
        (["--config", str(bad)], f"argument --config: {bad}: divider.recip_bits = 'many'"),
        (["--config", str(tmp_path / "missing.toml")], "argument --config: path = "),
        (["--part", "ecp9"], "argument --part: part = 'ecp9' is not a part: legal values"),
        (["--part", "up5k", "ecp9"], "argument --part: part = 'ecp9' is not a part: legal"),
        (["--part", "none", "up5k"], "argument --part: none up5k is not allowed: none skips"),
    ]
    for argv, why in cases:
        status = cli.main(["trade", "--scenes", "sphere", "--out", str(tmp_path / "o"), *argv])
        captured = capsys.readouterr()
        lines = captured.err.strip().splitlines()
        assert status == 2 and captured.out == "" and len(lines) == 1, captured
        assert lines[0].startswith(f"shading trade: error: {why}"), lines[0]
    assert not (tmp_path / "o").exists()


def test_the_throughput_front_says_why_a_family_has_no_point():
    """A family with no throughput on the part is named with its reason: no core clocks (no
    shading core built with it) or core clocks but no Fmax (its units not placed on the part,
    as the cubic and the piecewise form on the UP5K, which they do not fit)."""
    nan = float("nan")

    def row(label, family, core, mpx, on):
        return {
            "label": label, "family": family, "nmse": 1e-4, "px_per_clock_core": core,
            "hw_mpx_per_s": mpx, "pareto_cycles": False, "pareto_bits": False,
            "pareto_lut": False, "pareto_throughput": on,
        }  # fmt: skip

    rows = [
        row("default", "cos^k", 0.99, 99.0, True),
        row("brdf=log2", "log2", 0.99, 98.0, False),
        row("brdf=cubic", "cubic", 0.99, nan, False),
        row("brdf=x", "x", nan, nan, False),
    ]
    (line,) = [x for x in trade.front_lines(rows) if x.startswith("* NMSE vs throughput: ")]
    assert line == (
        "* NMSE vs throughput: default (cos^k); no point of cubic, log2, x (x: no shading core "
        "built with it; cubic: no Fmax, its units not placed on the part: no throughput)"
    )
