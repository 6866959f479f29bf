// Vector bench of rtl/divider_shift.v: replays stim.hex, checks every output every cycle
// against expect.hex / mask.hex (written by sim/soak.py from the model).  Plain Verilog-2005.

`resetall
`timescale 1ns / 1ps
`default_nettype none

module tb_divider_shift #(
    parameter A_WIDTH = 21,
    parameter K_WIDTH = 11,
    parameter RECIP_BITS = 20,
    parameter ROM_FILE = "rom/divider_recip_k11_n20.hex",
    parameter CYCLES = 1,
    parameter STIM_FILE = "stim.hex",
    parameter EXPECT_FILE = "expect.hex",
    parameter MASK_FILE = "mask.hex"
);

localparam Q_WIDTH = A_WIDTH + RECIP_BITS;
// {rst_n, start, a_we, a_in, k_we, k_in}
localparam STIM_W = 2 + 1 + A_WIDTH + 1 + K_WIDTH;
// {busy, valid, q, div_zero}
localparam OUT_W = 2 + Q_WIDTH + 1;

reg  [STIM_W-1:0]  stim_word = {STIM_W{1'b0}};
wire               rst_n, start, a_we, k_we;
wire [A_WIDTH-1:0] a_in;
wire [K_WIDTH-1:0] k_in;
assign {rst_n, start, a_we, a_in, k_we, k_in} = stim_word;

wire               busy, valid, div_zero;
wire [Q_WIDTH-1:0] q;
wire [OUT_W-1:0]   got_word = {busy, valid, q, div_zero};

`include "vector_loop.vh"

divider_shift #(
    .A_WIDTH(A_WIDTH),
    .K_WIDTH(K_WIDTH),
    .RECIP_BITS(RECIP_BITS),
    .ROM_FILE(ROM_FILE)
) dut (
    .clk(clk),
    .rst_n(rst_n),
    .a_in(a_in),
    .a_we(a_we),
    .k_in(k_in),
    .k_we(k_we),
    .start(start),
    .busy(busy),
    .valid(valid),
    .q(q),
    .div_zero(div_zero)
);

endmodule

`resetall
