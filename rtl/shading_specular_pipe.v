// SPDX-License-Identifier: Apache-2.0
/*
 * The specular unit's per-pixel datapath (rtl/specular_unit.v, its stages S1..S8) as a stream:
 * a new pixel every clock, each with its own a, table, zero flag and C, so that pixels of
 * successive lines follow each other with no gap.  CHANNELS copies of multiplier 13 share one
 * angle: the shading core's diffuse jobs (one C per colour channel, one dz and z0 per span).
 * Every result equals model.specular.pixel_value for the pixel's accumulator value.
 *
 * Pipeline: the caller's accumulator register is S0 (acc_in, with a_in, tsel_in, zero_in and
 * c_in of the same pixel); S1 |zeta| without its carry (sign, one's complement, "too big"),
 * S2 |zeta| saturated to MAG_INT_BITS integer bits, S3 and S4 multiplier 11 (x a: the two
 * halves of |zeta| times a, each one 18 x 18 multiplier of an FPGA, then their sum), S5 the
 * address rounded, S6 and S7 the ROM-12 read (outside: rom_addr out at S5, rom_q in at S7, a
 * ROM of two read registers: the block RAM's and one in the fabric, shading_rom READ_REGS = 2)
 * beside the zero flag (>= pi/2, or zero_in), S8 the gated word, S9 multiplier 13 (x C), S10 rounding and
 * saturation: intensity holds the pixel that was in S0 ten clocks before (the unit's S3 and
 * S5 each take two stages here, so that no multiplier's carry chain and no block RAM's output
 * shares a clock with other logic).  The data
 * path has no reset (it is loaded from S0 every clock; the caller's valid flags say which
 * results are pixels).
 *
 * A_ONE = 1: every pixel's a is 1.0 (2^A_FRAC_BITS: the shading core's diffuse jobs, n = 1 in
 * a k = 1 range or with the inflection-matched a), so |zeta| x a is |zeta| shifted up by
 * A_FRAC_BITS: S3 and S4 hold |zeta| and that shift instead of the two halves' products and
 * their sum (the same stages and latency, the same address bit for bit, no multiplier 11);
 * a_in is not read.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module shading_specular_pipe #(
    // Colour channels: multipliers 13 sharing one angle (1 or 3)
    parameter CHANNELS = 1,
    // Accumulator bits (signed, units of pi/2 with Z_FRAC_BITS fraction bits)
    parameter ACC_WIDTH = 40,
    // Accumulator fraction bits
    parameter Z_FRAC_BITS = 26,
    // |zeta| integer bits kept before multiplier 11 (model mag_int_bits)
    parameter MAG_INT_BITS = 1,
    // a word bits (ROM 9)
    parameter A_WIDTH = 17,
    // a word fraction bits
    parameter A_FRAC_BITS = 14,
    // Table select bits of the ROM-12 address
    parameter TSEL_BITS = 2,
    // ROM-12 address bits per table
    parameter ROM_ADDR_BITS = 12,
    // ROM-12 word bits
    parameter ROM_DATA_BITS = 16,
    // C bits (unsigned)
    parameter C_WIDTH = 16,
    // C fraction bits
    parameter C_FRAC_BITS = 8,
    // Output intensity bits
    parameter OUT_WIDTH = 8,
    // 1: a is 1.0 for every pixel (a_in unread, no multiplier 11); 0: a_in, multiplied
    parameter A_ONE = 0
) (
    input  wire                              clk,
    input  wire [ACC_WIDTH-1:0]              acc_in,
    input  wire [A_WIDTH-1:0]                a_in,
    input  wire [TSEL_BITS-1:0]              tsel_in,
    input  wire                              zero_in,
    input  wire [CHANNELS*C_WIDTH-1:0]       c_in,
    output wire [TSEL_BITS+ROM_ADDR_BITS-1:0] rom_addr,
    input  wire [ROM_DATA_BITS-1:0]          rom_q,
    output wire [CHANNELS*OUT_WIDTH-1:0]     intensity
);

localparam MAG_WIDTH = MAG_INT_BITS + Z_FRAC_BITS;
localparam PROD_WIDTH = MAG_WIDTH + A_WIDTH;
// |zeta| in two halves for multiplier 11
localparam ML = (MAG_WIDTH + 1) / 2;
localparam MH = MAG_WIDTH - ML;
localparam SHIFT = Z_FRAC_BITS + A_FRAC_BITS - ROM_ADDR_BITS;
localparam RND_WIDTH = PROD_WIDTH + 1 - SHIFT;
localparam OP_WIDTH = C_WIDTH + ROM_DATA_BITS;
localparam OSHIFT = C_FRAC_BITS + ROM_DATA_BITS;
localparam OFULL_WIDTH = OP_WIDTH - OSHIFT + 1;

generate
    if (CHANNELS != 1 && CHANNELS != 3) begin : g_check_channels
        shading_specular_pipe_PARAMETER_ERROR_CHANNELS_must_be_1_or_3 u_error ();
    end
    if (SHIFT < 1) begin : g_check_shift
        shading_specular_pipe_PARAMETER_ERROR_Z_FRAC_BITS_plus_A_FRAC_BITS_must_exceed_ROM_ADDR_BITS
            u_error ();
    end
    if (MAG_WIDTH < 2) begin : g_check_mag_width
        shading_specular_pipe_PARAMETER_ERROR_MAG_INT_BITS_plus_Z_FRAC_BITS_must_be_at_least_2
            u_error ();
    end
    if (MAG_WIDTH >= ACC_WIDTH) begin : g_check_mag
        shading_specular_pipe_PARAMETER_ERROR_MAG_INT_BITS_plus_Z_FRAC_BITS_must_be_below_ACC_WIDTH
            u_error ();
    end
    if (A_ONE != 0 && A_ONE != 1) begin : g_check_a_one
        shading_specular_pipe_PARAMETER_ERROR_A_ONE_must_be_0_or_1 u_error ();
    end
    if (A_ONE == 1 && A_WIDTH <= A_FRAC_BITS) begin : g_check_a_one_width
        shading_specular_pipe_PARAMETER_ERROR_A_ONE_needs_an_integer_bit_of_a u_error ();
    end
endgenerate

// Per-pixel side data, delayed to the stage that uses it
// Shift registers, the newest stage in the low bits: tsel and zero_in to S5, C to S8
reg [5*TSEL_BITS-1:0]        tsel_reg;
reg [4:0]                    zin_reg;
reg [8*CHANNELS*C_WIDTH-1:0] c_reg;

reg [MAG_WIDTH-1:0]        low_reg;
reg                        neg_reg;
reg                        big_reg;
reg [MAG_WIDTH-1:0]        mag_reg;
reg [PROD_WIDTH-1:0]       prod_reg;
reg [RND_WIDTH-1:0]        addr_reg;
reg                        zero_reg;
reg                        zero2_reg;
reg [ROM_DATA_BITS-1:0]    rom_d_reg;
reg [CHANNELS*OP_WIDTH-1:0] out_prod_reg;
reg [CHANNELS*OUT_WIDTH-1:0] intensity_reg;

// S0 -> S1: |zeta| >= 2^MAG_WIDTH (big) without negating (as in specular_unit)
wire                 acc_neg = acc_in[ACC_WIDTH-1];
wire                 acc_big = acc_neg ? (~&acc_in[ACC_WIDTH-1:MAG_WIDTH]
                                          || ~|acc_in[MAG_WIDTH-1:0])
                                       : |acc_in[ACC_WIDTH-1:MAG_WIDTH];
// S1 -> S2: |zeta| = low + 1 if negative, saturated
wire [MAG_WIDTH-1:0] mag_next = big_reg ? {MAG_WIDTH{1'b1}}
                                        : low_reg + {{(MAG_WIDTH-1){1'b0}}, neg_reg};
// S4 -> S5: rounded at the ROM-12 address LSB
wire [PROD_WIDTH:0]  prod_rnd = {1'b0, prod_reg} + ({{PROD_WIDTH{1'b0}}, 1'b1} << (SHIFT - 1));
// S5 -> S6: the address; >= pi/2 reads as 0
wire                 rom_ovf = |addr_reg[RND_WIDTH-1:ROM_ADDR_BITS];
localparam CW = CHANNELS * C_WIDTH;
wire [TSEL_BITS-1:0] tsel5 = tsel_reg[4*TSEL_BITS +: TSEL_BITS];
wire [CW-1:0]        c8 = c_reg[7*CW +: CW];
assign rom_addr = {tsel5, addr_reg[ROM_ADDR_BITS-1:0]};

always @(posedge clk) begin
    tsel_reg <= {tsel_reg[0 +: 4*TSEL_BITS], tsel_in};
    zin_reg <= {zin_reg[3:0], zero_in};
    c_reg <= {c_reg[0 +: 7*CW], c_in};

    low_reg <= acc_in[MAG_WIDTH-1:0] ^ {MAG_WIDTH{acc_neg}};
    neg_reg <= acc_neg;
    big_reg <= acc_big;
    mag_reg <= mag_next;
    addr_reg <= prod_rnd[PROD_WIDTH:SHIFT];
    zero_reg <= rom_ovf || zin_reg[4];
    zero2_reg <= zero_reg;
    rom_d_reg <= zero2_reg ? {ROM_DATA_BITS{1'b0}} : rom_q;
end

// S2 -> S3 -> S4: |zeta| x a
generate
    if (A_ONE == 1) begin : g_a_one
        // a = 2^A_FRAC_BITS: the product is |zeta| shifted, S3 holds |zeta| itself
        reg [MAG_WIDTH-1:0] mag3_reg;
        always @(posedge clk) begin
            mag3_reg <= mag_reg;
            prod_reg <= {{(A_WIDTH-A_FRAC_BITS){1'b0}}, mag3_reg, {A_FRAC_BITS{1'b0}}};
        end
        // verilator lint_off UNUSEDSIGNAL
        wire unused_a = &{1'b0, a_in};
        // verilator lint_on UNUSEDSIGNAL
    end else begin : g_multiplier_11
        // Multiplier 11: the two halves of |zeta| times a (S3), their sum (S4)
        reg [A_WIDTH-1:0]    a1_reg;
        reg [A_WIDTH-1:0]    a2_reg;
        reg [ML+A_WIDTH-1:0] plo_reg;
        reg [MH+A_WIDTH-1:0] phi_reg;
        always @(posedge clk) begin
            a1_reg <= a_in;
            a2_reg <= a1_reg;
            plo_reg <= mag_reg[ML-1:0] * a2_reg;
            phi_reg <= mag_reg[MAG_WIDTH-1:ML] * a2_reg;
            prod_reg <= {{MH{1'b0}}, plo_reg} + ({{ML{1'b0}}, phi_reg} << ML);
        end
    end
endgenerate

// S8 -> S9 -> S10 per channel: multiplier 13, rounding, saturation
genvar ch;
generate
    for (ch = 0; ch < CHANNELS; ch = ch + 1) begin : g_channel
        wire [OP_WIDTH:0] out_rnd = {1'b0, out_prod_reg[ch*OP_WIDTH +: OP_WIDTH]}
                                    + ({{OP_WIDTH{1'b0}}, 1'b1} << (OSHIFT - 1));
        wire [OFULL_WIDTH-1:0] out_full = out_rnd[OP_WIDTH:OSHIFT];
        wire [OUT_WIDTH-1:0] out_sat;
        if (OFULL_WIDTH > OUT_WIDTH) begin : g_sat
            assign out_sat = (|out_full[OFULL_WIDTH-1:OUT_WIDTH]) ? {OUT_WIDTH{1'b1}}
                                                                  : out_full[OUT_WIDTH-1:0];
        end else if (OFULL_WIDTH == OUT_WIDTH) begin : g_fit
            assign out_sat = out_full;
        end else begin : g_pad
            assign out_sat = {{(OUT_WIDTH-OFULL_WIDTH){1'b0}}, out_full};
        end
        // Bits the rounding drops on purpose
        // verilator lint_off UNUSEDSIGNAL
        wire unused_rnd = &{1'b0, out_rnd[OSHIFT-1:0]};
        // verilator lint_on UNUSEDSIGNAL
        always @(posedge clk) begin
            out_prod_reg[ch*OP_WIDTH +: OP_WIDTH] <= c8[ch*C_WIDTH +: C_WIDTH] * rom_d_reg;
            intensity_reg[ch*OUT_WIDTH +: OUT_WIDTH] <= out_sat;
        end
    end
endgenerate

assign intensity = intensity_reg;

// Bits the address rounding drops on purpose
// verilator lint_off UNUSEDSIGNAL
wire unused_bits = &{1'b0, prod_rnd[SHIFT-1:0]};
// verilator lint_on UNUSEDSIGNAL

endmodule

`resetall
