// SPDX-License-Identifier: Apache-2.0
/*
 * Round and saturate an unsigned value (combinational): y = min(round(x / 2^SHIFT),
 * 2^OUT_WIDTH - 1), rounding half up (add 2^(SHIFT-1), slice), as model.units.fixed's
 * round_shift and saturate do.  SHIFT may be 0 (x itself) or negative (x * 2^-SHIFT, exact).
 * The BRDF unit's datapath modules (rtl/brdf_cosine_quadratic.v, rtl/brdf_quadratic.v) and its
 * angle-table address (rtl/brdf_unit.v) use it: every rounding step of docs/brdf.md's fixed
 * point, "add half, slice", then the clip its next step needs.
 *
 * Checks: SHIFT above IN_WIDTH (nothing of x left) is refused at elaboration, by an instance
 * of the module brdf_round_PARAMETER_ERROR_SHIFT_must_be_at_most_IN_WIDTH, which does not
 * exist.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_round #(
    // Bits of the unsigned input
    parameter IN_WIDTH = 16,
    // Bits dropped (rounded half up); 0: none; negative: zero bits appended
    parameter SHIFT = 1,
    // Bits of the output, saturated to all ones
    parameter OUT_WIDTH = 8
) (
    input  wire [IN_WIDTH-1:0]  x,
    output wire [OUT_WIDTH-1:0] y
);

// The rounded value before saturation: the carry of the added half is kept
localparam FULL_WIDTH = (SHIFT > 0) ? IN_WIDTH + 1 - SHIFT : IN_WIDTH - SHIFT;

generate
    if (SHIFT > IN_WIDTH) begin : g_check_shift
        brdf_round_PARAMETER_ERROR_SHIFT_must_be_at_most_IN_WIDTH u_error ();
    end
endgenerate

wire [FULL_WIDTH-1:0] full;

generate
    if (SHIFT > 0) begin : g_round
        wire [IN_WIDTH:0] sum = {1'b0, x} + ({{IN_WIDTH{1'b0}}, 1'b1} << (SHIFT - 1));
        assign full = sum[IN_WIDTH:SHIFT];
        // The bits below the result's LSB, dropped on purpose
        // verilator lint_off UNUSEDSIGNAL
        wire unused_bits = &{1'b0, sum[SHIFT-1:0]};
        // verilator lint_on UNUSEDSIGNAL
    end else if (SHIFT == 0) begin : g_keep
        assign full = x;
    end else begin : g_scale
        assign full = {x, {(-SHIFT){1'b0}}};
    end
endgenerate

generate
    if (FULL_WIDTH > OUT_WIDTH) begin : g_sat
        assign y = (|full[FULL_WIDTH-1:OUT_WIDTH]) ? {OUT_WIDTH{1'b1}} : full[OUT_WIDTH-1:0];
    end else if (FULL_WIDTH == OUT_WIDTH) begin : g_fit
        assign y = full;
    end else begin : g_pad
        assign y = {{(OUT_WIDTH-FULL_WIDTH){1'b0}}, full};
    end
endgenerate

endmodule

`resetall
