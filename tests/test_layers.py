# SPDX-License-Identifier: Apache-2.0
"""The package map holds: imports point down only, no private name crosses a module, no cycle.

Layers (model/__init__.py): ``model.units`` 1 < ``model.render`` and ``model.hw`` 2 <
``model.study`` and ``sim`` 3 < ``model.fit`` 4 < ``model.cli`` 5; tests sit on top.  Every
import of every module (function-level ones included) is read with ``ast``:

* a module imports only its own package or a lower layer (``model/__init__.py`` re-exports the
  units; ``model/__main__.py`` runs the command line), and nothing under ``model/`` imports
  ``sim``;
* no ``_private`` name of one project module is imported or reached (``module._name``) from
  another, tests included — the batched paths the renderer needs are public calls;
* the project's modules import each other without a cycle;
* no module is over ``MAX_LINES`` lines unless its docstring gives the reason (a line starting
  ``Size:``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
MAX_LINES = 500
LAYERS = {
    "model.units": 1,
    "model.render": 2,
    "model.hw": 2,
    "model.study": 3,
    "sim": 3,
    "model.fit": 4,
    "model.cli": 5,
}
TOP = 9  # tests and scripts


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


SOURCES = {
    module_name(p): p
    for folder in ("model", "sim", "tests", "scripts")
    for p in sorted((ROOT / folder).rglob("*.py"))
}


def package_of(module: str) -> str:
    for pkg in sorted(LAYERS, key=len, reverse=True):
        if module == pkg or module.startswith(pkg + "."):
            return pkg
    return module.split(".")[0]


def layer(module: str) -> int:
    return LAYERS.get(package_of(module), TOP)


def resolve(name: str) -> str | None:
    """The project module an import names (``model.units.specular.config`` or a package)."""
    while name:
        if name in SOURCES:
            return name
        name = name.rpartition(".")[0]
    return None


def imports(module: str) -> list[tuple[str, str | None, int]]:
    """(imported project module, imported name or None, line) of every import in ``module``."""
    tree = ast.parse(SOURCES[module].read_text())
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                target = resolve(alias.name)
                if target:
                    found.append((target, None, node.lineno))
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                sub = resolve(f"{node.module}.{alias.name}")
                if sub and sub != resolve(node.module):
                    found.append((sub, None, node.lineno))  # a submodule
                elif resolve(node.module):
                    found.append((resolve(node.module), alias.name, node.lineno))
    return found


def test_every_import_points_down() -> None:
    wrong = []
    for module in SOURCES:
        if module in ("model", "model.__main__"):
            continue
        for target, _, line in imports(module):
            if module.startswith("model") and target.startswith("sim"):
                wrong.append(f"{module}:{line} imports {target}: model never imports sim")
            elif package_of(target) != package_of(module) and layer(target) >= layer(module):
                wrong.append(
                    f"{module}:{line} imports {target} (layer {layer(target)} >= {layer(module)})"
                )
    assert not wrong, "\n".join(wrong)


def private_reaches(module: str) -> list[str]:
    """``from x import _name`` and ``x._name`` where x is another project module."""
    tree = ast.parse(SOURCES[module].read_text())
    bound: dict[str, str] = {}
    out = []
    for target, name, line in imports(module):
        if name and name.startswith("_") and not name.startswith("__") and target != module:
            out.append(f"{module}:{line} imports {target}.{name}")
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                sub = resolve(f"{node.module}.{alias.name}")
                if sub:
                    bound[alias.asname or alias.name] = sub
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if resolve(alias.name) and alias.asname:
                    bound[alias.asname] = resolve(alias.name)
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in bound
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
        ):
            out.append(f"{module}:{node.lineno} reaches {bound[node.value.id]}.{node.attr}")
    return out


def test_no_private_name_crosses_a_module() -> None:
    found = [r for module in SOURCES for r in private_reaches(module)]
    assert not found, "\n".join(found)


def test_the_private_name_check_can_fail(tmp_path: Path) -> None:
    """The probe: a module that reaches into another's private name is reported."""
    probe = ROOT / "tests" / "_layers_probe.py"
    probe.write_text("from model.units import gouraud\nX = gouraud._probe_private\n")
    try:
        SOURCES["tests._layers_probe"] = probe
        assert private_reaches("tests._layers_probe") == [
            "tests._layers_probe:2 reaches model.units.gouraud._probe_private"
        ]
    finally:
        SOURCES.pop("tests._layers_probe")
        probe.unlink()


def test_no_import_cycle() -> None:
    graph = {m: {t for t, _, _ in imports(m) if t != m} for m in SOURCES}
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for t in graph.get(m, ()):
            # a package's __init__ importing its own submodules is not a cycle
            if t.startswith(m + ".") or m.startswith(t + "."):
                continue
            if state.get(t) == 1:
                raise AssertionError("import cycle: " + " -> ".join([*stack[stack.index(t) :], t]))
            if t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in SOURCES:
        if m not in state:
            visit(m)


@pytest.mark.parametrize("module", [m for m in SOURCES if not m.startswith("tests")])
def test_module_size_has_a_reason(module: str) -> None:
    text = SOURCES[module].read_text()
    lines = text.count("\n")
    if lines <= MAX_LINES:
        return
    doc = ast.get_docstring(ast.parse(text)) or ""
    assert any(line.startswith("Size:") for line in doc.splitlines()), (
        f"{SOURCES[module].relative_to(ROOT)} has {lines} lines (> {MAX_LINES}) and no "
        "'Size:' line in its docstring saying why"
    )
