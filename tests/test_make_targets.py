# SPDX-License-Identifier: Apache-2.0
"""Every command the README documents goes through its own code path in CI.

CI (``.ci/run``) runs ``make test``, ``make test-slow`` and ``SIM=verilator make sim``, each
``sim_fixed`` test (its simulators do not come from SIM) once: the quick ones in the first, the
slow ones in the last.
Every other make target the README's table lists is short enough to run whole in a test, or
runs as a quick subset of the same code path (the same module and function the target calls,
on a smaller input): ``EXERCISED`` names, per target, the tests that do it.  The tests here
check that the table and ``EXERCISED`` name the same commands and that every test named exists,
and run ``make lint`` whole (the slow tier).
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# command -> the tests that run its code path (whole, or on a smaller input)
EXERCISED: dict[str, tuple[str, ...]] = {
    "make demo": ("tests/test_cli.py::test_demo_and_bench_render_a_mesh_file",),
    "make test": ("tests/test_tiers.py::test_every_slow_name_is_a_test_function",),  # CI: whole
    "make sim": ("tests/test_sim_verilator.py::test_bench_passes_under_verilator",),  # CI: whole
    "make check": ("tests/test_tiers.py::test_every_slow_name_is_a_test_function",),
    # make test with the marker "not sim": the same tests, fewer
    "make model-test": ("tests/test_tiers.py::test_every_slow_name_is_a_test_function",),
    "make lint": ("tests/test_make_targets.py::test_make_lint_passes",),
    "make roms": (
        "tests/test_divider.py::test_committed_rom_equals_fresh_generation",
        "tests/test_specular.py::test_committed_rom_equals_fresh_generation",
    ),
    "make accuracy": ("tests/test_accuracy.py::test_docs_carry_what_the_command_prints",),
    "make brdf-budget": (
        "tests/test_brdf_fixed.py::test_the_page_shows_the_budget_table_the_search_prints",
    ),
    "python -m sim bench": (
        "tests/test_fit.py::test_the_fit_proves_the_core_through_the_bench_command",
        "tests/test_sim_scene.py::test_rtl_scene_equals_model_scene_byte_for_byte",
    ),
    "make bench": (
        "tests/test_cli.py::test_bench_prints_one_table_for_scenes_and_sizes",
        "tests/test_cli_meshes.py::test_bench_load_times_every_format",
    ),
    "make trade": ("tests/test_trade.py::test_sweep_on_dask_caches_and_resumes",),
    "make synth": ("tests/test_synth.py::test_small_run_gives_sane_figures",),
    "make fit": ("tests/test_fit.py::test_fitted_rtl_equals_the_model_byte_for_byte",),
    "make vectors": ("tests/test_vectors.py::test_committed_sets_are_current",),
    "make formal": (
        "tests/test_formal.py::test_quick_protocol_properties_are_proven_by_induction",
    ),
    "make gate": ("tests/test_gate.py::test_netlist_replays_its_vector_set",),
    "make coverage": (
        "tests/test_coverage.py::test_an_unexplained_gap_and_a_stale_waiver_fail_the_run_by_name",
    ),
    "make mutants": ("tests/test_mutation.py::test_sampled_mutants_are_killed",),
    "make pictures": (
        "tests/test_pictures.py::test_every_picture_the_docs_show_exists_and_is_recorded",
    ),
}


def readme_commands() -> set[str]:
    """The commands of the README's two-command block and of its table of targets."""
    text = (ROOT / "README.md").read_text()
    table = set(re.findall(r"^\| `((?:make [a-z-]+)|(?:python -m sim bench))`", text, re.M))
    block = set(re.findall(r"^(make [a-z-]+)\s+#", text, re.M))
    return table | block


def test_every_documented_command_is_exercised() -> None:
    documented = readme_commands()
    assert documented, "no command found in README.md"
    missing = sorted(documented - set(EXERCISED))
    assert not missing, f"README commands no test exercises: {missing}"
    stale = sorted(set(EXERCISED) - documented)
    assert not stale, f"EXERCISED names commands the README does not document: {stale}"


def test_every_named_test_exists() -> None:
    for command, tests in EXERCISED.items():
        for node in tests:
            path, name = node.split("::")
            source = (ROOT / path).read_text() if (ROOT / path).is_file() else ""
            assert re.search(rf"^(async )?def {re.escape(name)}\(", source, re.M), (command, node)


def test_make_lint_passes() -> None:
    """``make lint`` whole: every RTL file under Verilator (both modes), Icarus and Yosys, then
    ruff."""
    ran = subprocess.run(["make", "lint"], cwd=ROOT, capture_output=True, text=True, timeout=900)
    log = ran.stdout + ran.stderr
    assert ran.returncode == 0, log[-4000:]
    assert "RTL files clean" in log and "All checks passed!" in log, log[-4000:]
