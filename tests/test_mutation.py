# SPDX-License-Identifier: Apache-2.0
"""make mutants (sim/mutation.py): Yosys ``mutate`` lists of every design, each mutant through
the committed vector sets and the stronger checks, survivors proven equivalent or counted.

Quick tier: a fixed sample of the divider's and the Gouraud unit's lists (``SAMPLE`` mutants
spread evenly over the ones the record says are killed) through the same netlist and bench:
mutant 0, the original, passes every check (``run_design`` stops otherwise), every sampled
mutant is killed, by the check the record names, and the list Yosys makes now is the one the
record was made from.  The docs' table is the record's.  The proof from reset
(``mutation_proof.prove_from_reset``) finds a counterexample for a Gouraud mutant a check kills
and proves the survivor of the other proofs the record says it proves; the fourth proof (the
multipliers cut, then invariants asserted alongside) does the same on the specular unit's
list, and an invariant the original breaks gives a counterexample.  Slow tier: the Gouraud
unit's 174 proven with its invariants, and every
mutant of every list the record does not prove equivalent through the checks (the specular
unit's and the core's netlists take minutes to build, so they have no sample of their own),
the same kills as the record and the rest its survivors.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from sim import (
    mutation,
    mutation_checks,
    mutation_invariants,
    mutation_proof,
    mutation_report,
    units,
    vector_sets,
)
from sim.runner import SIM_BUILD

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "verification.md"
SAMPLE = 12
# builds kept between runs (the netlists are the same while the RTL is: a cache hit), one
# folder per pytest-xdist worker: ``mutation.prepare`` writes a design's folder afresh, so two
# workers preparing the same design in one folder would delete each other's files
BUILD = SIM_BUILD / "mutants" / os.environ.get("PYTEST_XDIST_WORKER", "main")


def _record() -> dict:
    return json.loads(mutation.RECORD.read_text())


# the specular unit's and the core's lists run whole in the slow tier (their netlists take
# minutes to build): a sample of them there would repeat a part of that
@pytest.mark.parametrize("design", ["divider_shift", "gouraud_segment"])
def test_sampled_mutants_are_killed(design: str) -> None:
    rec = _record()["designs"][design]
    ids = mutation.quick_sample(rec, SAMPLE)
    assert len(ids) == SAMPLE
    report = mutation.run_design(mutation.DESIGNS[design], ids, jobs=2, out=BUILD, prove=False)
    assert report.list_digest == rec["list_digest"], (
        f"the mutation list of {design} changed since docs/mutants.json: make mutants"
    )
    got = {o.id: o.killed_by for o in report.outcomes}
    assert all(got.values()), f"sampled mutants not killed: {[i for i, k in got.items() if not k]}"
    assert got == {i: rec["killed_by"][str(i)] for i in ids}


def test_the_record_is_current() -> None:
    """docs/mutants.json was made from the sources, ROM images and parameters there are now
    (remake it: make mutants)."""
    rec = _record()
    assert rec["seed"] == mutation.SEED and rec["list_size"] == mutation.LIST_SIZE
    assert set(rec["designs"]) == set(mutation.DESIGNS)
    stale = [
        name
        for name, design in mutation.DESIGNS.items()
        if rec["designs"][name]["inputs_digest"] != mutation.inputs_digest(design)
    ]
    assert not stale, f"docs/mutants.json is stale for {stale}: make mutants"


def test_the_docs_table_is_the_record_s() -> None:
    """docs/verification.md carries the table sim/mutation.py prints for the record, and its
    list of the equivalent mutants and survivors."""
    text = DOC.read_text()
    assert mutation_report.table(_record()) in text
    assert mutation_report.listing(_record()) in text


@pytest.mark.parametrize("name", list(mutation.DESIGNS))
def test_the_whole_list_gives_the_record_s_figures(name: str) -> None:
    """Every mutant of the design's list that the record does not prove equivalent through the
    checks (make mutants without the proofs, which the record holds; a proven one cannot fail
    a check, and running it through all of them, the 4M-cycle soak last, is most of the
    time): each killed by the check the record names, the rest exactly the record's
    survivors."""
    rec = _record()["designs"][name]
    proven = {o["id"] for o in rec["equivalent"]}
    ids = [i for i in range(1, rec["mutants"] + 1) if i not in proven]
    report = mutation.run_design(mutation.DESIGNS[name], ids, jobs=2, out=BUILD, prove=False)
    assert report.list_digest == rec["list_digest"], f"the mutation list of {name} changed"
    got = {str(o.id): o.killed_by for o in report.outcomes if o.killed_by}
    assert got == rec["killed_by"], name
    alive = sorted(o.id for o in report.outcomes if not o.killed_by)
    assert alive == sorted(o["id"] for o in rec["survivors"])


# The from-reset proof (mutation_proof.prove_from_reset) on the Gouraud unit's list: a mutant
# the record says a check kills (15: by a soak, after the committed set passed it) and a
# survivor of the other proofs the record has it prove (33: seg_reg bit 8, dead because a line
# has at most 256 segments), a few seconds each
FROM_RESET_KILLED, FROM_RESET_PROVEN = 15, 33


@pytest.fixture(scope="module")
def gouraud_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["gouraud_segment"], BUILD)


def test_the_from_reset_proof_finds_a_killed_mutant_s_counterexample(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """Sound: a mutant a check kills is not proven, pdr finds the trace from reset that tells
    it from the original."""
    rec = _record()["designs"]["gouraud_segment"]
    assert rec["killed_by"][str(FROM_RESET_KILLED)] != rec["vector_set"]
    design = mutation.DESIGNS["gouraud_segment"]
    command = gouraud_list.mutations[FROM_RESET_KILLED - 1].command
    verdict = mutation_proof.prove_from_reset(
        tmp_path / "killed", design.top, gouraud_list.design_il, command, design.contract, 60
    )
    assert verdict == "failed"


def test_the_from_reset_proof_proves_a_survivor_of_the_others(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The record's mutant it proves: equal from reset, where no proof from any shared state
    can show it (the bound on seg_reg holds only in the states a reset leads to)."""
    rec = _record()["designs"]["gouraud_segment"]
    (listed,) = [o for o in rec["equivalent"] if o["id"] == FROM_RESET_PROVEN]
    assert listed["equivalent"].startswith("scorr and pdr from reset")
    design = mutation.DESIGNS["gouraud_segment"]
    command = gouraud_list.mutations[FROM_RESET_PROVEN - 1].command
    assert command == listed["command"]
    verdict = mutation_proof.prove_from_reset(
        tmp_path / "proven", design.top, gouraud_list.design_il, command, design.contract, 60
    )
    assert verdict == "proven"


def test_operand_bit_jobs_show_every_bit_of_the_divider_s_operands() -> None:
    """The operand-bit check's jobs: each pair differs in one bit of one operand and the golden
    model gives the two different results; the divider's a and k have a pair for every bit
    (a wrong quotient shows each), so a register bit stuck or lost on its hold path shows."""
    cfg = vector_sets.SETS["divider_default"][0]
    expect = units.expect(cfg)
    jobs = mutation_checks.operand_bit_jobs(cfg)
    widths = {p.name: p.width for p in units.spec(cfg).operands}
    assert sorted((name, b) for name, b, _, _ in jobs) == sorted(
        (name, b) for name, w in widths.items() for b in range(w)
    )
    for name, b, job, other in jobs:
        assert {k for k in job if job[k] != other[k]} == {name}
        assert (job[name] - other[name]) % (1 << widths[name]) in (
            1 << b,
            (1 << widths[name]) - (1 << b),
        )
        assert expect(job).results != expect(other).results


def test_the_record_round_trips_through_a_report() -> None:
    """``report_from_record`` (what ``--merge --record`` merges into on a fresh clone) gives
    back every outcome, count and digest of the record: written again, the same record."""
    rec = _record()
    for name, entry in rec["designs"].items():
        commands = [f"mutant {i}" for i in range(1, entry["mutants"] + 1)]
        again = mutation.record([mutation.report_from_record(rec, name, commands)])
        assert again["designs"][name] == entry, name


def test_a_merge_is_proved_when_the_later_run_proved_every_survivor() -> None:
    """``merge``: a whole list run without the proofs (``--no-prove``), then its survivors
    through the checks and the proofs (``--survivors --merge``), is a proved record; a later
    run that left one survivor out, or gave none to the proofs, is not."""
    o = mutation.Outcome

    def report(outcomes, proved):
        return mutation.DesignReport(
            "d", 1, len(outcomes), {}, tuple(x for x in outcomes if x.equivalent),
            tuple(x for x in outcomes if x.survivor), tuple(outcomes), "i", "l", 0, 0, 0, 0,
            proved,
        )  # fmt: skip

    full = report([o(1, "m1", "set"), o(2, "m2", None), o(3, "m3", None)], False)
    both = report([o(2, "m2", None, "proof"), o(3, "m3", None)], True)
    merged = mutation.merge(full, both)
    assert merged.proved and [x.id for x in merged.survivors] == [3]
    assert [x.id for x in merged.equivalent] == [2]
    assert not mutation.merge(full, report([o(2, "m2", None, "proof")], True)).proved
    assert not mutation.merge(full, report([o(2, "m2", None), o(3, "m3", None)], False)).proved


def test_highlight_lines_stay_in_the_highlight() -> None:
    """The specular unit's last check: the lines' pixels inside the highlight of their n, each
    line written with its operands and started.  A pixel shows as lit (non-zero: C x the
    ROM-12 word, C in the top quarter of its range); where cos^n is near 1/256 the product
    may round to 0, so not every one is: 97 % of the first 200 lines' 193 317 pixels are."""
    from model.units.specular import datapath
    from model.units.specular.config import DEFAULT

    rows = mutation_checks.highlight_inputs(DEFAULT)
    jobs = [r for r in rows if r["n_we"]]
    assert len(jobs) == mutation_checks.HIGHLIGHT_JOBS
    assert sum(r["start"] for r in rows) == len(jobs)
    lit = total = 0
    for r in jobs[:200]:
        line = datapath.shade_line(r["c_in"], r["dz_in"], r["z0_in"], r["n_in"], r["len_in"])
        lit += int((line > 0).sum())
        total += line.size
    assert lit >= 0.97 * total, f"{total - lit} of {total} pixels outside the highlight"


def test_directed_spans_take_every_field_to_its_corners() -> None:
    """The core's last check: for each field, spans with it at each corner value of its range
    (``corners``), the term the angle feeds switched on; every span inside the frame."""
    from model.render import core

    fmt = core.SpanFormat(mutation_checks.CORE_CONFIG)
    rows = [core.unpack(fmt.layout(), w) for w in mutation_checks.directed_spans()]
    s = mutation_checks.CORE_CONFIG.specular
    for name in ("z0", "dz", "diff_z0", "diff_dz"):
        seen = {r[name] for r in rows}
        assert set(mutation_checks.corners(s.z_format.lo, s.z_format.hi, s.z_width)) <= seen
    # the diffuse accumulator at exactly -2.0 (-pi), the corner random fractions never meet
    assert any(r["diff_z0"] == -(2 << s.z_frac_bits) and r["diff"] for r in rows)
    assert all(r["x"] + r["l"] + 1 <= 1 << fmt.x_width for r in rows)


def test_highlight_spans_stay_in_the_highlight() -> None:
    """The core's last check (300 spans of it here): both terms on, every pixel's highlight
    angle where cos^n is above 1/256 and its diffuse angle within pi/2, every C in the top
    quarter of its range."""
    import math

    from model.render import core

    fmt = core.SpanFormat(mutation_checks.CORE_CONFIG)
    s = mutation_checks.CORE_CONFIG.specular
    right = 1 << s.z_frac_bits
    c_hi = (1 << s.c_width) - 1
    words = mutation_checks.highlight_spans(count=300)
    for r in (core.unpack(fmt.layout(), w) for w in words):
        edge = math.acos(2.0 ** (-8.0 / r["n"])) / (math.pi / 2) * right
        ends = (r["z0"], r["z0"] + r["l"] * r["dz"])
        assert r["spec"] and r["diff"] and 1 <= r["n"] <= 1000
        assert all(abs(z) <= edge + r["l"] for z in ends), r
        assert all(
            abs(z) < right + r["l"] for z in (r["diff_z0"], r["diff_z0"] + r["l"] * r["diff_dz"])
        )
        assert min(r["c"], *(r[f"diff_c{ch}"] for ch in range(core.CHANNELS))) >= c_hi - c_hi // 4


def test_a_rom_port_at_a_constant_address_reads_its_word(tmp_path: Path) -> None:
    """``cut_roms`` cuts every read port, and one whose address is a constant reads the
    table's word there (the core's read of n = 1's a) where the others read the cut's input:
    the word is what a proof of the diffuse path may rely on, and no other word is."""
    (tmp_path / "rom.v").write_text(
        "module rom (input wire [1:0] addr, output wire [7:0] q, output wire [7:0] q0);\n"
        "reg [7:0] mem [0:3];\n"
        "initial begin mem[0] = 8'h5a; mem[1] = 8'h01; mem[2] = 8'h02; mem[3] = 8'h03; end\n"
        "assign q = mem[addr];\nassign q0 = mem[2'd0];\nendmodule\n"
    )
    mutation_proof.run_yosys(
        "read_verilog rom.v\nprep -top rom\nmemory_collect\nwrite_rtlil rom.il\n", tmp_path, "rom"
    )
    cut = mutation_proof.cut_roms((tmp_path / "rom.il").read_text())
    assert "$mem_v2" not in cut
    (data,) = [ln for ln in cut.splitlines() if "connect" in ln and "mutation_rom0_data" in ln]
    # RD_DATA is { q0 q } (port 1, at address 0, then port 0): q0 the word 0x5a, q the input
    assert data.endswith("{ \\q0 \\q } { 8'01011010 \\mutation_rom0_data [7:0] }"), data


# The fourth proof (from reset, the multipliers cut, then the invariants of
# sim/mutation_invariants.py asserted alongside) on the specular unit's list: survivors of the
# third it proves (65: the accumulator's bit 0 set while it holds, after the line's last pixel;
# 263: the accumulator stepping once more after it, proven with the stage invariants) and a
# mutant the committed set kills (3), a few seconds each
CUT_PROVEN, STAGED_PROVEN, CUT_KILLED = 65, 263, 3


@pytest.fixture(scope="module")
def specular_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["specular_unit"], BUILD)


def _fourth(net: mutation.Netlist, mutant: int, folder: Path, invariants: tuple[str, ...]) -> str:
    design = net.design
    command = net.mutations[mutant - 1].command
    return mutation_proof.prove_from_reset(
        folder, design.top, net.design_il, command, design.contract, 60, True, invariants
    )


def test_the_product_cut_proves_a_survivor_and_finds_a_killed_mutant_s_counterexample(
    specular_list: mutation.Netlist, tmp_path: Path
) -> None:
    """With both multipliers cut (``cut_products``: the mutant's product is the original's
    where their operands agree), pdr proves 65, which it left undecided through the
    products, and still finds the trace from reset that tells 3 from the original."""
    rec = _record()["designs"]["specular_unit"]
    assert str(CUT_KILLED) in rec["killed_by"]
    assert _fourth(specular_list, CUT_PROVEN, tmp_path / "proven", ()) == "proven"
    assert _fourth(specular_list, CUT_KILLED, tmp_path / "killed", ()) == "failed"
    for name in ("proven", "killed"):
        miter = (tmp_path / name / "miter.v").read_text()
        assert "gold_mutation_mul0_in == gate_mutation_mul0_in ?" in miter
        assert "$mul" not in (tmp_path / name / "gold_reset.il").read_text()


def test_the_stage_invariants_prove_a_survivor_and_find_a_killed_mutant_s_counterexample(
    specular_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The specular unit's stage invariants (each stage's registers equal in the two copies
    while its valid bit is set), asserted with the outputs: 263, which pdr leaves undecided
    without them, proven; 3 still fails."""
    stages = mutation_invariants.DESIGN["specular_unit"]
    assert _fourth(specular_list, STAGED_PROVEN, tmp_path / "proven", stages) == "proven"
    assert _fourth(specular_list, CUT_KILLED, tmp_path / "killed", stages) == "failed"


def test_an_invariant_is_proven_not_assumed(
    specular_list: mutation.Netlist, tmp_path: Path
) -> None:
    """An invariant the original breaks (the accumulator 0 while a pixel is in stage S0) gives
    a counterexample on a mutant the same proof proves without it: the invariants are
    asserted, so a wrong one can never make a proof."""
    wrong = ("!gold:v_reg[0] || gold:acc_reg == 40'd0",)
    assert _fourth(specular_list, CUT_PROVEN, tmp_path / "wrong", wrong) == "failed"


# The Gouraud unit's 174 (start_reg bit 8 flipped while its bit 23 is set), proven with its own
# invariants (sim/mutation_invariants.py GOURAUD_CLAMPED, about 140 s of pdr: the slow tier)
CLAMP_PROVEN = 174


def test_the_clamp_invariants_prove_gouraud_174(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """174's invariants are found by its mutate command and prove it from reset."""
    command = gouraud_list.mutations[CLAMP_PROVEN - 1].command
    given = mutation_invariants.invariants("gouraud_segment", command)
    assert given == mutation_invariants.GOURAUD_CLAMPED
    design = gouraud_list.design
    verdict = mutation_proof.prove_from_reset(
        tmp_path, design.top, gouraud_list.design_il, command, design.contract, 300, True, given
    )
    assert verdict == "proven"


def test_the_clamp_invariants_find_a_killed_mutant_s_counterexample(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The same invariants on a mutant a soak kills (15): a counterexample."""
    command = gouraud_list.mutations[FROM_RESET_KILLED - 1].command
    design = gouraud_list.design
    verdict = mutation_proof.prove_from_reset(
        tmp_path, design.top, gouraud_list.design_il, command, design.contract, 60, True,
        mutation_invariants.GOURAUD_CLAMPED,
    )  # fmt: skip
    assert verdict == "failed"


def test_rounding_spans_put_every_quotient_near_a_rounding_point() -> None:
    """The core's rounding spans (100 of them here): Gouraud only, 1024 to 2047 pixels, each
    channel's quotient a x r within its window of a rounding point of dI, so a change of dI
    by one LSB is one of the divider's, and a long span shows it in a pixel for nearly every
    channel (the model's lines with dI and dI +- 1 compared)."""
    import numpy as np

    from model.render import core
    from model.render.pipeline import increment_from_quotient
    from model.units import divider, gouraud

    cfg = mutation_checks.CORE_CONFIG
    fmt = core.SpanFormat(cfg)
    n = cfg.divider.recip_bits
    shown = tried = 0
    for word in mutation_checks.rounding_spans(count=100):
        r = core.unpack(fmt.layout(), word)
        assert not r["spec"] and not r["diff"] and 1023 <= r["l"] < cfg.gouraud.len_max
        assert r["x"] + r["l"] + 1 <= 1 << fmt.x_width
        for ch in range(core.CHANNELS):
            start, end = r[f"i_start{ch}"], r[f"i_end{ch}"]
            assert min(start, end) >= 0 and max(start, end) < 1 << cfg.gouraud.i_width
            q = int(divider.divide(end - start, r["l"], cfg.divider))
            assert abs(q % (1 << n) - (1 << (n - 1))) <= max(mutation_checks.ROUNDING_WINDOWS)
            di = int(increment_from_quotient(np.array([q]), cfg)[0])
            line = gouraud.shade_line(start, di, r["l"] + 1, cfg.gouraud)
            for step in (-1, 1):
                tried += 1
                moved = gouraud.shade_line(start, di + step, r["l"] + 1, cfg.gouraud)
                shown += bool((moved != line).any())
    assert shown >= 0.95 * tried, f"{shown} of {tried}"


def test_table_highlight_spans_light_every_table() -> None:
    """The per-table highlight spans: n from each k range in about a quarter of them (400
    here), where n uniform in 1..1000 gives the first three tables 6 spans in 1000."""
    from collections import Counter

    from model.render import core

    cfg = mutation_checks.CORE_CONFIG
    fmt = core.SpanFormat(cfg)
    ranges = cfg.specular.k_ranges
    words = mutation_checks.highlight_spans(400, 1, per_table=True)
    tables = Counter(
        next(j for j, (lo, hi, _) in enumerate(ranges) if lo <= r["n"] <= hi)
        for r in (core.unpack(fmt.layout(), w) for w in words)
    )
    assert all(70 <= tables[j] <= 130 for j in range(len(ranges))), tables
