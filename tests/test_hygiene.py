# SPDX-License-Identifier: Apache-2.0
"""Rules the test files themselves keep, checked by reading their source."""

from __future__ import annotations

import ast
import re
import subprocess
from pathlib import Path

TESTS = Path(__file__).resolve().parent


def _decorator_name(node: ast.expr) -> str:
    target = node.func if isinstance(node, ast.Call) else node
    return target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")


def test_every_given_sets_its_deadline() -> None:
    """Every Hypothesis ``@given`` carries ``@settings(deadline=...)``: no test left at the
    200 ms default, which the first example's numba compile can miss."""
    missing = []
    for path in sorted(TESTS.glob("test_*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            names = [_decorator_name(d) for d in node.decorator_list]
            if "given" not in names:
                continue
            deadline = any(
                _decorator_name(d) == "settings"
                and isinstance(d, ast.Call)
                and any(k.arg == "deadline" for k in d.keywords)
                for d in node.decorator_list
            )
            if not deadline:
                missing.append(f"{path.name}::{node.name}")
    assert not missing, f"@given without @settings(deadline=...): {missing}"


def test_a_missing_teapot_fails_plainly_and_no_test_fetches_it(monkeypatch, tmp_path) -> None:
    """The teapot fixture names the missing file and `make setup` / the fetch script; no test
    file runs the fetch itself (the Makefile's setup does, before pytest)."""
    import pytest

    from model.render import meshes
    from tests.conftest import teapot_path

    missing = tmp_path / "teapot.bez"
    monkeypatch.setattr(meshes, "TEAPOT_PATH", missing)
    with pytest.raises(pytest.fail.Exception) as caught:
        teapot_path()
    message = str(caught.value)
    assert str(missing) in message and "make setup" in message, message
    assert meshes.TEAPOT_FETCH in message and "\n" not in message, message
    this = Path(__file__).resolve()
    fetching = [
        p.name
        for p in sorted(TESTS.glob("test_*.py"))
        if p.resolve() != this and "TEAPOT_FETCH" in p.read_text()
    ]
    assert not fetching, f"tests that fetch the teapot themselves: {fetching}"


def test_the_project_speaks_of_itself_not_of_its_tracker() -> None:
    """No tracked text file refers to a tracker entry by number ("issue" and a number): code,
    docs and tests say what a thing does and why."""
    root = TESTS.parent
    listed = subprocess.run(
        ["git", "ls-files", "-z"], cwd=root, capture_output=True, text=True, check=True
    ).stdout.split("\0")
    pattern = re.compile(r"\bissues?\s*#?\d", re.IGNORECASE)
    found = []
    for name in filter(None, listed):
        path = root / name
        if not path.is_file() or path.suffix in {".bin", ".png", ".hex", ".json"}:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if pattern.search(line):
                found.append(f"{name}:{number}: {line.strip()}")
    assert not found, "\n".join(found)
