"""Synthesise every RTL unit with Yosys for iCE40 and print its resource use (``make synth``).

Proves the RTL synthesisable (Yosys must finish without error) and gives the silicon side of the
speed/accuracy trade: LUT4s, flip-flops, carry cells, block RAMs and DSPs per unit at its default
configuration.  ROM images are read from rtl/rom as in simulation.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from model.units import divider, gouraud, specular
from sim.runner import RTL_DIR, hdl_parameters


def unit_parameters() -> dict[str, dict[str, object]]:
    """Toplevel -> Verilog parameters of its default configuration."""
    units = {
        "divider_shift": hdl_parameters(
            divider.DEFAULT, ROM_FILE=divider.rom_path(divider.DEFAULT)
        ),
        "gouraud_segment": hdl_parameters(gouraud.DEFAULT),
        "specular_unit": hdl_parameters(specular.DEFAULT),
    }
    return units


def synthesise(toplevel: str, params: dict[str, object]) -> dict[str, int]:
    with tempfile.TemporaryDirectory() as tmp:
        stat = Path(tmp) / "stat.json"
        chparams = " ".join(
            f'-set {k} "{v}"' if isinstance(v, str) else f"-set {k} {v}" for k, v in params.items()
        )
        script = (
            f"read_verilog -defer {RTL_DIR / (toplevel + '.v')}; "
            f"chparam {chparams} {toplevel}; synth_ice40 -top {toplevel}; "
            f"tee -q -o {stat} stat -json"
        )
        subprocess.run(["yosys", "-q", "-p", script], check=True, capture_output=True, text=True)
        module = next(iter(json.loads(stat.read_text())["modules"].values()))
        return module["num_cells_by_type"]


def main() -> int:
    if shutil.which("yosys") is None:
        print("yosys not found: install it with 'apt-get install yosys'", file=sys.stderr)
        return 1
    print("| unit | LUT4 | flip-flops | carry | block RAM (4 kbit) | DSP |")
    print("|---|---|---|---|---|---|")
    for toplevel, params in unit_parameters().items():
        cells = synthesise(toplevel, params)
        ffs = sum(v for k, v in cells.items() if k.startswith("SB_DFF"))
        print(
            f"| {toplevel} | {cells.get('SB_LUT4', 0)} | {ffs} | {cells.get('SB_CARRY', 0)} "
            f"| {cells.get('SB_RAM40_4K', 0)} | {cells.get('SB_MAC16', 0)} |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
