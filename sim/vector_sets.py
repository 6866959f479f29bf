# SPDX-License-Identifier: Apache-2.0
"""Take-away vector sets: stimulus and the model's responses, committed under sim/vectors/<set>/.

``make vectors`` (``python -m sim.vector_sets``) writes, for every set in ``SETS``, the soak's
constrained-random stimulus (sim/soak_stimulus.py, a fixed seed) and the protocol model's
prediction of every output in every cycle (sim/protocol.py, from the soak's kernels,
sim/soak_predict.py) as one binary vector file, with what a simulator needs to replay it
without Python:

* ``vectors.bin``: one binary record per cycle (sim/soak.py, ``write_vectors``): the stimulus
  word, then ``{mask, expect}`` of the RESET_ALL = 0 prediction, then of the RESET_ALL = 1
  prediction (``ProtocolModel(..., reset_all=True)``: data outputs 0 from a reset to the next
  result), each big-endian in whole bytes, read by ``$fread`` (sim/vectors/vector_loop.vh);
  the bench compares ``(got ^ expect) & mask`` with 0 in each instance with its own pair;
* ``params.txt``: ``UNIT <unit>`` then one ``NAME VALUE`` line per parameter of the bench
  ``sim/vectors/tb_<unit>.v`` (strings in double quotes; a ``"rom/..."`` path is relative to
  ``rtl/``), read by ``sim/vectors/replay.sh``;
* ``manifest.json``: the unit, its configuration and parameters, cycles, seed, the field layout
  of each word (MSB first), what the stimulus covers and how to replay.

``python -m sim.vector_sets --out DIR`` writes the sets elsewhere (tests/test_vectors.py
compares a fresh copy with the committed one, byte for byte).  The sets depend on the model
only: after a change of the model's timing (e.g. the specular unit's FILL_LATENCY) run
``make vectors`` again.

``write_stimulus`` writes a set of any length from the same generator into any folder (not
committed: ``python -m sim bench`` times a 200k-cycle one), and ``replay`` builds and runs a
set's bench under Icarus or ``verilator --binary`` as sim/vectors/replay.sh does
(sim/vector_run.py), the build and the run timed apart; ``load_time`` times a bench that only
reads the set's vector file as the replay does (``$fread``, 1024 records a call).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from model.units import brdf, divider, gouraud, specular
from model.units.gouraud import GouraudConfig
from sim import soak, soak_file, soak_predict, soak_stimulus, units, vector_run
from sim.runner import RTL_DIR, unit_parameters

VECTOR_DIR = soak.VECTOR_DIR
# The first seed tried; a set takes the first one from here on whose stimulus covers every
# corner of the protocol (an aborted job, back-to-back jobs, ...), recorded in its manifest.
SEED = 2026
DEFAULT_CYCLES = 3000
OTHER_CYCLES = 1500
FILES = ("vectors.bin", "params.txt", "manifest.json")

# Set name -> (configuration, cycles): every unit at its default configuration (the BRDF unit:
# each form with RTL at its default widths) and a few others.
SETS: dict[str, tuple[units.UnitConfig, int]] = {
    "divider_default": (divider.DEFAULT, DEFAULT_CYCLES),
    "divider_n4": (divider.ROM_CONFIGS["n4"], OTHER_CYCLES),
    "gouraud_default": (gouraud.DEFAULT, DEFAULT_CYCLES),
    "gouraud_p4": (GouraudConfig(p=4), OTHER_CYCLES),
    "gouraud_p16": (GouraudConfig(p=16), OTHER_CYCLES),
    "specular_default": (specular.DEFAULT, DEFAULT_CYCLES),
    "specular_narrow": (specular.NARROW, OTHER_CYCLES),
    "specular_up5k": (specular.UP5K, OTHER_CYCLES),
    "brdf_cosine_quadratic": (brdf.UNIT_CONFIGS["cosine_quadratic"], DEFAULT_CYCLES),
    "brdf_quadratic": (brdf.UNIT_CONFIGS["quadratic"], DEFAULT_CYCLES),
    "brdf_cubic": (brdf.UNIT_CONFIGS["cubic"], DEFAULT_CYCLES),
    "brdf_log2": (brdf.UNIT_CONFIGS["log2"], DEFAULT_CYCLES),
    "brdf_piecewise": (brdf.UNIT_CONFIGS["piecewise"], DEFAULT_CYCLES),
}


def bench_parameters(cfg: units.UnitConfig) -> dict[str, int | str]:
    """The bench's parameters for ``cfg``; ROM images as ``rom/<file>`` (relative to rtl/)."""
    out: dict[str, int | str] = {}
    for key, value in unit_parameters(cfg).items():
        if isinstance(value, str | Path) and key.endswith("ROM_FILE"):
            path = Path(value)
            if path.parent.resolve() != (RTL_DIR / "rom").resolve():
                raise ValueError(f"{key} = {value} is not a committed image under rtl/rom")
            out[key] = f"rom/{path.name}"
        elif isinstance(value, str | Path):
            out[key] = str(value)
        else:
            out[key] = int(value)
    return out


def _fields(fields: list[tuple[str, soak.Port]]) -> list[str]:
    """Each field as ``name[msb:lsb]`` of the word (``signed``: two's complement)."""
    out, lsb = [], soak.width(fields)
    for name, port in fields:
        lsb -= port.width
        out.append(f"{name}[{lsb + port.width - 1}:{lsb}]" + (" signed" if port.signed else ""))
    return out


def covers(stats: soak.Stats) -> bool:
    """The stimulus reached every corner of the protocol (as the soak requires)."""
    s = stats
    return (
        s.results_compared > 0
        and s.jobs_aborted > 0
        and s.back_to_back > 0
        and s.writes_at_start > 0
        and s.writes_ignored > 0
        and s.starts_ignored > 0
    )


def covering_stimulus(
    cfg: units.UnitConfig, cycles: int
) -> tuple[int, soak_stimulus.Stimulus, soak_predict.Prediction]:
    """The stimulus of the first seed from SEED on whose run covers every corner (``covers``)."""
    for seed in range(SEED, SEED + 50):
        stim = soak_stimulus.stimulus(cfg, cycles, seed)
        pred = soak_predict.predict(cfg, stim)
        if covers(pred.stats):
            return seed, stim, pred
    raise RuntimeError(f"no seed from {SEED} on covers the protocol in {cycles} cycles")


def manifest(name: str, cfg: units.UnitConfig, cycles: int, seed: int, stats: dict) -> dict:
    spec = units.spec(cfg)
    sf, of = soak.stim_fields(spec), soak.out_fields(spec)
    sb, ob = soak.record_bytes(spec)
    params = bench_parameters(cfg)
    return {
        "set": name,
        "unit": spec.toplevel,
        "bench": f"sim/vectors/tb_{spec.toplevel}.v",
        "rtl": f"rtl/{spec.toplevel}.f",
        "config": {"type": type(cfg).__name__, **asdict(cfg)},
        "parameters": params,
        "reset_all": [0, 1],
        "cycles": cycles,
        "seed": seed,
        "stimulus": f"sim/soak.py stimulus(cfg, {cycles}, seed={seed})",
        "files": {
            "vectors": {
                "file": "vectors.bin",
                "record_bytes": sb + 2 * ob,
                "layout": (
                    f"one record per cycle, read by $fread: the stimulus word in {sb} bytes, then "
                    f"{{mask, expect}} of the RESET_ALL = 0 instance in {ob} bytes "
                    f"({soak.width(of)} bits each), then {{mask, expect}} of the RESET_ALL = 1 "
                    f"instance in {ob} bytes, each big-endian and right-aligned"
                ),
            },
            "stim": {"bits": soak.width(sf), "fields": _fields(sf)},
            "expect": {"bits": soak.width(of), "fields": _fields(of)},
            "mask": {
                "bits": soak.width(of),
                "fields": (
                    "as expect: 1 = compare the bit, 0 = the output is undefined there (with "
                    "RESET_ALL = 0: the data outputs from a reset to the next result)"
                ),
            },
        },
        "timing": (
            "cycle i: drive stim[i], a rising clock edge 5 ns later, compare the outputs 5 ns "
            "after it (clock period 10 ns)"
        ),
        "coverage": stats,
        "replay": [
            f"sim/vectors/replay.sh {name} icarus",
            f"sim/vectors/replay.sh {name} verilator",
        ],
        "generated_by": "make vectors (python -m sim.vector_sets), from the model",
    }


def params_text(cfg: units.UnitConfig, cycles: int) -> str:
    spec = units.spec(cfg)
    lines = [
        f"# Parameters of sim/vectors/tb_{spec.toplevel}.v for this set (sim/vectors/replay.sh).",
        '# NAME VALUE; a string in double quotes, "rom/..." relative to rtl/ (make vectors).',
        f"UNIT {spec.toplevel}",
    ]
    for key, value in {**bench_parameters(cfg), "CYCLES": cycles}.items():
        lines.append(f'{key} "{value}"' if isinstance(value, str) else f"{key} {value}")
    return "\n".join(lines) + "\n"


def write_set(name: str, out_dir: Path) -> Path:
    """Write set ``name`` into ``out_dir/<name>/``; returns that folder."""
    cfg, cycles = SETS[name]
    folder = out_dir / name
    if folder.exists():
        shutil.rmtree(folder)
    seed, stim, pred = covering_stimulus(cfg, cycles)
    folder.mkdir(parents=True)
    soak_file.write_vector_file(cfg, stim, pred, folder / "vectors.bin")
    stats = {k: v for k, v in asdict(pred.stats).items() if k != "errors"}
    (folder / "params.txt").write_text(params_text(cfg, cycles))
    text = json.dumps(manifest(name, cfg, cycles, seed, stats), indent=2) + "\n"
    (folder / "manifest.json").write_text(text)
    return folder


def write_stimulus(
    cfg: units.UnitConfig,
    cycles: int,
    seed: int,
    folder: Path,
    seconds: dict[str, float] | None = None,
) -> soak.Stats:
    """A set of ``cycles`` cycles of the soak's stimulus for ``seed`` (not committed) in
    ``folder``: vectors.bin and params.txt; returns what the stimulus covers.  ``seconds``, if
    given, receives the CPU seconds of each step: stimulus, predict, write."""
    folder.mkdir(parents=True, exist_ok=True)
    t0 = time.process_time()
    stim = soak_stimulus.stimulus(cfg, cycles, seed)
    t1 = time.process_time()
    pred = soak_predict.predict(cfg, stim)
    t2 = time.process_time()
    soak_file.write_vector_file(cfg, stim, pred, folder / "vectors.bin")
    (folder / "params.txt").write_text(params_text(cfg, cycles))
    if seconds is not None:
        seconds.update(stimulus=t1 - t0, predict=t2 - t1, write=time.process_time() - t2)
    return pred.stats


@dataclass
class Replay:
    """One timed replay of a set: its bench built and run under ``sim``."""

    sim: str
    cycles: int
    mismatches: int  # -1: the bench did not finish
    passed: bool
    build_s: float
    run_s: float  # wall seconds of the fastest run
    log: str
    load_s: float = 0.0  # of run_s: reading the vector file alone (``load_time``)
    run_cpu_s: float = 0.0  # CPU seconds of the simulator process in the fastest run
    build_cached: bool = False


def set_parameters(set_dir: Path) -> tuple[str, dict[str, str]]:
    """(unit, NAME -> Verilog value text) of a set's params.txt, ROM paths made absolute."""
    unit, params = "", {}
    for line in (set_dir / "params.txt").read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        name, value = line.split(None, 1)
        if name == "UNIT":
            unit = value
        else:
            rom = value.startswith('"rom/')
            params[name] = f'"{RTL_DIR / value[1:-1]}"' if rom else value
    if not unit:
        raise ValueError(f"{set_dir / 'params.txt'} names no UNIT")
    return unit, params


def replay(
    set_dir: Path,
    sim: str,
    build: Path,
    timeout: float = 3600,
    repeats: int = 1,
    cache: bool = True,
) -> Replay:
    """Build the bench of set ``set_dir`` under ``sim`` (icarus or verilator, as
    sim/vectors/replay.sh: both RESET_ALL instances) in ``build`` (sim/vector_run.py: a build
    of the same configuration there is reused), run it ``repeats`` times; the build and the
    fastest run timed apart."""
    unit, params = set_parameters(set_dir)
    cycles = int(params.pop("CYCLES"))
    b = vector_run.build(unit, params, sim, build, cache=cache, timeout=timeout)
    if not b.ok:
        return Replay(sim, cycles, -1, False, b.seconds, 0.0, b.log)
    best = None
    for _ in range(repeats):  # the fastest of ``repeats`` runs (a run's output is the same)
        ran = vector_run.run(b, set_dir / "vectors.bin", cycles, timeout=timeout)
        if best is None or ran.wall_s < best.wall_s:
            best = ran
    assert best is not None
    return Replay(
        sim,
        cycles,
        best.mismatches,
        best.passed,
        b.seconds,
        best.wall_s,
        b.log + best.log,
        run_cpu_s=best.cpu_s,
        build_cached=b.cached,
    )


def load_time(
    set_dir: Path, sim: str, build: Path, timeout: float = 3600, repeats: int = 1
) -> float:
    """Wall seconds a bench that only reads the vector file of ``set_dir`` (``$fread``, 1024
    records a call, as the replay does; no unit, no clock) runs under ``sim`` (fastest of
    ``repeats`` runs): the replay's file-reading share."""
    _, params = set_parameters(set_dir)
    spec_bytes = (set_dir / "vectors.bin").stat().st_size // int(params["CYCLES"])
    cycles = int(params["CYCLES"])
    text = f"""module tb_load;
reg [{8 * spec_bytes - 1}:0] chunk [0:1023];
integer fd, i, total;
initial begin
    fd = $fopen("{set_dir / "vectors.bin"}", "rb");
    total = 0;
    for (i = 0; i < {cycles}; i = i + 1024) begin
        total = total + $fread(chunk, fd, 0, ({cycles} - i < 1024) ? {cycles} - i : 1024);
    end
    $display("read %0d bytes", total);
    $finish;
end
endmodule
"""
    build.mkdir(parents=True, exist_ok=True)
    (build / "tb_load.v").write_text(text)
    if sim == "icarus":
        cmd = ["iverilog", "-g2005", "-o", str(build / "tb_load.vvp"), str(build / "tb_load.v")]
        run = ["vvp", "-n", str(build / "tb_load.vvp")]
    else:
        obj = build / "obj_tb_load"
        cmd = ["verilator", "--binary", "-j", vector_run.BUILD_JOBS, *vector_run.VERILATOR_FLAGS]
        cmd += ["-Mdir", str(obj), str(build / "tb_load.v")]
        run = [str(obj / "Vtb_load")]
    built = subprocess.run(cmd, capture_output=True, text=True, cwd=build, timeout=timeout)
    if built.returncode != 0:
        raise RuntimeError(f"{sim} could not build the file-reading bench:\n{built.stderr}")
    best = float("inf")
    for _ in range(repeats):
        t0 = time.monotonic()
        subprocess.run(run, capture_output=True, text=True, cwd=build, timeout=timeout, check=True)
        best = min(best, time.monotonic() - t0)
    return best


def write_all(out_dir: Path = VECTOR_DIR, names: list[str] | None = None) -> list[Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    if names is None and out_dir == VECTOR_DIR:
        # a set no longer in SETS goes
        for old in out_dir.iterdir():
            if (old / "manifest.json").exists() and old.name not in SETS:
                shutil.rmtree(old)
    return [write_set(name, out_dir) for name in (names or list(SETS))]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m sim.vector_sets",
        description="Write the committed vector sets (sim/vectors/<set>/) from the model.",
    )
    parser.add_argument(
        "--out", type=Path, default=VECTOR_DIR, help="folder (default: %(default)s)"
    )
    parser.add_argument("sets", nargs="*", help=f"sets (default: all of {', '.join(SETS)})")
    args = parser.parse_args(argv)
    unknown = [s for s in args.sets if s not in SETS]
    if unknown:
        parser.error(f"no set {', '.join(unknown)}: legal are {', '.join(SETS)}")
    total = 0
    for folder in write_all(args.out.resolve(), args.sets or None):
        size = sum((folder / f).stat().st_size for f in FILES)
        total += size
        print(f"{folder}: {SETS[folder.name][1]} cycles, {size / 1024:.0f} kB")
    print(f"{total / 1024:.0f} kB in all")
    return 0


if __name__ == "__main__":
    sys.exit(main())
