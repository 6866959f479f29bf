// SPDX-License-Identifier: Apache-2.0
/*
 * A delay line: y is x DEPTH clock edges later (DEPTH = 0: y is x, no register).  The BRDF
 * unit's piecewise datapath (rtl/brdf_piecewise.v) aligns its two branches with it: the cubic's
 * result, the divider's quotient and the branch flag each wait for the slower branch.
 *
 * Reset: none of these registers is control state; RESET_ALL = 1 resets them all (rst_n is
 * synchronous, active low).
 *
 * Checks (at elaboration, each an instance of a module that does not exist, named after the
 * rule): WIDTH at least 1 (brdf_delay_PARAMETER_ERROR_WIDTH_must_be_at_least_1), DEPTH 0..64
 * (brdf_delay_PARAMETER_ERROR_DEPTH_must_be_0_to_64: a longer line belongs in a RAM; the
 * piecewise datapath's are at most 25), RESET_ALL 0 or 1
 * (brdf_delay_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1).
 *
 * Sources: this file; instantiated by rtl/brdf_piecewise.v (rtl/brdf_unit.f).
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_delay #(
    // Bits of x and y
    parameter WIDTH = 1,
    // Clock edges from x to y (0: a wire), 0..64
    parameter DEPTH = 1,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire             clk,
    input  wire             rst_n,
    input  wire [WIDTH-1:0] x,
    output wire [WIDTH-1:0] y
);

generate
    if (WIDTH < 1) begin : g_check_width
        brdf_delay_PARAMETER_ERROR_WIDTH_must_be_at_least_1 u_error ();
    end
    if (DEPTH < 0 || DEPTH > 64) begin : g_check_depth
        brdf_delay_PARAMETER_ERROR_DEPTH_must_be_0_to_64 u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        brdf_delay_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
endgenerate

generate
    if (DEPTH < 1) begin : g_wire
        assign y = x;
        // verilator lint_off UNUSEDSIGNAL
        wire unused_clk = &{1'b0, clk, rst_n};
        // verilator lint_on UNUSEDSIGNAL
    end else if (DEPTH <= 64) begin : g_line
        // Stage s at [s*WIDTH +: WIDTH]: x of s + 1 edges ago
        reg [DEPTH*WIDTH-1:0] line_reg;
        integer s;

        always @(posedge clk) begin
            line_reg[WIDTH-1:0] <= x;
            for (s = 1; s < DEPTH; s = s + 1) begin
                line_reg[s*WIDTH +: WIDTH] <= line_reg[(s-1)*WIDTH +: WIDTH];
            end
            if (RESET_ALL != 0 && !rst_n) begin
                line_reg <= {(DEPTH*WIDTH){1'b0}};
            end
        end
        assign y = line_reg[(DEPTH-1)*WIDTH +: WIDTH];
    end
endgenerate

endmodule

`resetall
