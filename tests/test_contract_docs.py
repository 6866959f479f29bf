# SPDX-License-Identifier: Apache-2.0
"""The contract tables of docs/<unit>.md point at tests that exist.

Each unit's page opens with "## Contract: every sentence and its test": a table
``| # | contract sentence | checked by |`` with one row per claim of the unit's contract.  Every
``path::test_name`` in "checked by" must name a test function that exists in that file
(``def name(`` or ``async def name(``), so renaming or deleting a test the contract relies on
fails here.  A row without a test is refused: a sentence of the contract is either tested or
removed from it.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
HEADING = "## Contract: every sentence and its test"
# unit page -> (title, README section that links it, fewest contract rows)
UNITS = {
    "divider": ("Shift-add divider (`divider_shift`)", "## Shift-add divider", 50),
    "gouraud": ("Segment Gouraud unit (`gouraud_segment`)", "## Segment Gouraud unit", 65),
    "specular": ("Specular unit (`specular_unit`, patent UA 71489)", "## Specular unit", 70),
}
REFERENCE = re.compile(r"((?:[\w.-]+/)*[\w.-]+\.py)::(\w+)")
CELL_SPLIT = re.compile(r"(?<!\\)\|")


def contract_rows(unit: str) -> list[tuple[int, str, str]]:
    """(number, sentence, checked by) of every row of the unit's contract table."""
    text = (DOCS / f"{unit}.md").read_text()
    assert HEADING in text, f"docs/{unit}.md has no section {HEADING!r}"
    section = text.split(HEADING, 1)[1]
    section = re.split(r"^## ", section, maxsplit=1, flags=re.M)[0]
    table = [line.strip() for line in section.splitlines() if line.strip().startswith("|")]
    assert table, f"docs/{unit}.md: no table under {HEADING!r}"
    header = [c.strip() for c in CELL_SPLIT.split(table[0].strip("|"))]
    assert header[0] == "#" and header[-1] == "checked by" and len(header) == 3, header
    assert header[1].startswith("contract sentence"), header
    assert set(table[1].replace("|", "").strip()) <= set("-: "), table[1]
    rows = []
    for line in table[2:]:
        cells = [c.strip() for c in CELL_SPLIT.split(line.strip().strip("|"))]
        assert len(cells) == 3, f"docs/{unit}.md: row with {len(cells)} cells: {line}"
        number, sentence, checked_by = cells
        assert number.isdigit(), f"docs/{unit}.md: row number {number!r}: {line}"
        rows.append((int(number), sentence, checked_by))
    return rows


def defines(path: Path, name: str) -> bool:
    return (
        re.search(rf"^\s*(?:async\s+)?def {re.escape(name)}\(", path.read_text(), re.M) is not None
    )


@pytest.mark.parametrize("unit", list(UNITS))
def test_page_title_and_contract_section(unit: str) -> None:
    """A page per unit, titled with the unit's name, whose first section is the contract."""
    title, _, _ = UNITS[unit]
    text = (DOCS / f"{unit}.md").read_text()
    assert text.splitlines()[0] == f"# {title}"
    first_section = re.search(r"^## .*$", text, re.M)
    assert first_section is not None and first_section.group(0) == HEADING


@pytest.mark.parametrize("unit", list(UNITS))
def test_every_row_is_numbered_and_has_a_sentence_and_a_check(unit: str) -> None:
    rows = contract_rows(unit)
    _, _, fewest = UNITS[unit]
    assert len(rows) >= fewest, f"docs/{unit}.md: {len(rows)} contract rows, expected >= {fewest}"
    assert [n for n, _, _ in rows] == list(range(1, len(rows) + 1)), "rows numbered 1..n"
    for number, sentence, checked_by in rows:
        assert sentence, f"docs/{unit}.md row {number}: no sentence"
        assert checked_by, f"docs/{unit}.md row {number}: empty 'checked by'"
        assert REFERENCE.search(checked_by), (
            f"docs/{unit}.md row {number}: no test named: {checked_by!r} (test the sentence "
            "or remove it from the contract)"
        )


@pytest.mark.parametrize("unit", list(UNITS))
def test_every_reference_names_an_existing_test(unit: str) -> None:
    """``path::name``: the file exists and defines ``name`` (a test function, sync or async)."""
    missing = []
    for number, _, checked_by in contract_rows(unit):
        for path, name in REFERENCE.findall(checked_by):
            file = ROOT / path
            if not name.startswith("test_"):
                missing.append(f"row {number}: {path}::{name} is not a test function name")
            elif not file.is_file():
                missing.append(f"row {number}: {path} does not exist")
            elif not defines(file, name):
                missing.append(f"row {number}: {path} defines no {name}()")
    assert not missing, f"docs/{unit}.md:\n" + "\n".join(missing)


def test_every_contract_test_is_cited() -> None:
    """Each test of tests/test_contract_<unit>.py checks a sentence some contract row cites."""
    cited = {
        (path, name)
        for unit in UNITS
        for _, _, checked_by in contract_rows(unit)
        for path, name in REFERENCE.findall(checked_by)
    }
    orphans = []
    for unit in UNITS:
        path = f"tests/test_contract_{unit}.py"
        names = re.findall(r"^def (test_\w+)\(", (ROOT / path).read_text(), re.M)
        assert names, path
        orphans += [f"{path}::{n}" for n in names if (path, n) not in cited]
    assert not orphans, "contract tests no row cites:\n" + "\n".join(orphans)


@pytest.mark.parametrize("unit", list(UNITS))
def test_readme_unit_section_links_its_page(unit: str) -> None:
    _, section, _ = UNITS[unit]
    readme = (ROOT / "README.md").read_text()
    start = readme.index(section)
    end = readme.find("\n## ", start + 1)
    assert f"(docs/{unit}.md)" in readme[start : end if end != -1 else None]


def test_a_renamed_test_is_caught(tmp_path: Path) -> None:
    """The check itself: a reference to a test that does not exist is reported."""
    fake = tmp_path / "t.py"
    fake.write_text("async def test_kept(dut):\n    pass\n\ndef test_other():\n    pass\n")
    assert defines(fake, "test_kept") and defines(fake, "test_other")
    assert not defines(fake, "test_renamed") and not defines(fake, "test_kep")
    row = "| 1 | a sentence | `sim/tb_divider.py::test_no_such_test` |"
    cells = [c.strip() for c in CELL_SPLIT.split(row.strip().strip("|"))]
    assert REFERENCE.findall(cells[2]) == [("sim/tb_divider.py", "test_no_such_test")]
    assert not defines(ROOT / "sim/tb_divider.py", "test_no_such_test")
