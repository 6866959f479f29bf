# SPDX-License-Identifier: Apache-2.0
"""Read what the tools write: Yosys ``stat -json``, nextpnr's ``--report`` JSON and its log.

Each call takes the text (or the parsed JSON) and returns plain Python values, so the tests run
them on output captured from real runs.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass

# Cell types of each family's netlist, by the resource they use.
_LUT = {
    "ice40": ("SB_LUT4",),
    "ecp5": ("LUT4",),
    "gowin": ("LUT1", "LUT2", "LUT3", "LUT4"),
    "xilinx": ("LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6"),
}
# Cells that hold LUTs besides a carry or an inversion: counted as that many LUTs (and listed
# under ``other`` too).  An iCE40 SB_CARRY and a Xilinx CARRY4 sit beside LUTs counted already.
_LUTS_IN = {"ice40": {}, "ecp5": {"CCU2C": 2}, "gowin": {"ALU": 1}, "xilinx": {"INV": 1}}
_FF_PREFIX = {"ice40": ("SB_DFF",), "ecp5": ("TRELLIS_FF",), "gowin": ("DFF",), "xilinx": ("FD",)}
# BRAM cell -> blocks it counts for (Part.bram_kind)
_BRAM = {
    "ice40": {"SB_RAM40_4K": 1, "SB_RAM40_4KNR": 1, "SB_RAM40_4KNW": 1, "SB_RAM40_4KNRNW": 1},
    "ecp5": {"DP16KD": 1, "PDPW16KD": 1},
    "gowin": {
        k: 1 for k in ("SP", "SPX9", "SDP", "SDPB", "SDPX9", "SDPX9B", "DP", "DPB", "DPX9", "DPX9B")
    }
    | {"pROM": 1, "pROMX9": 1},
    "xilinx": {"RAMB18E1": 1, "RAMB36E1": 2},
}
_DSP = {
    "ice40": ("SB_MAC16",),
    "ecp5": ("MULT18X18D", "ALU54B"),
    "gowin": (
        "MULT9X9",
        "MULT18X18",
        "MULT36X36",
        "MULTALU18X18",
        "MULTALU36X18",
        "MULTADDALU18X18",
        "ALU54D",
        "PADD9",
        "PADD18",
    ),
    "xilinx": ("DSP48E1",),
}


@dataclass(frozen=True)
class Cells:
    """A module's cells counted by resource; ``other`` lists the rest by type."""

    lut: int
    ff: int
    bram: int
    dsp: int
    other: tuple[tuple[str, int], ...]


def stat_modules(stat: str | dict) -> dict[str, dict[str, int]]:
    """``stat -json`` -> module name (``$paramod$...`` prefixes and backslashes dropped) ->
    cell type -> count."""
    data = json.loads(stat) if isinstance(stat, str) else stat
    out = {}
    for name, module in data["modules"].items():
        short = name.rsplit("\\", 1)[-1]
        out[short] = dict(module.get("num_cells_by_type", {}))
    return out


def stat_tree(stat: str | dict, top: str) -> dict[str, int]:
    """Cell type -> count of every leaf cell under the module ``top`` (its name without a
    ``$paramod$...`` prefix), each instance of a submodule counted once per instance (the
    ``stat -json`` of a hierarchy kept: a module's cells name its submodules by type)."""
    data = json.loads(stat) if isinstance(stat, str) else stat
    modules = {name: dict(m.get("num_cells_by_type", {})) for name, m in data["modules"].items()}
    found = [name for name in modules if name.rsplit("\\", 1)[-1] == top]
    if len(found) != 1:
        raise ValueError(f"top = {top!r} names {len(found)} modules of the design, not one")

    def below(name: str, seen: tuple[str, ...]) -> dict[str, int]:
        if name in seen:
            raise ValueError(f"{name} instantiates itself")
        out: dict[str, int] = {}
        for kind, n in modules[name].items():
            sub = kind if kind in modules else "\\" + kind
            parts = below(sub, (*seen, name)) if sub in modules else {kind: 1}
            for leaf, m in parts.items():
                out[leaf] = out.get(leaf, 0) + n * m
        return out

    return below(found[0], ())


def yosys_version(stat: str | dict) -> str:
    """The version ("Yosys 0.70") from the ``creator`` line of ``stat -json``."""
    data = json.loads(stat) if isinstance(stat, str) else stat
    m = re.match(r"(Yosys \S+)", data.get("creator", ""))
    return m.group(1) if m else "Yosys ?"


def classify(cells: dict[str, int], family: str) -> Cells:
    """Count ``cells`` (type -> count) as LUT, FF, BRAM, DSP and the rest, for ``family``.

    LUT counts every LUT cell plus the LUTs inside carry cells (an ECP5 CCU2C holds two, a
    Gowin ALU one), so an adder counts alike on every family."""
    lut = ff = bram = dsp = 0
    other = {}
    for kind, n in cells.items():
        if kind in _LUT[family]:
            lut += n
        elif kind.startswith(_FF_PREFIX[family]):
            ff += n
        elif kind in _BRAM[family]:
            bram += n * _BRAM[family][kind]
        elif kind in _DSP[family]:
            dsp += n
        elif not kind.startswith("$paramod") and "\\" not in kind:
            other[kind] = other.get(kind, 0) + n
            lut += n * _LUTS_IN[family].get(kind, 0)
    return Cells(lut, ff, bram, dsp, tuple(sorted(other.items())))


@dataclass(frozen=True)
class Timing:
    fmax_mhz: float | None
    path_from: str
    path_to: str
    path_ns: float | None


def short_cell(cell: str) -> str:
    """The register or net a nextpnr cell name was made from: ``u_unit.acc_reg[3]`` out of
    ``u_unit.acc_reg_SB_DFFESR_Q_D_SB_LUT4_O_LC`` or ``u_unit.acc_reg_TRELLIS_FF_Q``."""
    cut = re.search(r"(_SB_|_TRELLIS_|_LUT4|_DFF|_CCU2|_DP16KD|_MULT18|_ALU|_LUT[1-6]|\$)", cell)
    return cell[: cut.start()] if cut and cut.start() > 0 else cell


def report_timing(report: str | dict) -> Timing:
    """Fmax of the clock and its register-to-register critical path from ``--report`` JSON.

    With more than one clock domain (nextpnr-ice40 makes one of a DSP's clock pin tied to
    ground, ``$PACKER_GND_NET_$glb_clk``) the figure and the path are the slowest clock's."""
    data = json.loads(report) if isinstance(report, str) else report
    clocks = data.get("fmax", {})
    if not clocks:
        return Timing(None, "", "", None)
    slowest = min(clocks, key=lambda name: clocks[name]["achieved"])
    fmax = clocks[slowest]["achieved"]
    edge = f"posedge {slowest}"
    paths = data.get("critical_paths", [])
    own = [cp for cp in paths if cp.get("from") == edge and cp.get("to") == edge]
    for cp in own or paths:
        if cp.get("from", "").startswith("posedge") and cp.get("to", "").startswith("posedge"):
            path = cp["path"]
            if not path:
                continue
            ns = sum(step["delay"] for step in path)
            return Timing(
                round(fmax, 2),
                short_cell(path[0]["from"]["cell"]),
                short_cell(path[-1]["to"]["cell"]),
                round(ns, 3),
            )
    return Timing(round(fmax, 2), "", "", None)


def report_utilisation(report: str | dict) -> tuple[tuple[str, int, int], ...]:
    """(bel type, used, available) of every bel type the design uses, from ``--report``."""
    data = json.loads(report) if isinstance(report, str) else report
    util = data.get("utilization", {})
    return tuple(
        (k, int(v["used"]), int(v["available"])) for k, v in sorted(util.items()) if v["used"]
    )


# nextpnr's words when a design needs more of something than the device has.
_OVERFLOW = (
    re.compile(r"Design uses (\d+) cells of type '?([\w$]+)'?, but device only has (\d+)"),
    re.compile(r"(\d+) ([\w$]+) cells?\S* but (?:the )?device only has (\d+)"),
)
_NO_BELS = re.compile(r"no BELs remaining to implement cell type '([\w$]+)'")
_UTIL_LINE = re.compile(r"Info:\s+([\w$]+):\s+(\d+)\s*/\s*(\d+)")


def log_overflow(log: str) -> str | None:
    """What does not fit, from a nextpnr log ("ICESTORM_RAM 69/32"), or None if the log shows
    no shortage (the design fits or failed for another reason)."""
    for pattern in _OVERFLOW:
        m = pattern.search(log)
        if m:
            used, kind, avail = m.groups()
            return f"{kind} {used}/{avail}"
    over = [(k, int(u), int(a)) for k, u, a in _UTIL_LINE.findall(log) if int(u) > int(a)]
    if over:
        return ", ".join(f"{k} {u}/{a}" for k, u, a in over)
    m = _NO_BELS.search(log)
    if m or re.search(r"not enough|too many|Unable to place", log, re.I):
        kind = m.group(1) if m else "cells"
        return f"{kind} (placement ran out of sites)"
    return None
