# SPDX-License-Identifier: Apache-2.0
"""Shared pytest set-up: the two tiers (tests/tiers.py), the RTL regression summary, the seed
variables checked once, the teapot file every test that reads it asks for."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import pytest


def pytest_configure(config) -> None:
    """Refuse a bad seed variable once, in one line, before any test runs."""
    from sim.runner import env_seed

    for variable in ("BENCH_SEED", "SOAK_SEED"):
        try:
            env_seed(variable)
        except ValueError as exc:
            raise pytest.UsageError(str(exc)) from None


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items) -> None:
    """Mark the tests ``tests/tiers.py`` names ``slow``, and the ``sim`` tests whose simulator
    SIM does not choose ``sim_fixed`` (before ``-m`` deselects); a name there that matches no
    collected test of its file is an error."""
    from tests.tiers import classify, sim_fixed

    slow, stale = classify([item.nodeid for item in items])
    for item in items:
        if item.nodeid in slow:
            item.add_marker(pytest.mark.slow)
        if item.get_closest_marker("sim") and sim_fixed(item.nodeid):
            item.add_marker(pytest.mark.sim_fixed)
    if stale:
        raise pytest.UsageError(
            "tests/tiers.py names tests that do not exist (renamed or removed?): "
            + ", ".join(stale)
        )


def teapot_path() -> Path:
    """data/teapot.bez ($SHADING_DATA/teapot.bez if set), or a plain test failure naming the
    file and how to fetch it: tests never fetch it themselves."""
    from model.render import meshes

    path = meshes.TEAPOT_PATH
    if not path.is_file():
        pytest.fail(
            f"{path} is missing: the teapot's patches are fetched by `make setup` "
            f"(or {meshes.TEAPOT_FETCH}) before the tests run",
            pytrace=False,
        )
    return path


@pytest.fixture(scope="session")
def teapot_file() -> Path:
    """The teapot's Bezier patch file: every test that reads it (the built-in scene "teapot",
    the demo's default scene, the fit record's scene) asks for this fixture."""
    return teapot_path()


def record_sim(request, records: list[dict]) -> None:
    """Attach a bench's counts to the test report (user_properties travel through xdist)."""
    for rec in records:
        request.node.user_properties.append(("sim", rec))


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    totals: dict[str, dict[str, int]] = defaultdict(
        lambda: {"tests": 0, "compared": 0, "jobs": 0, "cycles": 0}
    )
    seeds: list[str] = []
    for report in terminalreporter.stats.get("passed", []) + terminalreporter.stats.get(
        "failed", []
    ):
        if report.when != "call":
            continue
        for key, rec in report.user_properties:
            if key == "sim":
                t = totals[rec["unit"]]
                t["tests"] += 1
                t["compared"] += rec["compared"]
                t["jobs"] += rec["jobs"]
                t["cycles"] += rec.get("cycles", 0)
                if "seed" in rec:
                    seeds.append(f"{rec['unit']}: seed {rec['seed']}, {rec['cycles']} cycles")
    if not totals:
        return
    tr = terminalreporter
    tr.section("RTL regression summary (every result compared bit for bit with the model)")
    for unit, t in sorted(totals.items()):
        tr.write_line(
            f"{unit}: {t['compared']} results compared in {t['jobs']} jobs, "
            f"{t['cycles']} cycles (every output checked in each) over {t['tests']} tests"
        )
    for line in seeds:
        tr.write_line(f"soak {line} (replay with SOAK_SEED=<seed>)")
    tr.write_line(f"all units: {sum(t['compared'] for t in totals.values())} results compared")
