# SPDX-License-Identifier: Apache-2.0
"""The synthesis table (markdown) and record (JSON) of a list of ``SynthResult``s."""

from __future__ import annotations

import json

from model.hw.parts import PARTS
from model.hw.synth import SynthResult

COLUMNS = (
    "unit", "config", "part", "LUT", "FF", "BRAM", "DSP", "fits", "Fmax MHz", "target", "met",
    "critical path (ns)",
)  # fmt: skip


def _fits(r: SynthResult) -> str:
    return "yes" if r.fits else f"**no** ({r.overflow})"


def _met(r: SynthResult) -> str:
    if r.meets_target is None:
        return "-"
    return "yes" if r.meets_target else "**NO**"


def _path(r: SynthResult) -> str:
    if r.path_ns is None:
        return "-"
    return f"{r.path_from} -> {r.path_to} ({r.path_ns:.2f})"


def row(r: SynthResult) -> list[str]:
    fmax = "-" if r.fmax_mhz is None else f"{r.fmax_mhz:.1f}"
    target = "-" if r.target_mhz is None else f">= {r.target_mhz:g}"
    return [
        f"`{r.unit}`", r.config, r.part, str(r.lut), str(r.ff), str(r.bram), str(r.dsp),
        _fits(r), fmax, target, _met(r), _path(r),
    ]  # fmt: skip


def table(results: list[SynthResult]) -> str:
    """The markdown table: one row per result, then what a BRAM counts on each part shown."""
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(row(r)) + " |" for r in results]
    parts = [PARTS[k] for k in dict.fromkeys(r.part for r in results) if k in PARTS]
    if parts:
        lines.append("")
        lines.append(
            "BRAM counts: "
            + "; ".join(f"{p.key} {p.bram_kind}, {p.bram} on the part" for p in parts)
            + "."
        )
    return "\n".join(lines) + "\n"


def record(results: list[SynthResult], command: str) -> dict:
    """The JSON record ``docs/synth.json`` holds: the command and every result in full (its
    ``inputs`` hashes say which RTL, ROM images and parameters it was made from)."""
    return {"command": command, "results": [r.to_json() for r in results]}


def dumps(results: list[SynthResult], command: str) -> str:
    return json.dumps(record(results, command), indent=1) + "\n"


def failures(results: list[SynthResult]) -> list[str]:
    """One line per result that misses its target or must fit and does not."""
    out = []
    for r in results:
        if r.ok:
            continue
        if not r.fits:
            out.append(f"{r.unit} ({r.config}) does not fit {r.part}: {r.overflow}")
        else:
            out.append(
                f"{r.unit} ({r.config}) on {r.part}: Fmax {r.fmax_mhz} MHz misses the target "
                f"{r.target_mhz:g} MHz"
            )
    return out
