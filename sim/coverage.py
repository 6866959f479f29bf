# SPDX-License-Identifier: Apache-2.0
"""``make coverage`` (``python -m sim.coverage``): line and toggle coverage of every unit and of
the shading core under Verilator, every gap covered or explained.

Each unit's vector bench (sim/vectors/tb_<unit>.v, both RESET_ALL instances) is built with
``--coverage-line --coverage-toggle`` once per configuration (sim/coverage_run.py: PATH's
Verilator, as ``verilator --binary`` for the soaks, with a main that writes the coverage file;
cached by content in ``sim_build/coverage_builds/``) and replays the unit's committed vector
sets (sim/vectors/<set>/) and soaks of the configurations tests/test_soak.py soaks, at a fixed
seed (sim/soak.py: stimulus, the protocol model's prediction, every output compared in every
cycle; a run that mismatches stops the report).  The shading core's stream bench
(sim/vectors/tb_shading_core.v) replays its committed span set and random spans with idles and
stalls at the configurations tests/test_core.py runs, with n at the decoder's edges and in the
kept range and full-scale ramps of 24 lengths added (``coverage_run.core_words``; with a BRDF
highlight also one span of n = 1 at angle 0 and the largest C, whose product carries into its
top bits), every pixel compared with the model (sim/core_run.py).

Per unit, ``verilator_coverage`` merges the runs' files into ``<out>/<unit>/coverage.dat`` and
annotates the sources into ``<out>/<unit>/annotated/`` (``%000000`` marks a point never hit).
The points of the unit's own files (its ``.f`` list) are counted (sim/coverage_points.py: line
points joined over the configurations, toggle points one per configuration), every gap is
looked up in the waivers (sim/coverage_waivers.toml) and listed in ``<out>/<unit>/gaps.md``;
the table goes to ``<out>/summary.md`` and stdout.  Exit status 1 names every gap no waiver
explains and every waiver that explains no gap (stale).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

from model.hw.sources import source_list
from sim import coverage_points, vector_run
from sim.coverage_run import UNITS, plan, run_plan

WAIVERS = Path(__file__).resolve().parent / "coverage_waivers.toml"
__all__ = ["UNITS", "WAIVERS", "UnitCoverage", "main", "report", "table"]


# ------------------------------------------------------------------------------ the report
@dataclass(frozen=True)
class UnitCoverage:
    """A unit's merged coverage and its check against the waivers."""

    unit: str
    runs: tuple[str, ...]  # a summary line per run
    points: tuple[coverage_points.Point, ...]
    check: coverage_points.Check
    source: dict[str, list[str]]


def merge(unit: str, dats: list[Path], out: Path) -> Path:
    """``verilator_coverage`` merges ``dats`` into ``out/<unit>/coverage.dat`` and annotates the
    sources into ``out/<unit>/annotated/``; returns the merged file."""
    folder = out / unit
    shutil.rmtree(folder / "annotated", ignore_errors=True)
    folder.mkdir(parents=True, exist_ok=True)
    merged = folder / "coverage.dat"
    tool = "verilator_coverage"
    subprocess.run([tool, "--write", str(merged), *map(str, dats)], check=True, capture_output=True)
    annotate = [tool, "--annotate", str(folder / "annotated"), "--annotate-min", "1", str(merged)]
    subprocess.run(annotate, check=True, capture_output=True)
    return merged


def cover_unit(
    unit: str,
    waivers: list[coverage_points.Waiver],
    out: Path,
    only: set[str] | None = None,
    jobs: int = 2,
) -> UnitCoverage:
    """Run ``unit``'s plan (``only``: the runs of these names), merge, check the gaps."""
    runs = [r for r in plan(unit) if only is None or r.name in only]
    if not runs:
        raise ValueError(f"no run of {unit} is among {sorted(only or ())}")
    done = run_plan(runs, out / unit / "runs", jobs)
    merge(unit, [dat for dat, _ in done], out)
    sources = source_list(unit, vector_run.RTL_DIR)
    source = {p.name: p.read_text().splitlines() for p in sources}
    read = [
        (r.config, coverage_points.read_points(dat)) for r, (dat, _) in zip(runs, done, strict=True)
    ]
    points = coverage_points.collect(read, sources)
    checked = coverage_points.check(unit, points, waivers, source)
    return UnitCoverage(unit, tuple(line for _, line in done), tuple(points), checked, source)


def _pct(part: int, whole: int) -> str:
    return f"{100 * part / whole:.1f} %" if whole else "-"


def table(results: list[UnitCoverage]) -> str:
    """The summary table (docs/verification.md carries the same)."""
    rows = [
        "| unit | lines covered | lines explained | lines total | toggle points covered "
        "| toggle points explained | toggle points total | unexplained |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        f = r.check.figures
        rows.append(
            f"| `{r.unit}` | {f.lines_covered} ({_pct(f.lines_covered, f.lines)}) "
            f"| {f.lines_explained} | {f.lines} "
            f"| {f.toggles_covered} ({_pct(f.toggles_covered, f.toggles)}) "
            f"| {f.toggles_explained} | {f.toggles} | {len(r.check.unexplained)} |"
        )
    return "\n".join(rows) + "\n"


def gaps_text(r: UnitCoverage) -> str:
    """Every gap of a unit: the explained ones grouped by waiver, then the unexplained."""
    lines = [f"# Coverage gaps of {r.unit}", "", "Runs:", ""]
    lines += [f"- {run}" for run in r.runs] + [""]
    by_waiver: dict[coverage_points.Waiver, list[coverage_points.Point]] = defaultdict(list)
    for p, w in r.check.explained:
        by_waiver[w].append(p)
    for w, ps in by_waiver.items():
        lines += [f"## {w.category}: {w.label()}", "", w.reason, ""]
        lines += [f"- {_text(g, r)}" for g in coverage_points.group(ps)] + [""]
    if r.check.unexplained:
        lines += ["## Unexplained", ""]
        lines += [f"- {_text(g, r)}" for g in coverage_points.group(list(r.check.unexplained))]
        lines.append("")
    if r.check.stale:
        lines += ["## Stale waivers (they match no gap)", ""]
        lines += [f"- {w.label()}" for w in r.check.stale] + [""]
    return "\n".join(lines)


def _text(ps: list[coverage_points.Point], r: UnitCoverage) -> str:
    return coverage_points.describe_group(ps, r.source)


def problems(results: list[UnitCoverage]) -> list[str]:
    """Every gap without a reason (a signal's bits together) and every waiver without a gap,
    one line each."""
    out = []
    for r in results:
        for ps in coverage_points.group(list(r.check.unexplained)):
            out.append(f"{r.unit}: unexplained gap {_text(ps, r)}")
        for w in r.check.stale:
            out.append(f"{r.unit}: stale waiver {w.label()}: it matches no gap")
    return out


def report(
    unit_names: list[str],
    out: Path,
    waivers_file: Path = WAIVERS,
    only: set[str] | None = None,
    jobs: int = 2,
) -> tuple[list[UnitCoverage], list[str]]:
    """Cover every unit of ``unit_names``; write each one's gaps and the summary under ``out``.
    Returns the results and the problems (empty: every gap explained, no waiver stale)."""
    waivers = coverage_points.load_waivers(waivers_file)
    out = out.resolve()
    results = []
    for unit in unit_names:
        if only is None or any(r.name in only for r in plan(unit)):
            results.append(cover_unit(unit, waivers, out, only, jobs))
    for r in results:
        (out / r.unit / "gaps.md").write_text(gaps_text(r))
    found = problems(results)
    summary = ["# Coverage", "", table(results)]
    summary += [f"Gaps of each unit, explained or not: `{out}/<unit>/gaps.md`.", ""]
    summary += [f"- {line}" for line in found]
    (out / "summary.md").write_text("\n".join(summary) + "\n")
    return results, found


def docs_table(path: Path) -> str:
    """The coverage table of ``path`` (docs/verification.md, section "Coverage"), as ``table``
    prints it."""
    text = path.read_text()
    section = text[text.index("## Coverage") :]
    rows = [line for line in section.splitlines() if line.startswith("|")]
    head = next(i for i, line in enumerate(rows) if line.startswith("| unit | lines covered"))
    out = [rows[head], rows[head + 1]]
    for line in rows[head + 2 :]:
        if not line.startswith("| `"):
            break
        out.append(line)
    return "\n".join(out) + "\n"


def docs_problems(printed: str, path: Path) -> list[str]:
    """[] if the table of ``path`` is ``printed``; else one line saying what differs."""
    documented = docs_table(path)
    if documented == printed:
        return []
    differ = [d for d in documented.splitlines() if d not in printed.splitlines()]
    return [f"{path}: its coverage table is not this run's (rows that differ: {differ})"]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sim.coverage", description=__doc__)
    parser.add_argument("--units", nargs="+", choices=UNITS, default=list(UNITS))
    parser.add_argument("--out", type=Path, default=Path("out/coverage"))
    parser.add_argument("--waivers", type=Path, default=WAIVERS)
    parser.add_argument("--runs", nargs="+", help="only the runs of these names (e.g. divider_n4)")
    parser.add_argument("--jobs", type=int, default=2, help="builds and runs at a time")
    parser.add_argument(
        "--docs",
        type=Path,
        help="a page whose coverage table must be this run's (a run of every unit and run)",
    )
    args = parser.parse_args(argv)
    t0 = time.monotonic()
    results, found = report(
        args.units, args.out, args.waivers, set(args.runs) if args.runs else None, args.jobs
    )
    for r in results:
        print(f"{r.unit}:")
        for line in r.runs:
            print(f"  {line}")
    print(table(results), end="")
    print(f"gaps: {args.out}/<unit>/gaps.md, annotated sources: {args.out}/<unit>/annotated/")
    if args.docs and args.units == list(UNITS) and not args.runs:
        found = [*found, *docs_problems(table(results), args.docs)]
    for line in found:
        print(line)
    print(f"coverage: {len(found)} problems, {time.monotonic() - t0:.0f} s")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
