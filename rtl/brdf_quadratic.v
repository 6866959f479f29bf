// SPDX-License-Identifier: Apache-2.0
/*
 * The BRDF unit's quadratic datapath (the thesis's fig. 9a): y = a c^2 + (1 - a) c = c (1 - a w)
 * from the angle-table word w = 1 - cos (c = 1 - w, exact) and n's coefficient a (the
 * coefficient table's word, read when n is written), bit for bit as model.units.brdf.fixed's
 * quadratic_kernel:
 *   m = round(a * w, COEF_FRAC_BITS + D - P)   (every product exact, then rounded)
 *   t = max(0, 1 - m)                          (P fraction bits)
 *   y = min(round(c * t, D + P - O), 2^O - 1)
 * Formats: w unsigned, D = COS_DATA_BITS fraction bits, 0 .. 2^D (2^D: cos = 0); k = a,
 * unsigned Q(COEF_BITS - COEF_FRAC_BITS).(COEF_FRAC_BITS); y unsigned, O = OUT_BITS fraction
 * bits.  Two multipliers and a subtractor, one coefficient per n.
 *
 * Pipeline (six stages, registered after each multiplier and each wide adder): s1 prod_reg =
 * a * w and c1_reg = 1 - w, s2 m_reg (rounding and saturation), s3 t_reg (the clip at 0 and
 * 1 - m), s4 and s5 c * t (rtl/brdf_mul.v: the partial products, then their sum), s6 y_reg
 * (rounding, saturation); the word of the w that enters at an edge is on y six edges later.
 * k is the running line's constant.  Reset: none of these registers is control state;
 * RESET_ALL = 1 resets them all (rst_n is synchronous, active low).
 *
 * Sources: this file, rtl/brdf_mul.v and rtl/brdf_round.v; instantiated by rtl/brdf_unit.v (rtl/brdf_unit.f).
 * Documentation: docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_quadratic #(
    // Angle-table word bits D: w = 1 - cos with D fraction bits (w itself is D + 1 bits)
    parameter COS_DATA_BITS = 20,
    // Fraction bits P of every intermediate value
    parameter WORK_BITS = 24,
    // Fraction bits O of the output word
    parameter OUT_BITS = 16,
    // Bits of the coefficient word a
    parameter COEF_BITS = 18,
    // Fraction bits of a (the unit derives them: COEF_BITS - 10)
    parameter COEF_FRAC_BITS = 8,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire                     clk,
    input  wire                     rst_n,
    input  wire [COS_DATA_BITS:0]   w,
    input  wire [COEF_BITS-1:0]     k,
    output wire [OUT_BITS-1:0]      y
);

localparam D = COS_DATA_BITS;
localparam P = WORK_BITS;
localparam O = OUT_BITS;
// a times w (D + 1 bits)
localparam PROD_WIDTH = COEF_BITS + D + 1;
// Bits dropped from a * w (COEF_FRAC_BITS + D fraction bits) to P fraction bits
localparam M_SHIFT = COEF_FRAC_BITS + D - P;
// c (D + 1 bits) times t (P + 1 bits)
localparam PROD2_WIDTH = D + P + 2;
// Bits dropped from c * t (D + P fraction bits) to O
localparam Y_SHIFT = D + P - O;

reg [PROD_WIDTH-1:0]  prod_reg;
reg [D:0]             c1_reg;
reg [P:0]             m_reg;
reg [D:0]             c2_reg;
reg [P:0]             t_reg;
reg [D:0]             c3_reg;
wire [PROD2_WIDTH-1:0] prod2;
reg [O-1:0]           y_reg;

assign y = y_reg;

// s1 -> s2: m rounded to P fraction bits and saturated to P + 1 bits (2^P or more: t = 0);
// s2 -> s3: t = 1 - m, clipped at 0
wire [P:0] m_sat;
wire [P:0] t_next = m_reg[P] ? {(P+1){1'b0}} : {1'b1, {P{1'b0}}} - m_reg;

brdf_round #(
    .IN_WIDTH(PROD_WIDTH),
    .SHIFT(M_SHIFT),
    .OUT_WIDTH(P + 1)
) u_round_m (
    .x(prod_reg),
    .y(m_sat)
);

// s3 -> s5: c * t, exact
brdf_mul #(
    .A_WIDTH(D + 1),
    .B_WIDTH(P + 1),
    .RESET_ALL(RESET_ALL)
) u_ct (
    .clk(clk),
    .rst_n(rst_n),
    .a(c3_reg),
    .b(t_reg),
    .p(prod2)
);

// s5 -> s6: c * t rounded to O fraction bits, saturated to 2^O - 1
wire [O-1:0] y_next;

brdf_round #(
    .IN_WIDTH(PROD2_WIDTH),
    .SHIFT(Y_SHIFT),
    .OUT_WIDTH(O)
) u_round_y (
    .x(prod2),
    .y(y_next)
);

always @(posedge clk) begin
    prod_reg <= k * w;
    c1_reg <= {1'b1, {D{1'b0}}} - w;
    m_reg <= m_sat;
    c2_reg <= c1_reg;
    t_reg <= t_next;
    c3_reg <= c2_reg;
    y_reg <= y_next;

    if (RESET_ALL != 0 && !rst_n) begin
        prod_reg <= {PROD_WIDTH{1'b0}};
        c1_reg <= {(D+1){1'b0}};
        m_reg <= {(P+1){1'b0}};
        c2_reg <= {(D+1){1'b0}};
        t_reg <= {(P+1){1'b0}};
        c3_reg <= {(D+1){1'b0}};
        y_reg <= {O{1'b0}};
    end
end

endmodule

`resetall
