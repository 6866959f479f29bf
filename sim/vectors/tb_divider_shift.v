// SPDX-License-Identifier: Apache-2.0
// Vector bench of rtl/divider_shift.v: replays a binary vector file (stimulus, expected outputs
// and mask of every cycle, written from the model by sim/soak.py and sim/vector_sets.py)
// and checks every output every cycle, in one instance with RESET_ALL = 0 and one with
// RESET_ALL = 1, each against its own expected outputs (vector_loop.vh).  Plain
// Verilog-2005; with GATE_LEVEL defined the instance takes no parameters (a synthesised netlist of divider_shift).
// Replay a committed set: sim/vectors/replay.sh <set> [icarus|verilator].

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module tb_divider_shift #(
    parameter A_WIDTH = 21,
    parameter K_WIDTH = 11,
    parameter RECIP_BITS = 20,
    parameter ROM_FILE = {`SHADING_ROM_DIR, "/divider_recip_k11_n20.hex"},
    // bit r set: an instance with RESET_ALL = r is replayed (3: both)
    parameter RESET_MODES = 3,
    parameter CYCLES = 1,
    // the set's binary vector file (vector_loop.vh); +VECTOR_FILE= and +CYCLES= override
    parameter VECTOR_FILE = "vectors.bin"
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

wire [2*OUT_W-1:0] got_words;

`include "vector_loop.vh"

genvar r;
generate
    for (r = 0; r < 2; r = r + 1) begin : reset_all
        if (((RESET_MODES >> r) & 1) == 1) begin : on
            wire               busy, valid, div_zero;
            wire [Q_WIDTH-1:0] q;
            assign got_words[r*OUT_W +: OUT_W] = {busy, valid, q, div_zero};
`ifdef GATE_LEVEL
            divider_shift dut (
`else
            divider_shift #(
                .A_WIDTH(A_WIDTH),
                .K_WIDTH(K_WIDTH),
                .RECIP_BITS(RECIP_BITS),
                .ROM_FILE(ROM_FILE),
                .RESET_ALL(r)
            ) dut (
`endif
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
        end else begin : off
            assign got_words[r*OUT_W +: OUT_W] = {OUT_W{1'b0}};
        end
    end
endgenerate

endmodule

`resetall
