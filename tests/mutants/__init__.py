# SPDX-License-Identifier: Apache-2.0
"""Saved mutants: the current RTL with one known defect put in, to prove the benches find it.

Each mutant is a ``model.hw.mutants.Mutant`` (the one mechanism for broken copies, which the
formal jobs use too): the unit's file from ``rtl/`` with one exact snippet replaced, made afresh
for every run (``build``), so it always follows the RTL and shares its ROM checks; if the
snippet is no longer in the RTL exactly once, ``build`` fails instead of testing a stale copy.

* ``divider_shift_div_zero_leak``: the defect the released divider shipped: div_zero is
  taken from the k register when the result is written, so a k write in the start cycle
  (accepted for the next division) leaks into the running division's flag.  The vector soak
  (tests/test_soak.py) and the cocotb bench (tests/test_sim_divider.py) must fail on it,
  naming div_zero.
* ``divider_shift_busy_stuck``: busy never falls once a division starts.  The cocotb bench
  must fail on it in bounded time (the watchdog of ``ProtocolMonitor.wait_idle``), not hang.
* ``divider_shift_div_zero_glitch``: div_zero flips for one cycle in the middle of a division
  (the second busy cycle) and back, a cycle in which the model predicts no change: the
  event-driven monitor of the cocotb bench must still catch it, naming div_zero.
* ``divider_shift_reset_all_q``: with RESET_ALL = 1 a reset sets q to all ones instead of 0
  (a data-path register's reset value; the RESET_ALL = 0 instance has no such reset).  The
  vector soak (tests/test_soak.py) must fail on the RESET_ALL = 1 instance only, naming q in
  the reset cycle: it holds that instance to its own prediction (data outputs 0 after reset).
* ``brdf_unit_round_quarter``: the BRDF unit's output rounding adds a quarter of the output LSB
  instead of a half (the rounding constant of C * F shifted one bit down), so C * F rounds up
  only from three quarters on.  The cocotb bench (tests/test_sim_brdf.py) must fail on it,
  naming intensity.
* ``brdf_unit_cubic_b_word``: the cubic's coefficient table reads the word of r and p0 on both
  ports (port B's address bit 0 stuck at 0), so b1 and b2 are r and p0's bits.  The cocotb
  bench must fail on it with the cubic, naming intensity.
* ``brdf_log2_octave_bit``: the log2 datapath (rtl/brdf_log2.v) takes f in the second octave
  (x in [1, 3), f = x - 1) with bit F where bit F + 1 belongs, so for x in [2, 3) f loses its
  half and the table is read a half octave low.  The cocotb bench must fail on it with the
  log2 form, naming intensity (the mutant replaces rtl/brdf_log2.v in the unit's sources).
* ``brdf_div_no_restore``: the piecewise form's divider (rtl/brdf_div.v) keeps u - y as the
  partial remainder even when it borrows (the restoring step dropped), so every quotient bit
  after the first 0 is wrong.  The cocotb bench must fail on it with the piecewise form,
  naming intensity (the mutant replaces rtl/brdf_div.v): the bench reaches the bloom part.
* ``brdf_piecewise_gate_stage``: the piecewise datapath gates the dividend with the branch
  flag one stage too early (the next pixel's), so only a bloom pixel followed by a cubic one
  (the junction crossed towards the peak) divides 0.  The cocotb bench must fail on it with the
  piecewise form, naming intensity (the mutant replaces rtl/brdf_piecewise.v): its lines cross
  the junction.
* ``shading_core_issues_on``: the shading core's issuer stays active after a span's last pixel
  when no span beat waits (act_reg held), so the interval counter wraps and the span's
  pixels go on coming.  Where another span follows, its pixels come out wrong at once; after the
  last span of a run only extra beats follow the expected ones, which the stream bench must see
  (tests/test_core.py, its watch after the last expected pixel).
* ``shading_brdf_pipe_cubic_b1_early``: the shading core's BRDF highlight path
  (rtl/shading_brdf_pipe.v) hands the cubic form its b1 from the pixel one stage behind the
  one it belongs to (the tap four clocks after w instead of five), so where a span of another
  n follows, that span's first pixel gets the previous span's b1.  Only back-to-back spans of
  different n with a lit highlight show it: the core's stream bench (tests/test_core.py) must
  fail on it, naming the pixel and the span beat.
* ``shading_brdf_pipe_piecewise_beta_early``: the same path hands the piecewise form its beta
  (the bloom part's slope, read into the register beside the multiplier beta x (r w - 1)) from
  the pixel one stage behind (the tap one clock after w instead of two), so the last pixel of a
  span gets the next span's beta.  Only back-to-back spans of different n whose last pixel lies
  in the bloom part show it: the core's stream bench must fail on it, naming the pixel and the
  span beat.
"""

from __future__ import annotations

from pathlib import Path

from model.hw import mutants
from model.hw.mutants import Mutant

MUTANTS = {
    "divider_shift_div_zero_leak": Mutant(
        "divider_shift_div_zero_leak",
        "            div_zero_reg <= run_zero_reg;\n",
        "            div_zero_reg <= k_zero_reg;  // MUTANT: the k register at result time\n",
        unit="divider_shift",
    ),
    "divider_shift_busy_stuck": Mutant(
        "divider_shift_busy_stuck",
        "            // The remaining reciprocal bits are all zero: the quotient is complete\n"
        "            busy_reg <= 1'b0;\n",
        "            // The remaining reciprocal bits are all zero: the quotient is complete\n"
        "            busy_reg <= 1'b1;  // MUTANT: busy never falls\n",
        unit="divider_shift",
    ),
    "divider_shift_div_zero_glitch": Mutant(
        "divider_shift_div_zero_glitch",
        "assign div_zero = div_zero_reg;\n",
        # One changed line: a register pair that is 1 in the second busy cycle only.
        "reg glitch_1, glitch_2; always @(posedge clk) begin glitch_1 <= rst_n && start && "
        "!busy_reg; glitch_2 <= rst_n && glitch_1 && busy_reg; end assign div_zero = "
        "div_zero_reg ^ glitch_2;  // MUTANT: div_zero flips for one cycle mid-division\n",
        unit="divider_shift",
    ),
    "divider_shift_reset_all_q": Mutant(
        "divider_shift_reset_all_q",
        "        q_reg <= {Q_WIDTH{1'b0}};\n",
        "        q_reg <= {Q_WIDTH{1'b1}};  // MUTANT: RESET_ALL = 1 resets q to all ones\n",
        unit="divider_shift",
    ),
    "brdf_unit_round_quarter": Mutant(
        "brdf_unit_round_quarter",
        "({{OP_WIDTH{1'b0}}, 1'b1} << (OSHIFT - 1));\n",
        "({{OP_WIDTH{1'b0}}, 1'b1} << (OSHIFT - 2));  // MUTANT: a quarter LSB\n",
        unit="brdf_unit",
    ),
    "brdf_unit_cubic_b_word": Mutant(
        "brdf_unit_cubic_b_word",
        # the cubic's port B (the piecewise form's ROM, next, has the same lines)
        "            .addr_b({n_addr, 1'b1}),\n"
        "            .q_b(coef_lo)\n"
        "        );\n"
        "        assign k_word = {coef_hi, coef_lo};\n"
        "    end else if (IS_PIECEWISE) begin : g_coef_rom_piecewise\n",
        "            .addr_b({n_addr, 1'b0}),  // MUTANT: {r, p0} read as {b1, b2}\n"
        "            .q_b(coef_lo)\n"
        "        );\n"
        "        assign k_word = {coef_hi, coef_lo};\n"
        "    end else if (IS_PIECEWISE) begin : g_coef_rom_piecewise\n",
        unit="brdf_unit",
    ),
    "brdf_log2_octave_bit": Mutant(
        "brdf_log2_octave_bit",
        "wire [F:0] v = oct_next ? {x[F+1], x[F-1:0]} : {x[F-1:0], 1'b0};\n",
        "wire [F:0] v = oct_next ? {x[F], x[F-1:0]} : {x[F-1:0], 1'b0};  // MUTANT: bit F\n",
        unit="brdf_log2",
    ),
    "brdf_div_no_restore": Mutant(
        "brdf_div_no_restore",
        "                t_reg <= ge ? diff[Y_WIDTH-1:0] : u[Y_WIDTH-1:0];\n",
        "                t_reg <= diff[Y_WIDTH-1:0];  // MUTANT: never restores\n",
        unit="brdf_div",
    ),
    "brdf_piecewise_gate_stage": Mutant(
        "brdf_piecewise_gate_stage",
        "    num_reg <= bloom5_reg ? c5_reg : {(D+1){1'b0}};\n",
        "    num_reg <= bloom4_reg ? c5_reg : {(D+1){1'b0}};  // MUTANT: the next pixel's flag\n",
        unit="brdf_piecewise",
    ),
    "shading_core_issues_on": Mutant(
        "shading_core_issues_on",
        "    end else if (issue && last_px) begin\n        act_reg <= 1'b0;\n",
        "    end else if (issue && last_px) begin\n        act_reg <= act_reg;  // MUTANT: on\n",
        unit="shading_core",
    ),
    "shading_brdf_pipe_cubic_b1_early": Mutant(
        "shading_brdf_pipe_cubic_b1_early",
        "localparam CUBIC_B1_AT = 5;\n",
        "localparam CUBIC_B1_AT = 4;  // MUTANT: b1 of the pixel a stage behind\n",
        unit="shading_brdf_pipe",
    ),
    "shading_brdf_pipe_piecewise_beta_early": Mutant(
        "shading_brdf_pipe_piecewise_beta_early",
        "localparam PIECEWISE_BETA_AT = 2;\n",
        "localparam PIECEWISE_BETA_AT = 1;  // MUTANT: beta of the pixel a stage behind\n",
        unit="shading_brdf_pipe",
    ),
}


def build(name: str, folder: Path) -> Path:
    """Write mutant ``name`` as ``folder/<name>.v`` and return its path."""
    return mutants.write(MUTANTS[name], folder)
