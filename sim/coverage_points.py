# SPDX-License-Identifier: Apache-2.0
"""Verilator coverage points, the gaps among them and the waivers that explain them.

``read_points`` reads a Verilator ``coverage.dat`` (``SystemC::Coverage-3``: one ``C '<key>'
<count>`` line per point, the key's fields ``f`` file, ``l`` line, ``n`` column, ``page``
(``v_line/...``, ``v_branch/...``, ``v_toggle/...``), ``o`` what the point is (``block``,
``if``, ``else``, ``case``, ... or the toggled bit, ``acc_reg[40]``), ``S`` the lines a block
spans, ``h`` the instance).  ``collect`` keeps the points of a unit's own source files and
joins the same point of every instance and run: a point is named by file, line, column and
what it is, never by instance.  A line point is joined over the configurations too (a
statement is the same in each); a toggle point is one per configuration (bit 40 of a
parameterised width is a different bit in each).

A line point (a block or a branch, ``--coverage-line``) is hit when it ran once; a toggle
point (one bit of a signal, ``--coverage-toggle``) when it changed twice, so that it rose and
fell.  A source line is covered when every point on it is.  A point that is not is a gap; a
gap must be explained by a waiver (``sim/coverage_waivers.toml``, ``load_waivers``), keyed by
file and by a piece of the line's text or by the signal's name and bits, never by a line
number; ``check`` returns the gaps nothing explains and the waivers that explain nothing
(stale)."""

from __future__ import annotations

import fnmatch
import re
import sys
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

LINE_MIN = 1  # a block or branch ran at least once
TOGGLE_MIN = 2  # a bit changed at least twice: it rose and it fell
KINDS = ("line", "toggle")
CATEGORIES = (
    "unreachable bits",  # bits legal operands never set (the bound in the reason)
    "unreachable state",  # a state the design's own invariant excludes (the reason says which)
    "parameter rule",  # code that exists only for refused parameters
    "simulation-only check",  # ROM image checks at time 0, never changing after
    "rule instance",  # an instance whose clock never ticks (the core's copy of a unit's rules)
    "elaboration only",  # constant functions the tools evaluate at elaboration, never run
    "constant",  # a bit tied to a constant at this configuration
    "stimulus gap",  # reachable, not reached: what would close it is in the reason
)


@dataclass(frozen=True, order=True)
class Point:
    """One coverage point, joined over instances and configurations."""

    file: str  # the source's file name (rtl/ holds one folder)
    kind: str  # "line" or "toggle"
    line: int
    column: int
    what: str  # block, if, else, case, ... or the bit, e.g. acc_reg[40]
    span: tuple[int, ...]  # the source lines the point stands for
    count: int
    config: str = ""  # a toggle point's configuration (a line point's: "")

    @property
    def covered(self) -> bool:
        return self.count >= (TOGGLE_MIN if self.kind == "toggle" else LINE_MIN)

    @property
    def signal(self) -> str:
        """A toggle point's signal, without its bit (``acc_reg``)."""
        return re.sub(r"(\[\d+\])+$", "", self.what)

    @property
    def bit(self) -> int | None:
        found = re.search(r"\[(\d+)\]$", self.what)
        return int(found.group(1)) if found else None


def _span(text: str | None, line: int) -> tuple[int, ...]:
    if not text:
        return (line,)
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out.extend(range(int(lo), int(hi or lo) + 1))
    return tuple(out)


def read_points(path: Path) -> list[dict[str, str]]:
    """Every point of a coverage.dat as its key's fields, the count under ``"count"``."""
    out = []
    for raw in path.read_text(errors="replace").splitlines():
        if not raw.startswith("C '"):
            continue
        key, _, count = raw[3:].rpartition("' ")
        fields = dict(part.split("\x02", 1) for part in key.split("\x01") if "\x02" in part)
        fields["count"] = count.strip()
        out.append(fields)
    return out


def collect(runs: list[tuple[str, list[dict[str, str]]]], sources: list[Path]) -> list[Point]:
    """The points of the files ``sources`` names in ``runs`` ((configuration, the points of a
    coverage file) each), joined: the highest count of any instance and run (a point is
    covered if one of them covers it; a toggle point only within its configuration)."""
    names = {p.resolve() for p in sources}
    best: dict[tuple, int] = {}
    spans: dict[tuple, tuple[int, ...]] = {}
    for config, raw in runs:
        for f in raw:
            if Path(f["f"]).resolve() not in names:
                continue
            kind = "toggle" if f.get("page", "").startswith("v_toggle") else "line"
            line = int(f.get("l", 0))
            key = (Path(f["f"]).name, kind, line, int(f.get("n", 0)), f.get("o", ""))
            key += (config if kind == "toggle" else "",)
            best[key] = max(best.get(key, 0), int(f["count"]))
            spans[key] = _span(f.get("S"), line)
    return sorted(Point(*k[:5], spans[k], n, k[5]) for k, n in best.items())


@dataclass(frozen=True)
class Figures:
    """A unit's coverage in numbers."""

    lines: int
    lines_covered: int
    lines_explained: int  # uncovered lines every gap of which a waiver explains
    toggles: int
    toggles_covered: int
    toggles_explained: int


def line_status(points: list[Point]) -> dict[tuple[str, int], list[Point]]:
    """Per source line (file, number): the line points that stand for it."""
    out: dict[tuple[str, int], list[Point]] = defaultdict(list)
    for p in points:
        if p.kind == "line":
            for n in p.span:
                out[(p.file, n)].append(p)
    return out


# ------------------------------------------------------------------------------ waivers
@dataclass(frozen=True)
class Waiver:
    """Why some gaps cannot be closed.  A line waiver names a piece of the text of a line the
    point stands for (``text``; ``*``: any line of the file), or a region of the file from the
    first line holding ``text`` to the next line after it holding ``until``; a toggle waiver
    names the signals (``signal``: a name or a list, globs; ``bits``, ranges ``"hi:lo"`` or
    single bits, keeps to some bits); ``configs`` keeps to some configurations (empty: all)."""

    units: tuple[str, ...]
    file: str
    kind: str
    category: str
    reason: str
    text: str = ""
    until: str = ""
    signals: tuple[str, ...] = ()
    bits: tuple[tuple[int, int], ...] = ()
    configs: tuple[str, ...] = ()

    def label(self) -> str:
        what = f"'{self.text}'" if self.kind == "line" else ", ".join(self.signals)
        if self.until:
            what += f" to '{self.until}'"
        if self.bits:
            what += _bits([b for lo, hi in self.bits for b in range(lo, hi + 1)])
        where = ", ".join(self.units) + (f"; {', '.join(self.configs)}" if self.configs else "")
        return f"{self.file} {self.kind} {what} ({where})"

    def matches(self, unit: str, p: Point, source: dict[str, list[str]]) -> bool:
        if unit not in self.units or p.file != self.file or p.kind != self.kind:
            return False
        if self.kind == "toggle":
            if self.configs and p.config not in self.configs:
                return False
            if not any(fnmatch.fnmatchcase(p.signal, g) for g in self.signals):
                return False
            if not self.bits:
                return True
            return p.bit is not None and any(lo <= p.bit <= hi for lo, hi in self.bits)
        if self.text == "*":
            return True
        lines = source.get(p.file, [])
        if self.until:
            return any(lo <= p.line <= hi for lo, hi in self.regions(lines))
        return any(0 < n <= len(lines) and self.text in lines[n - 1] for n in p.span)

    def regions(self, lines: list[str]) -> list[tuple[int, int]]:
        """The (first, last) line numbers of each region ``text`` .. ``until`` in ``lines``."""
        out, n = [], 0
        while n < len(lines):
            if self.text in lines[n]:
                end = next((m for m in range(n + 1, len(lines)) if self.until in lines[m]), None)
                if end is None:
                    break
                out.append((n + 1, end + 1))
                n = end
            n += 1
        return out


def load_waivers(path: Path) -> list[Waiver]:
    """The waivers of a TOML file: ``[[waiver]]`` tables with ``units``, ``file``, ``kind``,
    ``category``, ``reason`` and ``text`` (and ``until``) or ``signal`` (a name or a list;
    and ``bits``, ``configs``); a bad entry raises, naming it."""
    data = tomllib.loads(path.read_text())
    out = []
    for i, entry in enumerate(data.get("waiver", []), 1):
        where = f"{path.name}: waiver {i}"
        kind = entry.get("kind")
        if kind not in KINDS:
            raise ValueError(f"{where}: kind = {kind!r} must be one of {KINDS}")
        if entry.get("category") not in CATEGORIES:
            raise ValueError(f"{where}: category = {entry.get('category')!r}: one of {CATEGORIES}")
        key = "text" if kind == "line" else "signal"
        if not entry.get(key) or not entry.get("reason") or not entry.get("units"):
            raise ValueError(f"{where}: a {kind} waiver needs units, {key} and reason")
        bits = []
        raw_bits = entry.get("bits", [])
        for part in [raw_bits] if isinstance(raw_bits, str | int) else raw_bits:
            hi, _, lo = str(part).partition(":")
            bits.append((min(int(hi), int(lo or hi)), max(int(hi), int(lo or hi))))
        signals = entry.get("signal", [])
        out.append(
            Waiver(
                units=tuple(entry["units"]),
                file=entry["file"],
                kind=kind,
                category=entry["category"],
                reason=" ".join(entry["reason"].split()),
                text=entry.get("text", ""),
                until=entry.get("until", ""),
                signals=tuple([signals] if isinstance(signals, str) else signals),
                bits=tuple(bits),
                configs=tuple(entry.get("configs", ())),
            )
        )
    return out


@dataclass(frozen=True)
class Check:
    """A unit's gaps against the waivers."""

    unit: str
    figures: Figures
    explained: tuple[tuple[Point, Waiver], ...]
    unexplained: tuple[Point, ...]
    stale: tuple[Waiver, ...]  # waivers of this unit that match no gap of it


def check(
    unit: str, points: list[Point], waivers: list[Waiver], source: dict[str, list[str]]
) -> Check:
    """Each gap of ``unit`` with the first waiver that explains it; the gaps none explains;
    the waivers naming ``unit`` that explain none of its gaps."""
    explained, unexplained, used = [], [], set()
    for p in points:
        if p.covered:
            continue
        w = next((w for w in waivers if w.matches(unit, p, source)), None)
        if w is None:
            unexplained.append(p)
        else:
            explained.append((p, w))
            used.add(w)
    stale = tuple(w for w in waivers if unit in w.units and w not in used)
    status = line_status(points)
    waived = {p for p, _ in explained}
    bad_lines = [ps for ps in status.values() if not all(p.covered for p in ps)]
    toggles = [p for p in points if p.kind == "toggle"]
    figures = Figures(
        lines=len(status),
        lines_covered=len(status) - len(bad_lines),
        lines_explained=sum(all(p.covered or p in waived for p in ps) for ps in bad_lines),
        toggles=len(toggles),
        toggles_covered=sum(p.covered for p in toggles),
        toggles_explained=sum(p in waived for p in toggles),
    )
    return Check(unit, figures, tuple(explained), tuple(unexplained), stale)


def _bits(bits: list[int]) -> str:
    """Bit numbers as ranges, highest first: ``[20:0]``, ``[7, 3:1]``."""
    runs: list[list[int]] = []
    for b in sorted(set(bits), reverse=True):
        if runs and runs[-1][-1] == b + 1:
            runs[-1].append(b)
        else:
            runs.append([b])
    return "[" + ", ".join(f"{r[0]}:{r[-1]}" if len(r) > 1 else f"{r[0]}" for r in runs) + "]"


def group(points: list[Point]) -> list[list[Point]]:
    """Gaps in reading order: a line point alone, a signal's toggle points together."""
    out: dict[tuple, list[Point]] = {}
    for p in points:
        key = (p.file, p.line, p.signal, p.config) if p.kind == "toggle" else (p,)
        out.setdefault(key, []).append(p)
    return list(out.values())


def describe_group(ps: list[Point], source: dict[str, list[str]]) -> str:
    """A group of gaps (``group``) in one line."""
    p = ps[0]
    if p.kind != "toggle" or len(ps) == 1:
        return describe(p, source)
    bits = [q.bit for q in ps if q.bit is not None]
    lines = source.get(p.file, [])
    text = lines[p.line - 1].strip() if 0 < p.line <= len(lines) else ""
    counts = sorted({q.count for q in ps})
    changed = f"{counts[0]}x" if len(counts) == 1 else f"{counts[0]}x to {counts[-1]}x"
    what = f"{p.signal}{_bits(bits)} ({p.config})"
    return f"{p.file}:{p.line} toggle {what} changed {changed} (`{text}`)"


def describe(p: Point, source: dict[str, list[str]]) -> str:
    """A gap in one line: where, what, its count, and the text of its line."""
    lines = source.get(p.file, [])
    text = lines[p.line - 1].strip() if 0 < p.line <= len(lines) else ""
    if p.kind == "toggle":
        return f"{p.file}:{p.line} toggle {p.what} ({p.config}) changed {p.count}x (`{text}`)"
    span = f" (lines {p.span[0]}-{p.span[-1]})" if len(p.span) > 1 else ""
    return f"{p.file}:{p.line} {p.what}{span} ran {p.count}x: `{text}`"
