# SPDX-License-Identifier: Apache-2.0
"""Broken copies of the RTL, the one mechanism every check uses to show that it can fail.

A ``Mutant`` is a unit's file from ``rtl/`` with one exact snippet replaced by another, made
afresh for every run (``source``, ``write``), so that it always follows the RTL and keeps its
parameter rules and ROM checks; a snippet that no longer occurs exactly once raises
``MutantError`` naming the mutant and the file, instead of testing a stale copy.

Who uses it: the formal jobs (``model.hw.formal`` and ``model.hw.formal_<unit>``, ``breaks``
naming the property that must fail on the mutant), and the simulation mutants the vector soak
and the cocotb benches must catch (``tests/mutants``, ``breaks`` empty).  Netlist mutations
(``make mutants``, sim/mutation.py) are Yosys ``mutate`` cells in the synthesised netlist, not
source snippets.  Layer 2: imports ``model.units`` only (for the RTL folder).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from model.units import rom

RTL_DIR = rom.ROM_DIR.parent  # rtl/


class MutantError(ValueError):
    """A mutant that cannot be made: its snippet is not in the RTL exactly once."""


@dataclass(frozen=True)
class Mutant:
    """``unit``'s ``rtl/<unit>.v`` with ``original`` (exactly once in it) replaced."""

    name: str
    original: str
    replacement: str
    breaks: str = ""  # the formal property that must fail on it ("": a simulation mutant)
    unit: str = ""  # the file it changes, rtl/<unit>.v ("": the caller names the unit)


def mutate(text: str, mutant: Mutant, where: str) -> str:
    """``text`` (the source ``where`` names) with the mutant's snippet replaced."""
    count = text.count(mutant.original)
    if count != 1:
        raise MutantError(
            f"mutant {mutant.name}: its snippet occurs {count} times in {where}, expected once: "
            "update the mutant to the RTL"
        )
    return text.replace(mutant.original, mutant.replacement)


def source(mutant: Mutant, unit: str = "", path: Path | None = None) -> str:
    """The mutated text of ``path`` (default ``rtl/<unit>.v``, ``unit`` the mutant's own when
    not given)."""
    unit = unit or mutant.unit
    if not unit and path is None:
        raise MutantError(f"mutant {mutant.name}: no unit and no file to change")
    path = path if path is not None else RTL_DIR / f"{unit}.v"
    if not path.is_file():
        raise MutantError(f"mutant {mutant.name}: RTL file {path} does not exist")
    return mutate(path.read_text(), mutant, path.name)


def write(mutant: Mutant, folder: Path, unit: str = "") -> Path:
    """Write the mutated ``rtl/<unit>.v`` as ``folder/<name>.v`` (its module keeps its name)
    and return that path."""
    text = source(mutant, unit)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{mutant.name}.v"
    path.write_text(text)
    return path
