# SPDX-License-Identifier: Apache-2.0
"""Rules the test files themselves keep, checked by reading their source."""

from __future__ import annotations

import ast
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
