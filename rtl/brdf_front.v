// SPDX-License-Identifier: Apache-2.0
/*
 * The BRDF family's front: from the angle accumulator to the angle-table word w, one pixel per
 * clock, bit for bit as model.units.brdf's unit (the word fixed.evaluate reads for an
 * accumulator value).  The BRDF unit (rtl/brdf_unit.v) and the shading core's BRDF highlight
 * path (rtl/shading_brdf_pipe.v) each instantiate it after their accumulator.
 *
 * Stages (the caller's accumulator register is S0, acc):
 *   S1  |zeta| without its carry: the low MAG_WIDTH = Z_FRAC_BITS + 1 bits one's-complemented
 *       if negative, the sign, and "|zeta| >= 2^MAG_WIDTH" (big) from the high bits alone
 *   S2  |zeta| = low + sign, saturated below 2 (pi: every clamped value still reads pi/2 or
 *       more)
 *   S3  the angle-table address: |zeta| rounded to COS_ADDR_BITS fraction bits of pi/2 (add
 *       half, slice: rtl/brdf_round.v), its top bit set for pi/2 or more
 *   S4  the angle table's word (a synchronous read of the address) and the overflow flag
 *   S5  w: the table word, or 2^COS_DATA_BITS (cos = 0) from pi/2 on
 * w holds the pixel that was in S0 five clocks before.  The table holds w = 1 - cos with D =
 * COS_DATA_BITS fraction bits (TABLE = 0, every form but log2) or -log2 cos with D - 2
 * (TABLE = 1, the log2 form), 2^COS_ADDR_BITS words of D bits (model.units.brdf.angle_table).
 *
 * The table is an instance of the ROM module (rtl/shading_rom.v), which checks its image at
 * time 0 in simulation: magic "BRDA", depth, width, COS_ADDR_BITS, COS_DATA_BITS, TABLE, the
 * checksum and the end mark; a bad image prints the file, the field, what it holds and what
 * this instance needs, and ends the run with a non-zero exit status.  Its read register is
 * never reset, in either RESET_ALL mode, so that it maps onto block RAM; it needs none: it is
 * rewritten every clock from the address of the pixel in S3.
 *
 * Reset (RESET_ALL): none of these registers is control state; RESET_ALL = 1 resets them all
 * but the table's read register (rst_n is synchronous, active low).
 *
 * Checks: a parameter set the unit refuses is refused by rtl/brdf_unit.v first, by the unit's
 * rules; the rules here are the ones this module needs to elaborate at all (a module named
 * after the rule, which does not exist: brdf_front_PARAMETER_ERROR_<rule>).
 *
 * Sources: this file, rtl/brdf_round.v and rtl/shading_rom.v.  Documentation:
 * docs/brdf_unit.md and docs/core.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module brdf_front #(
    // Accumulator bits (signed, units of pi/2 with Z_FRAC_BITS fraction bits)
    parameter ACC_WIDTH = 40,
    // Accumulator fraction bits
    parameter Z_FRAC_BITS = 26,
    // Angle-table address bits A (fraction bits of |zeta|, units of pi/2), 2..Z_FRAC_BITS
    parameter COS_ADDR_BITS = 12,
    // Angle-table word bits D, 4..24
    parameter COS_DATA_BITS = 20,
    // What the table holds: 0 w = 1 - cos, 1 -log2 cos (the log2 form)
    parameter TABLE = 0,
    // $readmemh image of the angle table, by model.units.brdf (make roms)
    parameter ANGLE_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_w_a12_d20.hex"},
    // 0: no register here is reset; 1: rst_n resets every one but the table's read register
    parameter RESET_ALL = 0
) (
    input  wire                     clk,
    input  wire                     rst_n,
    input  wire [ACC_WIDTH-1:0]     acc,
    output wire [COS_DATA_BITS:0]   w
);

// |zeta| saturated to 1 integer bit: 2^Z_FRAC_BITS (pi/2) and beyond all read cos = 0
localparam MAG_WIDTH = Z_FRAC_BITS + 1;
// |zeta| bits dropped to form the angle-table address (rounded: add half, slice)
localparam ASHIFT = Z_FRAC_BITS - COS_ADDR_BITS;

generate
    if (COS_ADDR_BITS < 2 || COS_ADDR_BITS > Z_FRAC_BITS) begin : g_check_cos_addr_bits
        brdf_front_PARAMETER_ERROR_COS_ADDR_BITS_must_be_2_to_Z_FRAC_BITS u_error ();
    end
    if (MAG_WIDTH >= ACC_WIDTH) begin : g_check_acc_width
        brdf_front_PARAMETER_ERROR_ACC_WIDTH_must_exceed_Z_FRAC_BITS_plus_1 u_error ();
    end
    if (TABLE != 0 && TABLE != 1) begin : g_check_table
        brdf_front_PARAMETER_ERROR_TABLE_must_be_0_or_1 u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        brdf_front_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
endgenerate

reg [MAG_WIDTH-1:0]      low_reg;
reg                      neg_reg;
reg                      big_reg;
reg [MAG_WIDTH-1:0]      mag_reg;
reg [COS_ADDR_BITS:0]    addr_reg;
wire [COS_DATA_BITS-1:0] angle_q;
reg                      ovf_reg;
reg [COS_DATA_BITS:0]    w_reg;

assign w = w_reg;

// S0 -> S1: |zeta| >= 2^MAG_WIDTH (big) without negating: a negative accumulator is big unless
// its high bits are all ones and its low bits not all zeros; the low bits one's-complemented
// S1 -> S2: |zeta| = low + 1 if negative, saturated to MAG_WIDTH bits
wire                 acc_neg = acc[ACC_WIDTH-1];
wire                 acc_big = acc_neg ? (~&acc[ACC_WIDTH-1:MAG_WIDTH]
                                          || ~|acc[MAG_WIDTH-1:0])
                                       : |acc[ACC_WIDTH-1:MAG_WIDTH];
wire [MAG_WIDTH-1:0] mag_next = big_reg ? {MAG_WIDTH{1'b1}}
                                        : low_reg + {{(MAG_WIDTH-1){1'b0}}, neg_reg};

// S2 -> S3: |zeta| rounded to COS_ADDR_BITS fraction bits, saturated to one integer bit: the
// top bit set means pi/2 or more (an address of 2^COS_ADDR_BITS or more)
wire [COS_ADDR_BITS:0] addr_next;

brdf_round #(
    .IN_WIDTH(MAG_WIDTH),
    .SHIFT(ASHIFT),
    .OUT_WIDTH(COS_ADDR_BITS + 1)
) u_round_addr (
    .x(mag_reg),
    .y(addr_next)
);

// S4 -> S5: w = the table word, or 2^COS_DATA_BITS (cos = 0) from pi/2 on
wire [COS_DATA_BITS:0] w_next = ovf_reg ? {1'b1, {COS_DATA_BITS{1'b0}}} : {1'b0, angle_q};

always @(posedge clk) begin
    low_reg <= acc[MAG_WIDTH-1:0] ^ {MAG_WIDTH{acc_neg}};
    neg_reg <= acc_neg;
    big_reg <= acc_big;
    mag_reg <= mag_next;
    addr_reg <= addr_next;
    ovf_reg <= addr_reg[COS_ADDR_BITS];
    w_reg <= w_next;

    if (RESET_ALL != 0 && !rst_n) begin
        low_reg <= {MAG_WIDTH{1'b0}};
        neg_reg <= 1'b0;
        big_reg <= 1'b0;
        mag_reg <= {MAG_WIDTH{1'b0}};
        addr_reg <= {(COS_ADDR_BITS+1){1'b0}};
        ovf_reg <= 1'b0;
        w_reg <= {(COS_DATA_BITS+1){1'b0}};
    end
end

// ---------------------------------------------------------------- the angle table
// verilator lint_off UNUSEDSIGNAL
wire [COS_DATA_BITS-1:0] angle_unused_b;  // one read port
// verilator lint_on UNUSEDSIGNAL

shading_rom #(
    .WIDTH(COS_DATA_BITS),
    .DEPTH(2 ** COS_ADDR_BITS),
    .ADDR_BITS(COS_ADDR_BITS),
    .PORTS(1),
    .FILE(ANGLE_ROM_FILE),
    .NAME("ANGLE_ROM_FILE"),
    .MAGIC("BRDA"),
    .NUM_FIELDS(3),
    .FIELD_0(COS_ADDR_BITS), .FIELD_1(COS_DATA_BITS), .FIELD_2(TABLE),
    .FIELD_NAMES({"COS_ADDR_BITS   ", "COS_DATA_BITS   ", "TABLE           ",
                  {(8*16*9){1'b0}}})
) u_angle_rom (
    .clk(clk),
    .rd_en_a(1'b1),
    .addr_a(addr_reg[COS_ADDR_BITS-1:0]),
    .q_a(angle_q),
    .rd_en_b(1'b0),
    .addr_b({COS_ADDR_BITS{1'b0}}),
    .q_b(angle_unused_b)
);

endmodule

`resetall
