// Vector bench of rtl/gouraud_segment.v: replays stim.hex, checks every output every cycle
// against expect.hex / mask.hex (written by sim/soak.py from the model).  Plain Verilog-2005.

`resetall
`timescale 1ns / 1ps
`default_nettype none

module tb_gouraud_segment #(
    parameter I_INT = 8,
    parameter I_FRAC = 12,
    parameter P = 8,
    parameter LEN_WIDTH = 11,
    parameter CYCLES = 1,
    parameter STIM_FILE = "stim.hex",
    parameter EXPECT_FILE = "expect.hex",
    parameter MASK_FILE = "mask.hex"
);

localparam I_WIDTH = I_INT + I_FRAC;
// {rst_n, start, i0_we, i0_in, di_we, di_in, len_we, len_in}
localparam STIM_W = 2 + 1 + I_WIDTH + 1 + I_WIDTH + 1 + 1 + LEN_WIDTH;
// {busy, valid, pixels, mask, last}
localparam OUT_W = 2 + P * I_INT + P + 1;

reg  [STIM_W-1:0]    stim_word = {STIM_W{1'b0}};
wire                 rst_n, start, i0_we, di_we, len_we;
wire [I_WIDTH-1:0]   i0_in;
wire [I_WIDTH:0]     di_in;
wire [LEN_WIDTH-1:0] len_in;
assign {rst_n, start, i0_we, i0_in, di_we, di_in, len_we, len_in} = stim_word;

wire                 busy, valid, last;
wire [P*I_INT-1:0]   pixels;
wire [P-1:0]         mask;
wire [OUT_W-1:0]     got_word = {busy, valid, pixels, mask, last};

`include "vector_loop.vh"

gouraud_segment #(
    .I_INT(I_INT),
    .I_FRAC(I_FRAC),
    .P(P),
    .LEN_WIDTH(LEN_WIDTH)
) dut (
    .clk(clk),
    .rst_n(rst_n),
    .i0_in(i0_in),
    .i0_we(i0_we),
    .di_in(di_in),
    .di_we(di_we),
    .len_in(len_in),
    .len_we(len_we),
    .start(start),
    .busy(busy),
    .valid(valid),
    .pixels(pixels),
    .mask(mask),
    .last(last)
);

endmodule

`resetall
