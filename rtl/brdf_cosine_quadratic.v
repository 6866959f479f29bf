// SPDX-License-Identifier: Apache-2.0
/*
 * The BRDF unit's cosine-quadratic datapath (the thesis's fig. 9c): y = (1 - (7n/16) w)^2 from
 * the angle-table word w = 1 - cos and the n register's 7n, bit for bit as
 * model.units.brdf.fixed's cosine_quadratic_kernel:
 *   m    = round(7n * w, 4 + D - P)   (7n has 4 fraction bits; every product exact, then rounded)
 *   base = max(0, 1 - m)              (P fraction bits)
 *   y    = min(round(base^2, 2P - O), 2^O - 1)
 * Formats: w unsigned, D = COS_DATA_BITS fraction bits, 0 .. 2^D (2^D: cos = 0, from pi/2 on);
 * k = 7n, 13 bits (n up to 1023: the unit gates the result of an n outside 1..1000); y unsigned,
 * O = OUT_BITS fraction bits.  Two multipliers, no coefficient table.
 *
 * Pipeline (five stages, registered after each multiplier): s1 prod_reg = k * w, s2 base_reg
 * (rounding and the clip at 0), s3 and s4 base^2 (rtl/brdf_mul.v: the partial products, then
 * their sum), s5 y_reg (rounding, saturation); the word of the w that enters at an edge is on
 * y five edges later.  k is the running line's constant.
 * Reset: none of these registers is control state; RESET_ALL = 1 resets them all (rst_n is
 * synchronous, active low).
 *
 * Sources: this file, rtl/brdf_mul.v and rtl/brdf_round.v; instantiated by rtl/brdf_unit.v (rtl/brdf_unit.f).
 * Documentation: docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_cosine_quadratic #(
    // Angle-table word bits D: w = 1 - cos with D fraction bits (w itself is D + 1 bits)
    parameter COS_DATA_BITS = 20,
    // Fraction bits P of every intermediate value
    parameter WORK_BITS = 24,
    // Fraction bits O of the output word
    parameter OUT_BITS = 16,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire                     clk,
    input  wire                     rst_n,
    input  wire [COS_DATA_BITS:0]   w,
    input  wire [12:0]              k,
    output wire [OUT_BITS-1:0]      y
);

localparam D = COS_DATA_BITS;
localparam P = WORK_BITS;
localparam O = OUT_BITS;
// 7n (13 bits) times w (D + 1 bits)
localparam PROD_WIDTH = D + 14;
// Bits dropped from 7n * w (4 + D fraction bits) to P fraction bits
localparam M_SHIFT = 4 + D - P;
// Bits dropped from base^2 (2P fraction bits) to O
localparam Y_SHIFT = 2 * P - O;

reg [PROD_WIDTH-1:0] prod_reg;
reg [P:0]            base_reg;
wire [2*P+1:0]       sq;
reg [O-1:0]          y_reg;

assign y = y_reg;

// s1 -> s2: m rounded to P fraction bits and saturated to P + 1 bits (2^P or more: base = 0)
wire [P:0] m_sat;
wire [P:0] base_next = m_sat[P] ? {(P+1){1'b0}} : {1'b1, {P{1'b0}}} - m_sat;

brdf_round #(
    .IN_WIDTH(PROD_WIDTH),
    .SHIFT(M_SHIFT),
    .OUT_WIDTH(P + 1)
) u_round_m (
    .x(prod_reg),
    .y(m_sat)
);

// s2 -> s4: base^2, exact
brdf_mul #(
    .A_WIDTH(P + 1),
    .B_WIDTH(P + 1),
    .RESET_ALL(RESET_ALL)
) u_square (
    .clk(clk),
    .rst_n(rst_n),
    .a(base_reg),
    .b(base_reg),
    .p(sq)
);

// s4 -> s5: base^2 rounded to O fraction bits, saturated to 2^O - 1
wire [O-1:0] y_next;

brdf_round #(
    .IN_WIDTH(2 * P + 2),
    .SHIFT(Y_SHIFT),
    .OUT_WIDTH(O)
) u_round_y (
    .x(sq),
    .y(y_next)
);

always @(posedge clk) begin
    prod_reg <= k * w;
    base_reg <= base_next;
    y_reg <= y_next;

    if (RESET_ALL != 0 && !rst_n) begin
        prod_reg <= {PROD_WIDTH{1'b0}};
        base_reg <= {(P+1){1'b0}};
        y_reg <= {O{1'b0}};
    end
end

endmodule

`resetall
