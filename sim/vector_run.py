# SPDX-License-Identifier: Apache-2.0
"""Build and run the plain Verilog vector benches (sim/vectors/tb_<unit>.v) from Python.

``build`` compiles a unit's bench under Icarus (``iverilog -g2005``) or Verilator (what
``verilator --binary`` does: ``--main --exe --timing``, then make, with the runtime library's
objects compiled once for every bench, ``runtime``) once per configuration: the vector file
and its length are run-time plusargs (``+VECTOR_FILE=``, ``+CYCLES=``,
sim/vectors/vector_loop.vh), so one build replays any vector file of that configuration.  A
build is kept in ``<root>/<sim>_<unit>_<key>/``, the key a hash of the sources, the
parameters, the flags and the tool's version; a second ``build`` of the same key is a cache hit
(``Build.cached``).  ``run`` replays one vector file, optionally writing the RTL's results
(``+OUT_FILE=``), and times it apart from the build: wall seconds and the CPU seconds of the
simulator process alone (``os.wait4``), which other load on the machine changes far less than
the wall time.

Used by the soak (sim/soak.py), the vector sets and ``python -m sim bench`` (sim/vector_sets.py,
sim/__main__.py) and the scene co-simulation (sim/scene_cosim.py).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import shutil
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

from model.hw.sources import source_list

VECTOR_DIR = Path(__file__).resolve().parent / "vectors"
RTL_DIR = Path(str(files("model.rtl")))
SIMS = ("icarus", "verilator")
# verilator --binary: -O3 and fast X handling (the benches check X only under Icarus, four-state;
# Verilator is two-state), the RTL's lint warnings do not stop the build, C++ built by 2 jobs.
VERILATOR_FLAGS = (
    "-O3",
    "--x-assign",
    "fast",
    "--x-initial",
    "fast",
    "-Wno-fatal",
    "-Wno-lint",
    "-Wno-style",
)
BUILD_JOBS = "2"
# Verilator's compiled runtime library, shared by every build (``runtime``).
RUNTIME_ROOT = Path(os.environ.get("SIM_BUILD", "sim_build")).resolve() / "vector_builds"
# The bench's count line (sim/vectors/vector_loop.vh).
DONE = re.compile(r"^VECTORS (\d+) cycles (\d+) mismatches$", re.M)


@dataclass
class Build:
    """A built vector bench: how to run it, and what the build took."""

    sim: str
    unit: str
    folder: Path
    command: list[str]  # the run command, without plusargs
    seconds: float  # the build's wall time (0 when cached)
    cached: bool
    ok: bool
    log: str


@dataclass
class Run:
    """One replay of a vector file."""

    cycles: int
    mismatches: int  # -1: the bench did not finish
    passed: bool
    wall_s: float
    cpu_s: float  # user + system seconds of the simulator process
    returncode: int
    log: str


def tool_version(sim: str) -> str:
    exe = "iverilog" if sim == "icarus" else "verilator"
    if shutil.which(exe) is None:
        raise RuntimeError(
            f"{exe} is not on PATH: install it (make tools, scripts/ensure-tools.sh)"
        )
    flag = "-V" if sim == "icarus" else "--version"
    ran = subprocess.run([exe, flag], capture_output=True, text=True, timeout=60)
    return (ran.stdout + ran.stderr).splitlines()[0] if (ran.stdout + ran.stderr) else exe


def build(
    unit: str,
    params: dict[str, str],
    sim: str,
    root: Path,
    rtl: Path | None = None,
    cache: bool = True,
    timeout: float = 3600,
) -> Build:
    """Build ``sim/vectors/tb_<unit>.v`` with the files ``rtl/<unit>.f`` lists under ``sim``,
    ``rtl`` (a netlist or a broken copy) in place of ``rtl/<unit>.v``.

    ``params``: NAME -> Verilog value text (strings in double quotes), the unit's parameters
    and optionally RESET_MODES; the vector file and CYCLES are given to ``run``.
    """
    if sim not in SIMS:
        raise ValueError(f"sim={sim!r} is not allowed: it must be one of {', '.join(SIMS)}")
    top = f"tb_{unit}"
    # rtl takes the place of rtl/<unit>.v; the list's other files (the ROM module) stay, unused
    # by a flattened netlist
    listed = source_list(unit, RTL_DIR)
    if rtl:
        listed = [Path(rtl) if p.name == f"{unit}.v" else p for p in listed]
    sources = [VECTOR_DIR / f"{top}.v", *listed]
    common = [f"-I{VECTOR_DIR}", f'-DSHADING_ROM_DIR="{RTL_DIR / "rom"}"']
    digest = hashlib.sha256(tool_version(sim).encode())
    for path in [*sources, VECTOR_DIR / "vector_loop.vh"]:
        digest.update(path.read_bytes())
    digest.update(repr((sorted(params.items()), common, VERILATOR_FLAGS)).encode())
    folder = root / f"{sim}_{unit}_{digest.hexdigest()[:16]}"
    if sim == "icarus":
        exe = folder / f"{top}.vvp"
        cmd = ["iverilog", "-g2005", "-o", str(exe), "-s", top, *common]
        cmd += [f"-P{top}.{k}={v}" for k, v in params.items()] + [str(s) for s in sources]
        command = ["vvp", "-n", str(exe)]
    else:
        exe = folder / "obj" / f"V{top}"
        # verilator --binary = --main --exe --build --timing; the build is run here so that the
        # runtime library's objects come from runtime() instead of being compiled again
        cmd = ["verilator", "--main", "--exe", "--timing", *VERILATOR_FLAGS, "--top-module", top]
        cmd += ["-Mdir", str(folder / "obj"), *common]
        cmd += [f"-G{k}={v}" for k, v in params.items()] + [str(s) for s in sources]
        command = [str(exe)]
    done = folder / "built.ok"
    if cache and done.exists() and exe.exists():
        return Build(sim, unit, folder, command, 0.0, True, True, "")
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    t0 = time.monotonic()
    built = subprocess.run(cmd, capture_output=True, text=True, cwd=folder, timeout=timeout)
    log = built.stdout + built.stderr
    if built.returncode == 0 and sim == "verilator":
        objects = runtime(timeout=timeout)
        obj = folder / "obj"
        for path in objects.iterdir() if objects else ():
            if path.suffix in (".o", ".d"):
                shutil.copy2(path, obj / path.name)
                os.utime(obj / path.name)  # newer than the fresh V<top>.mk they depend on
        built = subprocess.run(
            ["make", "-j", BUILD_JOBS, "-C", str(obj), "-f", f"V{top}.mk"],
            capture_output=True,
            text=True,
            timeout=timeout,
        )
        log += built.stdout + built.stderr
    seconds = time.monotonic() - t0
    ok = built.returncode == 0 and exe.exists()
    if ok:
        done.write_text(" ".join(cmd) + "\n")
    return Build(sim, unit, folder, command, seconds, False, ok, log)


_runtime_lock = threading.Lock()


def runtime(root: Path = RUNTIME_ROOT, timeout: float = 3600) -> Path | None:
    """The folder of Verilator's compiled runtime library (verilated*.o, the same for every
    bench built with these flags: three quarters of a bench's C++ build), compiled once per
    Verilator version and flags into ``root`` and kept there; None if it cannot be built (each
    bench then compiles its own)."""
    digest = hashlib.sha256(repr((tool_version("verilator"), VERILATOR_FLAGS)).encode())
    folder = root / f"verilator_runtime_{digest.hexdigest()[:16]}"
    with _runtime_lock:
        if (folder / "ok").exists():
            return folder
        work = root / f"{folder.name}.{os.getpid()}.tmp"
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
        (work / "tb_runtime.v").write_text("module tb_runtime;\ninitial #1 $finish;\nendmodule\n")
        cmd = ["verilator", "--main", "--exe", "--timing", *VERILATOR_FLAGS, "-Mdir", "obj"]
        made = subprocess.run(
            [*cmd, "tb_runtime.v"], capture_output=True, text=True, cwd=work, timeout=timeout
        )
        names = ["verilated.o", "verilated_timing.o", "verilated_threads.o"]
        if made.returncode == 0:
            made = subprocess.run(
                ["make", "-j", BUILD_JOBS, "-C", "obj", "-f", "Vtb_runtime.mk", *names],
                capture_output=True,
                text=True,
                cwd=work,
                timeout=timeout,
            )
        if made.returncode != 0:
            shutil.rmtree(work, ignore_errors=True)
            return None
        keep = work / "objects"
        keep.mkdir()
        for path in (work / "obj").iterdir():
            if path.name.startswith("verilated") and path.suffix in (".o", ".d"):
                shutil.copy2(path, keep / path.name)
        (keep / "ok").write_text("verilator runtime objects\n")
        with contextlib.suppress(OSError):  # another process published it first: use that one
            keep.rename(folder)
        shutil.rmtree(work, ignore_errors=True)
        return folder if (folder / "ok").exists() else None


def run(
    b: Build,
    vector_file: Path,
    cycles: int,
    out_file: Path | None = None,
    timeout: float = 3600,
) -> Run:
    """Replay ``vector_file`` (``cycles`` records) through the built bench ``b``."""
    if not b.ok:
        return Run(cycles, -1, False, 0.0, 0.0, -1, b.log)
    cmd = [*b.command, f"+VECTOR_FILE={vector_file}", f"+CYCLES={cycles}"]
    if out_file is not None:
        cmd.append(f"+OUT_FILE={out_file}")
    with tempfile.TemporaryFile("w+") as out:
        t0 = time.monotonic()
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, cwd=b.folder)
        timer = threading.Timer(timeout, proc.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(proc.pid, 0)
        finally:
            timer.cancel()
        wall = time.monotonic() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        log = out.read()
    done = DONE.search(log)
    mismatches = int(done.group(2)) if done else -1
    finished = done is not None and int(done.group(1)) == cycles
    passed = proc.returncode == 0 and finished and mismatches == 0
    cpu = usage.ru_utime + usage.ru_stime
    return Run(cycles, mismatches, passed, wall, cpu, proc.returncode, log)
