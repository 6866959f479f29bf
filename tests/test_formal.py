# SPDX-License-Identifier: Apache-2.0
"""The formal proofs' quick subset (docs/formal.md), in make test.

The quick jobs of ``model.hw.formal`` at the divider's article configuration: every protocol
property proven by k-induction (div_zero among them), every cover reached, and the div_zero
property failing on the saved mutant ``div_zero_leak`` (the defect the released divider
shipped).  The full set (default configuration,
RESET_ALL 0 and 1, the quotient, every mutant, the netlist equivalence) is ``make formal``.
The segment Gouraud unit's quick jobs (``model.hw.formal_gouraud``) at its small configuration:
the protocol properties proven by k-induction, every cover reached, the valid_exact property
failing on its mutant.  The specular unit's (``model.hw.formal_specular``, default
configuration): its protocol properties proven by k-induction, every cover reached, the
n_err_of_the_line property failing on its mutant; and at its small configuration every
intensity proven equal to the reference formula (formal/specular_unit_datapath.v).  The BRDF
unit's (``model.hw.formal_brdf``, the cosine-quadratic form at its default widths): its
protocol properties proven by k-induction, every cover reached, the n_err_of_the_line property
failing on its mutant.
Also: the property files, the mutants and docs/formal.md agree, and bad input to the Python calls
and the command line is refused with a message naming it.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from model.hw import formal, formal_brdf, formal_core, formal_gouraud, formal_specular

ROOT = Path(__file__).resolve().parent.parent
PROPS = ROOT / "formal" / "divider_shift_props.v"
GOURAUD_PROPS = ROOT / "formal" / "gouraud_segment_props.v"
SPECULAR_PROPS = ROOT / "formal" / "specular_unit_props.v"
BRDF_PROPS = ROOT / "formal" / "brdf_unit_props.v"
CORE_PROPS = ROOT / "formal" / "shading_core_props.v"
AXIS_PROPS = ROOT / "formal" / "axis_props.v"
DOC = ROOT / "docs" / "formal.md"


@pytest.fixture(scope="module")
def quick(tmp_path_factory) -> dict[str, formal.FormalResult]:
    try:
        formal.tool_env()
    except formal.FormalError as exc:
        pytest.fail(str(exc))
    # Under the checkout: the WebAssembly Yosys cannot open the host's /tmp.
    out = ROOT / "out" / "formal" / "pytest" / os.environ.get("PYTEST_XDIST_WORKER", "main")
    results = {}
    for job in formal.jobs("divider_shift", quick=True):
        results[job.name] = formal.run_job(job, out)
    for job in formal.jobs("gouraud_segment", quick=True):
        results[job.name] = formal.run_job(job, out)
    for job in formal.jobs("specular_unit", quick=True):
        results[job.name] = formal.run_job(job, out)
    for job in formal.jobs("brdf_unit", quick=True):
        results[job.name] = formal.run_job(job, out)
    for job in formal.jobs("shading_core", quick=True):
        results[job.name] = formal.run_job(job, out)
    return results


def test_quick_protocol_properties_are_proven_by_induction(quick) -> None:
    r = quick["divider_shift_prove_article"]
    assert r.ok and r.status == "proven", r.detail
    assert "div_zero_of_the_job" in r.job.properties
    assert dict(r.rows)["div_zero_of_the_job"] == "proven"


def test_quick_every_cover_is_reached(quick) -> None:
    r = quick["divider_shift_cover_article"]
    assert r.ok, r.detail
    assert {p for p, _ in r.rows} == set(formal.DIVIDER_COVERS)
    assert all(s.startswith("reached in step") for _, s in r.rows), r.rows


def test_quick_div_zero_property_fails_on_the_leak(quick) -> None:
    r = quick["divider_shift_mutant_div_zero_leak"]
    assert r.ok and r.status == "failed", r.detail
    assert r.detail.startswith("div_zero_of_the_job fails at step"), r.detail


def check_unit_quick(quick, unit: str, config: str, module, properties, mutant: str, fails: str):
    """The quick subset's jobs of one unit: the protocol proven (every property of
    ``properties``), every cover reached, the mutant failing ``fails``."""
    r = quick[f"{unit}_prove_{config}"]
    assert r.ok and r.status == "proven", r.detail
    assert set(r.job.properties) == set(properties)
    r = quick[f"{unit}_cover_{config}"]
    assert r.ok, r.detail
    assert {p for p, _ in r.rows} == set(module.COVERS)
    assert all(s.startswith("reached in step") for _, s in r.rows), r.rows
    r = quick[f"{unit}_mutant_{mutant}"]
    assert r.ok and r.status == "failed", r.detail
    assert r.detail.startswith(f"{fails} fails at step"), r.detail


def test_quick_gouraud_protocol_covers_and_mutant(quick) -> None:
    check_unit_quick(quick, "gouraud_segment", "small", formal_gouraud, formal_gouraud.PROTOCOL,
                     "valid_held", "valid_exact")  # fmt: skip


def test_quick_specular_protocol_covers_and_mutant(quick) -> None:
    check_unit_quick(quick, "specular_unit", "default", formal_specular,
                     formal_specular.PROTOCOL, "n_err_leak", "n_err_of_the_line")  # fmt: skip


def test_quick_brdf_protocol_covers_and_mutant(quick) -> None:
    check_unit_quick(quick, "brdf_unit", "cosine_quadratic", formal_brdf, formal_brdf.PROTOCOL,
                     "n_err_leak", "n_err_of_the_line")  # fmt: skip


def test_brdf_property_file_mutants_and_doc_agree() -> None:
    """The BRDF unit's property file, mutants, helper wires and docs/formal.md agree; make
    formal proves both forms, each with RESET_ALL 0 and 1, and runs every mutant."""
    m = formal_brdf
    full = check_property_file(BRDF_PROPS, m, "brdf_unit", [*m.PROPERTIES, *m.COVERS])
    assert {j.kind for j in full} == {"prove", "cover", "mutant"}
    proofs = {(j.config, j.reset_all) for j in full if j.kind == "prove"}
    assert proofs == {(form, r) for form in m.CONFIGS for r in (0, 1)}
    assert {j.mutant for j in full if j.kind == "mutant"} == set(m.MUTANTS)
    # the fill latency the property file counts is the model's
    from model.units import brdf

    text = BRDF_PROPS.read_text()
    for form, cfg in m.CONFIGS.items():
        if form == "piecewise":  # its latency follows OUT_BITS: the file's rule, evaluated
            rule = "FILL_PIECEWISE = 7 + ((OUT_BITS + 8 > 14) ? OUT_BITS + 8 : 14);"
            assert rule in text and 7 + max(cfg.out_bits + 8, 14) == brdf.fill_latency(cfg)
            continue
        assert re.search(rf"\bFILL_{form.upper()} = {brdf.fill_latency(cfg)};", text), form
    assert re.search(r"\bLAST_STAGE = FILL - 1;", text)


def test_quick_specular_intensities_are_proven_at_small(quick) -> None:
    r = quick["specular_unit_prove_small"]
    assert r.ok and r.status == "proven", r.detail
    assert {"intensity_formula", formal_specular.REFERENCE} <= set(r.job.properties)
    assert dict(r.rows)["intensity_formula"] == "proven"


def test_quick_core_stream_protocol_proven_bounded_and_mutant(quick) -> None:
    r = quick["shading_core_prove_small"]
    assert r.ok and r.status == "proven", r.detail
    assert set(r.job.properties) == set(formal_core.PROTOCOL)
    r = quick["shading_core_bmc_small_quick"]
    assert r.ok and r.status == "bounded", r.detail
    assert set(r.job.properties) == set(formal_core.BOUNDED)
    r = quick["shading_core_mutant_one_pixel_too_many"]
    assert r.ok and r.status == "failed", r.detail
    assert r.detail.startswith("tlast_exact fails at step"), r.detail


def test_quick_core_with_a_brdf_highlight_proven_and_its_mutant_fails(quick) -> None:
    """The small configuration with the highlight through the cosine-quadratic form's pipe: the
    AXI4-Stream rules and no beat after reset proven by k-induction; the FIFO taking a pixel at
    the specular unit's stage 10 (two clocks before a BRDF pipe has made it) fails tlast_exact."""
    assert formal_core.CONFIGS["small_brdf"]["HIGHLIGHT"] == "cosine_quadratic"
    r = quick["shading_core_prove_small_brdf"]
    assert r.ok and r.status == "proven", r.detail
    assert set(r.job.properties) == set(formal_core.PROTOCOL)
    r = quick["shading_core_mutant_fifo_takes_the_specular_stage_brdf"]
    assert r.ok and r.status == "failed", r.detail
    assert r.detail.startswith("tlast_exact fails at step"), r.detail


def test_core_property_files_mutants_and_doc_agree() -> None:
    """The core's two property files, its mutants, helper wires, configuration and
    docs/formal.md agree with each other and with the RTL and the model of the core."""
    from model.render import core, pipeline  # model.hw does not import model.render

    m = formal_core
    text = CORE_PROPS.read_text() + AXIS_PROPS.read_text()
    for path in (CORE_PROPS, AXIS_PROPS):
        assert path.read_text().splitlines()[0] == "// SPDX-License-Identifier: Apache-2.0"
    for label in m.PROPERTIES:
        assert re.search(rf"\b{label}: assert\(", text), label
    for label in m.COVERS:
        assert re.search(rf"\b{label}: cover\(", text), label
    assert set(m.PROTOCOL) | set(m.BOUNDED) == set(m.PROPERTIES)
    assert not set(m.PROTOCOL) & set(m.BOUNDED)
    rtl = (ROOT / "rtl" / "shading_core.v").read_text()
    fifo = (ROOT / "rtl" / "shading_axis_fifo.v").read_text()
    for wire, reg in m.INTERNALS.items():
        assert re.search(rf"wire .*\b{wire};", text), wire
        name = reg.split(".")[-1]
        assert re.search(rf"reg .*\b{name};", fifo if reg.startswith("u_fifo.") else rtl), reg
    assert {x.breaks for x in m.MUTANTS.values()} == set(m.PROPERTIES)
    for x in m.MUTANTS.values():
        assert rtl.count(x.original) == 1, x.name
    doc = DOC.read_text()
    for name in [*m.PROPERTIES, *m.COVERS, *m.MUTANTS]:
        assert f"`{name}`" in doc, name
    # the reduced configuration names every parameter of the core (model.render.core), the
    # ROM images being the placeholders; the wait bound reads the core's latency
    params = core.core_parameters(pipeline.PipelineConfig())
    assert set(m.CONFIGS["small"]) | set(m.rom_parameters("small")) == set(params)
    brdf = pipeline.BRDF_METHODS[str(m.CONFIGS["small_brdf"]["HIGHLIGHT"])]
    params = core.core_parameters(brdf)
    assert set(m.CONFIGS["small_brdf"]) | set(m.rom_parameters("small_brdf")) == set(params)
    assert m.LATENCY == core.LATENCY == m.LATENCIES["small"]
    assert m.LATENCIES["small_brdf"] == core.latency(brdf)
    assert re.search(rf"\bSPEC_STAGES = {core.SPECULAR_STAGES};", rtl), "v_reg's width"
    full = formal.jobs("shading_core")
    assert {j.kind for j in full} == {"prove", "bmc", "cover", "mutant"}
    brdf_jobs = [j for j in full if j.config == "small_brdf"]
    assert {j.kind for j in brdf_jobs} == {"prove", "bmc", "cover", "mutant"}
    assert {j.mutant for j in brdf_jobs if j.mutant} == set(m.BRDF_MUTANTS)
    small = {j.mutant for j in full if j.config == "small" and j.mutant}
    assert small == set(m.MUTANTS) - {m.BRDF_MUTANTS[0]}


def check_property_file(props, module, unit: str, labels: list[str]) -> list:
    """The property file, the mutants, the helper wires and docs/formal.md of one unit agree:
    every label is an assert or cover, every helper wire is declared, every property fails on
    a mutant whose snippet occurs once in the RTL, every name is in the doc.  The unit's jobs."""
    text = props.read_text()
    assert text.splitlines()[0] == "// SPDX-License-Identifier: Apache-2.0"
    for label in labels:
        assert re.search(rf"\b{label}: (assert|cover)\(", text), label
    for wire in module.INTERNALS:
        assert re.search(rf"wire .*\b{wire};", text), wire
    # every property is shown to fail on a broken copy of the RTL
    assert {m.breaks for m in module.MUTANTS.values()} == set(module.PROPERTIES)
    rtl = (ROOT / "rtl" / f"{unit}.v").read_text()
    for m in module.MUTANTS.values():
        assert rtl.count(m.original) == 1, m.name
    doc = DOC.read_text()
    for name in [*labels, *module.MUTANTS]:
        assert f"`{name}`" in doc, name
    return formal.jobs(unit)


def test_specular_property_file_mutants_and_doc_agree() -> None:
    m = formal_specular
    labels = [*m.PROPERTIES, m.REFERENCE, *m.COVERS, *m.DATA_COVERS]
    full = check_property_file(SPECULAR_PROPS, m, "specular_unit", labels)
    assert {j.kind for j in full} == {"prove", "cover", "mutant", "equiv", "bmc"}
    # every mutant, and the data-path one again at the default (the bounded check's)
    mutants = [j for j in full if j.kind == "mutant"]
    assert len(mutants) == len(m.MUTANTS) + 1
    assert any(j.config == "default" and j.mutant == m.DEFAULT_DATA_MUTANT for j in mutants)
    # the data path: proven at small (with the reference's own property), bounded at default
    small = next(j for j in full if j.kind == "prove" and j.config == "small")
    assert set(small.properties) == {*m.PROPERTIES, m.REFERENCE}
    bmc = next(j for j in full if j.kind == "bmc")
    assert bmc.config == "default" and "intensity_formula" in bmc.properties
    # the reference is its own file, not the RTL's pipeline: no register, no stage name
    ref = m.REFERENCE_FILE.read_text()
    assert ref.splitlines()[0] == "// SPDX-License-Identifier: Apache-2.0"
    assert "always" not in ref and "_reg" not in ref


def test_gouraud_property_file_mutants_and_doc_agree() -> None:
    labels = [*formal_gouraud.PROPERTIES, formal_gouraud.PRODUCT, *formal_gouraud.COVERS]
    full = check_property_file(GOURAUD_PROPS, formal_gouraud, "gouraud_segment", labels)
    assert {j.kind for j in full} == {"prove", "cover", "mutant", "equiv"}
    assert any(j.kind == "prove" and j.config == "default" and j.arith for j in full)


def test_table_and_json_name_every_result(quick) -> None:
    results = list(quick.values())
    text = formal.table(results)
    head = text.splitlines()[0]
    assert re.split(r"\s*\|\s*", head.strip()) == [
        "property",
        "unit",
        "configuration",
        "result",
        "time",
    ]
    assert "mutant div_zero_leak" in text and "NOT OK" not in text
    record = formal.to_json(results)
    assert record["ok"] is True and len(record["results"]) == len(results)


def test_property_file_mutants_and_doc_agree() -> None:
    text = PROPS.read_text()
    assert text.splitlines()[0] == "// SPDX-License-Identifier: Apache-2.0"
    for label in [*formal.DIVIDER_PROPERTIES, *formal.DIVIDER_COVERS]:
        assert re.search(rf"\b{label}: (assert|cover)\(", text), label
    # every property is shown to fail on a broken copy of the RTL
    assert {m.breaks for m in formal.MUTANTS.values()} == set(formal.DIVIDER_PROPERTIES)
    rtl = (ROOT / "rtl" / "divider_shift.v").read_text()
    for m in formal.MUTANTS.values():
        assert rtl.count(m.original) == 1, m.name
    doc = DOC.read_text()
    for name in [*formal.DIVIDER_PROPERTIES, *formal.DIVIDER_COVERS, *formal.MUTANTS]:
        assert f"`{name}`" in doc, name


def test_bad_input_is_refused_with_a_message(tmp_path) -> None:
    with pytest.raises(ValueError, match=r"'nonesuch'.*divider_shift, gouraud_segment"):
        formal.jobs("nonesuch")
    job = formal.jobs("divider_shift", quick=True)[0]
    with pytest.raises(ValueError, match=r"config 'huge' is unknown"):
        formal.run_job(formal.FormalJob("x", "divider_shift", "prove", "huge"), tmp_path)
    with pytest.raises(ValueError, match=r"job kind 'guess' is unknown"):
        formal.run_job(formal.FormalJob("x", "divider_shift", "guess", "default"), tmp_path)
    with pytest.raises(formal.FormalError, match=r"nowhere\.v does not exist"):
        bad = formal.FormalJob("bad_rtl", job.unit, job.kind, job.config, rtl="nowhere.v")
        formal.run_job(bad, ROOT / "out" / "formal" / "pytest")


@pytest.mark.parametrize(
    "args, message",
    [
        (["--units", "nonesuch"], "'nonesuch' is unknown"),
        (["--jobs", "0"], "--jobs: 0 is out of range"),
        # specular_unit is accepted (the next check refuses --jobs 0)
        (["--units", "specular_unit", "--jobs", "0"], "--jobs: 0 is out of range"),
    ],
)
def test_cli_refuses_bad_arguments(args, message) -> None:
    proc = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "formal.py"), *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert message in proc.stderr


def test_quick_specular_kept_range_protocol_is_proven(quick) -> None:
    """The kept range of n the fit emits (N_FIRST = 17): the protocol proven by k-induction."""
    r = quick["specular_unit_prove_kept"]
    assert formal_specular.CONFIGS["kept"].n_first > 1
    assert r.ok and r.status == "proven", r.detail
    assert set(r.job.properties) == set(formal_specular.PROTOCOL)


# Every mutant job of make formal, and its RESET_ALL = 1 proofs (the slow tier, so CI runs them)
FORMAL_UNITS = ("divider_shift", "gouraud_segment", "specular_unit", "brdf_unit", "shading_core")
MUST_FAIL = {
    j.name: j
    for u in FORMAL_UNITS
    for j in formal.jobs(u)
    if j.kind == "mutant" or (j.kind == "prove" and j.reset_all == 1)
}


@pytest.mark.parametrize("name", sorted(MUST_FAIL))
def test_every_formal_mutant_fails_its_property(name: str) -> None:
    """Each saved mutant of the formal jobs fails the property it targets (and no other one
    first); each RESET_ALL = 1 proof is proven."""
    job = MUST_FAIL[name]
    out = ROOT / "out" / "formal" / "pytest" / os.environ.get("PYTEST_XDIST_WORKER", "main")
    r = formal.run_job(job, out)
    if job.kind == "prove":
        assert r.ok and r.status == "proven", r.detail
        return
    assert r.ok and r.status == "failed", f"{name}: {r.status}: {r.detail}"
    assert r.detail.startswith(f"{job.properties[0]} fails at step"), r.detail


def test_the_slow_tier_runs_every_mutant_and_reset_all_proof() -> None:
    """Every unit's mutants and its RESET_ALL = 1 proofs are in MUST_FAIL."""
    modules = {"divider_shift": formal, "gouraud_segment": formal_gouraud}
    modules |= {"specular_unit": formal_specular, "shading_core": formal_core}
    modules |= {"brdf_unit": formal_brdf}
    for unit, module in modules.items():
        names = {j.mutant for j in MUST_FAIL.values() if j.unit == unit and j.kind == "mutant"}
        assert names == set(module.MUTANTS), unit
    proofs = {j.unit for j in MUST_FAIL.values() if j.kind == "prove"}
    assert proofs == {"divider_shift", "gouraud_segment", "specular_unit", "brdf_unit"}
