// SPDX-License-Identifier: Apache-2.0
/*
 * The shift-add divider's quotient as one product, and its rounding to a Gouraud increment:
 * q = a * r with r = round(2^RECIP_BITS / k) (the divider's ROM word: the shift register and
 * the accumulating adder of rtl/divider_shift.v add exactly these partial products, one
 * reciprocal bit per clock), then di = (q + 2^(RECIP_BITS-1)) >>> RECIP_BITS
 * (model.render.pipeline.increment_from_quotient).  Here the partial products are added in
 * a pipeline, so a span's three divisions take one clock each instead of up to RECIP_BITS + 1.
 *
 * Timing (every stage moves at an edge with ce): a and r are registered (r comes from a block
 * RAM, whose output has no time left for logic), then four partial products of their halves
 * (each one 18 x 18 multiplier of an FPGA), then a * r_lo-half and a * r_hi-half sums, then q
 * into q_reg; di is combinational from q_reg: four stages.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module shading_increment #(
    // Dividend bits (signed: the difference of two Gouraud registers)
    parameter A_WIDTH = 21,
    // Reciprocal fraction bits N (the ROM word has N + 1 bits)
    parameter RECIP_BITS = 20,
    // Increment bits (signed)
    parameter DI_WIDTH = 21
) (
    input  wire                  clk,
    input  wire                  ce,
    input  wire [A_WIDTH-1:0]    a,
    input  wire [RECIP_BITS:0]   r,
    output wire [DI_WIDTH-1:0]   di
);

localparam Q_WIDTH = A_WIDTH + RECIP_BITS + 1;

generate
    if (A_WIDTH < 2 || RECIP_BITS < 1 || DI_WIDTH < 2 || DI_WIDTH > Q_WIDTH) begin : g_check
        shading_increment_PARAMETER_ERROR_widths_out_of_range u_error ();
    end
endgenerate

// a and r each split in two: a = a_hi * 2^AL + a_lo (a_hi signed), r = r_hi * 2^RL + r_lo;
// each of the four partial products fits one 18 x 18 multiplier of an FPGA
localparam AL = A_WIDTH / 2;
localparam AH = A_WIDTH - AL;
localparam RL = (RECIP_BITS + 1) / 2;
localparam RH = RECIP_BITS + 1 - RL;

reg [A_WIDTH-1:0]           a_reg;
reg [RECIP_BITS:0]          r_reg;
reg [AL+RL-1:0]             ll_reg;   // a_lo * r_lo (unsigned)
reg [AL+RH-1:0]             lh_reg;   // a_lo * r_hi (unsigned)
reg signed [AH+RL:0]        hl_reg;   // a_hi * r_lo
reg signed [AH+RH:0]        hh_reg;   // a_hi * r_hi
reg signed [Q_WIDTH-1:0]    lo_reg;   // a_lo * r
reg signed [Q_WIDTH-1:0]    hi_reg;   // a_hi * r
reg signed [Q_WIDTH-1:0]    q_reg;

wire [AL-1:0]        a_lo = a_reg[AL-1:0];
wire signed [AH-1:0] a_hi = a_reg[A_WIDTH-1:AL];
wire [RL-1:0]        r_lo = r_reg[RL-1:0];
wire [RH-1:0]        r_hi = r_reg[RECIP_BITS:RL];

always @(posedge clk) begin
    if (ce) begin
        a_reg <= a;
        r_reg <= r;
        ll_reg <= a_lo * r_lo;
        lh_reg <= a_lo * r_hi;
        hl_reg <= a_hi * $signed({1'b0, r_lo});
        hh_reg <= a_hi * $signed({1'b0, r_hi});
        lo_reg <= $signed({{(Q_WIDTH-AL-RL){1'b0}}, ll_reg})
                  + ($signed({{(Q_WIDTH-AL-RH){1'b0}}, lh_reg}) <<< RL);
        hi_reg <= $signed({{(Q_WIDTH-AH-RL-1){hl_reg[AH+RL]}}, hl_reg})
                  + ($signed({{(Q_WIDTH-AH-RH-1){hh_reg[AH+RH]}}, hh_reg}) <<< RL);
        q_reg <= lo_reg + (hi_reg <<< AL);
    end
end

wire signed [Q_WIDTH-1:0] q_rnd = q_reg + ({{(Q_WIDTH-1){1'b0}}, 1'b1} << (RECIP_BITS - 1));
wire signed [Q_WIDTH-1:0] q_shr = q_rnd >>> RECIP_BITS;
assign di = q_shr[DI_WIDTH-1:0];

// The increment never needs the high bits (|q / 2^N| <= |a|), nor the dropped fraction
// verilator lint_off UNUSEDSIGNAL
wire unused_bits = &{1'b0, q_shr};
// verilator lint_on UNUSEDSIGNAL

endmodule

`resetall
