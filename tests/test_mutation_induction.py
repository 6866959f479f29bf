# SPDX-License-Identifier: Apache-2.0
"""The sixth proof of ``make mutants`` (sim/mutation_induction.py, the core's invariants in
sim/mutation_accumulator.py) on the core's list, shown able to fail: the lemma holds at the
worst length with the bound 4 and fails with 5 there (the worst case found independently, over
every difference at that length, with numpy), the step fails without the accumulator's range
or sign, and a mutant of the Gouraud saturation the committed set kills breaks the step, in
one query and through the whole proof as make mutants runs it (which stops at that query).
The whole proof of 205 (about 5 minutes on two processes) is make mutants' only; the record's
text for it is the proof's.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from model.units import divider
from sim import mutation, mutation_accumulator, mutation_induction
from sim.mutation_accumulator import Accumulator
from sim.mutation_induction import Query
from tests.mutation_common import BUILD, record

# The core's mutant the sixth proof proves (the Gouraud value of a negative accumulator set
# to 2 on channel 2), and one of the saturation's mutants the committed set kills (channel
# 1's "over" tied to 1: every value saturates)
PROVEN, KILLED = 205, 23
# The worst length of the lemma (where l dI - a reaches its minimum over every a)
WORST_LENGTH = 2046


@pytest.fixture(scope="module")
def core_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["shading_core"], BUILD)


def _problem(
    core_list: mutation.Netlist, folder: Path, mutant: int, **kwargs: object
) -> Accumulator:  # fmt: skip
    command = core_list.mutations[mutant - 1].command
    il = core_list.design_il.read_text()
    channel = mutation_accumulator.gouraud_channel(il, command)
    assert channel is not None
    shape = mutation_accumulator.shape(il, channel)
    smt2 = mutation_accumulator.accumulator_miter(folder, core_list.design_il, command, shape)
    return Accumulator(smt2.read_text(), shape, **kwargs)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def proven_miter(core_list: mutation.Netlist, tmp_path_factory: pytest.TempPathFactory) -> (
    Path
):  # fmt: skip
    folder = tmp_path_factory.mktemp("induction")
    _problem(core_list, folder, PROVEN)
    return folder


def _names(problem: Accumulator) -> list[str]:
    state = problem.machine.state(lambda f: f"s.{f}")
    return [name for name, _ in problem.invariants(state)]


def test_the_mutations_channel_is_read_off_its_cell(core_list: mutation.Netlist) -> None:
    """205's cell drives g_val[23:16] (channel 2), 23's reads g_gouraud[1]; a mutation of the
    highlight (the record's 114) is none of the proof's."""
    il = core_list.design_il.read_text()

    def channel(i: int) -> int | None:
        return mutation_accumulator.gouraud_channel(il, core_list.mutations[i - 1].command)

    assert (channel(PROVEN), channel(KILLED), channel(114)) == (2, 1, None)
    shape = mutation_accumulator.shape(il, 2)
    assert (shape.channels, shape.i_width, shape.g_width, shape.len_width) == (3, 20, 33, 11)
    assert shape.bias == 2048


def _worst_over_a(length: int, recip: int) -> tuple[int, int]:
    """min over every difference a of l dI(a) - a, and the a that reaches it (the model's
    increment: dI = (a r + 2^19) >> 20, arithmetic), over the a whose i_end is legal."""
    a = np.arange(-(1 << 20) + 1, 1 << 20, dtype=np.int64)
    di = (a * recip + (1 << 19)) >> 20
    gap = length * di - a
    k = int(np.argmin(gap))
    return int(gap[k]), int(a[k])


def test_the_lemma_holds_with_4_and_fails_with_5_at_the_worst_length(
    core_list: mutation.Netlist, proven_miter: Path
) -> None:
    """With i_end = 0, the end value is bias + (l dI - a): at l = 2046 its least is 2048 -
    2044 = 4 (numpy over every a, the model's ROM word), so the lemma with the bound 4
    holds there and with 5 fails there, and 5 still holds at 2042."""
    smt2 = (proven_miter / "induction" / "miter.smt2").read_text()
    shape = mutation_accumulator.shape(core_list.design_il.read_text(), 2)
    exact = Accumulator(smt2, shape)
    words = divider.rom_words(divider.DEFAULT)
    gap, a = _worst_over_a(WORST_LENGTH, int(words[WORST_LENGTH]))
    assert (gap, a) == (-2044, -1047554)
    assert shape.bias + gap == mutation_accumulator.LOW
    assert exact.decide(Query("lemma", 0, value=WORST_LENGTH)) == "unsat"
    tight = Accumulator(smt2, shape, low=mutation_accumulator.LOW + 1)
    assert tight.decide(Query("lemma", 0, value=WORST_LENGTH)) == "sat"
    assert shape.bias + _worst_over_a(2042, int(words[2042]))[0] > mutation_accumulator.LOW
    assert tight.decide(Query("lemma", 0, value=2042)) == "unsat"


def test_the_base_holds_for_every_invariant(
    core_list: mutation.Netlist, proven_miter: Path
) -> None:  # fmt: skip
    """From any power-up state the two copies share, one clock in reset: every invariant and
    the contract."""
    smt2 = (proven_miter / "induction" / "miter.smt2").read_text()
    problem = Accumulator(smt2, mutation_accumulator.shape(core_list.design_il.read_text(), 2))
    base = [q for q in problem.queries() if q.kind == "base"]
    names = _names(problem)
    assert len(base) == len(names) + 1 == 216
    assert sum(name.startswith("copies equal: ") for name in names) == 187
    assert [problem.decide(q) for q in base] == ["unsat"] * len(base)


def test_the_step_needs_the_accumulator_s_range_and_sign(
    core_list: mutation.Netlist, proven_miter: Path
) -> None:
    """In a cycle that issues a pixel (ce and take 0, the issue signal 1): the sign stays 0
    only with the end value's range, and the side band's first slot (the Gouraud value the
    mutant changes) stays equal only with the sign."""
    smt2 = (proven_miter / "induction" / "miter.smt2").read_text()
    shape = mutation_accumulator.shape(core_list.design_il.read_text(), 2)
    whole = Accumulator(smt2, shape)
    names = _names(whole)
    sign = names.index("span: acc sign 0")
    slot = names.index("side band slot 1 equal while valid")
    issue = (0, 0, 1)
    assert whole.decide(Query("step", sign, issue)) == "unsat"
    assert whole.decide(Query("step", slot, issue)) == "unsat"
    no_range = Accumulator(smt2, shape, dropped=("span: e in range",))
    assert no_range.decide(Query("step", sign, issue)) == "sat"
    no_sign = Accumulator(smt2, shape, dropped=("span: acc sign 0",))
    assert no_sign.decide(Query("step", slot, issue)) == "sat"


def test_a_killed_saturation_mutant_breaks_the_step(
    core_list: mutation.Netlist, tmp_path: Path
) -> None:  # fmt: skip
    """23 (channel 1's over tied to 1), which the committed set kills: the side band's first
    slot differs after a pixel is issued."""
    assert str(KILLED) in record()["designs"]["shading_core"]["killed_by"]
    problem = _problem(core_list, tmp_path, KILLED)
    slot = _names(problem).index("side band slot 1 equal while valid")
    verdicts = {case: problem.decide(Query("step", slot, case)) for case in [(0, 0, 1), (1, 1, 1)]}
    assert verdicts == {(0, 0, 1): "sat", (1, 1, 1): "sat"}


def test_the_record_s_proof_of_205_is_the_sixth_proof_s_text(
    core_list: mutation.Netlist, proven_miter: Path
) -> None:
    """The record (``make mutants``) has 205 proven by the sixth proof, with the number of
    queries of each kind its invariants and lengths give."""
    smt2 = (proven_miter / "induction" / "miter.smt2").read_text()
    problem = Accumulator(smt2, mutation_accumulator.shape(core_list.design_il.read_text(), 2))
    queries = problem.queries()
    counts = {k: sum(1 for q in queries if q.kind == k) for k in ("base", "step", "lemma")}
    assert counts == {"base": 216, "step": 216 * 8, "lemma": 2048}
    rec = record()["designs"]["shading_core"]
    (how,) = [o["equivalent"] for o in rec["equivalent"] if o["id"] == PROVEN]
    assert how == mutation_accumulator.proven_text(2, counts)


def test_the_whole_proof_of_a_killed_mutant_fails_at_a_step(
    core_list: mutation.Netlist, tmp_path: Path
) -> None:  # fmt: skip
    """The sixth proof as make mutants runs it, on 23: not proven, the first query it fails a
    step's, named in induction_failed.txt (a few seconds: the queries stop there; the whole
    proof of 205, 2048 lemmas besides, is make mutants')."""
    command = core_list.mutations[KILLED - 1].command
    found = mutation_accumulator.accumulator_equivalence(
        tmp_path, core_list.design_il, command, jobs=2
    )
    assert found is None
    failed = (tmp_path / "induction_failed.txt").read_text()
    assert "kind='step'" in failed and " sat" in failed


def test_the_functional_netlist_keeps_its_roms_and_reads_their_images(
    proven_miter: Path,
) -> None:  # fmt: skip
    """Every ROM is an array a step leaves as it is, the two copies' images are the same, and
    the reciprocal ROM's words are the model's (round(2^20 / l), 0 at l = 0)."""
    smt2 = (proven_miter / "induction" / "miter.smt2").read_text()
    machine = mutation_induction.Machine(smt2)
    roms = machine.roms()
    assert len(roms) == 20
    images = mutation_induction.rom_images(smt2)
    assert all(images[r] == images[("gate." if r[:4] == "gold" else "gold.") + r[5:]] for r in roms)
    recip = images["gold." + mutation_accumulator.RECIP_ROM]
    assert recip == dict(enumerate(int(w) for w in divider.rom_words(divider.DEFAULT)))
