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
 * RAM, whose output has no time left for logic), then the two halves of the product a * r_lo
 * and a * r_hi (each one multiplier), then their sum into q_reg; di is combinational from
 * q_reg: three stages.
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

// The reciprocal split in two halves: r = r_hi * 2^LO + r_lo
localparam LO = (RECIP_BITS + 1) / 2;
localparam HI = RECIP_BITS + 1 - LO;

reg [A_WIDTH-1:0]             a_reg;
reg [RECIP_BITS:0]            r_reg;
reg signed [A_WIDTH+LO:0]     lo_reg;
reg signed [A_WIDTH+HI:0]     hi_reg;
reg signed [Q_WIDTH-1:0]      q_reg;

always @(posedge clk) begin
    if (ce) begin
        a_reg <= a;
        r_reg <= r;
        lo_reg <= $signed(a_reg) * $signed({1'b0, r_reg[LO-1:0]});
        hi_reg <= $signed(a_reg) * $signed({1'b0, r_reg[RECIP_BITS:LO]});
        q_reg <= {{(Q_WIDTH-A_WIDTH-LO-1){lo_reg[A_WIDTH+LO]}}, lo_reg}
                 + ({{(Q_WIDTH-A_WIDTH-HI-1){hi_reg[A_WIDTH+HI]}}, hi_reg} <<< LO);
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
