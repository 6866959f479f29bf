# SPDX-License-Identifier: Apache-2.0
"""The runs of ``make coverage`` (sim/coverage.py): what each unit replays (``plan``), the
Verilator builds with line and toggle coverage (``build``: PATH's Verilator, the bench's loop
in a main that writes the coverage file at the end, the runtime library compiled once;
cached by content in ``sim_build/coverage_builds/``), and the replays, each checked as the
soaks check it (every output compared in every cycle; the core's pixel beats against its
model) before its coverage file counts (``run_plan``).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import threading
from collections import defaultdict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from model.hw.sources import source_list
from model.render import core
from model.render.pipeline import METHODS, PipelineConfig
from model.units import brdf, divider, gouraud, specular
from sim import core_run, soak, units, vector_run, vector_sets
from sim.runner import SIM_BUILD, unit_parameters

UNITS = ("divider_shift", "gouraud_segment", "specular_unit", "brdf_unit", "shading_core")
BUILDS = SIM_BUILD / "coverage_builds"
COVER_FLAGS = ("--coverage-line", "--coverage-toggle")
FLAGS = ("--x-assign", "fast", "--x-initial", "fast", "-Wno-fatal", "-Wno-lint", "-Wno-style")
# C++ unoptimised, two jobs: the benches run in seconds, the build is what costs.
MAKE_VARS = ("OPT_FAST=-O0", "OPT_SLOW=-O0", "OPT_GLOBAL=-O0")
RUNTIME = ("verilated.o", "verilated_cov.o", "verilated_timing.o", "verilated_threads.o")
SOAK_SEED = 1
# The BRDF unit's soaks: the form it defaults to (rtl/brdf_unit.v FORM = "cosine_quadratic")
# deep; the piecewise form 80k, not 20k: only n = 3..6 set b1's bits 12 and 10 (the soak draws
# such an n about once in 500 writes), and at 20k cycles they never fell; the others 20k.
BRDF_SOAKS = {"cosine_quadratic": 350_000, "piecewise": 80_000}
CORE_SEED = 7

# The bench's main: verilator --binary's loop, then the coverage file (+COVERAGE_FILE=).
MAIN = """\
#include "verilated.h"
#include "verilated_cov.h"
#include "V{top}.h"
#include <memory>
#include <string>
int main(int argc, char** argv, char**) {{
    const std::unique_ptr<VerilatedContext> contextp{{new VerilatedContext}};
    contextp->commandArgs(argc, argv);
    const std::unique_ptr<V{top}> topp{{new V{top}{{contextp.get()}}}};
    while (!contextp->gotFinish()) {{
        topp->eval();
        if (!topp->eventsPending()) break;
        contextp->time(topp->nextTimeSlot());
    }}
    topp->final();
    std::string file = "coverage.dat";
    const char* arg = contextp->commandArgsPlusMatch("COVERAGE_FILE=");
    if (arg && arg[0]) file = std::string(arg).substr(std::string("+COVERAGE_FILE=").size());
    contextp->coveragep()->write(file.c_str());
    return contextp->gotFinish() ? 0 : 1;
}}
"""


@dataclass(frozen=True)
class Replay:
    """A unit's vector bench on a committed set (``cycles`` 0) or on a soak of ``cycles``."""

    name: str
    config: str  # the configuration's name (toggle points are per configuration)
    cfg: units.UnitConfig
    cycles: int = 0


@dataclass(frozen=True)
class CoreReplay:
    """The core's stream bench on span beats: the committed set (``spans`` 0) or random ones."""

    name: str
    config: str
    cfg: PipelineConfig
    spans: int = 0
    idle_pct: int = 0
    stall_pct: int = 0


def plan(unit: str) -> list[Replay | CoreReplay]:
    """Every run of ``unit``: its committed vector sets, then soaks of the configurations
    tests/test_soak.py soaks (the default configuration deep, the others 20k cycles; the BRDF
    unit's piecewise form 80k, ``BRDF_SOAKS``)."""
    if unit == "shading_core":
        out: list[Replay | CoreReplay] = [
            CoreReplay("core_default", "default", METHODS["diffuse"]),
            CoreReplay("core_default_soak", "default", METHODS["diffuse"], 3000, 20, 30),
        ]
        out += [
            CoreReplay(f"core_{k}", k, c, 1000, 20, 30)
            for k, c in core_run.shipped_configs().items()
        ]
        return out
    sets = [Replay(n, n.split("_", 1)[1], cfg) for n, (cfg, _) in vector_sets.SETS.items()]
    soaks = {
        "divider_shift": [
            Replay("divider_default_soak", "default", divider.DEFAULT, 150_000),
            Replay("divider_article_soak", "article", divider.ROM_CONFIGS["article"], 20_000),
            Replay("divider_n4_soak", "n4", divider.ROM_CONFIGS["n4"], 20_000),
        ],
        "gouraud_segment": [
            Replay("gouraud_default_soak", "default", gouraud.DEFAULT, 350_000),
            Replay("gouraud_p2_f4_soak", "p2_f4", gouraud.GouraudConfig(p=2, i_frac=4), 20_000),
            Replay("gouraud_p16_soak", "p16", gouraud.GouraudConfig(p=16), 20_000),
        ],
        "specular_unit": [
            Replay("specular_default_soak", "default", specular.DEFAULT, 350_000),
            Replay("specular_narrow_soak", "narrow", specular.NARROW, 20_000),
            Replay("specular_inflection_soak", "inflection", specular.INFLECTION, 20_000),
            Replay("specular_kept_soak", "kept", specular.KEPT, 20_000),
            Replay("specular_up5k_soak", "up5k", specular.UP5K, 20_000),
        ],
        # a configuration is a form (the committed sets brdf_<form> name the same ones)
        "brdf_unit": [
            Replay(f"brdf_{form}_soak", form, cfg, BRDF_SOAKS.get(form, 20_000))
            for form, cfg in brdf.UNIT_CONFIGS.items()
        ],
    }[unit]
    return [r for r in sets if units.spec(r.cfg).toplevel == unit] + soaks


# ------------------------------------------------------------------------------ builds
_locks: dict[str, threading.Lock] = defaultdict(threading.Lock)
_locks_lock = threading.Lock()


def _lock(folder: Path) -> threading.Lock:
    with _locks_lock:
        return _locks[str(folder)]


def runtime_objects(root: Path = BUILDS) -> Path:
    """Verilator's runtime library compiled with coverage, once per Verilator version."""
    digest = hashlib.sha256(repr((vector_run.tool_version("verilator"), COVER_FLAGS)).encode())
    folder = root / f"runtime_{digest.hexdigest()[:16]}"
    with _lock(folder):
        if not (folder / "ok").exists():
            _compile_runtime(folder, root)
    return folder


def _compile_runtime(folder: Path, root: Path) -> None:
    work = root / f"{folder.name}.{os.getpid()}.tmp"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    (work / "tb_runtime.v").write_text("module tb_runtime;\ninitial #1 $finish;\nendmodule\n")
    cmd = ["verilator", "--cc", "--exe", "--timing", *COVER_FLAGS, "-Mdir", "obj", "tb_runtime.v"]
    subprocess.run([*cmd, "--main"], check=True, capture_output=True, cwd=work, timeout=600)
    make = ["make", "-j", vector_run.BUILD_JOBS, "-C", "obj", "-f", "Vtb_runtime.mk", *RUNTIME]
    subprocess.run(make, check=True, capture_output=True, cwd=work, timeout=600)
    (work / "obj" / "ok").write_text("verilator runtime objects with coverage\n")
    if not (folder / "ok").exists():
        shutil.rmtree(folder, ignore_errors=True)
        (work / "obj").rename(folder)
    shutil.rmtree(work, ignore_errors=True)


def build(top: str, params: dict[str, str], sources: list[Path], root: Path = BUILDS) -> Path:
    """The coverage build of bench ``top`` on ``sources`` with ``params`` (Verilog value text):
    the executable, cached by the sources, the parameters, the flags and the tool's version."""
    common = [f"-I{vector_run.VECTOR_DIR}", f'-DSHADING_ROM_DIR="{vector_run.RTL_DIR / "rom"}"']
    digest = hashlib.sha256(vector_run.tool_version("verilator").encode())
    for path in [*sources, vector_run.VECTOR_DIR / "vector_loop.vh"]:
        digest.update(path.read_bytes())
    digest.update(repr((sorted(params.items()), common, COVER_FLAGS, FLAGS, MAIN)).encode())
    folder = root / f"{top}_{digest.hexdigest()[:16]}"
    with _lock(folder):
        return _build(top, folder, params, sources, common, root)


def _build(
    top: str, folder: Path, params: dict[str, str], sources: list[Path], common: list[str],
    root: Path,
) -> Path:  # fmt: skip
    exe = folder / "obj" / f"V{top}"
    if (folder / "built.ok").exists() and exe.exists():
        return exe
    objects = runtime_objects(root)
    shutil.rmtree(folder, ignore_errors=True)
    (folder / "obj").mkdir(parents=True)
    main = folder / "main.cpp"
    main.write_text(MAIN.format(top=top))
    cmd = ["verilator", "--cc", "--exe", "--timing", *COVER_FLAGS, *FLAGS, "--top-module", top]
    cmd += ["-Mdir", str(folder / "obj"), *common, *(f"-G{k}={v}" for k, v in params.items())]
    cmd += [*(str(s) for s in sources), str(main)]
    made = subprocess.run(cmd, capture_output=True, text=True, cwd=folder, timeout=1800)
    if made.returncode == 0:
        for name in RUNTIME:
            shutil.copy2(objects / name, folder / "obj" / name)
            os.utime(folder / "obj" / name)
        make = ["make", "-j", vector_run.BUILD_JOBS, "-C", str(folder / "obj"), "-f", f"V{top}.mk"]
        make += list(MAKE_VARS)
        made = subprocess.run(make, capture_output=True, text=True, timeout=1800)
    if made.returncode != 0 or not exe.exists():
        raise RuntimeError(
            f"verilator could not build {top} with coverage:\n{made.stdout}{made.stderr}"
        )
    (folder / "built.ok").write_text(" ".join(cmd) + "\n")
    return exe


# ------------------------------------------------------------------------------ runs
def _run(exe: Path, args: list[str], dat: Path) -> str:
    dat.unlink(missing_ok=True)
    ran = subprocess.run(
        [str(exe), *args, f"+COVERAGE_FILE={dat}"],
        capture_output=True,
        text=True,
        cwd=exe.parent.parent,
        timeout=3600,
    )
    log = ran.stdout + ran.stderr
    if ran.returncode != 0 or not dat.exists():
        raise RuntimeError(f"{exe.name} {' '.join(args)} failed (exit {ran.returncode}):\n{log}")
    return log


def run_unit_replay(r: Replay, work: Path) -> tuple[Path, str]:
    """Replay ``r`` through the unit's coverage build: (the coverage file, a summary line)."""
    spec = units.spec(r.cfg)
    params = soak.verilog_parameters(unit_parameters(r.cfg))
    top = f"tb_{spec.toplevel}"
    sources = [vector_run.VECTOR_DIR / f"{top}.v", *source_list(spec.toplevel, vector_run.RTL_DIR)]
    exe = build(top, params, sources)
    if r.cycles:
        # the soak's own path: stimulus, both RESET_ALL predictions, the vector file
        vectors = work / f"{r.name}.bin"
        soak.write_segment(r.cfg, r.cycles, SOAK_SEED, 0, vectors)
        cycles, what = r.cycles, f"soak seed {SOAK_SEED}"
    else:
        vectors = vector_sets.VECTOR_DIR / r.name / "vectors.bin"
        cycles, what = vector_sets.SETS[r.name][1], "committed set"
    dat = work / f"{r.name}.dat"
    log = _run(exe, [f"+VECTOR_FILE={vectors}", f"+CYCLES={cycles}"], dat)
    done = vector_run.DONE.search(log)
    if done is None or int(done.group(1)) != cycles or int(done.group(2)) != 0:
        raise RuntimeError(f"{r.name}: the bench did not pass its {cycles} cycles:\n{log}")
    return dat, f"{r.name}: {what}, {cycles} cycles, 0 mismatches"


def core_words(r: CoreReplay) -> list[int]:
    """``r.spans`` random span beats (``core_run.random_spans``: every field random in its
    range, 1 to 23 pixels; with a BRDF highlight half of them lit, its values in most pixels),
    then n set: at the decoder's and the kept range's edges in the first beats, inside the kept
    range in a third of the others with the specular unit's highlight (a uniform n in 0..1023
    hits a small table or a short kept range a few times in a thousand); with a BRDF highlight
    one span of it at full scale (n = 1, angle 0) times the largest C; and full-scale ramps,
    down in some channels and up in the others, of 24 lengths up to the longest span."""
    fmt = core.SpanFormat(r.cfg)
    layout, s, g = fmt.layout(), r.cfg.specular, r.cfg.gouraud
    rng = np.random.default_rng(CORE_SEED)
    lengths = rng.integers(1, 24, r.spans)
    lengths[[0, r.spans // 2]] = g.len_max
    brdf = r.cfg.brdf is not None
    words = core_run.random_spans(fmt, lengths, CORE_SEED, lit=0.5 if brdf else 0.0)
    edges = sorted({0, 1, *s.n_hi, *(h + 1 for h in s.n_hi), s.n_first - 1, s.n_first})
    edges = [n for n in {*edges, s.n_last, s.n_last + 1, (1 << core.N_WIDTH) - 1} if n >= 0]
    top = (1 << g.i_width) - 1
    out = []
    for i, word in enumerate(words):
        row = core.unpack(layout, word)
        if i < len(edges):
            row["n"] = sorted(edges)[i]
        elif not brdf and rng.random() < 1 / 3:
            row["n"] = int(rng.integers(s.n_first, s.n_last + 1))
        out.append(core.pack(layout, row))
    if brdf:
        # the highlight at full scale (n = 1 at angle 0: the form's 2^O - 1) times the largest
        # C: C x F's rounding carries out and the intensity saturates (the ramps after it
        # bring the carry down again)
        row = core.unpack(layout, words[0])
        row.update(l=3, spec=1, n=1, z0=0, dz=0, c=(1 << s.c_width) - 1)
        out.append(core.pack(layout, row))
    for i, pixels in enumerate(sorted({int(v) for v in np.linspace(2, g.len_max, 24)})):
        row = core.unpack(layout, words[i % len(words)])
        row["l"] = pixels - 1
        for c in range(core.CHANNELS):
            down = (c + i) % 2 == 0
            row[f"i_start{c}"], row[f"i_end{c}"] = (top, 0) if down else (0, top)
        out.append(core.pack(layout, row))
    return out


def run_core_replay(r: CoreReplay, work: Path) -> tuple[Path, str]:
    """Span beats through the core's coverage build, every pixel beat compared with the model."""
    fmt = core.SpanFormat(r.cfg)
    params = core_run.parameters(r.cfg, work / f"{r.name}_roms")
    sources = [core_run.BENCH, *source_list("shading_core", vector_run.RTL_DIR)]
    exe = build("tb_shading_core", soak.verilog_parameters(params), sources)
    words = core_words(r) if r.spans else core_run.vector_set_words(r.cfg)
    want = core.core_pixels(words, fmt, bool(params["SPECULAR"]), bool(params["DIFFUSE"]))
    span_file, out_file = work / f"{r.name}.spans.hex", work / f"{r.name}.pixels.hex"
    span_file.write_text("".join(f"{w:0{-(-fmt.width // 4)}x}\n" for w in words))
    args = [
        f"+SPAN_FILE={span_file}", f"+OUT_FILE={out_file}", f"+SPANS={len(words)}",
        f"+PIXELS={len(want)}", f"+IDLE_PCT={r.idle_pct}", f"+STALL_PCT={r.stall_pct}",
        f"+SEED={CORE_SEED}", f"+MAX_CYCLES={40 * len(want) + 10000}",
    ]  # fmt: skip
    dat = work / f"{r.name}.dat"
    log = _run(exe, args, dat)
    done = core_run.DONE.search(log)
    beats = []
    for line in out_file.read_text().splitlines():
        if line.strip():
            d, last, user = line.split()
            beats.append((int(d, 16), int(last, 16), int(user, 16)))
    bad = core_run.compare(beats, want, words, fmt)
    if done is None or int(done.group(7)) or bad:
        raise RuntimeError(f"{r.name}: the core differs from its model:\n{log}\n" + "\n".join(bad))
    return dat, f"{r.name}: {len(words)} span beats, {len(want)} pixel beats equal to the model's"


def run_plan(runs: list[Replay | CoreReplay], work: Path, jobs: int = 2) -> list[tuple[Path, str]]:
    """Every run (builds first, ``jobs`` at a time; then the runs in the same pool)."""
    work.mkdir(parents=True, exist_ok=True)

    def one(r: Replay | CoreReplay) -> tuple[Path, str]:
        return run_core_replay(r, work) if isinstance(r, CoreReplay) else run_unit_replay(r, work)

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        return list(pool.map(one, runs))
