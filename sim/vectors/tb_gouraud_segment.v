// SPDX-License-Identifier: Apache-2.0
// Vector bench of rtl/gouraud_segment.v: replays a binary vector file (stimulus, expected outputs
// and mask of every cycle, written from the model by sim/soak.py and sim/vector_sets.py)
// and checks every output every cycle, in one instance with RESET_ALL = 0 and one with
// RESET_ALL = 1, each against its own expected outputs (vector_loop.vh).  Plain
// Verilog-2005; with GATE_LEVEL defined the instance takes no parameters (a synthesised netlist of gouraud_segment).
// Replay a committed set: sim/vectors/replay.sh <set> [icarus|verilator].

`resetall
`timescale 1ns / 1ps
`default_nettype none

module tb_gouraud_segment #(
    parameter I_INT = 8,
    parameter I_FRAC = 12,
    parameter P = 8,
    parameter LEN_WIDTH = 11,
    // bit r set: an instance with RESET_ALL = r is replayed (3: both)
    parameter RESET_MODES = 3,
    parameter CYCLES = 1,
    // the set's binary vector file (vector_loop.vh); +VECTOR_FILE= and +CYCLES= override
    parameter VECTOR_FILE = "vectors.bin"
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

wire [2*OUT_W-1:0]   got_words;

`include "vector_loop.vh"

genvar r;
generate
    for (r = 0; r < 2; r = r + 1) begin : reset_all
        if (((RESET_MODES >> r) & 1) == 1) begin : on
            wire               busy, valid, last;
            wire [P*I_INT-1:0] pixels;
            wire [P-1:0]       mask;
            assign got_words[r*OUT_W +: OUT_W] = {busy, valid, pixels, mask, last};
`ifdef GATE_LEVEL
            gouraud_segment dut (
`else
            gouraud_segment #(
                .I_INT(I_INT),
                .I_FRAC(I_FRAC),
                .P(P),
                .LEN_WIDTH(LEN_WIDTH),
                .RESET_ALL(r)
            ) dut (
`endif
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
        end else begin : off
            assign got_words[r*OUT_W +: OUT_W] = {OUT_W{1'b0}};
        end
    end
endgenerate

endmodule

`resetall
