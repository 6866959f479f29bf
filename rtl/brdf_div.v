// SPDX-License-Identifier: Apache-2.0
/*
 * A pipelined restoring divider: q = floor(x / y), one quotient bit per stage, one division
 * per clock, q on its output Q_BITS clock edges after x and y.  The BRDF unit's piecewise form
 * divides with it (rtl/brdf_piecewise.v: the bloom part c / (s2 + beta (r w - 1))).
 *
 * Precondition: x < y 2^Q_BITS (so y > 0 and the quotient has Q_BITS bits); the caller proves
 * it.  Under it nothing here wraps:
 *   t0 = x >> Q_BITS < y fits Y_WIDTH bits (x has at most Y_WIDTH + Q_BITS bits: checked);
 *   stage j, for quotient bit i = Q_BITS - 1 - j, holds the partial remainder t = floor(x / 2^(i
 *   + 1)) - y floor(q / 2^(i + 1)) < y (Y_WIDTH bits) and the dividend bits still to come;
 *   it forms u = 2 t + x[i] < 2 y (Y_WIDTH + 1 bits), compares with y (u - y in [-y, y): Y_WIDTH
 *   + 1 bits signed, its sign the borrow), and keeps u - y (below y) with quotient bit 1 or u
 *   (below y) with 0: the restoring step.  After the last stage the bits are q = floor(x / y),
 *   the last remainder unused.
 * The dividend bits still to come and the quotient bits so far share one Q_BITS-bit register
 * per stage (the classic shift register: a dividend bit leaves at the top as a quotient bit
 * enters at the bottom); y rides along with its dividend.
 *
 * Reset: none of these registers is control state; RESET_ALL = 1 resets them all (rst_n is
 * synchronous, active low).
 *
 * Checks (at elaboration, each an instance of a module that does not exist, named after the
 * rule): X_WIDTH and Y_WIDTH at least 1
 * (brdf_div_PARAMETER_ERROR_X_WIDTH_and_Y_WIDTH_must_be_at_least_1),
 * Q_BITS 1..X_WIDTH (brdf_div_PARAMETER_ERROR_Q_BITS_must_be_1_to_X_WIDTH), X_WIDTH at most
 * Y_WIDTH + Q_BITS (brdf_div_PARAMETER_ERROR_X_WIDTH_must_be_at_most_Y_WIDTH_plus_Q_BITS),
 * RESET_ALL 0 or 1 (brdf_div_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1); tested in
 * tests/test_rtl_params.py.
 *
 * Sources: this file; instantiated by rtl/brdf_piecewise.v (rtl/brdf_unit.f).  Documentation:
 * docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_div #(
    // Bits of the dividend x
    parameter X_WIDTH = 42,
    // Bits of the divisor y
    parameter Y_WIDTH = 37,
    // Quotient bits, one pipeline stage each (x must be below y 2^Q_BITS), 1..X_WIDTH
    parameter Q_BITS = 17,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire               clk,
    input  wire               rst_n,
    input  wire [X_WIDTH-1:0] x,
    input  wire [Y_WIDTH-1:0] y,
    output wire [Q_BITS-1:0]  q
);

// Each rule is checked once the ones before it hold (one message for one mistake)
localparam BAD_WIDTH = (X_WIDTH < 1 || Y_WIDTH < 1);
localparam BAD_Q_BITS = !BAD_WIDTH && (Q_BITS < 1 || Q_BITS > X_WIDTH);
localparam BAD_X_WIDTH = !BAD_WIDTH && !BAD_Q_BITS && X_WIDTH > Y_WIDTH + Q_BITS;

generate
    if (BAD_WIDTH) begin : g_check_width
        brdf_div_PARAMETER_ERROR_X_WIDTH_and_Y_WIDTH_must_be_at_least_1 u_error ();
    end
    if (BAD_Q_BITS) begin : g_check_q_bits
        brdf_div_PARAMETER_ERROR_Q_BITS_must_be_1_to_X_WIDTH u_error ();
    end
    if (BAD_X_WIDTH) begin : g_check_x_width
        brdf_div_PARAMETER_ERROR_X_WIDTH_must_be_at_most_Y_WIDTH_plus_Q_BITS u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        brdf_div_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
endgenerate

// Each stage's inputs, stage j at [j*W +: W]: the partial remainder, the divisor, and the
// dividend bits to come above the quotient bits so far (qx_bus: stage Q_BITS's is q)
wire [Q_BITS*Y_WIDTH-1:0]    t_bus;
wire [Q_BITS*Y_WIDTH-1:0]    y_bus;
wire [(Q_BITS+1)*Q_BITS-1:0] qx_bus;

// Stage 0's inputs: t0 = x >> Q_BITS, the low Q_BITS bits of x to come
generate
    if (X_WIDTH == Q_BITS) begin : g_t0_zero
        assign t_bus[Y_WIDTH-1:0] = {Y_WIDTH{1'b0}};
    end else if (X_WIDTH - Q_BITS == Y_WIDTH) begin : g_t0_fit
        assign t_bus[Y_WIDTH-1:0] = x[X_WIDTH-1:Q_BITS];
    end else begin : g_t0_pad
        assign t_bus[Y_WIDTH-1:0] = {{(Y_WIDTH-X_WIDTH+Q_BITS){1'b0}}, x[X_WIDTH-1:Q_BITS]};
    end
endgenerate
assign y_bus[Y_WIDTH-1:0] = y;
assign qx_bus[Q_BITS-1:0] = x[Q_BITS-1:0];
assign q = qx_bus[Q_BITS*Q_BITS +: Q_BITS];

genvar j;
generate
    for (j = 0; j < Q_BITS; j = j + 1) begin : g_stage
        wire [Y_WIDTH-1:0] t_in = t_bus[j*Y_WIDTH +: Y_WIDTH];
        wire [Y_WIDTH-1:0] y_in = y_bus[j*Y_WIDTH +: Y_WIDTH];
        wire [Q_BITS-1:0]  qx_in = qx_bus[j*Q_BITS +: Q_BITS];
        // u = 2 t + the next dividend bit (below 2 y), u - y in [-y, y) with its sign on top
        wire [Y_WIDTH:0]   u = {t_in, qx_in[Q_BITS-1]};
        wire [Y_WIDTH:0]   diff = u - {1'b0, y_in};
        wire               ge = !diff[Y_WIDTH];
        wire [Q_BITS-1:0]  qx_next;
        reg  [Q_BITS-1:0]  qx_reg;

        if (Q_BITS == 1) begin : g_one
            assign qx_next = ge;
        end else begin : g_shift
            assign qx_next = {qx_in[Q_BITS-2:0], ge};
        end

        always @(posedge clk) begin
            qx_reg <= qx_next;
            if (RESET_ALL != 0 && !rst_n) begin
                qx_reg <= {Q_BITS{1'b0}};
            end
        end
        assign qx_bus[(j+1)*Q_BITS +: Q_BITS] = qx_reg;

        if (j < Q_BITS - 1) begin : g_carry
            // The remainder (below y either way) and the divisor for the next stage
            reg [Y_WIDTH-1:0] t_reg;
            reg [Y_WIDTH-1:0] y_reg;
            always @(posedge clk) begin
                t_reg <= ge ? diff[Y_WIDTH-1:0] : u[Y_WIDTH-1:0];
                y_reg <= y_in;
                if (RESET_ALL != 0 && !rst_n) begin
                    t_reg <= {Y_WIDTH{1'b0}};
                    y_reg <= {Y_WIDTH{1'b0}};
                end
            end
            assign t_bus[(j+1)*Y_WIDTH +: Y_WIDTH] = t_reg;
            assign y_bus[(j+1)*Y_WIDTH +: Y_WIDTH] = y_reg;
        end else begin : g_last
            // The last stage: only its quotient bit is needed, not its remainder
            // verilator lint_off UNUSEDSIGNAL
            wire unused_rem = &{1'b0, diff[Y_WIDTH-1:0]};
            // verilator lint_on UNUSEDSIGNAL
        end
    end
endgenerate

endmodule

`resetall
