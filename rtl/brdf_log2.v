// SPDX-License-Identifier: Apache-2.0
/*
 * The BRDF unit's logarithmic datapath (the thesis's fig. 9b): cos^n = 2^(n log2 cos)
 * approximated as y = 1 - log2(1 + x) / 2, x = n (-log2 cos), from the angle-table word
 * lc = -log2 cos (unsigned Q2.(D - 2), the log2 form's angle table) and the n register, the
 * second table (the log2 device: log2(1 + f), f in [0, 1)) read in the pipeline, bit for bit
 * as model.units.brdf.fixed's log2_kernel:
 *   x  = n * lc                              (exact, F = D - 2 fraction bits)
 *   y  = 0                                   if x >= 3 (then 1 - log2(1 + x) / 2 <= 0)
 *   u  = 1 + x = 2^e (1 + f), e = 0 or 1     (e = 1 from x >= 1 on)
 *   j  = round(f, E)                         (E = LOG_ADDR_BITS; j = 2^E: the next octave)
 *   lg = (e + j[E]) + table[j mod 2^E]       (L = LOG_DATA_BITS fraction bits)
 *   y  = min(round(max(0, 2 - lg), L + 1 - O), 2^O - 1)   (O = OUT_BITS fraction bits)
 * Rounding is add half, slice (rtl/brdf_round.v).  f is taken with F + 1 fraction bits in both
 * octaves: v = 2x (e = 0, x < 1) or x - 1 (e = 1), so that one rounding serves both; for
 * x < 1, round(x, F - E) = round(2x, F + 1 - E) for every shift (also 0 and negative), and
 * neither v needs an adder (x - 1 for x in [1, 3) is x's bits with bit F dropped).
 * Formats: w unsigned, D = COS_DATA_BITS fraction bits, D + 1 bits wide: the front's word,
 * 2^D from pi/2 on (the front's overflow), which this form reads as the table's largest word
 * 2^D - 1 (the model's word past the table's end); k = n, 10 bits (n up to 1023: the unit
 * gates the result of an n outside 1..1000); the table word t unsigned, L fraction bits;
 * y unsigned, O fraction bits.  One multiplier (n x lc), no coefficient table.
 *
 * Pipeline (seven stages, registered after the multiplier, the table and each adder): s1
 * and s2 n * lc (rtl/brdf_mul.v: the partial products, then their sum), s3 the table address
 * (addr_reg: j rounded, its carry into the octave oct3_reg, the "x >= 3" flag zero3_reg), s4
 * the table read and s5 its word registered again in the fabric (the ROM's two read
 * registers, READ_REGS = 2, outside this module: log_addr out, log_q two clocks later, so that
 * no adder follows the block RAM's slow output in its clock; the octave and the flag ride
 * along), s6 lv_reg = max(0, 2 - lg) (0 also when x >= 3), s7 y_reg (rounding, saturation);
 * the word of the w that enters at an edge is on y seven edges later.  k is the running line's constant.  Reset: none of these registers is
 * control state; RESET_ALL = 1 resets them all (rst_n is synchronous, active low).
 *
 * Checks: every parameter is checked at elaboration; a bad value instantiates a module named
 * after the rule, which does not exist (brdf_log2_PARAMETER_ERROR_<rule>; rtl/brdf_unit.v
 * refuses the same values first, by the unit's rules).
 *
 * Sources: this file, rtl/brdf_mul.v and rtl/brdf_round.v; the table is an instance of
 * rtl/shading_rom.v in rtl/brdf_unit.v (rtl/brdf_unit.f).  Documentation: docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_log2 #(
    // Angle-table word bits D: -log2 cos with D - 2 fraction bits (w itself is D + 1 bits), 4..24
    parameter COS_DATA_BITS = 20,
    // Address bits E of the log2 table (f rounded to E fraction bits), 2..16
    parameter LOG_ADDR_BITS = 10,
    // Word bits L of the log2 table (log2(1 + f), L fraction bits), 4..24
    parameter LOG_DATA_BITS = 16,
    // Fraction bits O of the output word, 1..24
    parameter OUT_BITS = 16,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire                     clk,
    input  wire                     rst_n,
    input  wire [COS_DATA_BITS:0]   w,
    input  wire [9:0]               k,
    output wire [LOG_ADDR_BITS-1:0] log_addr,
    input  wire [LOG_DATA_BITS-1:0] log_q,
    output wire [OUT_BITS-1:0]      y
);

localparam D = COS_DATA_BITS;
localparam E = LOG_ADDR_BITS;
localparam L = LOG_DATA_BITS;
localparam O = OUT_BITS;
// Fraction bits of lc, x and u (model: d - LOG2COS_INT_BITS)
localparam F = D - 2;
// n (10 bits) times lc (D bits)
localparam X_WIDTH = D + 10;
// Bits dropped from v (F + 1 fraction bits) to the table's E address bits
localparam J_SHIFT = F + 1 - E;
// Bits dropped from lv (L + 1 fraction bits: 1 - lg / 2) to O
localparam Y_SHIFT = L + 1 - O;

generate
    if (D < 4 || D > 24) begin : g_check_cos_data_bits
        brdf_log2_PARAMETER_ERROR_COS_DATA_BITS_must_be_4_to_24 u_error ();
    end
    if (E < 2 || E > 16) begin : g_check_log_addr_bits
        brdf_log2_PARAMETER_ERROR_LOG_ADDR_BITS_must_be_2_to_16 u_error ();
    end
    if (L < 4 || L > 24) begin : g_check_log_data_bits
        brdf_log2_PARAMETER_ERROR_LOG_DATA_BITS_must_be_4_to_24 u_error ();
    end
    if (O < 1 || O > 24) begin : g_check_out_bits
        brdf_log2_PARAMETER_ERROR_OUT_BITS_must_be_1_to_24 u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        brdf_log2_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
endgenerate

// Stage registers
reg [E-1:0]   addr_reg;
reg [1:0]     oct3_reg;
reg           zero3_reg;
reg [1:0]     oct4_reg;
reg           zero4_reg;
reg [1:0]     oct5_reg;
reg           zero5_reg;
reg [L+1:0]   lv_reg;
reg [O-1:0]   y_reg;

assign log_addr = addr_reg;
assign y = y_reg;

// ---------------------------------------------------------------- s1, s2: x = n lc
// lc: the table word, or its largest, 2^D - 1, for the front's 2^D (pi/2 and beyond; the
// low bits are then 0)
wire [D-1:0] lc = w[D-1:0] | {D{w[D]}};
wire [X_WIDTH-1:0] x;

brdf_mul #(
    .A_WIDTH(10),
    .B_WIDTH(D),
    .SIGNED(0),
    .RESET_ALL(RESET_ALL)
) u_x (
    .clk(clk),
    .rst_n(rst_n),
    .a(k),
    .b(lc),
    .p(x)
);

// ---------------------------------------------------------------- s3: the table address
// x >= 3: a bit above F + 1, or bits F + 1 and F both set; the octave e: x >= 1 (x < 3)
wire zero_next = (|x[X_WIDTH-1:F+2]) || (x[F+1] && x[F]);
wire oct_next = x[F+1] || x[F];
// f with F + 1 fraction bits: 2x for x < 1, x - 1 for x in [1, 3)
wire [F:0] v = oct_next ? {x[F+1], x[F-1:0]} : {x[F-1:0], 1'b0};
// j = round(f, E), up to 2^E (E + 1 bits: never saturated)
wire [E:0] j;

brdf_round #(
    .IN_WIDTH(F + 1),
    .SHIFT(J_SHIFT),
    .OUT_WIDTH(E + 1)
) u_round_j (
    .x(v),
    .y(j)
);

// ---------------------------------------------------------------- s6: lv = max(0, 2 - lg)
// 2 - lg = (2 - e') - t, e' = oct5 (0, 1 or 2), in L + 3 bits two's complement: below 0
// only at e' = 2 with t > 0; 0 too when x >= 3
wire [L+1:0] two_minus_e = (oct5_reg == 2'd0) ? {2'b10, {L{1'b0}}}
                         : (oct5_reg == 2'd1) ? {2'b01, {L{1'b0}}} : {(L+2){1'b0}};
wire [L+2:0] lv_sum = {1'b0, two_minus_e} - {3'b000, log_q};
wire [L+1:0] lv_next = (zero5_reg || lv_sum[L+2]) ? {(L+2){1'b0}} : lv_sum[L+1:0];

// ---------------------------------------------------------------- s7: y = round(lv)
wire [O-1:0] y_next;

brdf_round #(
    .IN_WIDTH(L + 2),
    .SHIFT(Y_SHIFT),
    .OUT_WIDTH(O)
) u_round_y (
    .x(lv_reg),
    .y(y_next)
);

always @(posedge clk) begin
    addr_reg <= j[E-1:0];
    oct3_reg <= {1'b0, oct_next} + {1'b0, j[E]};
    zero3_reg <= zero_next;
    oct4_reg <= oct3_reg;
    zero4_reg <= zero3_reg;
    oct5_reg <= oct4_reg;
    zero5_reg <= zero4_reg;
    lv_reg <= lv_next;
    y_reg <= y_next;

    if (RESET_ALL != 0 && !rst_n) begin
        addr_reg <= {E{1'b0}};
        oct3_reg <= 2'b00;
        zero3_reg <= 1'b0;
        oct4_reg <= 2'b00;
        zero4_reg <= 1'b0;
        oct5_reg <= 2'b00;
        zero5_reg <= 1'b0;
        lv_reg <= {(L+2){1'b0}};
        y_reg <= {O{1'b0}};
    end
end

endmodule

`resetall
