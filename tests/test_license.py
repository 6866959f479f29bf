# SPDX-License-Identifier: Apache-2.0
"""The licence an engineer can build on: Apache-2.0, stated once in LICENSE, in pyproject.toml and
by an SPDX line near the top of every source file (Python, Verilog, shell, TOML, FuseSoC cores,
file lists, the Makefile and the CI script)."""

from __future__ import annotations

import subprocess

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TAG = "SPDX-License-Identifier: Apache-2.0"
SOURCE_SUFFIXES = {".py", ".v", ".vh", ".sh", ".toml", ".core", ".f"}
SOURCE_NAMES = {"Makefile", "run"}


def tracked() -> list[Path]:
    out = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    return [ROOT / name for name in out.split()]


def sources() -> list[Path]:
    return [
        p
        for p in tracked()
        if p.suffix in SOURCE_SUFFIXES
        or p.name in SOURCE_NAMES
        or (p.suffix == "" and p.is_file() and p.read_bytes()[:2] == b"#!")
    ]


def test_licence_file_is_apache_2() -> None:
    text = (ROOT / "LICENSE").read_text()
    assert "Apache License" in text and "Version 2.0, January 2004" in text


def test_pyproject_names_the_licence() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == "Apache-2.0"
    assert project["license-files"] == ["LICENSE"]


def test_there_are_sources_to_check() -> None:
    kinds = {p.suffix or p.name for p in sources()}
    assert {".py", ".v", "Makefile"} <= kinds, kinds


@pytest.mark.parametrize("path", sources(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_source_file_carries_the_spdx_line(path: Path) -> None:
    head = path.read_text().splitlines()[:4]
    where = path.relative_to(ROOT)
    assert any(TAG in line for line in head), f"{where}: no '{TAG}' in its first lines"
