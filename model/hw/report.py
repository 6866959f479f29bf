# SPDX-License-Identifier: Apache-2.0
"""The synthesis table (markdown) and record (JSON) of a list of ``SynthResult``s."""

from __future__ import annotations

import json
from pathlib import Path

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


def load(path: str | Path) -> list[SynthResult]:
    """The results of a record written by ``dumps`` (``docs/synth.json``)."""
    return [SynthResult.from_json(r) for r in json.loads(Path(path).read_text())["results"]]


BESIDE_COLUMNS = (
    "unit",
    "config",
    "part",
    "LUT",
    "FF",
    "BRAM",
    "DSP",
    "fits",
    "Fmax MHz",
    "target",
)


def _delta(value: float | None, base: float | None, digits: int) -> str:
    if value is None:
        return "-"
    text = f"{value:.{digits}f}"
    if base is None:
        return text
    return f"{text} ({value - base:+.{digits}f})"


def beside(
    results: list[SynthResult],
    unit: str,
    base: tuple[str, str],
    also: tuple[tuple[str, str], ...] = (),
) -> str:
    """Markdown table of every recorded configuration of ``unit``, part by part beside the row
    of ``base`` (unit, configuration) on the same part: each of ``unit``'s LUT, FF, BRAM, DSP
    and Fmax with its difference from ``base``'s in brackets (none where ``base`` has no
    figure); the rows of ``also`` on a part follow ``base``'s there as they are.  ValueError if
    the record holds no row of ``unit``, or a part of ``unit``'s lacks ``base``."""
    own = [r for r in results if r.unit == unit]
    if not own:
        units = ", ".join(dict.fromkeys(r.unit for r in results))
        raise ValueError(f"unit {unit!r} has no row in the record: it holds {units}")
    parts = list(dict.fromkeys(r.part for r in own))
    ref = {r.part: r for r in results if (r.unit, r.config) == base}
    missing = [p for p in parts if p not in ref]
    if missing:
        raise ValueError(
            f"base {base!r} has no row on {', '.join(missing)}: the record holds it on "
            f"{', '.join(ref) or 'no part'}"
        )
    lines = ["| " + " | ".join(BESIDE_COLUMNS) + " |", "|" + "---|" * len(BESIDE_COLUMNS)]
    for part in parts:
        b = ref[part]
        extra = [r for key in also for r in results if (r.unit, r.config, r.part) == (*key, part)]
        for r in [b, *extra, *(r for r in own if r.part == part)]:
            other = b if r.unit == unit else None
            figures = [
                _delta(getattr(r, f), getattr(other, f) if other else None, 0)
                for f in ("lut", "ff", "bram", "dsp")
            ]
            fmax = _delta(r.fmax_mhz, other.fmax_mhz if other else None, 1)
            target = "-" if r.target_mhz is None else f">= {r.target_mhz:g}"
            cells = [f"`{r.unit}`", r.config, part, *figures, "yes" if r.fits else "no", fmax]
            lines.append("| " + " | ".join([*cells, target]) + " |")
    return "\n".join(lines) + "\n"
