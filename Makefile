# Two commands on a fresh machine: `make demo` and `make test` (see README.md).
# Every target creates .venv and installs what is missing by itself; a second run is quick.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
RTL    := $(wildcard rtl/*.v)
PYTEST := $(PY) -m pytest
# Parallel pytest workers for the cocotb regressions (each bench builds in its own folder).
JOBS   ?= auto

.PHONY: setup tools demo test model-test sim lint roms synth bench trade pictures accuracy clean

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
	@scripts/ensure-tools.sh iverilog vvp verilator

demo: setup tools
	$(PY) -m model demo

# All tests: the model tests and every cocotb regression.
test: setup tools
	$(PYTEST) -n $(JOBS) tests

model-test: setup
	$(PYTEST) -n $(JOBS) -m "not sim" tests

# Every cocotb regression under Icarus; WAVES=1 make sim dumps FST waveforms in sim_build/.
sim: setup tools
	$(PYTEST) -n $(JOBS) -m sim tests

# Every RTL file as Verilog-2005 three ways: Verilator -Wall in its default (SystemVerilog) mode
# and in 1364-2005 mode, and Icarus -g2005 (Yosys reads it in make synth and the tests).
lint: setup
	@scripts/ensure-tools.sh verilator iverilog
	@for f in $(RTL); do \
		verilator --lint-only -Wall $$f || exit 1; \
		verilator --lint-only -Wall --language 1364-2005 $$f || exit 1; \
		iverilog -g2005 -Wall -o /dev/null $$f || exit 1; \
	done
	@echo "verilator -Wall (default, 1364-2005), iverilog -g2005: $(words $(RTL)) RTL files clean"
	$(PY) -m ruff check model sim tests scripts
	$(PY) -m ruff format --check model sim tests scripts

roms: setup
	$(PY) -m model roms

# Every accuracy figure of the README as a worst case (exhaustive or proven), with the conditions
# it holds under: the table the README carries (tests/test_accuracy.py checks they agree).
accuracy: setup
	$(PY) -m model accuracy

# Pixels per second of the bit-exact pipeline against the float references (one run, ratios),
# the seconds a 70k-triangle mesh file takes to load in each format (target: under 2 s), then the
# RTL scene co-simulation (sphere 64 x 64 through the three units under Icarus).
bench: setup tools
	$(PY) -m model bench
	$(PY) -m model bench-load
	$(PY) -m sim bench

# The speed/accuracy trade: sweep every knob over the built-in scenes (Dask; cached, resumable).
trade: setup
	$(PY) -m model trade

# Every picture README.md and docs/ show, made again: the demo's sheet (copied to
# docs/demo_sheet.png), the trade figure, and docs/pictures.json, what each was made from
# (tests/test_pictures.py checks that they are current).
pictures: setup
	$(PY) -m model demo
	$(PY) -m model trade --figure docs/
	$(PY) -m model.study.report pictures

# Yosys (iCE40) synthesis of every unit at its default configuration: resource table.
synth: setup
	@scripts/ensure-tools.sh yosys
	$(PY) scripts/synth.py

clean:
	rm -rf sim_build out .pytest_cache .ruff_cache
