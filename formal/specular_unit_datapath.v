// SPDX-License-Identifier: Apache-2.0
/*
 * The specular unit's data path as the contract states it (docs/specular.md, "The datapath,
 * step by step"), for the formal proofs of formal/specular_unit_props.v: one pixel's intensity
 * from the pixel's angle zeta and the line's C and n, written as the formula, not as the RTL's
 * pipeline (no stages; |zeta| by a negation, not the RTL's one's complement and carry).  The
 * property file accumulates zeta as the contract does: zeta_0 = z0, zeta_i = zeta_(i-1) + dz,
 * in the accumulator's width (Z_INT_BITS + Z_FRAC_BITS + LEN_WIDTH bits, which the contract
 * says z0 + l dz never leaves):
 *
 *   a     = ROM 9 word of n (address n - N_FIRST), the table j = the k range holding n
 *   mag   = min(|zeta|, 2^(MAG_INT_BITS + Z_FRAC_BITS) - 1)    |zeta| saturated
 *   addr  = floor((mag * a + 2^(SHIFT-1)) / 2^SHIFT)
 *   word  = 0 if addr >= 2^ROM_ADDR_BITS (a |zeta| >= pi/2) or n is invalid, else table j's
 *           word addr of ROM 12
 *   out   = min(floor((C * word + 2^(OSHIFT-1)) / 2^OSHIFT), 2^OUT_WIDTH - 1), 0 for an invalid n
 *
 * The ROM words are inputs: the module names the word it reads (a_index: ROM 9, cos_index
 * and cos_index_u: ROM 12) and the property file answers from its own copies of the
 * committed images (the same files the RTL reads, read with $readmemh), so the property
 * proves the unit's pipeline, not the tables' contents (the contract tests check every word
 * against cos^k and sqrt(n/k)).  Outputs besides out: the pieces the covers and
 * the induction helpers of the property file read, and clamp_matters: the word read with
 * |zeta| NOT saturated differs from word (the contract says the saturation never changes a
 * result; the property clamp_never_changes_a_result asserts clamp_matters = 0).
 */

module specular_unit_ref #(
    parameter C_INT_BITS = 8,
    parameter C_FRAC_BITS = 8,
    parameter Z_INT_BITS = 3,
    parameter Z_FRAC_BITS = 26,
    parameter LEN_WIDTH = 11,
    parameter A_INT_BITS = 3,
    parameter A_FRAC_BITS = 14,
    parameter ROM_ADDR_BITS = 12,
    parameter ROM_DATA_BITS = 16,
    parameter OUT_WIDTH = 8,
    parameter NUM_TABLES = 4,
    parameter N_HI0 = 1,
    parameter N_HI1 = 2,
    parameter N_HI2 = 6,
    parameter MAG_INT_BITS = 1,
    parameter N_FIRST = 1,
    parameter N_LAST = 1000,
    // 1: the two products (scaled = mag * a, lit = C * word) are inputs, computed outside on
    // operands the caller asserts equal to mag, a, c and word (the bounded check at the default)
    parameter EXT_PRODUCTS = 0
) (
    input  wire [C_INT_BITS+C_FRAC_BITS-1:0] c,
    input  wire signed [Z_INT_BITS+Z_FRAC_BITS+LEN_WIDTH-1:0] zeta,
    input  wire [9:0]                        n,
    output wire [9:0]                        a_index,     // ROM 9's word read: a_word
    input  wire [A_INT_BITS+A_FRAC_BITS-1:0] a_word,
    output wire [31:0]                       cos_index,   // ROM 12's word read: cos_word
    input  wire [ROM_DATA_BITS-1:0]          cos_word,
    output wire [31:0]                       cos_index_u, // the same without the saturation
    input  wire [ROM_DATA_BITS-1:0]          cos_word_u,
    output wire                              nerr,   // n outside 1..1000 or N_FIRST..N_LAST
    output wire [1:0]                        table_j,
    output wire [A_INT_BITS+A_FRAC_BITS-1:0] a,
    output wire                              past_half_pi,  // addr >= 2^ROM_ADDR_BITS
    output wire [ROM_DATA_BITS-1:0]          word,
    output wire                              clamp_matters,
    output wire [MAG_INT_BITS+Z_FRAC_BITS-1:0] mag,
    output wire [MAG_INT_BITS+Z_FRAC_BITS+A_INT_BITS+A_FRAC_BITS-1:0] scaled,
    output wire [MAG_INT_BITS+Z_FRAC_BITS+A_INT_BITS+A_FRAC_BITS:0] addr,
    output wire                              saturated,     // the rounded product > the max
    output wire [OUT_WIDTH-1:0]              out,
    // with EXT_PRODUCTS = 1: mag * a and C * word (else unused)
    input  wire [MAG_INT_BITS+Z_FRAC_BITS+A_INT_BITS+A_FRAC_BITS-1:0] scaled_in,
    input  wire [C_INT_BITS+C_FRAC_BITS+ROM_DATA_BITS:0] lit_in
);

localparam Z_W = Z_INT_BITS + Z_FRAC_BITS;
localparam RW = Z_W + LEN_WIDTH + 1;  // |zeta| of the most negative zeta fits
localparam A_W = A_INT_BITS + A_FRAC_BITS;
localparam C_W = C_INT_BITS + C_FRAC_BITS;
localparam SHIFT = Z_FRAC_BITS + A_FRAC_BITS - ROM_ADDR_BITS;
localparam OSHIFT = C_FRAC_BITS + ROM_DATA_BITS;
localparam PW = RW + A_W + 1;
localparam MAG_W = MAG_INT_BITS + Z_FRAC_BITS;
localparam OW = C_W + ROM_DATA_BITS + 1;
localparam TABLE = 1 << ROM_ADDR_BITS;

assign nerr = (n == 10'd0) || (n > 10'd1000) || (n < N_FIRST) || (n > N_LAST);
assign table_j = (n <= N_HI0) ? 2'd0 : (n <= N_HI1) ? 2'd1 : (n <= N_HI2) ? 2'd2 : 2'd3;
assign a_index = n - N_FIRST;
assign a = a_word;  // for an invalid n any word: the word below is 0

wire signed [RW-1:0] zeta_w = zeta;
wire [RW-1:0] abs_zeta = zeta_w[RW-1] ? -zeta_w : zeta_w;

assign mag = (abs_zeta >= (1 << MAG_W)) ? {MAG_W{1'b1}} : abs_zeta[MAG_W-1:0];

wire [OW-1:0] lit;
generate
    if (EXT_PRODUCTS != 0) begin : g_ext
        assign scaled = scaled_in;
        assign lit = lit_in;
    end else begin : g_own
        assign scaled = mag * a;  // exact
        assign lit = {{(ROM_DATA_BITS+1){1'b0}}, c} * {{(C_W+1){1'b0}}, word};
    end
endgenerate
assign addr = ({1'b0, scaled} + (1 << (SHIFT - 1))) >> SHIFT;
assign past_half_pi = addr >= TABLE;
assign cos_index = table_j * TABLE + addr[ROM_ADDR_BITS-1:0];
assign word = (nerr || past_half_pi) ? {ROM_DATA_BITS{1'b0}} : cos_word;

// the same without the saturation
wire [PW-1:0] scaled_u = {{(A_W+1){1'b0}}, abs_zeta} * {{(RW+1){1'b0}}, a};
wire [PW-1:0] addr_u = (scaled_u + ({{(PW-1){1'b0}}, 1'b1} << (SHIFT - 1))) >> SHIFT;
assign cos_index_u = table_j * TABLE + addr_u[ROM_ADDR_BITS-1:0];
wire [ROM_DATA_BITS-1:0] word_u = (nerr || addr_u >= TABLE) ? {ROM_DATA_BITS{1'b0}} : cos_word_u;
assign clamp_matters = word_u != word;

wire [OW-1:0] rounded = (lit + ({{(OW-1){1'b0}}, 1'b1} << (OSHIFT - 1))) >> OSHIFT;
assign saturated = rounded > ((1 << OUT_WIDTH) - 1);
assign out = nerr ? {OUT_WIDTH{1'b0}} : saturated ? {OUT_WIDTH{1'b1}} : rounded[OUT_WIDTH-1:0];

endmodule
