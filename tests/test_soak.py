# SPDX-License-Identifier: Apache-2.0
"""Constrained-random soaks: the bulk random RTL checking, through the plain Verilog vector benches.

Random strobes, start timing and resets, writes in the start cycle and in busy cycles, values
across 0 and at the extremes (sim/soak.py); every output is compared with the protocol model
in every cycle.  The seed is printed in the run's summary; ``SOAK_SEED=<seed>`` replays a run.
Saved mutants must fail it: the div_zero defect the released divider shipped, naming div_zero,
a wrong RESET_ALL = 1 reset value of q, in that instance only (each RESET_ALL instance is
held to its own prediction), and the BRDF unit's output rounding by a quarter LSB, naming
intensity and a job whose operands give the expected value through ``brdf.unit_line``.
Each unit's default configuration soaks deep (``DEEP_CYCLES``: most of the results ``make test``
compares), the other configurations and each form of the BRDF unit 20k cycles, and
``make test-slow`` soaks each default configuration for ``LONG_CYCLES`` (10M);
``SOAK_CYCLES=<n>`` gives every soak n cycles instead (any length: a long soak runs as
segments of 1M cycles, sim/soak.py).  They run under ``verilator --binary`` when it is on PATH
(``make test`` installs it; one build per configuration, kept in sim_build/vector_builds/ for
the next run, sim/vector_run.py), else Icarus; ``SOAK_SIM=icarus|verilator`` picks one.
Icarus replays every committed vector set in tests/test_vectors.py.
"""

from __future__ import annotations

import os
import random
import re
import shutil
from pathlib import Path

import pytest

from model.units import brdf, divider, gouraud, specular
from sim import soak, vector_run
from sim.runner import SIM_BUILD, env_seed, unit_parameters
from tests import mutants
from tests.conftest import record_sim

pytestmark = pytest.mark.sim

SHORT_SOAK = 20_000
# make test-slow: each unit's default configuration for 10M cycles (tests/tiers.py).
LONG_CYCLES = 10_000_000
# The default configurations' soaks (a Gouraud or specular cycle gives about 0.6 results, a
# divider cycle 0.1): the replay is what they cost (the stimulus, prediction and file take a
# few million cycles a CPU second, sim/soak_predict.py).
DEEP_CYCLES = {"divider_default": 150_000, "gouraud_default": 350_000, "specular_default": 350_000}

# Every unit's default configuration deep; a few others, and the ones users ship, for 20k.
CONFIGS = {
    "divider_default": (divider.DEFAULT, DEEP_CYCLES["divider_default"]),
    "divider_article": (divider.ROM_CONFIGS["article"], SHORT_SOAK),
    "divider_n4": (divider.ROM_CONFIGS["n4"], SHORT_SOAK),
    "gouraud_default": (gouraud.DEFAULT, DEEP_CYCLES["gouraud_default"]),
    "gouraud_p2_f4": (gouraud.GouraudConfig(p=2, i_frac=4), SHORT_SOAK),
    "gouraud_p16": (gouraud.GouraudConfig(p=16), SHORT_SOAK),
    "specular_default": (specular.DEFAULT, DEEP_CYCLES["specular_default"]),
    "specular_narrow": (specular.ROM_CONFIGS["narrow"], SHORT_SOAK),
    "specular_inflection": (specular.ROM_CONFIGS["inflection"], SHORT_SOAK),
    # the configurations users ship: the kept range of n (N_FIRST > 1, as shading fit emits)
    # and the UP5K tables
    "specular_kept": (specular.KEPT, SHORT_SOAK),
    "specular_up5k": (specular.UP5K, SHORT_SOAK),
    # the BRDF unit: each form with RTL at its default widths
    "brdf_cosine_quadratic": (brdf.UNIT_CONFIGS["cosine_quadratic"], SHORT_SOAK),
    "brdf_quadratic": (brdf.UNIT_CONFIGS["quadratic"], SHORT_SOAK),
    "brdf_cubic": (brdf.UNIT_CONFIGS["cubic"], SHORT_SOAK),
    "brdf_log2": (brdf.UNIT_CONFIGS["log2"], SHORT_SOAK),
    "brdf_piecewise": (brdf.UNIT_CONFIGS["piecewise"], SHORT_SOAK),
}


def soak_sim() -> str:
    """``SOAK_SIM``; unset: Verilator when it is on PATH, else Icarus."""
    default = "verilator" if shutil.which("verilator") else "icarus"
    sim = os.environ.get("SOAK_SIM", "").strip().lower() or default
    if sim not in vector_run.SIMS:
        raise ValueError(f"SOAK_SIM={sim!r} is not allowed: it must be icarus or verilator")
    return sim


def soak_cycles(default: int) -> int:
    """``SOAK_CYCLES`` (every soak that many cycles) or ``default``; a bad value is refused
    naming it."""
    raw = os.environ.get("SOAK_CYCLES", "").strip()
    if not raw:
        return default
    try:
        cycles = int(raw.replace("_", ""), 0)
    except ValueError:
        cycles = 0
    if cycles < 1:
        raise ValueError(
            f"SOAK_CYCLES={raw!r} is not allowed: it must be a whole number of cycles, at "
            "least 1 (e.g. SOAK_CYCLES=50000000), or unset for each soak's own length"
        )
    return cycles


def soak_seed() -> int:
    seed = env_seed("SOAK_SEED")
    return random.SystemRandom().randrange(1 << 31) if seed is None else seed


def record_soak(request, result: soak.SoakResult) -> None:
    s = result.stats
    record_sim(
        request,
        [
            {
                "unit": f"{result.unit} (vector soak)",
                "test": f"soak seed {result.seed}",
                "jobs": s.jobs_completed,
                "compared": s.results_compared,
                "cycles": result.cycles,
                "seed": result.seed,
            }
        ],
    )


@pytest.mark.parametrize("name", list(CONFIGS))
def test_soak_every_output_every_cycle(request, name: str) -> None:
    cfg, cycles = CONFIGS[name]
    soak_and_check(request, name, cfg, soak_cycles(cycles))


@pytest.mark.parametrize("name", list(DEEP_CYCLES))
def test_ten_million_cycle_soak(request, name: str) -> None:
    """Each unit's default configuration for LONG_CYCLES (make test-slow), in 1M-cycle segments
    of one seed's stimulus (sim/soak.py SEGMENT)."""
    soak_and_check(request, f"{name}_long", CONFIGS[name][0], soak_cycles(LONG_CYCLES))


def soak_and_check(request, name: str, cfg, cycles: int) -> None:
    """One soak of ``cycles`` cycles: no mismatch, and (from SHORT_SOAK cycles on) every corner
    of the protocol reached."""
    seed = soak_seed()
    result = soak.run_soak(
        cfg,
        cycles,
        seed,
        SIM_BUILD / f"soak_{name}",
        unit_parameters(cfg),
        sim=soak_sim(),
        build_root=SIM_BUILD / "vector_builds",
    )
    record_soak(request, result)
    print(result.summary())
    t = result.seconds
    print(
        f"{name}: stimulus {t['stimulus']:.2f} s, predict {t['predict']:.2f} s, write "
        f"{t['write']:.2f} s (CPU), build {t['build']:.2f} s, replay {t['replay']:.2f} s"
    )
    assert result.mismatch_count == 0, (
        f"{result.summary()}\nreplay with SOAK_SEED={seed}\n" + "\n".join(result.mismatches)
    )
    assert result.cycles == cycles
    if cycles < SHORT_SOAK:  # a short SOAK_CYCLES run need not reach every corner
        return
    # The stimulus reached every corner of the protocol it is meant to.
    s = result.stats
    assert s.results_compared > 0 and s.jobs_aborted > 0 and s.back_to_back > 0, s
    assert s.writes_at_start > 0 and s.writes_ignored > 0 and s.starts_ignored > 0, s


def test_soak_finds_the_div_zero_leak(request) -> None:
    """The released divider (div_zero from the k register at result time) fails the soak, and
    every mismatch names div_zero and the job it belongs to."""
    cfg = divider.DEFAULT
    seed = soak_seed()
    result = soak.run_soak(
        cfg,
        SHORT_SOAK,
        seed,
        SIM_BUILD / "soak_divider_mutant",
        unit_parameters(cfg),
        rtl=mutants.build("divider_shift_div_zero_leak", SIM_BUILD / "mutants"),
    )
    assert result.mismatch_count > 0, f"the mutant passed the soak (SOAK_SEED={seed})"
    assert all(": div_zero = " in m for m in result.mismatches), result.mismatches
    assert any("write in the start cycle" in m for m in result.mismatches), result.mismatches


# A mismatch line of the soak (sim/soak.py ``_describe``) for an intensity output: in a valid
# cycle it names the job, between results the job whose last result the output holds.
INTENSITY_MISMATCH = re.compile(
    r"^RESET_ALL = [01], cycle (\d+): intensity = (\d+), expected (\d+) \(valid expected "
    r"([01])\); (?:job|the result held from job) with inputs c=(\d+), dz=(-?\d+), "
    r"z0=(-?\d+), n=(\d+), len=(\d+) \(started at cycle (\d+)"
)


def test_soak_finds_the_brdf_round_quarter_mutant() -> None:
    """The BRDF unit rounding C * F with a quarter of the output LSB instead of a half fails the
    soak in both RESET_ALL instances; every mismatch names intensity, one LSB low, and the job
    it reports reproduces the expected value through ``brdf.unit_line`` of its operands: in a
    valid cycle pixel (cycle - start cycle - fill latency), between results the line's last
    pixel (the held result)."""
    cfg = brdf.UNIT_CONFIGS["cosine_quadratic"]
    seed = soak_seed()
    result = soak.run_soak(
        cfg,
        SHORT_SOAK,
        seed,
        SIM_BUILD / "soak_brdf_mutant",
        unit_parameters(cfg),
        rtl=mutants.build("brdf_unit_round_quarter", SIM_BUILD / "mutants"),
        sim=soak_sim(),
        build_root=SIM_BUILD / "vector_builds",
    )
    assert result.mismatch_count > 0, f"the mutant passed the soak (SOAK_SEED={seed})"
    assert {m[:14] for m in result.mismatches} == {"RESET_ALL = 0,", "RESET_ALL = 1,"}
    for text in result.mismatches:
        m = INTENSITY_MISMATCH.match(text)
        assert m, f"{text} (SOAK_SEED={seed})"
        cycle, got, want, valid, c, dz, z0, n, length, started = (int(v) for v in m.groups())
        assert got == want - 1, text
        values, n_err = brdf.unit_line(c, dz, z0, n, length, cfg)
        pixel = cycle - started - brdf.fill_latency(cfg) if valid else length
        assert n_err == 0 and 0 <= pixel <= length and values[pixel] == want, text


def test_soak_holds_reset_all_1_to_its_own_reset_values() -> None:
    """A divider whose RESET_ALL = 1 reset sets q to all ones fails the soak in the RESET_ALL = 1
    instance only, naming q = -1 (expected 0) in the first reset cycle: each instance is
    compared with its own prediction, and RESET_ALL = 0 leaves q undefined there."""
    cfg = divider.DEFAULT
    seed = soak_seed()
    result = soak.run_soak(
        cfg,
        5000,
        seed,
        SIM_BUILD / "soak_divider_reset_all_mutant",
        unit_parameters(cfg),
        rtl=mutants.build("divider_shift_reset_all_q", SIM_BUILD / "mutants"),
        build_root=SIM_BUILD / "vector_builds",
    )
    assert result.mismatch_count > 0, f"the mutant passed the soak (SOAK_SEED={seed})"
    assert all(m.startswith("RESET_ALL = 1, ") for m in result.mismatches), result.mismatches
    assert result.mismatches[0].startswith("RESET_ALL = 1, cycle 0: q = -1, expected 0 "), (
        result.mismatches[0]
    )
    assert all(": q = -1, expected 0 " in m for m in result.mismatches), result.mismatches
    alone = soak.run_soak(
        cfg,
        5000,
        seed,
        SIM_BUILD / "soak_divider_reset_all_mutant_0",
        {**unit_parameters(cfg), "RESET_MODES": 1},
        rtl=mutants.build("divider_shift_reset_all_q", SIM_BUILD / "mutants"),
        build_root=SIM_BUILD / "vector_builds",
    )
    assert alone.mismatch_count == 0, alone.mismatches  # the RESET_ALL = 0 instance alone


def test_soak_cycles_come_from_the_environment(monkeypatch) -> None:
    """SOAK_CYCLES=N gives every soak N cycles; unset, each keeps its own; a bad value is
    refused naming it."""
    monkeypatch.delenv("SOAK_CYCLES", raising=False)
    assert soak_cycles(1234) == 1234
    monkeypatch.setenv("SOAK_CYCLES", "50_000_000")
    assert soak_cycles(1234) == 50_000_000
    for bad in ("0", "-5", "lots"):
        monkeypatch.setenv("SOAK_CYCLES", bad)
        with pytest.raises(ValueError, match=f"SOAK_CYCLES='{bad}' is not allowed"):
            soak_cycles(1234)


def test_vector_words_round_trip() -> None:
    """The packing the Verilog benches decode: field order and widths, signed fields."""
    brdf_cfg = brdf.UNIT_CONFIGS["quadratic"]
    for cfg in (divider.DEFAULT, gouraud.DEFAULT, specular.DEFAULT, brdf_cfg):
        spec = soak.units.spec(cfg)
        fields = soak.stim_fields(spec)
        stim = soak.stimulus(cfg, 200, seed=7)
        for inputs in stim:
            word, mask = soak.pack(fields, inputs)
            assert mask == (1 << soak.width(fields)) - 1
            assert soak.unpack(fields, word) == inputs


@pytest.mark.parametrize("name", list(mutants.MUTANTS))
def test_every_mutant_is_one_change_to_the_current_rtl(name: str, tmp_path: Path) -> None:
    """A mutant differs from its RTL file in exactly the one marked line."""
    path = mutants.build(name, tmp_path)
    rtl = (soak.RTL_DIR / f"{mutants.MUTANTS[name].unit}.v").read_text().splitlines()
    got = path.read_text().splitlines()
    changed = [(a, b) for a, b in zip(rtl, got, strict=True) if a != b]
    assert len(changed) == 1 and "MUTANT" in changed[0][1], changed
