# SPDX-License-Identifier: Apache-2.0
"""FuseSoC cores (rtl/*.core) and plain file lists (rtl/*.f) of the three units.

``fusesoc --cores-root rtl core list`` lists the three cores; for each, the lint target
(Verilator -Wall) and the sim target (the unit's default vector set under Icarus, failing on
any mismatch) pass, built in a temporary folder.  Each file list names the unit's RTL, relative
to the list, and builds under Icarus and Verilator.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from sim.runner import RTL_DIR

pytestmark = pytest.mark.sim

UNITS = ["divider_shift", "gouraud_segment", "specular_unit"]
ROOT = RTL_DIR.parent


def fusesoc(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    exe = shutil.which("fusesoc", path=str(Path(sys.executable).parent)) or shutil.which("fusesoc")
    assert exe, "fusesoc is not installed: pip install -e '.[dev]' (make setup)"
    return subprocess.run(
        [exe, "--cores-root", str(RTL_DIR), *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=600,
        env={**os.environ, "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}"},
    )


def test_core_list_names_the_three_units(tmp_path: Path) -> None:
    ran = fusesoc("core", "list", cwd=tmp_path)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    for unit in UNITS:
        assert f"shading:units:{unit}:0.1" in ran.stdout, ran.stdout + ran.stderr


@pytest.mark.parametrize("unit", UNITS)
def test_lint_and_sim_targets_pass(unit: str, tmp_path: Path) -> None:
    build = tmp_path / "build"
    for target in ("lint", "sim"):
        ran = fusesoc(
            "run",
            "--build-root",
            str(build),
            "--target",
            target,
            f"shading:units:{unit}",
            cwd=tmp_path,
        )
        log = ran.stdout + ran.stderr
        assert ran.returncode == 0, f"fusesoc run --target {target} {unit}:\n{log}"
        if target == "sim":
            assert f"PASS tb_{unit}: 3000 cycles" in log and "MISMATCH" not in log, log


@pytest.mark.parametrize("unit", UNITS)
def test_file_list_builds(unit: str, tmp_path: Path) -> None:
    """rtl/<unit>.f: Verilator reads it with -F (paths relative to the list), Icarus with -c
    from rtl/ (the ROM images' default folder "rom" is relative to the working folder)."""
    flist = RTL_DIR / f"{unit}.f"
    ran = subprocess.run(
        ["verilator", "--lint-only", "-Wall", "--top-module", unit, "-F", str(flist)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert ran.returncode == 0, ran.stdout + ran.stderr
    ran = subprocess.run(
        ["iverilog", "-g2005", "-o", str(tmp_path / "a.vvp"), "-c", str(flist)],
        capture_output=True,
        text=True,
        cwd=RTL_DIR,
    )
    assert ran.returncode == 0, ran.stdout + ran.stderr
