# SPDX-License-Identifier: Apache-2.0
"""The specular unit's formal jobs (make formal; docs/formal.md): its configurations and
parameters, property numbers, covers, induction helper connections and deliberate errors.

``model.hw.formal`` runs them like the divider's and the Gouraud unit's; this module holds the
unit's data only.  The property file is ``formal/specular_unit_props.v``: port-level timing
(busy, valid), the n error flag and reset; with DATA (``data_job``: 1 in every job at ``small``,
2 in the bounded check at ``default`` and its mutant) also every intensity against the reference
formula of ``formal/specular_unit_datapath.v`` (``sources``), the ROMs as their images or, at
the default, the unit's reads and products with their addresses and operands asserted
(``memory``).
Without DATA the data output is not observed but in the proof of ``intensity_zero_on_n_err``
(ARITH), and both ROMs are removed with their read data left free (``MEMORY``): the ROM
contents take no part.  Layer 2: imports ``model.units`` and ``model.hw.mutants``
(``Mutant``).
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Protocol

from model.hw.mutants import Mutant
from model.units import rom, specular


class FormalJob(Protocol):
    """What is read of a ``model.hw.formal.FormalJob`` (not imported: formal imports this)."""

    config: str
    kind: str


UNIT = "specular_unit"
FORMAL_DIR = rom.ROM_DIR.parent.parent / "formal"  # beside rtl/, as model.hw.formal.FORMAL_DIR
REFERENCE_FILE = FORMAL_DIR / "specular_unit_datapath.v"  # specular_unit_ref: the formula
# default: SpecularConfig's default (the RTL's default parameters, LEN_WIDTH 11, FILL_LATENCY 8);
# small: every width reduced and n = 1..8 kept (all four tables, ROM 12 of 4 x 8 words), where
# the data path is proven unbounded
SMALL = specular.SpecularConfig(
    c_int_bits=2,
    c_frac_bits=3,
    z_int_bits=3,
    z_frac_bits=4,
    len_width=3,
    a_int_bits=1,
    a_frac_bits=4,
    rom_addr_bits=3,
    rom_data_bits=5,
    out_width=2,
    n_first=1,
    n_last=8,
)
# kept: the kept range of n that shading fit emits (N_FIRST = 17, N_LAST = 40: ROM 9 holds a
# for those n only, every other n is an error), its protocol proven like the default's
CONFIGS = {"default": specular.DEFAULT, "small": SMALL, "kept": specular.KEPT}
# Property labels of formal/specular_unit_props.v and the CHECK number that selects each alone.
PROPERTIES = {
    "busy_exact": 1,
    "valid_exact": 2,
    "n_err_of_the_line": 3,
    "reset_idle": 4,
    "intensity_zero_on_n_err": 5,
    "intensity_formula": 6,
}
DATA_PROPERTIES = ("intensity_formula",)  # with DATA = 1 only
PROTOCOL = tuple(p for p in PROPERTIES if p not in DATA_PROPERTIES)
# A property of the reference alone (no mutant of the RTL can break it): the saturation of
# |zeta| never changes a word (contract row 35); CHECK 7, with DATA = 1
REFERENCE = "clamp_never_changes_a_result"
COVERS = (
    "c_idle",
    "c_busy",
    "c_valid_busy",
    "c_len_zero",
    "c_long_line",
    "c_back_to_back",
    "c_start_while_busy",
    "c_write_in_start",
    "c_strobes_while_busy",
    "c_reset_while_busy",
    "c_n_err",
    "c_n_ok",
    "c_n_write_in_start",
)
DATA_COVERS = (  # with DATA = 1 only
    "c_lit_table0",
    "c_lit_table1",
    "c_lit_table2",
    "c_lit_table3",
    "c_saturated",
    "c_past_half_pi",
    "c_negative_angle_lit",
    "c_clamped",
    "c_third_pixel_lit",
)
# Registers the induction helpers read: wire in the property file -> register of the unit.
INTERNALS = {
    "f_int_len": "len_reg",
    "f_int_nerr": "nerr_reg",
    "f_int_nerr_run": "nerr_run_reg",
    "f_int_busy": "busy_reg",
    "f_int_cnt": "cnt_reg",
    "f_int_v": "v_reg",
    "f_int_last": "last_reg",
    "f_int_zero": "zero_reg",
    "f_int_rom_d": "rom_d_reg",
    "f_int_out_prod": "out_prod_reg",
    # read with DATA = 1 only
    "f_int_c": "c_reg",
    "f_int_dz": "dz_reg",
    "f_int_z0": "z0_reg",
    "f_int_a": "u_rom9.q_a_reg",  # ROM 9's read register (the ROM module)
    "f_int_tsel": "tsel_reg",
    "f_int_c_run": "c_run_reg",
    "f_int_dz_run": "dz_run_reg",
    "f_int_a_run": "a_run_reg",
    "f_int_tsel_run": "tsel_run_reg",
    "f_int_acc": "acc_reg",
    "f_int_mag_next": "mag_next",
    "f_int_mag": "mag_reg",
    "f_int_prod": "prod_reg",
    "f_int_addr": "addr_reg",
    "f_int_rom_q": "u_rom12.q_a_reg",  # ROM 12's read register
    "f_int_rom_addr": "rom_addr",
    "f_int_a_addr": "a_addr",
}
DEFINE = "-DSPECULAR_INTERNALS"
# The ROM words take no part: both ROMs are removed, their read data left free in every cycle
# (sby makes an undriven wire a free input); without ARITH the data path goes with them.
MEMORY = "memory_collect; delete t:$mem_v2; opt_clean"
# DATA = 2 (the bounded check at the default): ROM 12 removed, its read data free in every cycle
# (the reference takes the word the unit read, its address asserted: it holds for any word);
# ROM 9 kept (its read register holds the word from the n write to the start); the property
# file's products merged with the unit's (opt_merge: the same $mul cell of the same registers)
MEMORY_DATA2 = "memory_collect; delete t:$mem_v2 n:*u_rom12.rom %i; opt_clean; opt_merge; opt_clean"

MUTANTS = {
    m.name: m
    for m in (
        Mutant(
            "busy_stuck",
            "        if (last_reg[LAST_STAGE]) begin\n            busy_reg <= 1'b0;\n",
            "        if (last_reg[LAST_STAGE]) begin\n            busy_reg <= 1'b1;\n",
            "busy_exact",
        ),
        Mutant(
            "start_while_busy_restarts",
            "wire start_ok = start && !busy_reg;\n",
            "wire start_ok = start;\n",
            "busy_exact",
        ),
        Mutant(
            "len_write_in_start_reaches_line",
            "        cnt_reg <= len_reg;\n",
            "        cnt_reg <= len_we ? len_in : len_reg;\n",
            "busy_exact",
        ),
        Mutant(
            "len_write_while_busy",
            "    // Control unit, stage S0: counter 5 and the pixel flags\n",
            "    if (len_we) len_reg <= len_in;\n",
            "busy_exact",
        ),
        Mutant(
            "valid_held",
            "    valid_reg <= 1'b0;\n\n    // Operand registers",
            "\n    // Operand registers",
            "valid_exact",
        ),
        Mutant(
            "one_pixel_too_many",
            "        cnt_reg <= len_reg;\n",
            "        cnt_reg <= len_reg + 1'b1;\n",
            "valid_exact",
        ),
        Mutant(
            "n_err_leak",
            "        n_err_reg <= nerr_run_reg;\n",
            "        n_err_reg <= nerr_reg;\n",
            "n_err_of_the_line",
        ),
        Mutant(
            "reset_keeps_busy",
            "        busy_reg <= 1'b0;\n        valid_reg <= 1'b0;\n        n_err_reg <= 1'b0;\n",
            "        valid_reg <= 1'b0;\n        n_err_reg <= 1'b0;\n",
            "reset_idle",
        ),
        Mutant(
            "no_zero_gate_on_n_err",
            "    zero_reg <= rom_ovf || nerr_run_reg;\n",
            "    zero_reg <= rom_ovf;\n",
            "intensity_zero_on_n_err",
        ),
        Mutant(
            "abs_ones_complement",
            ": low_reg + {{(MAG_WIDTH-1){1'b0}}, neg_reg};\n",
            ": low_reg;\n",
            "intensity_formula",
        ),
        Mutant(
            "n_write_in_start_reaches_table",
            "rom_addr = {tsel_run_reg, rom_angle};\n",
            "rom_addr = {tsel_reg, rom_angle};\n",
            "intensity_formula",
        ),
        Mutant(
            "no_output_saturation",
            "(|out_full[OFULL_WIDTH-1:OUT_WIDTH]) ? {OUT_WIDTH{1'b1}}",
            "(|out_full[OFULL_WIDTH-1:OUT_WIDTH]) ? {OUT_WIDTH{1'b0}}",
            "intensity_formula",
        ),
    )
}
DEFAULT_BMC_DEPTH = 14  # reset, writes, start, 8 fill cycles, a line of 3 pixels
# The data-path mutant the bounded check at the default must catch (also run at small)
DEFAULT_DATA_MUTANT = "abs_ones_complement"


def data_job(config: str, kind: str) -> int:
    """DATA of a job: 0 the data path is not observed; 1 every intensity against the reference,
    which reads its own copy of both ROM images (``small``: ROM 12 has 32 words); 2 the same
    with the ROM words taken from the unit's reads and the two products computed from the
    unit's operand registers, their addresses and operands asserted equal to the formula's (the
    bounded check at ``default`` and the mutants there: two copies of a 16384-word ROM, or two
    different 27 x 17-bit multipliers, would make the solver compare tables and multipliers,
    not the pipeline; the property file leaves the reference out of a protocol mutant)."""
    if config == "small":
        return 1
    return 2 if kind in ("bmc", "mutant") else 0


def rom_files(config: str) -> list[Path]:
    """The ROM images a configuration reads (copied into the job's folder): the committed ones,
    or for a configuration without committed images (``small``) the model's images
    (``specular.rom_text``, what ``make roms`` writes) in a temporary folder."""
    cfg = CONFIGS[config]
    paths = [specular.rom_path(cfg, "a"), specular.rom_path(cfg, "cos")]
    if all(p.is_file() for p in paths):
        return paths
    folder = Path(tempfile.gettempdir()) / "shading-formal-roms"
    folder.mkdir(exist_ok=True)
    for which, path in zip(("a", "cos"), paths, strict=True):
        (folder / path.name).write_text(specular.rom_text(cfg, which))
    return [folder / p.name for p in paths]


def sources(job: FormalJob) -> list[Path]:
    """Verilog read with the property file: the reference formula."""
    return [REFERENCE_FILE]


def memory(job: FormalJob) -> str:
    """The job's ROM handling: with DATA = 1 the ROMs become their images as constant logic
    (the unit's and the reference's copies; a memory would be free state in the induction
    step); with DATA = 2 (bounded, from reset) ROM 12 is removed and ROM 9 stays a memory
    initialised from its image, the products merged (``MEMORY_DATA2``; a mutant job gets the
    helper connections here, as ``model.hw.formal`` makes them for prove and bmc jobs only);
    without DATA both are removed (``MEMORY``)."""
    data = data_job(job.config, job.kind)
    if data == 2 and job.kind == "mutant" and "intensity_formula" not in job.properties:
        data = 0  # a protocol mutant at the default: the data path is not observed
    if data == 2 and job.kind == "mutant":  # the same connections as the bounded check's
        connect = [f"connect -nounset -set {w} \\dut.{r}" for w, r in INTERNALS.items()]
        return "; ".join([*connect, MEMORY_DATA2])
    return {0: MEMORY, 1: "memory_map -rom-only; opt_clean", 2: MEMORY_DATA2}[data]


def params(config: str, kind: str = "prove") -> dict[str, object]:
    """The parameters of the property file (or, for equiv, of the unit): the configuration's
    RTL parameters, the ROM images by the names they are copied under, and DATA."""
    a, cos = rom_files(config)
    out: dict[str, object] = {}
    for name, value in CONFIGS[config].hdl_parameters().items():
        out[name] = f'"{value}"' if isinstance(value, str) else value
    out.update(A_ROM_FILE=f'"{a.name}"', COS_ROM_FILE=f'"{cos.name}"')
    if kind != "equiv":  # clamp_never_changes_a_result at small only (a hard product at default)
        out["DATA"] = data_job(config, kind)
        out["CLAMP"] = int(config == "small")
        out["HELPERS"] = int(kind != "bmc")  # a bounded check needs no induction helpers
    return out


def jobs(make, quick: bool = False) -> list:
    """The unit's jobs, made by ``make(name, unit, kind, config, **fields)`` (FormalJob);
    ``quick``: the protocol proof, the covers and one mutant at the default, the protocol proof
    at ``kept`` (N_FIRST > 1, as the fit emits), the data-path proof at ``small``; else also
    the bounded check of the data path at the default (DATA = 2) and its mutant."""
    out = []

    def add(name: str, kind: str, config: str, **kw) -> None:
        out.append(make(f"{UNIT}_{name}", UNIT, kind, config, **kw))

    add("prove_default", "prove", "default", arith=True, properties=PROTOCOL)
    add("prove_kept", "prove", "kept", arith=True, properties=PROTOCOL)
    if not quick:  # RESET_ALL = 1 resets the data path too (intensity_zero_on_n_err reads it)
        kw = {"reset_all": 1, "arith": True, "properties": PROTOCOL}
        add("prove_default_r1", "prove", "default", **kw)
    add("cover_default", "cover", "default", depth=24, properties=COVERS)
    data = (*PROPERTIES, REFERENCE)
    add("prove_small", "prove", "small", arith=True, properties=data)
    if not quick:
        add("cover_small", "cover", "small", depth=18, properties=(*COVERS, *DATA_COVERS))
    if not quick:  # the intensities at the default: bounded (DATA = 2, docs/formal.md)
        kw = {"arith": True, "properties": PROPERTIES}
        add("bmc_default", "bmc", "default", depth=DEFAULT_BMC_DEPTH, **kw)
    if not quick:  # the netlist: ROM 12 as logic is 32 words at small (16384 at default)
        add("equiv_small", "equiv", "small", depth=0, properties=("netlist_equals_rtl",))
    for m in ["n_err_leak"] if quick else list(MUTANTS):
        prop = MUTANTS[m].breaks
        arith = prop in ("intensity_zero_on_n_err", *DATA_PROPERTIES)
        config = "small" if prop in DATA_PROPERTIES else "default"
        kw = {"arith": arith, "properties": (prop,), "mutant": m}
        add(f"mutant_{m}", "mutant", config, depth=16 if config == "small" else 24, **kw)
    if not quick:  # the same bounded check (DATA = 2) catches a data-path mutant at the default
        m = MUTANTS[DEFAULT_DATA_MUTANT]
        kw = {"arith": True, "properties": (m.breaks,), "mutant": m.name}
        add(f"mutant_{m.name}_default", "mutant", "default", depth=12, **kw)
    return out
