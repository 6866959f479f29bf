# SPDX-License-Identifier: Apache-2.0
"""The Python examples of the pages run as written: each ```python block of the pages below is
executed in a fresh namespace (from the repository's folder), and must not raise."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = ("README.md", "docs/meshes.md", "docs/scenes.md", "docs/api.md")
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def blocks() -> list[tuple[str, int, str]]:
    found = []
    for page in PAGES:
        text = (ROOT / page).read_text()
        for m in BLOCK.finditer(text):
            found.append((page, text[: m.start()].count("\n") + 1, m.group(1)))
    return found


def test_the_pages_have_python_examples() -> None:
    assert {page for page, _, _ in blocks()} == set(PAGES)


@pytest.mark.parametrize(("page", "line", "code"), blocks(), ids=lambda x: str(x)[:20])
def test_python_example_runs(page: str, line: int, code: str, monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    exec(compile(code, f"{page}:{line}", "exec"), {"__name__": f"example_{line}"})
