// SPDX-License-Identifier: Apache-2.0
/*
 * The BRDF unit's piecewise datapath (docs/brdf.md, "Piecewise"): the cubic c P(c) where
 * tau = 1 - r w > 0 (c > s, the whole epicentre), else the bloom part c / (alpha - beta c),
 * its denominator written s2 + beta (r w - 1), from the angle-table word w = 1 - cos and n's six
 * coefficients (the coefficient table's words, read when n is written), bit for bit as
 * model.units.brdf.fixed's piecewise_kernel:
 *   rw  = round(r * w, R_FRAC + D - P)                  (the cubic's product, shared)
 *   y   = the cubic's word (rtl/brdf_cubic.v)            if rw < 2^P (tau > 0)
 *   den = round(s2, S2_FRAC - P) + round(beta * (rw - 2^P), BETA_FRAC)     (P fraction bits)
 *   num = c 2^NS, den' = den 2^DS                       (NS - DS = P + O - D, one of them 0)
 *   y   = min((2 num + den') // (2 den'), 2^O - 1)      otherwise (c / den rounded half up)
 * Rounding is add half, slice.  The cubic is an instance of rtl/brdf_cubic.v, its product r w
 * (rw_prod) shared; the quotient comes from a pipelined restoring divider (rtl/brdf_div.v).
 *
 * Formats: w unsigned, D = COS_DATA_BITS fraction bits, 0 .. 2^D (2^D: cos = 0); k = {r, p0,
 * b1, b2, s2, beta}, each COEF_BITS wide, unsigned (model FixedConfig.coef_formats for every
 * COEF_BITS from 11 to 21): the cubic's r Q11, p0 Q1, b1 Q0, b2 Q0, then s2 = 2 s and beta =
 * 2 (n - 1)(1 - s) in Q1.(COEF_BITS - 1) (s2 in [1, 2), beta below 1.39); y unsigned, O =
 * OUT_BITS fraction bits.  Five multipliers (the cubic's four, beta x (r w - 1)), six
 * coefficients per n.
 *
 * Widths, proven here for every word of those formats (and checked on the model's table where
 * a bound needs the table: tests/test_brdf_piecewise.py, every n and every table word):
 *  1. rw <= 2^(P+11): r < 2^11 and w <= 1, rounded.  rw - 2^P lies in [-2^P, 2^(P+11) - 2^P]:
 *     RWM_WIDTH = P + 12 bits signed hold it, its sign is the branch (1: rw < 2^P, the cubic);
 *     in the bloom branch 0 <= rw - 2^P < 2^(P+11): its P + 11 low bits, unsigned.  It is one
 *     sum of the product (C + D + 1 bits, or scaled up: P + 12 + RW_SH bits in all) and a
 *     constant, modulo 2^(P + 12 + RW_SH), whose exact value, below 2^(P+11+RW_SH) in
 *     magnitude, those bits hold.
 *  2. beta < 2 times rw - 2^P < 2^(P+11): below 2^(BETA_FRAC + P + 12), exact in COEF_BITS +
 *     P + 11 bits; rounded to P fraction bits, at most 2^(P+12).
 *  3. round(s2) <= 2^(P+1) (s2 < 2), and >= 2^P for the table's words: s2 = 2 s >= 1 for every
 *     n (s = 0.5^(1/n) >= 1/2; the image's checksum holds the unit to the model's words).
 *  4. den = round(s2) + round(beta (rw - 1)) <= 2^(P+12) + 2^(P+1) < 2^(P+13): DEN_WIDTH =
 *     P + 13 bits; den >= round(s2) >= 2^P > 0 for every pixel (the product term is >= 0 in the
 *     bloom branch, and in the cubic branch it is whatever the gated product gives, >= 0).
 *  5. In the bloom branch w >= 1 (w = 0 gives rw = 0 < 2^P): c = 2^D - w < 2^D, so
 *     num / den' = (c 2^-D) / (den 2^-P) 2^O < 2^O.
 *  6. (2 num + den') // (2 den') = (a + 1) >> 1, a = (2 num) // den': with 2 num = a den' + r,
 *     0 <= r < den', the quotient is (a + 1) / 2 + r / (2 den'), and r / (2 den') < 1/2 adds
 *     nothing to the floor whether a + 1 is even or odd.  So the divider divides 2 num (c
 *     shifted: no adder) by den', and its precondition 2 num < den' 2^(O+1) holds by 5:
 *     a < 2^(O+1), the O + 1 quotient bits Q_BITS are the only ones that can be 1 (bit O is 1
 *     when c / den >= 1/2: at the junction the bloom part is 1/2, and the rounding of the
 *     words can take it past: never at the default widths, but with 11-bit coefficients,
 *     whose s2 rounds low, as the test measures).  In the cubic branch the dividend is gated
 *     to 0: the
 *     precondition holds for every pixel (den > 0 by 4) and the quotient 0 is discarded.
 *  7. (a + 1) >> 1 <= 2^O, equal only for a = 2^(O+1) - 1, which saturates to 2^O - 1 = a >> 1:
 *     q = a[O:1] + (a[0] & ~&a[O:1]), an O-bit incrementer that never carries out.
 *  8. The divider's operands: x = 2 num, X_WIDTH = D + 2 + NS bits; y = den', Y_WIDTH =
 *     P + 13 + DS bits; X_WIDTH - Q_BITS = P + 1 (NS > 0 or NS = DS = 0) or D + 1 - O (DS > 0),
 *     at most Y_WIDTH, as rtl/brdf_div.v requires.
 *
 * Pipeline (one pixel per clock; s<e> is the register written at the e-th edge after w):
 *   s1, s2    r * w (in the cubic instance), c1 = 2^D - w, c2
 *   s3        rw - 2^P in one adder (the rounding half and -2^P one constant) and its sign
 *   s4, s5    beta * (rw - 2^P) (rtl/brdf_mul.v, beta whole: SPLIT_A = 0, two blocks)
 *   s6        den, and num = c (0 in the cubic branch)
 *   s7 ..     the divider, one stage per quotient bit: a after s(O + 7)
 *   s(LATENCY) y: the quotient rounded and saturated (7) or the cubic's word (its s13), by the
 *             branch flag; LATENCY = max(14, O + 8) (model.units.brdf.form_latency): the cubic's
 *             word waits O - 6 edges, or for O < 6 the quotient waits 6 - O.
 * k is the running line's constant (loaded at a start, seven edges before its line's first w;
 * the next start comes only after the line's last result): s2 rounded to P fraction bits is
 * registered from it in s2r_reg (no rounding adds to den's adder), beta in beta_reg (so that
 * the multiplier's operand comes from a register placed beside it).  Reset: none of these
 * registers is control state; RESET_ALL = 1 resets them all (rst_n is synchronous, active
 * low).
 *
 * Checks: a COEF_BITS outside 11..21 (r needs 11 integer bits, three coefficients fill a ROM
 * word of at most 64 bits) is refused at elaboration, by an instance of the module
 * brdf_piecewise_PARAMETER_ERROR_COEF_BITS_must_be_11_to_21, which does not exist
 * (rtl/brdf_unit.v refuses it first, by the unit's rule).
 *
 * Sources: this file, rtl/brdf_cubic.v, rtl/brdf_div.v, rtl/brdf_delay.v, rtl/brdf_mul.v and
 * rtl/brdf_round.v; instantiated by rtl/brdf_unit.v (rtl/brdf_unit.f).  Documentation:
 * docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_piecewise #(
    // Angle-table word bits D: w = 1 - cos with D fraction bits (w itself is D + 1 bits)
    parameter COS_DATA_BITS = 20,
    // Fraction bits P of every intermediate value
    parameter WORK_BITS = 24,
    // Fraction bits O of the output word
    parameter OUT_BITS = 16,
    // Bits of each of the six coefficient words (k is 6 COEF_BITS wide), 11..21
    parameter COEF_BITS = 18,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire                     clk,
    input  wire                     rst_n,
    input  wire [COS_DATA_BITS:0]   w,
    input  wire [6*COEF_BITS-1:0]   k,
    output wire [OUT_BITS-1:0]      y
);

localparam D = COS_DATA_BITS;
localparam P = WORK_BITS;
localparam O = OUT_BITS;
localparam C = COEF_BITS;
// Fraction bits of r, s2 and beta (model FixedConfig.coef_formats for COEF_BITS 11..21)
localparam R_FRAC = C - 11;
localparam S2_FRAC = C - 1;
localparam BETA_FRAC = C - 1;
// r times w (D + 1 bits), from the cubic instance
localparam RW_WIDTH = C + D + 1;
// Bits dropped from r * w (R_FRAC + D fraction bits) to P fraction bits: rounded (> 0) or
// zeros appended (< 0)
localparam RW_SHIFT = R_FRAC + D - P;
localparam RW_SH = (RW_SHIFT > 0) ? RW_SHIFT : 0;
localparam RW_EXT = (RW_SHIFT < 0) ? -RW_SHIFT : 0;
// round(r w) - 2^P, signed (1.), and its sum before the slice (the product's width, scaled)
localparam RWM_WIDTH = P + 12;
localparam SUM_WIDTH = RWM_WIDTH + RW_SH;
// rw - 2^P in the bloom branch (unsigned)
localparam RWB_WIDTH = P + 11;
// beta times it (2.)
localparam BP_WIDTH = C + RWB_WIDTH;
// den (4.)
localparam DEN_WIDTH = P + 13;
// The alignment of c (D fraction bits) and den (P) for an O-bit quotient (the model's)
localparam NUM_SHIFT = (P + O >= D) ? P + O - D : 0;
localparam DEN_SHIFT = (P + O >= D) ? 0 : D - P - O;
// The divider: 2 num by den' (6., 8.)
localparam X_WIDTH = D + 2 + NUM_SHIFT;
localparam Y_WIDTH = DEN_WIDTH + DEN_SHIFT;
localparam Q_BITS = O + 1;
// Stages (model.units.brdf.form_latency) and the waits that align the branches
localparam LATENCY = (O + 8 > 14) ? O + 8 : 14;
localparam CUBIC_WAIT = LATENCY - 14;
localparam QUOTIENT_WAIT = LATENCY - (O + 8);
localparam FLAG_WAIT = LATENCY - 7;

generate
    if (C < 11 || C > 21) begin : g_check_coef_bits
        brdf_piecewise_PARAMETER_ERROR_COEF_BITS_must_be_11_to_21 u_error ();
    end
endgenerate

// The coefficients, r in the highest bits: the cubic's four, then s2 and beta
wire [4*C-1:0] cubic_k = k[6*C-1:2*C];
wire [C-1:0]   s2_k = k[2*C-1:C];
wire [C-1:0]   beta_k = k[C-1:0];

// Stage registers; c*_reg: c = 1 - w of the pixel in that stage, bloom*_reg: its branch
reg [D:0]           c1_reg;
reg [D:0]           c2_reg;
reg [D:0]           c3_reg;
reg [D:0]           c4_reg;
reg [D:0]           c5_reg;
reg [RWB_WIDTH-1:0] rwb_reg;
reg                 bloom3_reg;
reg                 bloom4_reg;
reg                 bloom5_reg;
reg                 bloom6_reg;
reg [D:0]           num_reg;
reg [DEN_WIDTH-1:0] den_reg;
reg [O-1:0]         y_reg;
// The line's s2 rounded to P fraction bits and its beta (from k, every clock: the multiplier
// reads a register of its own, which the placer puts beside it)
reg [P+1:0]         s2r_reg;
reg [C-1:0]         beta_reg;

assign y = y_reg;

// ---------------------------------------------------------------- the cubic, r w shared
wire [O-1:0]          y_cubic;
wire [RW_WIDTH-1:0]   rw_prod;

brdf_cubic #(
    .COS_DATA_BITS(D),
    .WORK_BITS(P),
    .OUT_BITS(O),
    .COEF_BITS(C),
    .RESET_ALL(RESET_ALL)
) u_cubic (
    .clk(clk),
    .rst_n(rst_n),
    .w(w),
    .k(cubic_k),
    .y(y_cubic),
    .rw_prod(rw_prod)
);

// ---------------------------------------------------------------- s3: rw - 2^P, the branch
// round(r w, S) - 2^P = (r w + 2^(S-1) - 2^(P+S)) >> S (arithmetic), one adder with one
// constant; S <= 0: (r w 2^-S) - 2^P
wire [SUM_WIDTH-1:0] rw_ext;

generate
    if (RW_EXT > 0) begin : g_rw_scale
        assign rw_ext = {rw_prod, {RW_EXT{1'b0}}};
    end else begin : g_rw_keep
        assign rw_ext = rw_prod;
    end
endgenerate

localparam [SUM_WIDTH-1:0] RW_HALF = ({{(SUM_WIDTH-1){1'b0}}, 1'b1} << RW_SH) >> 1;
localparam [SUM_WIDTH-1:0] RW_ONE = {{(SUM_WIDTH-1){1'b0}}, 1'b1} << (P + RW_SH);
localparam [SUM_WIDTH-1:0] RW_K = RW_HALF - RW_ONE;
wire [SUM_WIDTH-1:0] rwm_sum = rw_ext + RW_K;
wire [RWM_WIDTH-1:0] rwm = rwm_sum[SUM_WIDTH-1:RW_SH];

// ---------------------------------------------------------------- s4..s6: den
wire [BP_WIDTH-1:0] prod_bp;

brdf_mul #(
    .A_WIDTH(C),
    .B_WIDTH(RWB_WIDTH),
    .SIGNED(0),
    .SPLIT_A(0),  // beta whole: 2 multiplier blocks, not 4 (rtl/brdf_mul.v)
    .RESET_ALL(RESET_ALL)
) u_bp (
    .clk(clk),
    .rst_n(rst_n),
    .a(beta_reg),
    .b(rwb_reg),
    .p(prod_bp)
);

// s2 rounded to P fraction bits (at most 2^(P+1): no saturation)
wire [P+1:0] s2r_next;

brdf_round #(
    .IN_WIDTH(C),
    .SHIFT(S2_FRAC - P),
    .OUT_WIDTH(P + 2)
) u_round_s2 (
    .x(s2_k),
    .y(s2r_next)
);

// round(beta (rw - 2^P), BETA_FRAC) + s2r: the bits above BETA_FRAC, the rounding bit and s2r
// (below 2^(P+13): 4.)
wire [DEN_WIDTH-1:0] den_next = {1'b0, prod_bp[BP_WIDTH-1:BETA_FRAC]}
                                + {{(DEN_WIDTH-1){1'b0}}, prod_bp[BETA_FRAC-1]}
                                + {{(DEN_WIDTH-P-2){1'b0}}, s2r_reg};

// ---------------------------------------------------------------- s7..: a = 2 num / den'
wire [X_WIDTH-1:0] div_x = {num_reg, {(NUM_SHIFT+1){1'b0}}};
wire [Y_WIDTH-1:0] div_y;
wire [Q_BITS-1:0]  div_q;

generate
    if (DEN_SHIFT > 0) begin : g_den_scale
        assign div_y = {den_reg, {DEN_SHIFT{1'b0}}};
    end else begin : g_den_keep
        assign div_y = den_reg;
    end
endgenerate

brdf_div #(
    .X_WIDTH(X_WIDTH),
    .Y_WIDTH(Y_WIDTH),
    .Q_BITS(Q_BITS),
    .RESET_ALL(RESET_ALL)
) u_div (
    .clk(clk),
    .rst_n(rst_n),
    .x(div_x),
    .y(div_y),
    .q(div_q)
);

// ---------------------------------------------------------------- s(LATENCY): the select
wire [Q_BITS-1:0] a_wait;
wire [O-1:0]      cubic_wait;
wire              bloom_wait;

brdf_delay #(
    .WIDTH(Q_BITS),
    .DEPTH(QUOTIENT_WAIT),
    .RESET_ALL(RESET_ALL)
) u_wait_quotient (
    .clk(clk),
    .rst_n(rst_n),
    .x(div_q),
    .y(a_wait)
);

brdf_delay #(
    .WIDTH(O),
    .DEPTH(CUBIC_WAIT),
    .RESET_ALL(RESET_ALL)
) u_wait_cubic (
    .clk(clk),
    .rst_n(rst_n),
    .x(y_cubic),
    .y(cubic_wait)
);

brdf_delay #(
    .WIDTH(1),
    .DEPTH(FLAG_WAIT),
    .RESET_ALL(RESET_ALL)
) u_wait_flag (
    .clk(clk),
    .rst_n(rst_n),
    .x(bloom6_reg),
    .y(bloom_wait)
);

// (a + 1) >> 1 saturated to 2^O - 1 (7.)
wire [O-1:0] a_half = a_wait[O:1];
wire         a_up = a_wait[0] && !(&a_half);
wire [O-1:0] q_sat;

generate
    if (O > 1) begin : g_round_q
        assign q_sat = a_half + {{(O-1){1'b0}}, a_up};
    end else begin : g_round_q1
        assign q_sat = a_half | a_up;
    end
endgenerate

wire [O-1:0] y_next = bloom_wait ? q_sat : cubic_wait;

// Bits dropped on purpose: below the rounding bit of beta (rw - 2^P), and the bits the
// rounding of r w drops
// verilator lint_off UNUSEDSIGNAL
wire unused_bits = &{1'b0, prod_bp[BETA_FRAC-2:0]};

generate
    if (RW_SH > 0) begin : g_rw_dropped
        wire unused_rw = &{1'b0, rwm_sum[RW_SH-1:0]};
    end
endgenerate
// verilator lint_on UNUSEDSIGNAL

always @(posedge clk) begin
    c1_reg <= {1'b1, {D{1'b0}}} - w;
    c2_reg <= c1_reg;
    c3_reg <= c2_reg;
    c4_reg <= c3_reg;
    c5_reg <= c4_reg;
    rwb_reg <= rwm[RWB_WIDTH-1:0];
    bloom3_reg <= !rwm[RWM_WIDTH-1];
    bloom4_reg <= bloom3_reg;
    bloom5_reg <= bloom4_reg;
    bloom6_reg <= bloom5_reg;
    num_reg <= bloom5_reg ? c5_reg : {(D+1){1'b0}};
    den_reg <= den_next;
    y_reg <= y_next;
    s2r_reg <= s2r_next;
    beta_reg <= beta_k;

    if (RESET_ALL != 0 && !rst_n) begin
        c1_reg <= {(D+1){1'b0}};
        c2_reg <= {(D+1){1'b0}};
        c3_reg <= {(D+1){1'b0}};
        c4_reg <= {(D+1){1'b0}};
        c5_reg <= {(D+1){1'b0}};
        rwb_reg <= {RWB_WIDTH{1'b0}};
        bloom3_reg <= 1'b0;
        bloom4_reg <= 1'b0;
        bloom5_reg <= 1'b0;
        bloom6_reg <= 1'b0;
        num_reg <= {(D+1){1'b0}};
        den_reg <= {DEN_WIDTH{1'b0}};
        y_reg <= {O{1'b0}};
        s2r_reg <= {(P+2){1'b0}};
        beta_reg <= {C{1'b0}};
    end
end

endmodule

`resetall
