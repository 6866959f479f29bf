// SPDX-License-Identifier: Apache-2.0
// Vector bench of rtl/brdf_unit.v: replays a binary vector file (stimulus, expected outputs
// and mask of every cycle, written from the model by sim/soak.py and sim/vector_sets.py)
// and checks every output every cycle, in one instance with RESET_ALL = 0 and one with
// RESET_ALL = 1, each against its own expected outputs (vector_loop.vh).  Plain
// Verilog-2005; with GATE_LEVEL defined the instance takes no parameters (a synthesised netlist of brdf_unit).
// Replay a committed set: sim/vectors/replay.sh <set> [icarus|verilator].

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module tb_brdf_unit #(
    parameter [8*16-1:0] FORM = "cosine_quadratic",
    parameter C_INT_BITS = 8,
    parameter C_FRAC_BITS = 8,
    parameter Z_INT_BITS = 3,
    parameter Z_FRAC_BITS = 26,
    parameter LEN_WIDTH = 11,
    parameter OUT_WIDTH = 8,
    parameter COS_ADDR_BITS = 12,
    parameter COS_DATA_BITS = 20,
    parameter COEF_BITS = 18,
    parameter WORK_BITS = 24,
    parameter OUT_BITS = 16,
    parameter LOG_ADDR_BITS = 10,
    parameter LOG_DATA_BITS = 16,
    parameter ANGLE_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_w_a12_d20.hex"},
    parameter COEF_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_quadratic_coef_c18_q10.8.hex"},
    parameter LOG_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_log2_a10_d16.hex"},
    // bit r set: an instance with RESET_ALL = r is replayed (3: both)
    parameter RESET_MODES = 3,
    parameter CYCLES = 1,
    // the set's binary vector file (vector_loop.vh); +VECTOR_FILE= and +CYCLES= override
    parameter VECTOR_FILE = "vectors.bin"
);

localparam C_WIDTH = C_INT_BITS + C_FRAC_BITS;
localparam Z_WIDTH = Z_INT_BITS + Z_FRAC_BITS;
// {rst_n, start, c_we, c_in, dz_we, dz_in, z0_we, z0_in, n_we, n_in, len_we, len_in}
localparam STIM_W = 2 + 1 + C_WIDTH + 2 * (1 + Z_WIDTH) + 1 + 10 + 1 + LEN_WIDTH;
// {busy, valid, intensity, n_err}
localparam OUT_W = 2 + OUT_WIDTH + 1;

reg  [STIM_W-1:0]    stim_word = {STIM_W{1'b0}};
wire                 rst_n, start, c_we, dz_we, z0_we, n_we, len_we;
wire [C_WIDTH-1:0]   c_in;
wire [Z_WIDTH-1:0]   dz_in, z0_in;
wire [9:0]           n_in;
wire [LEN_WIDTH-1:0] len_in;
assign {rst_n, start, c_we, c_in, dz_we, dz_in, z0_we, z0_in, n_we, n_in, len_we, len_in} =
    stim_word;

wire [2*OUT_W-1:0]   got_words;

`include "vector_loop.vh"

genvar r;
generate
    for (r = 0; r < 2; r = r + 1) begin : reset_all
        if (((RESET_MODES >> r) & 1) == 1) begin : on
            wire                 busy, valid, n_err;
            wire [OUT_WIDTH-1:0] intensity;
            assign got_words[r*OUT_W +: OUT_W] = {busy, valid, intensity, n_err};
`ifdef GATE_LEVEL
            brdf_unit dut (
`else
            brdf_unit #(
                .FORM(FORM),
                .C_INT_BITS(C_INT_BITS),
                .C_FRAC_BITS(C_FRAC_BITS),
                .Z_INT_BITS(Z_INT_BITS),
                .Z_FRAC_BITS(Z_FRAC_BITS),
                .LEN_WIDTH(LEN_WIDTH),
                .OUT_WIDTH(OUT_WIDTH),
                .COS_ADDR_BITS(COS_ADDR_BITS),
                .COS_DATA_BITS(COS_DATA_BITS),
                .COEF_BITS(COEF_BITS),
                .WORK_BITS(WORK_BITS),
                .OUT_BITS(OUT_BITS),
                .LOG_ADDR_BITS(LOG_ADDR_BITS),
                .LOG_DATA_BITS(LOG_DATA_BITS),
                .ANGLE_ROM_FILE(ANGLE_ROM_FILE),
                .COEF_ROM_FILE(COEF_ROM_FILE),
                .LOG_ROM_FILE(LOG_ROM_FILE),
                .RESET_ALL(r)
            ) dut (
`endif
                .clk(clk),
                .rst_n(rst_n),
                .c_in(c_in),
                .c_we(c_we),
                .dz_in(dz_in),
                .dz_we(dz_we),
                .z0_in(z0_in),
                .z0_we(z0_we),
                .n_in(n_in),
                .n_we(n_we),
                .len_in(len_in),
                .len_we(len_we),
                .start(start),
                .busy(busy),
                .valid(valid),
                .intensity(intensity),
                .n_err(n_err)
            );
        end else begin : off
            assign got_words[r*OUT_W +: OUT_W] = {OUT_W{1'b0}};
        end
    end
endgenerate

endmodule

`resetall
