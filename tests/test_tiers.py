# SPDX-License-Identifier: Apache-2.0
"""The two tiers of the suite (tests/tiers.py): every slow name is a real test and a stale one
is refused."""

from __future__ import annotations

from pathlib import Path

from tests.tiers import SLOW, classify

ROOT = Path(__file__).resolve().parent.parent


def test_every_slow_name_is_a_test_function() -> None:
    """Statically (the collection hook in conftest.py also refuses a stale name, parameters
    included, in every run that collects its file)."""
    for key in SLOW:
        file, name = key.split("::")
        text = (ROOT / file).read_text()
        assert f"def {name.split('[')[0]}(" in text, key


def test_a_renamed_slow_test_is_refused() -> None:
    file = next(iter(SLOW)).split("::")[0]
    slow, stale = classify([f"{file}::test_that_is_there", "tests/test_other.py::test_x"])
    assert slow == set()
    assert set(stale) == {k for k in SLOW if k.startswith(file + "::")}
