// SPDX-License-Identifier: Apache-2.0
/*
 * A synchronous AXI4-Stream FIFO (the verilog-axis axis_fifo pattern): DEPTH words of memory
 * and an output register, tdata with tlast and tuser.  s_axis_tready = not full; a beat moves
 * on either side when tvalid && tready; m_axis_tvalid and m_axis_t* hold until the beat moves.
 * rst_n (synchronous, active low) empties it.
 *
 * Timing: a beat written at an edge is on m_axis one clock later at the earliest.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module shading_axis_fifo #(
    // tdata bits
    parameter DATA_WIDTH = 48,
    // tuser bits
    parameter USER_WIDTH = 1,
    // Words of memory: a power of two, 2..4096
    parameter DEPTH = 32
) (
    input  wire                  clk,
    input  wire                  rst_n,

    input  wire [DATA_WIDTH-1:0] s_axis_tdata,
    input  wire                  s_axis_tlast,
    input  wire [USER_WIDTH-1:0] s_axis_tuser,
    input  wire                  s_axis_tvalid,
    output wire                  s_axis_tready,

    output wire [DATA_WIDTH-1:0] m_axis_tdata,
    output wire                  m_axis_tlast,
    output wire [USER_WIDTH-1:0] m_axis_tuser,
    output wire                  m_axis_tvalid,
    input  wire                  m_axis_tready
);

localparam ADDR_BITS = (DEPTH > 2048) ? 12 : (DEPTH > 1024) ? 11 : (DEPTH > 512) ? 10
                     : (DEPTH > 256) ? 9 : (DEPTH > 128) ? 8 : (DEPTH > 64) ? 7
                     : (DEPTH > 32) ? 6 : (DEPTH > 16) ? 5 : (DEPTH > 8) ? 4
                     : (DEPTH > 4) ? 3 : (DEPTH > 2) ? 2 : 1;
localparam WORD = DATA_WIDTH + 1 + USER_WIDTH;

generate
    if (DEPTH < 2 || DEPTH > 4096 || (1 << ADDR_BITS) != DEPTH) begin : g_check_depth
        shading_axis_fifo_PARAMETER_ERROR_DEPTH_must_be_a_power_of_2_from_2_to_4096 u_error ();
    end
    if (DATA_WIDTH < 1 || USER_WIDTH < 1) begin : g_check_widths
        shading_axis_fifo_PARAMETER_ERROR_DATA_WIDTH_and_USER_WIDTH_must_be_at_least_1
            u_error ();
    end
endgenerate

reg [WORD-1:0]    mem [0:DEPTH-1];
reg [ADDR_BITS:0] wr_ptr_reg;
reg [ADDR_BITS:0] rd_ptr_reg;
reg [WORD-1:0]    out_reg;
reg               out_valid_reg;

wire empty = (wr_ptr_reg == rd_ptr_reg);
wire full = (wr_ptr_reg == (rd_ptr_reg ^ {1'b1, {ADDR_BITS{1'b0}}}));
wire write = s_axis_tvalid && !full;
wire read = !empty && (!out_valid_reg || m_axis_tready);

assign s_axis_tready = !full;
assign m_axis_tdata = out_reg[DATA_WIDTH-1:0];
assign m_axis_tlast = out_reg[DATA_WIDTH];
assign m_axis_tuser = out_reg[WORD-1:DATA_WIDTH+1];
assign m_axis_tvalid = out_valid_reg;

// Memory and the output register's data: no reset (read only behind valid pointers)
always @(posedge clk) begin
    if (write) begin
        mem[wr_ptr_reg[ADDR_BITS-1:0]] <= {s_axis_tuser, s_axis_tlast, s_axis_tdata};
    end
    if (read) begin
        out_reg <= mem[rd_ptr_reg[ADDR_BITS-1:0]];
    end
end

always @(posedge clk) begin
    if (write) begin
        wr_ptr_reg <= wr_ptr_reg + 1'b1;
    end
    if (read) begin
        rd_ptr_reg <= rd_ptr_reg + 1'b1;
        out_valid_reg <= 1'b1;
    end else if (m_axis_tready) begin
        out_valid_reg <= 1'b0;
    end
    if (!rst_n) begin
        wr_ptr_reg <= {(ADDR_BITS+1){1'b0}};
        rd_ptr_reg <= {(ADDR_BITS+1){1'b0}};
        out_valid_reg <= 1'b0;
    end
end

endmodule

`resetall
