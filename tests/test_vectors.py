# SPDX-License-Identifier: Apache-2.0
"""The committed vector sets (sim/vectors/<set>/, make vectors) and their Python-free replay.

* every committed set equals what the model writes now, byte for byte (a stale set fails);
* every set replays clean under Icarus through sim/vectors/replay.sh, and each unit's default
  set under Verilator (one Verilator build per unit; the BRDF unit's cosine-quadratic form):
  both RESET_ALL instances, every cycle;
* the bench fails loudly: a corrupted expected word gives a MISMATCH line naming its cycle and
  a non-zero exit under both simulators; a short file is refused;
* the vector mode of ``python -m sim bench``: a generated stimulus (``write_stimulus``)
  replays clean through ``vector_sets.replay`` under both simulators, timed, and a flipped
  expected bit fails it (and the bench's exit status); no speed is asserted (a benchmark).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
from pathlib import Path

import pytest

from model.units import brdf, divider, gouraud
from sim import soak, units, vector_sets
from sim.__main__ import vector_bench

pytestmark = pytest.mark.sim

REPLAY = vector_sets.VECTOR_DIR / "replay.sh"
DONE = re.compile(r"^VECTORS (\d+) cycles (\d+) mismatches$", re.M)


def replay(set_dir: str | Path, tool: str, build: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(REPLAY), str(set_dir), tool],
        capture_output=True,
        text=True,
        env={**os.environ, "REPLAY_BUILD": str(build)},
        timeout=600,
    )


def assert_clean(ran: subprocess.CompletedProcess, cycles: int) -> None:
    log = ran.stdout + ran.stderr
    assert ran.returncode == 0, log
    done = DONE.search(log)
    assert done and int(done.group(1)) == cycles and done.group(2) == "0", log
    assert re.search(r"^PASS .*RESET_ALL = 0 and 1 compared", log, re.M), log
    assert "MISMATCH" not in log, log


def test_committed_sets_are_current(tmp_path: Path) -> None:
    """make vectors now writes exactly the committed files (run it after a model change)."""
    vector_sets.write_all(tmp_path)
    committed = sorted(p.parent.name for p in vector_sets.VECTOR_DIR.glob("*/manifest.json"))
    assert committed == sorted(vector_sets.SETS), "run make vectors: the sets differ from SETS"
    stale = []
    for name in vector_sets.SETS:
        for f in vector_sets.FILES:
            if (vector_sets.VECTOR_DIR / name / f).read_bytes() != (
                tmp_path / name / f
            ).read_bytes():
                stale.append(f"{name}/{f}")
    assert not stale, f"stale vector files (run make vectors): {stale}"


def test_sets_are_small_and_cover_the_protocol() -> None:
    total = 0
    for name, (_, cycles) in vector_sets.SETS.items():
        folder = vector_sets.VECTOR_DIR / name
        total += sum((folder / f).stat().st_size for f in vector_sets.FILES)
        manifest = json.loads((folder / "manifest.json").read_text())
        assert manifest["cycles"] == cycles and manifest["seed"] >= vector_sets.SEED
        size = soak.record_size(units.spec(vector_sets.SETS[name][0]))
        assert (folder / "vectors.bin").stat().st_size == cycles * size, name
        c = manifest["coverage"]
        assert c["results_compared"] > 0 and c["jobs_aborted"] > 0 and c["back_to_back"] > 0, c
        assert c["writes_at_start"] > 0 and c["starts_ignored"] > 0, c
    assert total < 1_000_000, f"the vector sets take {total} bytes"


@pytest.mark.parametrize("name", list(vector_sets.SETS))
def test_replay_icarus(name: str, tmp_path: Path) -> None:
    assert_clean(replay(name, "icarus", tmp_path), vector_sets.SETS[name][1])


@pytest.mark.parametrize(
    "name", ["divider_default", "gouraud_default", "specular_default", "brdf_cosine_quadratic"]
)
def test_replay_verilator(name: str, tmp_path: Path) -> None:
    assert_clean(replay(name, "verilator", tmp_path), vector_sets.SETS[name][1])


def corrupt(src: Path, dst: Path, cfg=None) -> int:
    """A copy of set ``src`` in ``dst`` with one compared bit flipped in both instances' expected
    words (bit 0 of the first cycle from the middle on whose masks compare it); returns that
    cycle."""
    dst.mkdir()
    for f in vector_sets.FILES:
        if (src / f).exists():  # a generated set (write_stimulus) has no manifest
            (dst / f).write_bytes((src / f).read_bytes())
    spec = units.spec(cfg or vector_sets.SETS[src.name][0])
    records = soak.read_vectors(spec, dst / "vectors.bin")
    half = len(records) // 2
    cycle = next(i for i in range(half, len(records)) if records[i][2] & records[i][4] & 1)
    data = bytearray((dst / "vectors.bin").read_bytes())
    size, pair = soak.record_size(spec), soak.record_bytes(spec)[1]
    data[(cycle + 1) * size - 1] ^= 1  # RESET_ALL = 1's expect bit 0: the record's last bit
    data[(cycle + 1) * size - 1 - pair] ^= 1  # RESET_ALL = 0's: the last of the pair before
    (dst / "vectors.bin").write_bytes(bytes(data))
    got = soak.read_vectors(spec, dst / "vectors.bin")[cycle]
    assert got[1] == records[cycle][1] ^ 1 and got[3] == records[cycle][3] ^ 1
    return cycle


@pytest.mark.parametrize("tool", ["icarus", "verilator"])
def test_a_wrong_expected_word_fails_loudly(tool: str, tmp_path: Path) -> None:
    cycle = corrupt(vector_sets.VECTOR_DIR / "divider_n4", tmp_path / "bad")
    ran = replay(tmp_path / "bad", tool, tmp_path / "build")
    log = ran.stdout + ran.stderr
    assert ran.returncode != 0, log
    for r in (0, 1):
        assert re.search(
            rf"^MISMATCH cycle {cycle} RESET_ALL={r} got \w+ expected \w+ mask \w+$", log, re.M
        ), log
    assert re.search(r"^FAIL .*2 mismatches", log, re.M), log


def test_a_short_long_or_padded_file_is_refused(tmp_path: Path) -> None:
    bad = tmp_path / "short"
    bad.mkdir()
    src = vector_sets.VECTOR_DIR / "divider_n4"
    for f in vector_sets.FILES:
        (bad / f).write_bytes((src / f).read_bytes())
    data = (bad / "vectors.bin").read_bytes()
    size = len(data) // vector_sets.SETS["divider_n4"][1]
    (bad / "vectors.bin").write_bytes(data[: -5 * size])
    ran = replay(bad, "icarus", tmp_path / "build")
    assert ran.returncode != 0 and "has fewer than CYCLES" in ran.stdout, ran.stdout + ran.stderr
    (bad / "vectors.bin").write_bytes(data + data[:size])
    ran = replay(bad, "icarus", tmp_path / "build2")
    assert ran.returncode != 0 and "has more than CYCLES" in ran.stdout, ran.stdout + ran.stderr
    # the divider_n4 stimulus word is 18 bits: the top 6 bits of its 3 bytes pad it
    padded = bytearray(data)
    padded[7 * size] |= 0x80
    (bad / "vectors.bin").write_bytes(bytes(padded))
    ran = replay(bad, "icarus", tmp_path / "build3")
    assert ran.returncode != 0 and "record 7 of" in ran.stdout, ran.stdout + ran.stderr


@pytest.mark.parametrize("tool", ["icarus", "verilator"])
def test_timed_replay_of_a_generated_stimulus(tool: str, tmp_path: Path) -> None:
    """The vector mode's replay: a tiny generated stimulus passes, timed; one flipped expected
    bit fails it with both instances' MISMATCH lines."""
    stats = vector_sets.write_stimulus(divider.ROM_CONFIGS["n4"], 400, 7, tmp_path / "set")
    assert stats.results_compared > 0
    run = vector_sets.replay(tmp_path / "set", tool, tmp_path / "build")
    assert run.passed and run.mismatches == 0 and run.cycles == 400, run.log
    assert run.build_s > 0 and run.run_s > 0
    assert vector_sets.load_time(tmp_path / "set", tool, tmp_path / "load") > 0
    cycle = corrupt(tmp_path / "set", tmp_path / "bad", divider.ROM_CONFIGS["n4"])
    bad = vector_sets.replay(tmp_path / "bad", tool, tmp_path / "build_bad")
    assert not bad.passed and bad.mismatches == 2, bad.log
    assert f"MISMATCH cycle {cycle} RESET_ALL=1" in bad.log, bad.log


def test_vector_mode_table_and_failure(monkeypatch, capsys) -> None:
    """``vector_bench`` prints one row per unit and simulator and exits 0; a flipped expected
    bit in one unit's stimulus makes it print FAIL and exit 1."""
    assert vector_bench(200, sims=("icarus",)) == 0
    out = capsys.readouterr().out
    forms = [f"brdf_{form}" for form in brdf.UNIT_CONFIGS]
    for unit in ("divider_shift", "gouraud_segment", "specular_unit", *forms):
        assert re.search(rf"^{unit} +icarus +200 +\d+ ", out, re.M), out
        assert re.search(rf"^{unit} +[\d,]+ +[\d,]+ +[\d,]+ +[\d,]+ ", out, re.M), out
    write = vector_sets.write_stimulus

    def flipped(cfg, cycles, seed, folder, seconds=None):
        stats = write(cfg, cycles, seed, folder, seconds)
        if isinstance(cfg, gouraud.GouraudConfig):
            corrupt(folder, folder.with_name("flipped"), cfg)
            (folder / "vectors.bin").write_bytes(
                (folder.with_name("flipped") / "vectors.bin").read_bytes()
            )
        return stats

    monkeypatch.setattr(vector_sets, "write_stimulus", flipped)
    assert vector_bench(200, sims=("icarus",)) == 1
    out = capsys.readouterr().out
    assert "FAIL gouraud_segment under icarus" in out and "vector mode FAILED" in out, out
