# SPDX-License-Identifier: Apache-2.0
"""The legal ranges the unit pages give under "## Parameters" are the ones the model refuses
outside: for every integer field of a unit's configuration the page writes
``NAME`` [default, lo..hi ...], and the configuration is built at lo - 1, lo, hi and hi + 1:
a ValueError exactly at lo - 1 and hi + 1.  Where the RTL has a rule
``PARAMETER_ERROR_<NAME>_must_be_<lo>_to_<hi>``, its ends are the page's too."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from model.units import divider, gouraud, specular

ROOT = Path(__file__).resolve().parent.parent
UNITS = {
    "divider": (divider.DEFAULT, "divider_shift"),
    "gouraud": (gouraud.DEFAULT, "gouraud_segment"),
    "specular": (specular.DEFAULT, "specular_unit"),
}
# The other fields a bound is checked with where the default's bind first (the pages name the
# joint rules): recip_bits = 1 needs k_width <= 2; a_int_bits = 1 holds a only up to n = 63 with
# the patent's tables; at a_frac_bits = 1 the largest a rounds to 8, which needs 4 integer bits.
COMPANIONS = {
    ("divider", "recip_bits"): {"k_width": 1},
    ("specular", "a_int_bits"): {"n_last": 63},
    ("specular", "a_frac_bits"): {"a_int_bits": 4},
}
RANGE = re.compile(r"`([A-Z][A-Z0-9_]*)`\s+\[(\d+),\s+(\d+)\.\.(\d+)")
CHOICES = re.compile(r"`([A-Z][A-Z0-9_]*)`\s+\[(\d+):\s+([\d, or]+)\]")


def parameters_section(unit: str) -> str:
    text = (ROOT / "docs" / f"{unit}.md").read_text()
    section = text.split("\n## Parameters\n", 1)[1]
    return re.split(r"^## ", section, maxsplit=1, flags=re.M)[0]


def int_fields(cfg) -> list[str]:
    return [f.name for f in dataclasses.fields(cfg) if isinstance(getattr(cfg, f.name), int)]


def page_ranges(unit: str) -> dict[str, tuple[int, int, int]]:
    """field -> (default, lo, hi) as the page writes them."""
    return {
        name.lower(): (int(default), int(lo), int(hi))
        for name, default, lo, hi in RANGE.findall(parameters_section(unit))
    }


def refused(cfg, **fields) -> bool:
    try:
        dataclasses.replace(cfg, **fields)
    except ValueError:
        return True
    return False


@pytest.mark.parametrize("unit", UNITS)
def test_the_page_gives_every_field_a_range_or_its_values(unit: str) -> None:
    cfg, _ = UNITS[unit]
    section = parameters_section(unit)
    given = set(page_ranges(unit)) | {name.lower() for name, _, _ in CHOICES.findall(section)}
    # NUM_TABLES is the RTL's count of the k_ranges entries (test_the_k_ranges_parameters)
    given -= {"num_tables"} if unit == "specular" else set()
    assert given == set(int_fields(cfg)), (unit, sorted(given ^ set(int_fields(cfg))))


def test_the_k_ranges_parameters_are_refused_exactly_outside_the_page_range() -> None:
    """NUM_TABLES (the k_ranges entries) and K0..K3 (each table's k) in the page's ranges."""
    section = parameters_section("specular")
    default, lo, hi = page_ranges("specular")["num_tables"]
    assert default == len(specular.DEFAULT.k_ranges)
    cuts = [1, 2, 3, 6, 50, 400]  # n_hi of the first tables of a set of `tables` tables

    def tables(count: int, k: int = 1) -> tuple[tuple[int, int, int], ...]:
        if count == 0:
            return ()
        ends = [*cuts[: count - 1], 1000]
        return tuple((a + 1, b, k) for a, b in zip([0, *ends], ends, strict=False))

    # a = sqrt(n / k) up to sqrt(1000) at k = 1: ROM 9's words get 8 integer bits
    base = dataclasses.replace(specular.DEFAULT, a_int_bits=8)
    outcome = {v: refused(base, k_ranges=tables(v)) for v in (lo - 1, lo, hi, hi + 1)}
    assert outcome == {lo - 1: True, lo: False, hi: False, hi + 1: True}, outcome
    k_lo, k_hi = map(int, re.search(r"the k of each table, (\d+)\.\.(\d+)", section).groups())
    outcome = {k: refused(base, k_ranges=tables(1, k)) for k in (k_lo - 1, k_lo, k_hi, k_hi + 1)}
    assert outcome == {k_lo - 1: True, k_lo: False, k_hi: False, k_hi + 1: True}, outcome


@pytest.mark.parametrize(
    ("unit", "field"), [(u, f) for u in UNITS for f in int_fields(UNITS[u][0])]
)
def test_the_model_refuses_exactly_outside_the_page_range(unit: str, field: str) -> None:
    cfg, top = UNITS[unit]
    ranges = page_ranges(unit)
    if field not in ranges:  # a set of values (Gouraud P)
        (default, values) = next(
            (d, v) for n, d, v in CHOICES.findall(parameters_section(unit)) if n.lower() == field
        )
        listed = {int(v) for v in re.findall(r"\d+", values)}
        assert int(default) == getattr(cfg, field) and int(default) in listed
        accepted = {v for v in range(max(listed) * 2 + 1) if not refused(cfg, **{field: v})}
        assert accepted == listed, (unit, field, sorted(accepted))
        return
    default, lo, hi = ranges[field]
    assert default == getattr(cfg, field), (unit, field, default)
    base = dataclasses.replace(cfg, **COMPANIONS.get((unit, field), {}))
    outcome = {v: refused(base, **{field: v}) for v in (lo - 1, lo, hi, hi + 1)}
    assert outcome == {lo - 1: True, lo: False, hi: False, hi + 1: True}, (unit, field, outcome)
    rtl = (ROOT / "rtl" / f"{top}.v").read_text()
    for rule_lo, rule_hi in re.findall(
        rf"PARAMETER_ERROR_{field.upper()}_must_be_(\d+)_to_(\d+)\b", rtl
    ):
        assert (int(rule_lo), int(rule_hi)) == (lo, hi), (top, field, rule_lo, rule_hi)
