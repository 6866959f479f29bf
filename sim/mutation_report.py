# SPDX-License-Identifier: Apache-2.0
"""The report of ``make mutants`` (sim/mutation.py) from its record (docs/mutants.json): the
per-design table and the list of proven equivalent mutants and survivors, as
docs/verification.md carries them (``write_docs`` puts them there; tests/test_mutation.py checks
that they are the record's)."""

from __future__ import annotations

from pathlib import Path


def table(rec: dict) -> str:
    """The per-design table of a record (docs/verification.md carries it)."""
    rows = [
        "| design | mutants | killed by its committed set | killed by a stronger check "
        "| proven equivalent | survivors | list + build + runs + proofs, s |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, d in rec["designs"].items():
        first = d["killed"][d["vector_set"]]
        later = sum(d["killed"].values()) - first
        t = d["seconds"]
        equivalent = len(d["equivalent"]) if d.get("proved", True) else "not tried"
        rows.append(
            f"| `{name}` | {d['mutants']} | {first} | {later} | {equivalent} "
            f"| {len(d['survivors'])} "
            f"| {t['list']} + {t['build']} + {t['runs']} + {t['proofs']} |"
        )
    return "\n".join(rows) + "\n"


def listing(rec: dict) -> str:
    """The record's equivalent mutants and survivors, by design, id and mutate command (the
    list docs/verification.md carries under the table)."""
    lines = []
    for name, d in rec["designs"].items():
        for kind, key in (("proven equivalent", "equivalent"), ("survivor", "survivors")):
            for o in d[key]:
                how = f" ({o['equivalent']})" if o.get("equivalent") else ""
                lines.append(f"- `{name}` {kind} {o['id']}{how}: `{o['command']}`")
    return "\n".join(lines) + "\n"


def write_docs(rec: dict, path: Path) -> None:
    """Put the record's table and listing between their markers in ``path``."""
    text = path.read_text()
    for name, body in (("table", table(rec)), ("listing", listing(rec))):
        start, end = f"<!-- mutation {name} -->\n", f"<!-- end mutation {name} -->"
        head, rest = text.split(start, 1)
        text = head + start + body + end + rest.split(end, 1)[1]
    path.write_text(text)
