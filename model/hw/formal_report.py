# SPDX-License-Identifier: Apache-2.0
"""The formal jobs' outcomes and the printed table (make formal; docs/formal.md).

``summarise(job, rc, log)`` reads a SymbiYosys or Yosys log into (status, ok, detail, rows);
``config_label``, ``table`` and ``to_json`` report a list of ``model.hw.formal.FormalResult``.
``model.hw.formal`` runs the jobs and re-exports ``table`` and ``to_json``.  A ``bmc`` job is a
bounded check that must pass ("bounded to depth N"); a ``mutant`` job must fail with its
property.  Layer 2: imports nothing of the project.
"""

from __future__ import annotations

import re
from typing import Protocol


class FormalJob(Protocol):
    """What is read of a ``model.hw.formal.FormalJob`` (not imported: formal imports this)."""

    unit: str
    kind: str
    config: str
    reset_all: int
    depth: int
    properties: tuple[str, ...]
    mutant: str


class FormalResult(Protocol):
    """What is read of a ``model.hw.formal.FormalResult``."""

    job: FormalJob
    status: str
    ok: bool
    seconds: float
    rows: tuple[tuple[str, str], ...]

    def to_json(self) -> dict: ...


FAILED = re.compile(r"failed assertion \S*?\.(\w+) at .*? step (\d+)")
REACHED = re.compile(r"Reached cover statement in step (\d+) at \S+: (?:\S*\.)?(\w+)")


def summarise(job: FormalJob, rc: int, log: str) -> tuple[str, bool, str, list]:
    if job.kind == "equiv":
        proven = rc == 0 and "Equivalence successfully proven!" in log
        counts = re.findall(r"Of those cells (\d+) are proven and (\d+) are unproven", log)
        status = "proven" if proven else ("failed" if counts else "error")
        detail = f"{counts[-1][0]} $equiv cells proven, {counts[-1][1]} unproven" if counts else ""
        detail = detail or tail(log)
        return status, proven, detail, [(job.properties[0], status)]
    done = re.search(r"DONE \((\w+), rc=(\d+)\)", log)
    if done is None or done.group(1) == "ERROR":
        return "error", False, tail(log), [(p, "error") for p in job.properties]
    if job.kind == "cover":
        reached: dict[str, int] = {}
        for m in REACHED.finditer(log):
            reached.setdefault(m.group(2), int(m.group(1)))
        rows = [
            (c, f"reached in step {reached[c]}" if c in reached else "unreached")
            for c in job.properties
        ]
        missing = [c for c in job.properties if c not in reached]
        ok = not missing and done.group(1) == "PASS"
        detail = f"unreached: {', '.join(missing)}" if missing else f"{len(reached)} reached"
        return ("reached" if ok else "unreached"), ok, detail, rows
    fails = [(m.group(1), int(m.group(2))) for m in FAILED.finditer(log)]
    if job.kind == "prove":
        proven = done.group(1) == "PASS" and "successful proof by k-induction" in log
        if proven:
            rows = [(p, "proven") for p in job.properties]
            return "proven", True, f"k-induction, depth {job.depth}", rows
        detail = "; ".join(f"{n} at step {s}" for n, s in fails) or tail(log)
        return "failed", False, detail, [(p, "failed") for p in job.properties]
    if job.kind == "bmc":  # a bounded check: no assert fails within the depth
        if done.group(1) == "PASS":
            rows = [(p, f"bounded to depth {job.depth}") for p in job.properties]
            return "bounded", True, f"no failure within depth {job.depth}", rows
        detail = "; ".join(f"{n} at step {s}" for n, s in fails) or tail(log)
        return "failed", False, detail, [(p, "failed") for p in job.properties]
    # mutant: bmc must fail, with the property it is meant to break
    want = job.properties[0]
    hit = [s for n, s in fails if n == want]
    if done.group(1) == "FAIL" and hit:
        step = f"failed at step {hit[0]}"
        return "failed", True, f"{want} fails at step {hit[0]}", [(want, step)]
    if done.group(1) == "PASS":
        bound = f"bounded to depth {job.depth}"
        return "bounded", False, f"no failure within depth {job.depth}", [(want, bound)]
    return "failed", False, f"failed elsewhere: {fails}", [(want, "failed elsewhere")]


def tail(log: str, lines: int = 8) -> str:
    return " | ".join(ln.strip() for ln in log.strip().splitlines()[-lines:])


def config_label(job: FormalJob) -> str:
    text = f"{job.config}, RESET_ALL={job.reset_all}"
    if job.mutant:
        text += f", mutant {job.mutant}"
    return text


def table(results: list[FormalResult]) -> str:
    """The printed table: one row per property and job (property, unit, configuration, result,
    time)."""
    head = ("property", "unit", "configuration", "result", "time")
    rows = []
    for r in results:
        kind = {"prove": "", "cover": "cover ", "mutant": "must fail: ", "equiv": "equiv "}
        kind["bmc"] = ""
        for prop, status in r.rows:
            if r.job.kind == "prove" and status == "proven":
                status = f"proven (k-induction, depth {r.job.depth})"
            mark = "" if r.ok else "  <-- NOT OK"
            rows.append(
                (
                    kind[r.job.kind] + prop,
                    r.job.unit,
                    config_label(r.job),
                    status + mark,
                    f"{r.seconds:.1f} s",
                )
            )
    widths = [max(len(x[i]) for x in [head, *rows]) for i in range(len(head))]
    lines = [
        " | ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)) for row in [head, *rows]
    ]
    lines.insert(1, "-+-".join("-" * w for w in widths))
    return "\n".join(lines)


def to_json(results: list[FormalResult]) -> dict:
    return {
        "ok": all(r.ok for r in results),
        "results": [r.to_json() for r in results],
    }
