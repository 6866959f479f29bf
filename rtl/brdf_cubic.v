// SPDX-License-Identifier: Apache-2.0
/*
 * The BRDF unit's cubic datapath (the thesis's c P(c) about the match point s): y = c (p0 +
 * tau (b1 + b2 tau)), tau = 1 - r w, from the angle-table word w = 1 - cos (c = 1 - w, exact)
 * and n's four coefficients r = 1/(1 - s), p0, b1, b2 (the coefficient table's word, read when
 * n is written), bit for bit as model.units.brdf.fixed's cubic_kernel (_tau, _cubic_value):
 *   rw = round(r * w, R_FRAC + D - P)                   (every product exact, then rounded)
 *   t  = 1 - rw saturated to [-16, 16)                  (signed Q5.P: TAU_INT_BITS = 5)
 *   h  = round(b2 * t, B2_FRAC) + round(b1, B1_FRAC - P)
 *   q  = round(t * h, P) + round(p0, P0_FRAC - P)       (signed, P fraction bits)
 *   y  = min(round(c * max(0, q), D + P - O), 2^O - 1)
 * Rounding is add half, slice (of a signed value: then an arithmetic shift, as the model's
 * round_shift); round(x, s) + k is taken as (x's bits above s) + (x's bit s - 1) + k, the same
 * value without a carry through the dropped bits.  Since rw >= 0, t <= 1 < 16: only the floor
 * -16 can bind (rw > 17).
 * Formats: w unsigned, D = COS_DATA_BITS fraction bits, 0 .. 2^D (2^D: cos = 0); k = {r, p0,
 * b1, b2}, each COEF_BITS wide, unsigned: r Q11.(COEF_BITS - 11) (r reaches 1443.2 at
 * n = 1000), p0 Q1.(COEF_BITS - 1) (p0 = 1 at n = 1), b1 and b2 Q0.COEF_BITS (below 0.35);
 * y unsigned, O = OUT_BITS fraction bits.  The widths below hold any word of those formats:
 * t in [-2^(P+4), 2^P] (P + 5 bits), h in [-2^(P+4), 2^(P+1)] (P + 5 bits), q in
 * [-2^(P+5), 2^(P+8) + 2^(P+1)] (P + 10 bits), max(0, q) P + 9 bits.  Four multipliers, two
 * of them signed (rtl/brdf_mul.v, SIGNED = 1), four coefficients per n.
 *
 * Pipeline (thirteen stages, registered after each multiplier and each wide adder): s1 and s2
 * r * w (rtl/brdf_mul.v: the partial products, then their sum), s3 rw_reg (rounding and
 * saturation), s4 t_reg (1 - rw and the floor -16), s5 and s6 b2 * t, s7 h_reg, s8 and s9
 * t * h, s10 q_reg (rounding, + p0, the clip at 0), s11 and s12 c * q, s13 y_reg (rounding,
 * saturation); the word of the w that enters at an edge is on y thirteen edges later.  c and t
 * ride along in c*_reg and t*_reg.  k is the running line's constant (loaded at a start, seven
 * edges before its line's first w arrives): b1 and p0 rounded to P fraction bits are
 * registered from it in b1r_reg and p0r_reg, so that no rounding of a coefficient adds to h's
 * or q's adder.  Reset: none of these registers is control state; RESET_ALL = 1 resets them
 * all (rst_n is synchronous, active low).
 *
 * Shared: rw_prod is the product r * w, exact (RW_WIDTH = COEF_BITS + COS_DATA_BITS + 1 bits,
 * R_FRAC + D fraction bits), two edges after w: the piecewise form's bloom part
 * (rtl/brdf_piecewise.v, which instantiates this module) rounds it its own way; the cubic form
 * leaves it unread.
 *
 * Checks: a COEF_BITS below 11 (r needs 11 integer bits) is refused at elaboration, by an
 * instance of the module brdf_cubic_PARAMETER_ERROR_COEF_BITS_must_be_at_least_11, which does
 * not exist (rtl/brdf_unit.v refuses it first, by the unit's rule).
 *
 * Sources: this file, rtl/brdf_mul.v and rtl/brdf_round.v; instantiated by rtl/brdf_unit.v and
 * rtl/brdf_piecewise.v (rtl/brdf_unit.f).  Documentation: docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_cubic #(
    // Angle-table word bits D: w = 1 - cos with D fraction bits (w itself is D + 1 bits)
    parameter COS_DATA_BITS = 20,
    // Fraction bits P of every intermediate value
    parameter WORK_BITS = 24,
    // Fraction bits O of the output word
    parameter OUT_BITS = 16,
    // Bits of each of the four coefficient words (k is 4 COEF_BITS wide), 11 or more
    parameter COEF_BITS = 18,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire                     clk,
    input  wire                     rst_n,
    input  wire [COS_DATA_BITS:0]   w,
    input  wire [4*COEF_BITS-1:0]   k,
    output wire [OUT_BITS-1:0]      y,
    output wire [COEF_BITS+COS_DATA_BITS:0] rw_prod
);

localparam D = COS_DATA_BITS;
localparam P = WORK_BITS;
localparam O = OUT_BITS;
localparam C = COEF_BITS;
// Fraction bits of r, p0, b1 and b2 (model FixedConfig.coef_formats for COEF_BITS >= 11)
localparam R_FRAC = C - 11;
localparam P0_FRAC = C - 1;
localparam B1_FRAC = C;
localparam B2_FRAC = C;
// r times w (D + 1 bits)
localparam RW_WIDTH = C + D + 1;
// Bits dropped from r * w (R_FRAC + D fraction bits) to P fraction bits
localparam RW_SHIFT = R_FRAC + D - P;
// rw saturated to P + 6 bits (2^(P+6) - 1 is above the floor's 17 2^P)
localparam RWS_WIDTH = P + 6;
// t, h: signed, P fraction bits, P + 5 bits
localparam T_WIDTH = P + 5;
// b2 (a 0 on top: signed) times t
localparam BT_WIDTH = C + 1 + T_WIDTH;
// t times h
localparam TH_WIDTH = 2 * T_WIDTH;
// q: signed, P + 10 bits; max(0, q): unsigned, P + 9 bits
localparam Q_WIDTH = P + 10;
localparam QC_WIDTH = P + 9;
// c (D + 1 bits) times max(0, q)
localparam CQ_WIDTH = D + 1 + QC_WIDTH;
// Bits dropped from c * q (D + P fraction bits) to O
localparam Y_SHIFT = D + P - O;

generate
    if (C < 11) begin : g_check_coef_bits
        brdf_cubic_PARAMETER_ERROR_COEF_BITS_must_be_at_least_11 u_error ();
    end
endgenerate

// The coefficients, r in the highest bits
wire [C-1:0] r_k = k[4*C-1:3*C];
wire [C-1:0] p0_k = k[3*C-1:2*C];
wire [C-1:0] b1_k = k[2*C-1:C];
wire [C-1:0] b2_k = k[C-1:0];

// Stage registers; c*_reg: c = 1 - w of the pixel in that stage
reg [D:0]               c1_reg;
reg [D:0]               c2_reg;
reg [RWS_WIDTH-1:0]     rw_reg;
reg [D:0]               c3_reg;
reg [T_WIDTH-1:0]       t_reg;
reg [D:0]               c4_reg;
reg [T_WIDTH-1:0]       t5_reg;
reg [D:0]               c5_reg;
reg [T_WIDTH-1:0]       t6_reg;
reg [D:0]               c6_reg;
reg [T_WIDTH-1:0]       h_reg;
reg [T_WIDTH-1:0]       t7_reg;
reg [D:0]               c7_reg;
reg [D:0]               c8_reg;
reg [D:0]               c9_reg;
reg [QC_WIDTH-1:0]      q_reg;
reg [D:0]               c10_reg;
reg [O-1:0]             y_reg;
// The line's b1 and p0 rounded to P fraction bits (from k, every clock)
reg [P:0]               b1r_reg;
reg [P+1:0]             p0r_reg;

assign y = y_reg;

// ---------------------------------------------------------------- s1..s3: rw = r w, rounded
wire [RW_WIDTH-1:0] prod_rw;

assign rw_prod = prod_rw;

brdf_mul #(
    .A_WIDTH(C),
    .B_WIDTH(D + 1),
    .SIGNED(0),
    .RESET_ALL(RESET_ALL)
) u_rw (
    .clk(clk),
    .rst_n(rst_n),
    .a(r_k),
    .b(w),
    .p(prod_rw)
);

wire [RWS_WIDTH-1:0] rw_sat;

brdf_round #(
    .IN_WIDTH(RW_WIDTH),
    .SHIFT(RW_SHIFT),
    .OUT_WIDTH(RWS_WIDTH)
) u_round_rw (
    .x(prod_rw),
    .y(rw_sat)
);

// ---------------------------------------------------------------- s4: t = 1 - rw, floor -16
// tau = 2^P - rw in P + 7 bits (signed); below -2^(P+4) when its top three bits are not all
// ones (tau <= 2^P: never all zeros with a 1 below them that would pass 2^(P+4) - 1)
wire [P+6:0] tau = {7'b0000001, {P{1'b0}}} - {1'b0, rw_reg};
wire         tau_low = tau[P+6] && !(&tau[P+6:P+4]);
wire [T_WIDTH-1:0] t_next = tau_low ? {1'b1, {(T_WIDTH-1){1'b0}}} : tau[T_WIDTH-1:0];

// ---------------------------------------------------------------- s5..s7: h = b2 t + b1
wire [BT_WIDTH-1:0] prod_bt;

brdf_mul #(
    .A_WIDTH(C + 1),
    .B_WIDTH(T_WIDTH),
    .SIGNED(1),
    .RESET_ALL(RESET_ALL)
) u_bt (
    .clk(clk),
    .rst_n(rst_n),
    .a({1'b0, b2_k}),
    .b(t_reg),
    .p(prod_bt)
);

// round(b2 t, B2_FRAC) + b1r: the bits above B2_FRAC (signed), the rounding bit and b1r; the
// sum fits T_WIDTH bits (its range above), the adder is one bit wider
wire [T_WIDTH:0] h_sum = prod_bt[BT_WIDTH-1:B2_FRAC]
                         + {{T_WIDTH{1'b0}}, prod_bt[B2_FRAC-1]}
                         + {{(T_WIDTH-P){1'b0}}, b1r_reg};

// b1 and p0 rounded to P fraction bits (b1r <= 2^P, p0r <= 2^(P+1): no saturation)
wire [P:0]   b1r_next;
wire [P+1:0] p0r_next;

brdf_round #(
    .IN_WIDTH(C),
    .SHIFT(B1_FRAC - P),
    .OUT_WIDTH(P + 1)
) u_round_b1 (
    .x(b1_k),
    .y(b1r_next)
);

brdf_round #(
    .IN_WIDTH(C),
    .SHIFT(P0_FRAC - P),
    .OUT_WIDTH(P + 2)
) u_round_p0 (
    .x(p0_k),
    .y(p0r_next)
);

// ---------------------------------------------------------------- s8..s10: q = t h + p0
wire [TH_WIDTH-1:0] prod_th;

brdf_mul #(
    .A_WIDTH(T_WIDTH),
    .B_WIDTH(T_WIDTH),
    .SIGNED(1),
    .RESET_ALL(RESET_ALL)
) u_th (
    .clk(clk),
    .rst_n(rst_n),
    .a(t7_reg),
    .b(h_reg),
    .p(prod_th)
);

// round(t h, P) + p0r, the bits above P (signed, Q_WIDTH of them), then the clip at 0
wire [Q_WIDTH-1:0] q_sum = prod_th[TH_WIDTH-1:P]
                           + {{(Q_WIDTH-1){1'b0}}, prod_th[P-1]}
                           + {{(Q_WIDTH-P-2){1'b0}}, p0r_reg};
wire [QC_WIDTH-1:0] q_next = q_sum[Q_WIDTH-1] ? {QC_WIDTH{1'b0}} : q_sum[QC_WIDTH-1:0];

// ---------------------------------------------------------------- s11..s13: y = c q
wire [CQ_WIDTH-1:0] prod_cq;

brdf_mul #(
    .A_WIDTH(D + 1),
    .B_WIDTH(QC_WIDTH),
    .SIGNED(0),
    .RESET_ALL(RESET_ALL)
) u_cq (
    .clk(clk),
    .rst_n(rst_n),
    .a(c10_reg),
    .b(q_reg),
    .p(prod_cq)
);

wire [O-1:0] y_next;

brdf_round #(
    .IN_WIDTH(CQ_WIDTH),
    .SHIFT(Y_SHIFT),
    .OUT_WIDTH(O)
) u_round_y (
    .x(prod_cq),
    .y(y_next)
);

// Bits dropped on purpose: below each rounding bit, and h_sum's carry (the sum fits T_WIDTH)
// verilator lint_off UNUSEDSIGNAL
wire unused_bits = &{1'b0, prod_bt[B2_FRAC-2:0], prod_th[P-2:0], h_sum[T_WIDTH]};
// verilator lint_on UNUSEDSIGNAL

always @(posedge clk) begin
    c1_reg <= {1'b1, {D{1'b0}}} - w;
    c2_reg <= c1_reg;
    rw_reg <= rw_sat;
    c3_reg <= c2_reg;
    t_reg <= t_next;
    c4_reg <= c3_reg;
    t5_reg <= t_reg;
    c5_reg <= c4_reg;
    t6_reg <= t5_reg;
    c6_reg <= c5_reg;
    h_reg <= h_sum[T_WIDTH-1:0];
    t7_reg <= t6_reg;
    c7_reg <= c6_reg;
    c8_reg <= c7_reg;
    c9_reg <= c8_reg;
    q_reg <= q_next;
    c10_reg <= c9_reg;
    y_reg <= y_next;
    b1r_reg <= b1r_next;
    p0r_reg <= p0r_next;

    if (RESET_ALL != 0 && !rst_n) begin
        c1_reg <= {(D+1){1'b0}};
        c2_reg <= {(D+1){1'b0}};
        rw_reg <= {RWS_WIDTH{1'b0}};
        c3_reg <= {(D+1){1'b0}};
        t_reg <= {T_WIDTH{1'b0}};
        c4_reg <= {(D+1){1'b0}};
        t5_reg <= {T_WIDTH{1'b0}};
        c5_reg <= {(D+1){1'b0}};
        t6_reg <= {T_WIDTH{1'b0}};
        c6_reg <= {(D+1){1'b0}};
        h_reg <= {T_WIDTH{1'b0}};
        t7_reg <= {T_WIDTH{1'b0}};
        c7_reg <= {(D+1){1'b0}};
        c8_reg <= {(D+1){1'b0}};
        c9_reg <= {(D+1){1'b0}};
        q_reg <= {QC_WIDTH{1'b0}};
        c10_reg <= {(D+1){1'b0}};
        y_reg <= {O{1'b0}};
        b1r_reg <= {(P+1){1'b0}};
        p0r_reg <= {(P+2){1'b0}};
    end
end

endmodule

`resetall
