# SPDX-License-Identifier: Apache-2.0
"""The Python examples of the pages run as written and print what the pages show.

Each ```python block of the pages below is executed in a fresh namespace (from the repository's
folder) and must not raise.  A line ``print(...)  # prints <output>`` must print ``<output>``:
``...`` in it stands for any text, and runs of whitespace (numpy's column padding, line wraps)
compare equal to one space.  Every ``print(`` line of a block carries such a comment, so no
example shows an output nobody compares."""

from __future__ import annotations

import io
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
# docs/fpga.md's example places and routes a unit (test_synth.py runs that call); it shows no
# output.  Every other page with a Python example is run.
SKIP = {"docs/fpga.md"}
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)
PRINTS = re.compile(r"#\s*prints\s+(.*?)\s*$")


def pages() -> list[str]:
    docs = sorted(f"docs/{p.name}" for p in (ROOT / "docs").glob("*.md"))
    return ["README.md"] + [
        p for p in docs if p not in SKIP and BLOCK.search((ROOT / p).read_text())
    ]


def blocks() -> list[tuple[str, int, str]]:
    found = []
    for page in pages():
        text = (ROOT / page).read_text()
        for m in BLOCK.finditer(text):
            found.append((page, text[: m.start()].count("\n") + 2, m.group(1)))
    return found


def squash(text: str) -> str:
    return " ".join(text.split())


def shows(expected: str, printed: str) -> bool:
    """``printed`` is what ``expected`` shows (``...`` any text, whitespace runs alike)."""
    pattern = ".*?".join(re.escape(squash(part)) for part in expected.split("..."))
    return re.fullmatch(pattern, squash(printed), re.S) is not None


def test_the_pages_have_python_examples() -> None:
    assert {"README.md", "docs/api.md", "docs/meshes.md", "docs/scenes.md"} <= set(pages())
    assert {page for page, _, _ in blocks()} == set(pages())


def test_shows_matches_as_documented() -> None:
    assert shows("[ 25. -33.3 0.1]", "[ 25.        -33.3   0.1]\n")
    assert shows("[10 11 ... 29]", "[10 11 12 13\n 28 29]\n")
    assert not shows("8 [5, 6, 7, 8]", "11 [8, 9, 10, 11]\n")
    assert not shows("3 [1, 2]", "3 [1, 2, 3]\n")  # the whole output, not a prefix


@pytest.mark.parametrize(("page", "line", "code"), blocks(), ids=lambda x: str(x)[:20])
def test_python_example_runs_and_prints_what_the_page_shows(
    page: str, line: int, code: str, monkeypatch
) -> None:
    lines = code.splitlines()
    expected = {}
    for number, text in enumerate(lines, 1):
        if "print(" in text:
            m = PRINTS.search(text)
            assert m, f"{page}:{line + number - 1}: a print without '# prints <output>': {text}"
            expected[number] = m.group(1)
    printed: dict[int, str] = {}

    def recording_print(*args, **kwargs) -> None:
        kwargs.pop("file", None)
        buffer = io.StringIO()
        print(*args, file=buffer, **kwargs)
        number = sys._getframe(1).f_lineno
        printed[number] = printed.get(number, "") + buffer.getvalue()

    monkeypatch.chdir(ROOT)
    namespace = {"__name__": f"example_{line}", "print": recording_print}
    exec(compile(code, f"{page}:{line}", "exec"), namespace)
    for number, shown in expected.items():
        where = f"{page}:{line + number - 1}"
        assert number in printed, f"{where}: printed nothing (a print over several lines?)"
        assert shows(shown, printed[number]), (
            f"{where}: the page shows {shown!r}, the example prints {printed[number]!r}"
        )
