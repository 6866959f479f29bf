# SPDX-License-Identifier: Apache-2.0
"""The soak's numba kernels (sim/soak_stimulus.py, sim/soak_predict.py) against the reference.

* ``soak_predict.predict`` gives every cycle the outputs ``ProtocolModel.step`` gives, in both
  RESET_ALL modes, with the same counts and the same jobs, on a few thousand cycles of random
  stimulus of every configuration the soaks run (tests/test_soak.py ``CONFIGS``), from a reset
  and from a cycle where nothing is known yet;
* ``soak_file.vector_bytes`` equals ``soak.write_vectors`` of those predictions, byte for
  byte;
* the stimulus is a function of its seed and segment and draws what the soak is for: the
  extremes, values next to 0, powers of two of either sign, writes in start and busy cycles,
  resets of 1 to 3 cycles, the specular unit's n at its edges and inside a kept range, the
  BRDF unit's n at the edges of 1..1000 and of the register.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest

from model.units import brdf, divider, specular
from sim import soak, soak_file, soak_predict, soak_stimulus, units, vector_sets
from tests.test_soak import CONFIGS

CYCLES = 4000
ROOT = Path(__file__).resolve().parent.parent


def _counts(stats: soak.Stats) -> dict[str, int]:
    return {k: v for k, v in asdict(stats).items() if k != "errors"}


@pytest.mark.parametrize("name", list(CONFIGS))
def test_kernels_predict_what_the_protocol_model_predicts(name: str, tmp_path: Path) -> None:
    cfg = CONFIGS[name][0]
    spec = units.spec(cfg)
    whole = soak_stimulus.stimulus(cfg, CYCLES, seed=11)
    for first in (0, 3):  # from the reset, and from the first cycle after it (nothing known)
        stim = whole.tail(first)
        inputs = stim.as_inputs()
        assert soak_stimulus.from_inputs(spec, inputs).value.tolist() == stim.value.tolist()
        fast = soak_predict.predict(cfg, stim)
        refs = [soak.predict(cfg, inputs, reset_all=mode) for mode in (False, True)]
        for mode, ref in enumerate(refs):
            for cycle, want in enumerate(ref.outputs):
                got = fast.outputs(cycle, reset_all=bool(mode))
                assert got == want, (
                    f"{name}, RESET_ALL = {mode}, cycle {first + cycle}: kernels {got}, "
                    f"ProtocolModel {want}; inputs {inputs[cycle]}"
                )
            assert _counts(fast.stats) == _counts(ref.stats), name
        ref = refs[0]
        for cycle in range(0, len(inputs), 37):
            for got, want in (
                (fast.job_at(cycle), ref.jobs[cycle]),
                (fast.result_job_at(cycle), ref.result_jobs[cycle]),
            ):
                assert (got is None) == (want is None), (name, cycle)
                if got is not None and want is not None:
                    for key in ("operands", "results", "busy_cycles", "valid_offsets"):
                        assert getattr(got, key) == getattr(want, key), (name, cycle, key)
                    assert (got.started_at, got.write_at_start) == (
                        want.started_at,
                        want.write_at_start,
                    ), (name, cycle)
        path = soak.write_vectors(
            spec, inputs, refs[0].outputs, tmp_path / f"ref{first}.bin", refs[1].outputs
        )
        data = soak_file.vector_bytes(cfg, stim, fast).tobytes()
        assert data == path.read_bytes(), f"{name}: the vector files differ"
    assert fast.stats.results_compared > 0 and fast.stats.resets > 0


def test_stimulus_follows_its_seed_and_segment() -> None:
    cfg = divider.DEFAULT
    a = soak_stimulus.stimulus(cfg, 5000, seed=3)
    same = soak_stimulus.stimulus(cfg, 5000, seed=3)
    for key in ("rst_n", "start", "we", "value"):
        assert np.array_equal(getattr(a, key), getattr(same, key)), key
    assert not np.array_equal(a.value, soak_stimulus.stimulus(cfg, 5000, seed=4).value)
    other = soak_stimulus.stimulus(cfg, 5000, seed=3, segment=1)
    assert not np.array_equal(a.value, other.value)
    assert other.rst_n[:3].tolist() == [0, 0, 0]  # every segment starts from a reset
    assert soak.stimulus(cfg, 5000, 3) == a.as_inputs()


def _runs(bits: np.ndarray) -> list[int]:
    """Lengths of the runs of 0 in ``bits``."""
    out, n = [], 0
    for b in [*bits.tolist(), 1]:
        if b == 0:
            n += 1
        elif n:
            out.append(n)
            n = 0
    return out


def test_stimulus_draws_what_the_soak_is_for() -> None:
    cfg = divider.DEFAULT
    stim = soak_stimulus.stimulus(cfg, 60_000, seed=5)
    lo, hi = cfg.a_range
    written = stim.value[:, 0][stim.we[:, 0] == 1].tolist()
    assert {lo, lo + 1, -2, -1, 0, 1, 2, hi - 1, hi} <= set(written)
    powers = {v for v in written if v != 0 and abs(v) & (abs(v) - 1) == 0}
    assert {1 << 19, -(1 << 19), 1 << 10, -(1 << 10)} <= powers
    k_written = set(stim.value[:, 1][stim.we[:, 1] == 1].tolist())
    assert {0, 1, 2, cfg.k_max - 1, cfg.k_max} <= k_written
    runs = _runs(stim.rst_n)
    assert runs[0] == 3 and set(runs[1:]) == {1, 2, 3}, runs
    pred = soak_predict.predict(cfg, stim)
    s = pred.stats
    assert s.writes_at_start > 0 and s.writes_ignored > 0 and s.starts_ignored > 0

    kept = specular.KEPT
    stim = soak_stimulus.stimulus(kept, 60_000, seed=5)
    n_col = [p.name for p in units.spec(kept).operands].index("n")
    n = set(stim.value[:, n_col][stim.we[:, n_col] == 1].tolist())
    edges = {kept.n_first - 1, kept.n_first, kept.n_last, kept.n_last + 1, 0, 1023}
    assert edges <= n, sorted(edges - n)
    assert set(range(kept.n_first, kept.n_last + 1)) <= n  # every n of the kept range 17..40
    length = units.spec(kept).operands[-1]
    lengths = stim.value[:, -1][stim.we[:, -1] == 1]
    assert length.name == "len" and lengths.max() == kept.len_max
    assert np.mean(lengths <= soak_stimulus.SHORT_LINE) > 0.9

    cfg = brdf.UNIT_CONFIGS["quadratic"]
    stim = soak_stimulus.stimulus(cfg, 20_000, seed=5)
    n_col = [p.name for p in units.spec(cfg).operands].index("n")
    n = set(stim.value[:, n_col][stim.we[:, n_col] == 1].tolist())
    assert {0, 1, 2, specular.N_MAX, specular.N_MAX + 1, 1023} <= n, sorted(n)
    assert len(n & set(range(3, specular.N_MAX))) > 100  # and inside the range


def _figure(value: int) -> str:
    """A count as the pages write it: 3000, 20 000."""
    return str(value) if value < 10_000 else f"{value:,}".replace(",", " ")


def test_brdf_data_sheet_states_the_soaks_and_sets() -> None:
    """docs/brdf_unit.md's soak paragraph: the cycles each form soaks (``CONFIGS``), the n the
    stimulus favours (``draw_plan``) and the committed sets' cycles (``vector_sets.SETS``)."""
    page = " ".join((ROOT / "docs" / "brdf_unit.md").read_text().split())
    soaks = {CONFIGS[f"brdf_{form}"][1] for form in brdf.UNIT_CONFIGS}
    sets = {vector_sets.SETS[f"brdf_{form}"][1] for form in brdf.UNIT_CONFIGS}
    assert len(soaks) == len(sets) == 1
    assert f"for {_figure(soaks.pop())} cycles through the plain-Verilog bench" in page
    assert f"({_figure(sets.pop())} cycles each, `make vectors`)" in page
    edges = [int(v) for v in soak_stimulus.draw_plan(CONFIGS["brdf_quadratic"][0]).n_edges]
    listed = ", ".join(map(str, edges[:-1])) + f" and {edges[-1]}"
    assert f"n at {listed} and across the register" in page
