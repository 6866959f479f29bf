# SPDX-License-Identifier: Apache-2.0
"""The proofs of ``make mutants`` (sim/mutation_proof.py) on mutants of the record's lists, each
shown able to fail: the proof from reset finds a counterexample for a Gouraud mutant a check
kills and proves the survivor of the other proofs the record says it proves; the fourth proof
(the multipliers cut, then invariants asserted alongside) does the same on the specular unit's
list, and an invariant the original breaks gives a counterexample; the window proves the log2
and cubic survivors and finds a counterexample for a killed mutant, and for one of those
survivors with every word compared.  The ROM cuts and fills they read.  Slow tier: the core's
one-pixel-span invariants on its miter.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from model.units import brdf
from sim import (
    aiger_eval,
    mutation,
    mutation_brdf,
    mutation_cuts,
    mutation_invariants,
    mutation_proof,
    mutation_stages,
    mutation_window,
)
from tests.mutation_common import BRDF_DESIGNS, BUILD, DOC, record

# The from-reset proof (mutation_proof.prove_from_reset) on the Gouraud unit's list: a mutant
# the record says a check kills (15: by a soak, after the committed set passed it) and a
# survivor of the other proofs the record has it prove (33: seg_reg bit 8, dead because a line
# has at most 256 segments), a few seconds each
FROM_RESET_KILLED, FROM_RESET_PROVEN = 15, 33


@pytest.fixture(scope="module")
def gouraud_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["gouraud_segment"], BUILD)


def test_the_from_reset_proof_finds_a_killed_mutant_s_counterexample(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """Sound: a mutant a check kills is not proven, pdr finds the trace from reset that tells
    it from the original."""
    rec = record()["designs"]["gouraud_segment"]
    assert rec["killed_by"][str(FROM_RESET_KILLED)] != rec["vector_set"]
    design = mutation.DESIGNS["gouraud_segment"]
    command = gouraud_list.mutations[FROM_RESET_KILLED - 1].command
    verdict = mutation_proof.prove_from_reset(
        tmp_path / "killed", design.top, gouraud_list.design_il, command, design.contract, 60
    )
    assert verdict == "failed"


def test_the_from_reset_proof_proves_a_survivor_of_the_others(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The record's mutant it proves: equal from reset, where no proof from any shared state
    can show it (the bound on seg_reg holds only in the states a reset leads to)."""
    rec = record()["designs"]["gouraud_segment"]
    (listed,) = [o for o in rec["equivalent"] if o["id"] == FROM_RESET_PROVEN]
    assert listed["equivalent"].startswith("scorr and pdr from reset")
    design = mutation.DESIGNS["gouraud_segment"]
    command = gouraud_list.mutations[FROM_RESET_PROVEN - 1].command
    assert command == listed["command"]
    verdict = mutation_proof.prove_from_reset(
        tmp_path / "proven", design.top, gouraud_list.design_il, command, design.contract, 60
    )
    assert verdict == "proven"


def test_a_rom_port_at_a_constant_address_reads_its_word(tmp_path: Path) -> None:
    """``cut_roms`` cuts every read port, and one whose address is a constant reads the
    table's word there (the core's read of n = 1's a) where the others read the cut's input:
    the word is what a proof of the diffuse path may rely on, and no other word is."""
    (tmp_path / "rom.v").write_text(
        "module rom (input wire [1:0] addr, output wire [7:0] q, output wire [7:0] q0);\n"
        "reg [7:0] mem [0:3];\n"
        "initial begin mem[0] = 8'h5a; mem[1] = 8'h01; mem[2] = 8'h02; mem[3] = 8'h03; end\n"
        "assign q = mem[addr];\nassign q0 = mem[2'd0];\nendmodule\n"
    )
    mutation_proof.run_yosys(
        "read_verilog rom.v\nprep -top rom\nmemory_collect\nwrite_rtlil rom.il\n", tmp_path, "rom"
    )
    cut = mutation_cuts.cut_roms((tmp_path / "rom.il").read_text())
    assert "$mem_v2" not in cut
    (data,) = [ln for ln in cut.splitlines() if "connect" in ln and "mutation_rom0_data" in ln]
    # RD_DATA is { q0 q } (port 1, at address 0, then port 0): q0 the word 0x5a, q the input
    assert data.endswith("{ \\q0 \\q } { 8'01011010 \\mutation_rom0_data [7:0] }"), data


def test_a_short_rom_is_filled_with_zero_words_to_its_address_reach(tmp_path: Path) -> None:
    """``roms_filled`` gives a table of 3 words on a 2-bit address a fourth word, 0, so that
    mapped to logic it reads no ``x``; a memory with a write port is left as it is."""
    (tmp_path / "rom.v").write_text(
        "module rom (input wire clk, input wire [1:0] addr, input wire we,\n"
        "            output wire [7:0] q, output wire [7:0] r);\n"
        "reg [7:0] mem [0:2];\nreg [7:0] ram [0:2];\n"
        "initial begin mem[0] = 8'h5a; mem[1] = 8'h01; mem[2] = 8'h02; end\n"
        "always @(posedge clk) if (we) ram[addr] <= 8'h11;\n"
        "assign q = mem[addr];\nassign r = ram[addr];\nendmodule\n"
    )
    mutation_proof.run_yosys(
        "read_verilog rom.v\nprep -top rom\nmemory_collect\nwrite_rtlil rom.il\n", tmp_path, "rom"
    )
    il = (tmp_path / "rom.il").read_text()
    filled = mutation_cuts.roms_filled(il)
    blocks = re.findall(r"^\s*cell \$mem_v2 (\S+)\n(.*?)^\s*end$", filled, re.M | re.S)
    params = {name: dict(re.findall(r"parameter \\(\w+) (\S+)", b)) for name, b in blocks}
    rom, ram = params["\\mem"], params["\\ram"]
    assert (rom["SIZE"], rom["ABITS"]) == ("4", "2")
    assert rom["INIT"] == "32'" + "00000000" + "00000010" + "00000001" + "01011010"
    assert ram["SIZE"] == "3"
    assert mutation_cuts.roms_filled(filled) == filled


# The fourth proof (from reset, the multipliers cut, then the invariants of
# sim/mutation_invariants.py asserted alongside) on the specular unit's list: survivors of the
# third it proves (65: the accumulator's bit 0 set while it holds, after the line's last pixel;
# 263: the accumulator stepping once more after it, proven with the stage invariants) and a
# mutant the committed set kills (3), a few seconds each
CUT_PROVEN, STAGED_PROVEN, CUT_KILLED = 65, 263, 3


@pytest.fixture(scope="module")
def specular_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["specular_unit"], BUILD)


def _fourth(net: mutation.Netlist, mutant: int, folder: Path, invariants: tuple[str, ...]) -> str:
    design = net.design
    command = net.mutations[mutant - 1].command
    return mutation_proof.prove_from_reset(
        folder, design.top, net.design_il, command, design.contract, 60, True, invariants
    )


def test_the_product_cut_proves_a_survivor_and_finds_a_killed_mutant_s_counterexample(
    specular_list: mutation.Netlist, tmp_path: Path
) -> None:
    """With both multipliers cut (``cut_products``: the mutant's product is the original's
    where their operands agree), pdr proves 65, which it left undecided through the
    products, and still finds the trace from reset that tells 3 from the original."""
    rec = record()["designs"]["specular_unit"]
    assert str(CUT_KILLED) in rec["killed_by"]
    assert _fourth(specular_list, CUT_PROVEN, tmp_path / "proven", ()) == "proven"
    assert _fourth(specular_list, CUT_KILLED, tmp_path / "killed", ()) == "failed"
    for name in ("proven", "killed"):
        miter = (tmp_path / name / "miter.v").read_text()
        assert "gold_mutation_mul0_in == gate_mutation_mul0_in ?" in miter
        assert "$mul" not in (tmp_path / name / "gold_reset.il").read_text()


def test_the_stage_invariants_prove_a_survivor_and_find_a_killed_mutant_s_counterexample(
    specular_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The specular unit's stage invariants (each stage's registers equal in the two copies
    while its valid bit is set), asserted with the outputs: 263, which pdr leaves undecided
    without them, proven; 3 still fails."""
    stages = mutation_invariants.DESIGN["specular_unit"]
    assert _fourth(specular_list, STAGED_PROVEN, tmp_path / "proven", stages) == "proven"
    assert _fourth(specular_list, CUT_KILLED, tmp_path / "killed", stages) == "failed"


def test_the_stages_found_in_a_netlist_are_the_specular_unit_s_own(
    specular_list: mutation.Netlist,
) -> None:
    """The stage analysis (sim/mutation_stages.py, which gives the BRDF unit's stage
    invariants) finds in the specular unit's netlist the stages its hand-written list names
    (``SPECULAR_STAGES``), register for register: its ROM-12 word ``rom12_q`` is the ROM's read
    register ``u_rom12.q_a_reg``, each whole register one bit range."""

    def by_stage(invariants: tuple[str, ...]) -> list[set[str]]:
        return [
            {
                re.sub(r"\[[\d:]+\]$", "", w)
                for w in re.findall(r"gold:([\w.]+(?:\[[\d:]+\])?) ==", i)
            }
            for i in invariants
        ]

    il = specular_list.design_il.read_text()
    found = by_stage(mutation_stages.staged_invariants(il, "specular_unit", "acc_reg", "v_reg"))
    hand = by_stage(mutation_invariants.SPECULAR_STAGES)
    hand = [{"u_rom12.q_a_reg" if r == "rom12_q" else r for r in regs} for regs in hand]
    assert found == hand


@pytest.fixture(scope="module")
def log2_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["brdf_unit_log2"], BUILD)


# The BRDF unit's log2 form: its step condition tied true (64: the accumulator steps once more
# after a line's last pixel, a survivor of the stage invariants alone) and a bit of its step
# tied to 0 (43, which its committed set kills)
STEP_PROVEN, STEP_KILLED = 64, 43


def test_the_unstaged_equalities_prove_a_step_condition_mutant_and_find_a_killed_one(
    log2_list: mutation.Netlist, tmp_path: Path
) -> None:
    """With the stage invariants and the other registers' equalities (``stronger``), pdr
    proves 64 (in seconds; the stage invariants alone left it undecided in 15 minutes), and
    the same invariants give 43 a counterexample."""
    il = log2_list.design_il.read_text()
    rec = record()["designs"]["brdf_unit_log2"]
    assert str(STEP_KILLED) in rec["killed_by"]
    for mutant, verdict in ((STEP_PROVEN, "proven"), (STEP_KILLED, "failed")):
        command = log2_list.mutations[mutant - 1].command
        given = mutation_invariants.invariants("brdf_unit_log2", command, il)
        more = mutation_invariants.stronger("brdf_unit_log2", il)
        assert "gold:v_reg[13:0] == gate:v_reg[13:0]" in more and not set(more) & set(given)
        assert _fourth(log2_list, mutant, tmp_path / str(mutant), given + more) == verdict


# The quadratic form's step condition tied true, as log2's 64: the outputs and invariants are
# inductive as they stand, which ABC's ``ind`` shows and ``pdr`` after ``scorr`` did not in 900 s
QUADRATIC_STEP = 137


def test_k_induction_proves_the_quadratic_form_s_step_condition_mutant(tmp_path: Path) -> None:
    """Quadratic 137 (the accumulator steps once more after a line's last pixel) with its
    invariants and the stronger ones: ABC's ``ind`` proves it before ``scorr`` and ``pdr`` are
    run (its verdict file says so, and pdr's is never written)."""
    net = mutation.prepare(mutation.DESIGNS["brdf_unit_quadratic"], BUILD)
    il = net.design_il.read_text()
    command = net.mutations[QUADRATIC_STEP - 1].command
    assert "-mode const1" in command and "$logic_not$brdf_unit.v:469" in command
    given = mutation_invariants.invariants("brdf_unit_quadratic", command, il)
    given += mutation_invariants.stronger("brdf_unit_quadratic", il)
    assert _fourth(net, QUADRATIC_STEP, tmp_path, given) == "proven"
    assert (tmp_path / mutation_proof.IND_STATUS).read_text().split()[0] == "snl_UNSAT"
    assert not (tmp_path / mutation_proof.PDR_STATUS).exists()


# The log2 form's survivors of every check and of the proofs from reset: 2 - e' with a low bit
# set where the octave e' is 2 (143, bit 1; 277, bit 3), where the original's word is 0 and the
# mutant's 2 or 8, which no C shows.  A mutation inside the window that the committed set kills
# (1, a bit of the x register tied to 1) and one in the front before the address register (3)
WINDOW_PROVEN, WINDOW_KILLED, WINDOW_BEFORE = 143, 1, 3
# How the record names the window's proof (``equivalence``), with the inputs its cone reads
WINDOW_TEXT = "every address and line word swept (23 inputs)"


def test_the_window_proves_a_log2_survivor_and_finds_a_killed_mutant_s_counterexample(
    log2_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The fifth proof (``prove_window``) proves 143 with words below ``tiny`` allowed to
    differ, and finds a counterexample for it with every word compared (its word does change,
    where the original's is 0: the model says so at the n and address the counterexample
    names) and for 1, which the committed set kills; 3 lies before the window's address
    register."""
    window = log2_list.design.window
    rec = record()["designs"]["brdf_unit_log2"]
    assert str(WINDOW_KILLED) in rec["killed_by"]
    how = {e["id"]: e["equivalent"] for e in rec["equivalent"]}
    assert how[WINDOW_PROVEN].startswith(WINDOW_TEXT)

    def prove(mutant: int, given: mutation_window.Window) -> tuple[str, int]:
        command = log2_list.mutations[mutant - 1].command
        return mutation_window.prove_in_window(
            tmp_path / f"{mutant}_{given.tiny}", "brdf_unit", log2_list.design_il, command, given
        )

    # the cone reads n (10 bits, cycle 0) and the address (13 bits, cycle 5) alone
    assert prove(WINDOW_PROVEN, window) == ("proven", 23)
    assert prove(WINDOW_PROVEN, dataclasses.replace(window, tiny=0)) == ("failed", 23)
    cex = (tmp_path / f"{WINDOW_PROVEN}_0" / "window_cex.txt").read_text()
    found = re.fullmatch(r"n_in = (\d+) in cycle 0\nmutation_cut = (\d+) in cycle 5\n", cex)
    assert found, cex
    n, address = (int(g) for g in found.groups())
    cfg = brdf.UNIT_CONFIGS["log2"]
    assert brdf.evaluate(cfg, np.array([address << cfg.addr_shift]), n).tolist() == [0]
    assert prove(WINDOW_KILLED, window) == ("failed", 23)
    assert prove(WINDOW_BEFORE, window) == ("outside", 0)


# The cubic form's survivor of the other proofs (c7_reg bit 18 flipped while bit 20 is set:
# c = 1 reads 1.25, where every n's word is full scale already): its coefficient table holds
# 2000 words on 11 address bits, and the window reads it filled (``roms_filled``)
CUBIC_WINDOW = 124


def test_the_window_proves_the_cubic_survivor_through_its_filled_table(tmp_path: Path) -> None:
    """The fifth proof proves cubic 124: the cone of its unrolled miter reads n and the
    address alone once the 48 words the cubic's table leaves undefined read 0 (the record says
    the window proved it)."""
    net = mutation.prepare(mutation.DESIGNS["brdf_unit_cubic"], BUILD)
    rec = record()["designs"]["brdf_unit_cubic"]
    how = {e["id"]: e["equivalent"] for e in rec["equivalent"]}
    assert how[CUBIC_WINDOW].startswith(WINDOW_TEXT)
    command = net.mutations[CUBIC_WINDOW - 1].command
    verdict = mutation_window.prove_in_window(
        tmp_path, "brdf_unit", net.design_il, command, net.design.window
    )
    assert verdict == ("proven", 23)
    assert len(aiger_eval.support(aiger_eval.read_aiger(tmp_path / "window_cone.aig"))) == 23
    # the one table filled is the coefficient table, whose address n gives (the angle table,
    # which the window's free address reads, has a word at every address)
    il = net.design_il.read_text()
    short = [
        name
        for name, block in re.findall(r"^\s*cell \$mem_v2 (\S+)\n(.*?)^\s*end$", il, re.M | re.S)
        if int(re.search(r"parameter \\SIZE (\d+)", block).group(1))
        < 1 << int(re.search(r"parameter \\ABITS (\d+)", block).group(1))
    ]
    assert short == ["\\genblk25.g_coef_rom_cubic.u_coef_rom.rom"], short


def test_the_window_s_tiny_word_is_the_rounding_s() -> None:
    """A word below ``tiny`` shows 0 at every C: C x word is rounded by adding half of the
    dropped bits' weight 2^(s - 1) (s = C's fraction bits + the word's) and slicing, so the
    largest C shows 0 exactly while C_max x word < 2^(s - 1): tiny = ceil(2^(s - 1) / C_max)
    (129 at the defaults: 2^23 / 65535 = 128.002)."""
    for form in brdf.RTL_FORMS:
        cfg = brdf.UNIT_CONFIGS[form]
        a = cfg.angle
        s = a.c_frac_bits + cfg.out_bits
        assert mutation_brdf.brdf_window(cfg).tiny == -(-(1 << (s - 1)) // a.c_format.hi), form
    assert mutation.DESIGNS["brdf_unit_log2"].window.tiny == 129


def test_an_asynchronous_rom_port_s_reset_is_unbuildable_and_never_read() -> None:
    """The cosine-quadratic list holds a mutation of the angle ROM's asynchronous read port's
    reset (RD_ARST), which Yosys requires to be 0: it cannot go into a netlist, and the cell
    never reads it, so the proofs list it as equivalent by the cell's definition.  Its address
    is read: the same mutation of RD_ADDR is neither."""
    net = mutation.prepare(mutation.DESIGNS["brdf_unit_cosine_quadratic"], BUILD)
    il = net.design_il.read_text()
    held = [
        m.command
        for m in net.mutations
        if mutation_proof.mutate_field(m.command, "port") in ("RD_EN", "RD_ARST", "RD_SRST")
    ]
    assert held, "the list has no mutation of a read port's enable or reset"
    for command in held:
        assert mutation_proof.unbuildable(il, command), command
        assert "never reads" in mutation_proof.unread_port(il, command), command
        address = re.sub(r"-port \S+", "-port RD_ADDR", command)
        assert not mutation_proof.unbuildable(il, address)
        assert mutation_proof.unread_port(il, address) is None


def test_an_invariant_is_proven_not_assumed(
    specular_list: mutation.Netlist, tmp_path: Path
) -> None:
    """An invariant the original breaks (the accumulator 0 while a pixel is in stage S0) gives
    a counterexample on a mutant the same proof proves without it: the invariants are
    asserted, so a wrong one can never make a proof."""
    wrong = ("!gold:v_reg[0] || gold:acc_reg == 40'd0",)
    assert _fourth(specular_list, CUT_PROVEN, tmp_path / "wrong", wrong) == "failed"


# The Gouraud unit's 174 (start_reg bit 8 flipped while its bit 23 is set): make mutants proves
# it with its own invariants (sim/mutation_invariants.py GOURAUD_CLAMPED, about 140 s of pdr; its
# record says so, and test_the_record_is_current holds the record to this netlist), as it proves
# the core's 244 with the core's
CLAMP_PROVEN = 174


def test_the_clamp_invariants_are_given_to_gouraud_174(gouraud_list: mutation.Netlist) -> None:
    """174's invariants are found by its mutate command, and its record says they prove it."""
    command = gouraud_list.mutations[CLAMP_PROVEN - 1].command
    given = mutation_invariants.invariants("gouraud_segment", command)
    assert given == mutation_invariants.GOURAUD_CLAMPED
    rec = record()["designs"]["gouraud_segment"]
    proven = {e["id"]: e["equivalent"] for e in rec["equivalent"]}
    assert f"with {len(given)} invariants proven alongside" in proven[CLAMP_PROVEN]


def test_the_clamp_invariants_find_a_killed_mutant_s_counterexample(
    gouraud_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The same invariants on a mutant a soak kills (15): a counterexample."""
    command = gouraud_list.mutations[FROM_RESET_KILLED - 1].command
    design = gouraud_list.design
    verdict = mutation_proof.prove_from_reset(
        tmp_path, design.top, gouraud_list.design_il, command, design.contract, 60, True,
        mutation_invariants.GOURAUD_CLAMPED,
    )  # fmt: skip
    assert verdict == "failed"


# The core's invariants for its 244 (a one-pixel span loads the divider's increment where the
# original loads 0: make mutants proves it with them in about three minutes of pdr), on 143 (a
# bit of that increment tied to 0), which the core's committed set kills
ONE_PIXEL_KILLED = 143


@pytest.fixture(scope="module")
def core_list() -> mutation.Netlist:
    return mutation.prepare(mutation.DESIGNS["shading_core"], BUILD)


def test_an_invariant_reads_a_memory_word_by_its_escaped_name() -> None:
    """A word of a memory mapped to registers (``u_fifo.mem[3]``) is named as Verilog escapes a
    name, a backslash up to the next white space; a plain name still takes a bit select."""
    given = (
        "gold:\\u_fifo.mem[3] == gate:\\u_fifo.mem[3] ",
        "!gold:v_reg[2] || gold:side_reg[149:100] == gate:side_reg[149:100]",
    )
    assert mutation_cuts.invariant_wires(given) == ["u_fifo.mem[3]", "v_reg", "side_reg"]
    assert [mutation_cuts.invariant_verilog(i) for i in given] == [
        "gold_mutation_probe_u_fifo__mem_3_ == gate_mutation_probe_u_fifo__mem_3_ ",
        "!gold_mutation_probe_v_reg[2] || gold_mutation_probe_side_reg[149:100]"
        " == gate_mutation_probe_side_reg[149:100]",
    ]


def test_the_one_pixel_span_invariants_find_a_killed_mutant_s_counterexample(
    core_list: mutation.Netlist, tmp_path: Path
) -> None:
    """The invariants that prove the core's 244 (found by its mutate command in the record),
    on a mutant the core's committed set kills (143): a counterexample."""
    rec = record()["designs"]["shading_core"]
    (proven,) = [o["command"] for o in rec["equivalent"] if o["id"] == 244]
    given = mutation_invariants.invariants("shading_core", proven)
    assert given == mutation_invariants.CORE_ONE_PIXEL_SPAN
    assert str(ONE_PIXEL_KILLED) in record()["designs"]["shading_core"]["killed_by"]
    command = core_list.mutations[ONE_PIXEL_KILLED - 1].command
    design = core_list.design
    verdict = mutation_proof.prove_from_reset(
        tmp_path, design.top, core_list.design_il, command, design.contract, 300, True, given
    )
    assert verdict == "failed"


def test_the_window_s_mutants_by_form_and_file_are_the_docs() -> None:
    """docs/verification.md's count of the mutants the window proves, in all and the piecewise
    form's by the source file of their mutation (its first ``-src``), as the record has them."""
    text = DOC.read_text()
    found = re.search(
        r"window proves those (\d+):.*?piecewise form's (\d+) \((\d+) in its split\s+"
        r"multipliers, `brdf_mul.v`.*?(\d+) in its pipelined divider, `brdf_div.v`.*?(\d+)\s+"
        r"elsewhere in its cubic part, `brdf_cubic.v`; and one in `brdf_piecewise.v`",
        text,
        re.S,
    )
    assert found, "docs/verification.md no longer counts the window's mutants by file"
    designs = record()["designs"]
    window = {
        name: [e for e in designs[name]["equivalent"] if e["equivalent"].startswith(WINDOW_TEXT)]
        for name in BRDF_DESIGNS
    }
    files = [re.search(r"-src (\w+)\.v:", o["command"]).group(1)
             for o in window["brdf_unit_piecewise"]]  # fmt: skip
    by_file = {f: files.count(f) for f in set(files)}
    assert [int(g) for g in found.groups()] == [
        sum(len(v) for v in window.values()),
        len(files),
        by_file["brdf_mul"],
        by_file["brdf_div"],
        by_file["brdf_cubic"],
    ]
    assert by_file["brdf_piecewise"] == 1 and len(by_file) == 4
