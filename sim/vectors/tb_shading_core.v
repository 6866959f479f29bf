// SPDX-License-Identifier: Apache-2.0
// Stream bench of rtl/shading_core.v (sim/core_run.py): span beats from a $readmemh file into
// s_axis, with an idle cycle before a beat with probability IDLE_PCT %, m_axis_tready low with
// probability STALL_PCT % (a seeded LFSR), every output beat written to +OUT_FILE (tdata,
// tlast, tuser as hex), the AXI4-Stream rules checked on both ports in every cycle (tvalid
// held until tready, tdata/tlast/tuser stable while stalled), and the clocks counted from the
// first span beat taken to the last pixel beat.  Python compares the beats with the model
// (model.render.core.core_pixels); with +EXPECT_FILE (the model's beats, the same format) the
// bench compares them itself and exits non-zero on any mismatch (the FuseSoC sim target and the
// committed set sim/vectors/core_default/, no Python); +STOP_ON_ERROR=1 ends the run at the
// first error or mismatch (make mutants: a mutant is killed by its first wrong beat, the rest
// of the run would only count more); +NO_OUT_FILE writes no beats (make mutants again: with
// +EXPECT_FILE the bench's own comparison is the verdict, and a 20 000-span check's file would
// be 34 MB a mutant).  After the last expected pixel beat the bench runs TAIL_CYCLES more
// cycles with m_axis_tready high and fails on any beat in them: a core that sends a pixel
// too many is caught however late the extra beat comes in the run.  Plain Verilog-2005, for
// Icarus and for Verilator's --binary mode.

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module tb_shading_core #(
    parameter X_WIDTH = 12,
    parameter Y_WIDTH = 12,
    parameter SPECULAR = 1,
    parameter DIFFUSE = 1,
    parameter FIFO_DEPTH = 32,
    parameter A_WIDTH = 21,
    parameter K_WIDTH = 11,
    parameter RECIP_BITS = 20,
    parameter RECIP_ROM_FILE = {`SHADING_ROM_DIR, "/divider_recip_k11_n20.hex"},
    parameter I_INT = 8,
    parameter I_FRAC = 12,
    parameter LEN_WIDTH = 11,
    parameter C_INT_BITS = 8,
    parameter C_FRAC_BITS = 8,
    parameter Z_INT_BITS = 3,
    parameter Z_FRAC_BITS = 26,
    parameter SPEC_LEN_WIDTH = 11,
    parameter A_INT_BITS = 3,
    parameter A_FRAC_BITS = 14,
    parameter ROM_ADDR_BITS = 12,
    parameter ROM_DATA_BITS = 16,
    parameter OUT_WIDTH = 8,
    parameter NUM_TABLES = 4,
    parameter N_HI0 = 1,
    parameter N_HI1 = 2,
    parameter N_HI2 = 6,
    parameter N_HI3 = 1000,
    parameter K0 = 1,
    parameter K1 = 2,
    parameter K2 = 4,
    parameter K3 = 16,
    parameter [8*10-1:0] ALPHA = "taylor",
    parameter MAG_INT_BITS = 1,
    parameter N_FIRST = 1,
    parameter N_LAST = 1000,
    parameter A_ROM_FILE = {`SHADING_ROM_DIR,
                            "/specular_a_taylor_n1k1_n2k2_n3-6k4_n7-1000k16_q3.14.hex"},
    parameter COS_ROM_FILE = {`SHADING_ROM_DIR, "/specular_cos_k1-2-4-16_a12_d16.hex"},
    parameter [8*16-1:0] HIGHLIGHT = "specular",
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
    // the largest span file the bench holds
    parameter MAX_SPANS = 1 << 20
);

localparam SPAN_WIDTH = (X_WIDTH + Y_WIDTH + LEN_WIDTH + 2 + 6 * (I_INT + I_FRAC)
                         + 4 * (C_INT_BITS + C_FRAC_BITS) + 4 * (Z_INT_BITS + Z_FRAC_BITS)
                         + 10 + 7) / 8 * 8;
localparam PIX_WIDTH = (X_WIDTH + Y_WIDTH + 24 + 7) / 8 * 8;
// Cycles watched after the last expected pixel beat: more than a span's pixels in flight and
// in the output FIFO (the longest pipe, the piecewise highlight's, is under 50 stages)
localparam TAIL_CYCLES = 4 * FIFO_DEPTH + 256;

reg clk = 1'b0;
reg rst_n = 1'b0;
reg [SPAN_WIDTH-1:0] s_tdata = {SPAN_WIDTH{1'b0}};
reg s_tvalid = 1'b0;
wire s_tready;
wire [PIX_WIDTH-1:0] m_tdata;
wire m_tlast;
wire m_tuser;
wire m_tvalid;
reg m_tready = 1'b0;

shading_core #(
    .X_WIDTH(X_WIDTH), .Y_WIDTH(Y_WIDTH), .SPECULAR(SPECULAR), .DIFFUSE(DIFFUSE),
    .FIFO_DEPTH(FIFO_DEPTH), .A_WIDTH(A_WIDTH), .K_WIDTH(K_WIDTH), .RECIP_BITS(RECIP_BITS),
    .RECIP_ROM_FILE(RECIP_ROM_FILE), .I_INT(I_INT), .I_FRAC(I_FRAC), .LEN_WIDTH(LEN_WIDTH),
    .C_INT_BITS(C_INT_BITS), .C_FRAC_BITS(C_FRAC_BITS), .Z_INT_BITS(Z_INT_BITS),
    .Z_FRAC_BITS(Z_FRAC_BITS), .SPEC_LEN_WIDTH(SPEC_LEN_WIDTH), .A_INT_BITS(A_INT_BITS),
    .A_FRAC_BITS(A_FRAC_BITS), .ROM_ADDR_BITS(ROM_ADDR_BITS), .ROM_DATA_BITS(ROM_DATA_BITS),
    .OUT_WIDTH(OUT_WIDTH), .NUM_TABLES(NUM_TABLES), .N_HI0(N_HI0), .N_HI1(N_HI1),
    .N_HI2(N_HI2), .N_HI3(N_HI3), .K0(K0), .K1(K1), .K2(K2), .K3(K3), .ALPHA(ALPHA),
    .MAG_INT_BITS(MAG_INT_BITS), .N_FIRST(N_FIRST), .N_LAST(N_LAST),
    .A_ROM_FILE(A_ROM_FILE), .COS_ROM_FILE(COS_ROM_FILE), .HIGHLIGHT(HIGHLIGHT),
    .COS_ADDR_BITS(COS_ADDR_BITS), .COS_DATA_BITS(COS_DATA_BITS), .COEF_BITS(COEF_BITS),
    .WORK_BITS(WORK_BITS), .OUT_BITS(OUT_BITS), .LOG_ADDR_BITS(LOG_ADDR_BITS),
    .LOG_DATA_BITS(LOG_DATA_BITS), .ANGLE_ROM_FILE(ANGLE_ROM_FILE),
    .COEF_ROM_FILE(COEF_ROM_FILE), .LOG_ROM_FILE(LOG_ROM_FILE)
) dut (
    .clk(clk),
    .rst_n(rst_n),
    .s_axis_tdata(s_tdata),
    .s_axis_tvalid(s_tvalid),
    .s_axis_tready(s_tready),
    .m_axis_tdata(m_tdata),
    .m_axis_tlast(m_tlast),
    .m_axis_tuser(m_tuser),
    .m_axis_tvalid(m_tvalid),
    .m_axis_tready(m_tready)
);

reg [SPAN_WIDTH-1:0] spans [0:MAX_SPANS-1];
reg [1023:0] span_file;
reg [1023:0] out_file;
reg [1023:0] expect_file;
integer expect_fd;
integer mismatches;
integer scanned;
reg [PIX_WIDTH-1:0] want_data;
reg want_last;
reg want_user;
integer n_spans;
integer n_pixels;
integer idle_pct;
integer stall_pct;
integer seed;
integer max_cycles;
integer stop_on_error;
integer fd;
integer sent;
integer received;
integer cycle;
integer first_in;
integer last_out;
integer errors;
integer stalls;
integer done_at;   // the cycle of the last expected pixel beat (-1: not yet)
reg [31:0] lfsr;
reg held_valid;
reg [PIX_WIDTH+1:0] held_beat;

function [31:0] next_lfsr(input [31:0] v);
    begin
        next_lfsr = {v[30:0], v[31] ^ v[21] ^ v[1] ^ v[0]};
    end
endfunction

// A pseudo-random percentage 0..99 from the LFSR
function integer pct(input [31:0] v);
    begin
        pct = v[15:0] % 100;
    end
endfunction

// End the run with a non-zero exit status, what went wrong already printed: $fatal under
// Icarus (vvp -n would end a $stop with 0), $stop under Verilator ($fatal is SystemVerilog)
task fail;
    begin
        $fflush;
`ifdef __ICARUS__
        $fatal(1, "tb_shading_core: FAIL");
`else
        $stop;
`endif
    end
endtask

always #5 clk = ~clk;

initial begin
    if (!$value$plusargs("SPAN_FILE=%s", span_file)) span_file = "spans.hex";
    if (!$value$plusargs("OUT_FILE=%s", out_file)) out_file = "pixels.hex";
    if (!$value$plusargs("SPANS=%d", n_spans)) n_spans = 0;
    if (!$value$plusargs("PIXELS=%d", n_pixels)) n_pixels = 0;
    if (!$value$plusargs("IDLE_PCT=%d", idle_pct)) idle_pct = 0;
    if (!$value$plusargs("STALL_PCT=%d", stall_pct)) stall_pct = 0;
    if (!$value$plusargs("SEED=%d", seed)) seed = 1;
    if (!$value$plusargs("MAX_CYCLES=%d", max_cycles)) max_cycles = 100000000;
    if (!$value$plusargs("STOP_ON_ERROR=%d", stop_on_error)) stop_on_error = 0;
    if (n_spans < 1 || n_spans > MAX_SPANS) begin
        $display("tb_shading_core: +SPANS=%0d is out of range: legal is 1..%0d", n_spans,
                 MAX_SPANS);
        fail;
    end
    $readmemh(span_file, spans, 0, n_spans - 1);
    if ($test$plusargs("NO_OUT_FILE")) fd = 0;
    else fd = $fopen(out_file, "w");
    expect_fd = 0;
    mismatches = 0;
    if ($value$plusargs("EXPECT_FILE=%s", expect_file)) begin
        expect_fd = $fopen(expect_file, "r");
        if (expect_fd == 0) begin
            $display("tb_shading_core: +EXPECT_FILE=%0s cannot be read", expect_file);
            fail;
        end
    end
    lfsr = seed ^ 32'h5eed1234;
    if (lfsr == 32'd0) lfsr = 32'h1;
    sent = 0;
    received = 0;
    cycle = 0;
    first_in = -1;
    last_out = -1;
    errors = 0;
    stalls = 0;
    done_at = -1;
    held_valid = 1'b0;
    held_beat = {(PIX_WIDTH+2){1'b0}};
    repeat (3) @(posedge clk);
    rst_n <= 1'b1;
end

// Drive and check at each rising edge (non-blocking: the values of the next cycle)
always @(posedge clk) begin
    if (rst_n) begin
        cycle = cycle + 1;
        // the input: a beat moves when tvalid && tready
        if (s_tvalid && s_tready) begin
            if (first_in < 0) first_in = cycle;
            sent = sent + 1;
        end
        // the output: a beat moves when tvalid && tready; a stalled beat must hold
        if (held_valid && !m_tvalid) begin
            $display("tb_shading_core: cycle %0d: m_axis_tvalid fell before tready", cycle);
            errors = errors + 1;
        end
        if (held_valid && m_tvalid && {m_tuser, m_tlast, m_tdata} !== held_beat) begin
            $display("tb_shading_core: cycle %0d: m_axis_t* changed while stalled", cycle);
            errors = errors + 1;
        end
        if (m_tvalid && m_tready && done_at >= 0) begin
            $display("tb_shading_core: cycle %0d: a pixel beat after the last expected one (%0d)",
                     cycle, n_pixels);
            errors = errors + 1;
        end
        if (m_tvalid && m_tready) begin
            if (fd != 0) $fwrite(fd, "%h %h %h\n", m_tdata, m_tlast, m_tuser);
            if (expect_fd != 0) begin
                scanned = $fscanf(expect_fd, "%h %h %h\n", want_data, want_last, want_user);
                if (scanned != 3 || {want_user, want_last, want_data}
                                    !== {m_tuser, m_tlast, m_tdata}) begin
                    if (mismatches < 10) begin
                        $display("tb_shading_core: pixel %0d: RTL %h %h %h, model %h %h %h",
                                 received, m_tdata, m_tlast, m_tuser, want_data, want_last,
                                 want_user);
                    end
                    mismatches = mismatches + 1;
                end
            end
            received = received + 1;
            if (received <= n_pixels) last_out = cycle;
            if (received == n_pixels) done_at = cycle;
            held_valid = 1'b0;
        end else begin
            held_valid = m_tvalid;
            held_beat = {m_tuser, m_tlast, m_tdata};
            if (m_tvalid) stalls = stalls + 1;
        end
        if (^{m_tvalid, s_tready} === 1'bx) begin
            $display("tb_shading_core: cycle %0d: tvalid or tready is X", cycle);
            errors = errors + 1;
        end
        // the next cycle's beat and tready
        lfsr = next_lfsr(lfsr);
        if (!(s_tvalid && !s_tready)) begin
            if (sent < n_spans && pct(lfsr) >= idle_pct) begin
                s_tvalid <= 1'b1;
                s_tdata <= spans[sent];
            end else begin
                s_tvalid <= 1'b0;
            end
        end
        lfsr = next_lfsr(lfsr);
        m_tready <= (pct(lfsr) >= stall_pct) || done_at >= 0;
        if ((done_at >= 0 && cycle >= done_at + TAIL_CYCLES) || cycle >= max_cycles
            || (stop_on_error != 0 && errors + mismatches != 0)) begin
            if (fd != 0) $fclose(fd);
            $display("DONE spans=%0d pixels=%0d first_in=%0d last_out=%0d cycles=%0d stalls=%0d errors=%0d",
                     sent, received, first_in, last_out, last_out - first_in + 1, stalls,
                     errors + mismatches);
            $fflush;
            if (errors + mismatches != 0 || received != n_pixels) begin
                $display("tb_shading_core: FAIL: %0d protocol errors, %0d mismatches, %0d of %0d pixels",
                         errors, mismatches, received, n_pixels);
                fail;
            end
            $finish;
        end
    end
end

endmodule

`resetall
