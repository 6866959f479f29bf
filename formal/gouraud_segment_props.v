// SPDX-License-Identifier: Apache-2.0
/*
 * Formal properties of the segment Gouraud unit (rtl/gouraud_segment.v), for SymbiYosys
 * (read_verilog -formal; model/hw/formal_gouraud.py holds the jobs, docs/formal.md lists every
 * property beside the contract rows of docs/gouraud.md it proves).
 *
 * gouraud_segment_formal wraps one gouraud_segment (instance "dut") with every input free and
 * holds a reference model of the protocol in shadow registers, driven by the ports only:
 *   f_i0, f_di, f_len   the operand registers as the contract says they behave (written with
 *                       their strobes while busy = 0, cleared by reset);
 *   f_job_*             the operands of the running line (the values held *before* the start
 *                       cycle's writes, contract rows 9 and 55);
 *   f_left              busy cycles still to come: ceil(len/P) at an accepted start, 1 for
 *                       len = 0 (one empty segment);
 *   f_done              segments of the running line made so far (segment s starts at pixel
 *                       s*P);
 *   f_nvalid            valid strobes seen at the port since the start;
 *   f_valid, f_last, f_mask   the expected strobes and mask (bit j = pixel s*P + j < len);
 *   f_acc, f_pix        (ARITH = 1) I0 + s*P*dI, accumulated by additions of P*dI, and the
 *                       expected pixels clamp(round(I0 + (s*P + j)*dI)) of each lane j;
 *                       PRODUCT = 1 (small configurations) also proves f_acc equal to
 *                       I0 + (s*P)*dI by a multiplication.
 * One labelled assert per property (busy_exact, ...: the names in docs/formal.md and in the
 * table of make formal), numbered by the P_* localparams.  CHECK = 0: every assert; n: only
 * number n (the deliberate-error runs); 99: none (the cover runs).
 *
 * Induction helpers (`ifdef GOURAUD_INTERNALS): the f_int_* wires are left undriven here and
 * the job's Yosys script connects them after `flatten` to the flattened registers
 * (connect -nounset -set f_int_seg \dut.seg_reg, ...).  They are asserted, never assumed.
 *
 * The one assumption: reset (rst_n = 0) in the first cycle.  Everything else is free.
 */

module gouraud_segment_formal #(
    parameter I_INT = 8,
    parameter I_FRAC = 12,
    parameter P = 8,
    parameter LEN_WIDTH = 11,
    parameter RESET_ALL = 0,
    // 1: also prove the pixels (P_LANES and the data path helpers)
    parameter ARITH = 0,
    // 1: also prove the accumulated start equal to I0 + (s*P)*dI by a multiplication
    parameter PRODUCT = 0,
    parameter CHECK = 0
) (
    input wire                      clk,
    input wire                      rst_n,
    input wire [I_INT+I_FRAC-1:0]   i0_in,
    input wire                      i0_we,
    input wire [I_INT+I_FRAC:0]     di_in,
    input wire                      di_we,
    input wire [LEN_WIDTH-1:0]      len_in,
    input wire                      len_we,
    input wire                      start
);

function integer clog2(input integer v);
    integer r;
    begin
        clog2 = 0;
        for (r = 1; r < v; r = r * 2) clog2 = clog2 + 1;
    end
endfunction

localparam I_WIDTH = I_INT + I_FRAC;
localparam DI_WIDTH = I_WIDTH + 1;
localparam LOG2P = clog2(P);
localparam ACC_WIDTH = LEN_WIDTH + I_WIDTH + 1 + ((I_WIDTH >= LEN_WIDTH) ? 1 : 0);
localparam C_WIDTH = LEN_WIDTH + 1;
localparam [I_INT-1:0] PIX_MAX = {I_INT{1'b1}};

// Property numbers (CHECK selects one)
localparam P_BUSY_EXACT = 1;
localparam P_VALID_EXACT = 2;
localparam P_LAST_EXACT = 3;
localparam P_SEGMENTS = 4;
localparam P_MASK = 5;
localparam P_RESET_IDLE = 6;
localparam P_PIXELS_HELD = 7;
localparam P_LANES = 8;
localparam P_HELPERS = 9;

wire                 busy;
wire                 valid;
wire [P*I_INT-1:0]   pixels;
wire [P-1:0]         mask;
wire                 last;

gouraud_segment #(
    .I_INT(I_INT),
    .I_FRAC(I_FRAC),
    .P(P),
    .LEN_WIDTH(LEN_WIDTH),
    .RESET_ALL(RESET_ALL)
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

// ---------------------------------------------------------------- the contract's formulas
// Segments of a line: ceil(len/P), 1 for len = 0 (the empty segment)
function [C_WIDTH-1:0] segs_of(input [LEN_WIDTH-1:0] len);
    reg [C_WIDTH-1:0] n;
    begin
        n = {1'b0, len} + (P - 1);
        segs_of = (len == {LEN_WIDTH{1'b0}}) ? 1 : (n >> LOG2P);
    end
endfunction

// mask of segment s (first pixel pos = s*P): bit j = (pos + j < len)
function [P-1:0] mask_of(input [C_WIDTH+LOG2P-1:0] pos, input [LEN_WIDTH-1:0] len);
    integer j;
    begin
        for (j = 0; j < P; j = j + 1) mask_of[j] = (pos + j < len);
    end
endfunction

// One pixel: round to nearest, ties up, of v (units of 2^-I_FRAC), clamped to 0..2^I_INT-1
function [I_INT-1:0] pixel_of(input [ACC_WIDTH-1:0] v);
    reg [ACC_WIDTH-1:0] r;
    begin
        r = $signed(v + ({{(ACC_WIDTH-1){1'b0}}, 1'b1} << (I_FRAC - 1))) >>> I_FRAC;
        if (r[ACC_WIDTH-1]) pixel_of = {I_INT{1'b0}};
        else if (r > {{(ACC_WIDTH-I_INT){1'b0}}, PIX_MAX}) pixel_of = PIX_MAX;
        else pixel_of = r[I_INT-1:0];
    end
endfunction

function check_on(input integer p);
    check_on = (CHECK == 0) || (CHECK == p);
endfunction

// ---------------------------------------------------------------- reference model
reg                  f_past_valid = 1'b0;
reg [I_WIDTH-1:0]    f_i0;
reg [DI_WIDTH-1:0]   f_di;
reg [LEN_WIDTH-1:0]  f_len;
reg [I_WIDTH-1:0]    f_job_i0;
reg [DI_WIDTH-1:0]   f_job_di;
reg [LEN_WIDTH-1:0]  f_job_len;
reg [C_WIDTH-1:0]    f_left;
reg [C_WIDTH-1:0]    f_done;
reg [C_WIDTH-1:0]    f_nvalid;
reg                  f_valid;
reg                  f_last;
reg [P-1:0]          f_mask;
reg [ACC_WIDTH-1:0]  f_acc;
reg [P*I_INT-1:0]    f_pix;

wire [C_WIDTH+LOG2P-1:0] f_pos = {f_done, {LOG2P{1'b0}}};
wire [ACC_WIDTH-1:0] f_di_ext = {{(ACC_WIDTH-DI_WIDTH){f_job_di[DI_WIDTH-1]}}, f_job_di};
wire [ACC_WIDTH-1:0] f_i0_ext = {{(ACC_WIDTH-I_WIDTH){1'b0}}, f_job_i0};
wire [ACC_WIDTH-1:0] f_bias = {{(ACC_WIDTH-1){1'b0}}, 1'b1} << (I_FRAC - 1);

reg  [P*I_INT-1:0]   f_lanes;
reg                  f_lanes_lo;  // a lane below 0 before the clamp
reg                  f_lanes_hi;  // a lane above 2^I_INT - 1 before the clamp
reg                  f_clamp_lo;
reg                  f_clamp_hi;
reg  [ACC_WIDTH-1:0] f_lane_v;
integer lj;
always @(*) begin
    f_lanes_lo = 1'b0;
    f_lanes_hi = 1'b0;
    for (lj = 0; lj < P; lj = lj + 1) begin
        f_lane_v = f_acc + f_di_ext * lj;
        f_lanes[lj*I_INT +: I_INT] = pixel_of(f_lane_v);
        f_lane_v = $signed(f_lane_v + f_bias) >>> I_FRAC;
        if (f_lane_v[ACC_WIDTH-1]) f_lanes_lo = 1'b1;
        else if (f_lane_v > {{(ACC_WIDTH-I_INT){1'b0}}, PIX_MAX}) f_lanes_hi = 1'b1;
    end
end

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    f_valid <= 1'b0;
    f_last <= 1'b0;
    if (valid) f_nvalid <= f_nvalid + 1'b1;
    if (f_left == {C_WIDTH{1'b0}}) begin
        if (i0_we) f_i0 <= i0_in;
        if (di_we) f_di <= di_in;
        if (len_we) f_len <= len_in;
        if (start) begin
            f_job_i0 <= f_i0;
            f_job_di <= f_di;
            f_job_len <= f_len;
            f_left <= segs_of(f_len);
            f_done <= {C_WIDTH{1'b0}};
            f_nvalid <= {C_WIDTH{1'b0}};
            f_acc <= {{(ACC_WIDTH-I_WIDTH){1'b0}}, f_i0};
        end
    end else begin
        f_left <= f_left - 1'b1;
        f_done <= f_done + 1'b1;
        f_valid <= 1'b1;
        f_last <= (f_left == 1);
        f_mask <= mask_of(f_pos, f_job_len);
        f_pix <= f_lanes;
        f_clamp_lo <= f_lanes_lo;
        f_clamp_hi <= f_lanes_hi;
        f_acc <= f_acc + (f_di_ext << LOG2P);
    end
    if (!rst_n) begin
        f_i0 <= {I_WIDTH{1'b0}};
        f_di <= {DI_WIDTH{1'b0}};
        f_len <= {LEN_WIDTH{1'b0}};
        f_left <= {C_WIDTH{1'b0}};
        f_done <= {C_WIDTH{1'b0}};
        f_nvalid <= {C_WIDTH{1'b0}};
        f_valid <= 1'b0;
        f_last <= 1'b0;
        f_mask <= {P{1'b0}};
    end
end

// ---------------------------------------------------------------- the one assumption
always @(*) begin
    if (!f_past_valid) assume(!rst_n);
end

// ---------------------------------------------------------------- properties (ports only)
always @(*) begin
    if (f_past_valid) begin
        // busy exactly ceil(len/P) cycles (1 for len = 0) after an accepted start, with len the
        // value held before the start cycle's writes; writes and start while busy change nothing
        if (check_on(P_BUSY_EXACT)) busy_exact: assert(busy == (f_left != {C_WIDTH{1'b0}}));
        // segment s valid s+1 cycles after the start edge, one per busy cycle
        if (check_on(P_VALID_EXACT)) valid_exact: assert(valid == f_valid);
        // last with the valid of the final segment only
        if (check_on(P_LAST_EXACT)) last_exact: assert(last == f_last);
        // the number of valid strobes of a line is ceil(len/P) (1 for len = 0)
        if (check_on(P_SEGMENTS) && valid && last)
            segments_per_line: assert(f_nvalid + 1'b1 == segs_of(f_job_len));
        // mask bit j = lane j inside the line; held between results; 0 after reset
        if (check_on(P_MASK)) mask_exact: assert(mask == f_mask);
        // every lane = clamp(round(I0 + (s*P + j)*dI))
        if (ARITH != 0 && check_on(P_LANES) && valid) lanes: assert(pixels == f_pix);
        if (check_on(P_HELPERS)) begin
            h_nvalid: assert(f_nvalid + {{(C_WIDTH-1){1'b0}}, f_valid} == f_done);
            if (f_left != {C_WIDTH{1'b0}})
                h_run_length: assert(f_left <= segs_of(f_job_len)
                                     && f_left + f_done == segs_of(f_job_len));
            if (PRODUCT != 0 && f_left != {C_WIDTH{1'b0}})
                acc_is_i0_plus_i_di: assert(f_acc == f_i0_ext + f_di_ext * f_pos);
        end
    end
end

always @(posedge clk) begin
    if (f_past_valid) begin
        // pixels change only with valid (or at a reset edge: the data path is not reset)
        if (check_on(P_PIXELS_HELD) && !valid && $past(rst_n))
            pixels_held: assert(pixels == $past(pixels));
        // a cycle with rst_n low, from any state: busy = valid = last = 0, mask = 0
        if (check_on(P_RESET_IDLE) && !$past(rst_n))
            reset_idle: assert(!busy && !valid && !last && mask == {P{1'b0}});
    end
end

// ---------------------------------------------------------------- covers (none is vacuous)
always @(posedge clk) begin
    if (f_past_valid && rst_n) begin
        c_idle: cover(!busy && !valid);
        c_busy: cover(busy);
        c_valid_segment: cover(valid && !last && mask == {P{1'b1}});
        c_last: cover(valid && last && mask == {P{1'b1}} && f_job_len != {LEN_WIDTH{1'b0}});
        c_len_zero: cover(valid && last && f_job_len == {LEN_WIDTH{1'b0}});
        c_partial_mask: cover(valid && last && mask != {P{1'b1}} && mask != {P{1'b0}});
        c_back_to_back: cover(valid && last && start);
        c_write_in_start: cover(busy && f_done == 0 && f_len != f_job_len);
        c_reset_while_busy: cover($past(busy) && !$past(rst_n));
        // a segment with a lane below 0 and one above the top before the clamp
        c_clamp_zero: cover(valid && f_clamp_lo);
        c_clamp_max: cover(valid && f_clamp_hi);
    end
end

// ---------------------------------------------------------------- induction helpers
`ifdef GOURAUD_INTERNALS
// Driven after flatten by the job's script (connect -nounset -set f_int_x \dut.x); see the header.
wire [I_WIDTH-1:0]   f_int_i0;
wire [DI_WIDTH-1:0]  f_int_di;
wire [LEN_WIDTH-1:0] f_int_len;
wire                 f_int_busy;
wire [LEN_WIDTH-1:0] f_int_seg;
wire [P-1:0]         f_int_last_mask;
wire [DI_WIDTH-1:0]  f_int_inc;
wire [ACC_WIDTH-1:0] f_int_start;

wire [C_WIDTH+LOG2P-1:0] f_last_pos = {segs_of(f_job_len) - 1'b1, {LOG2P{1'b0}}};

always @(*) begin
    if (f_past_valid && check_on(P_HELPERS)) begin
        h_i0_reg: assert(f_int_i0 == f_i0);
        h_di_reg: assert(f_int_di == f_di);
        h_len_reg: assert(f_int_len == f_len);
        h_busy_reg: assert(f_int_busy == busy);
        if (busy) begin
            h_seg_reg: assert({1'b0, f_int_seg} == f_left - 1'b1);
            h_last_mask_reg: assert(f_int_last_mask == mask_of(f_last_pos, f_job_len));
            if (ARITH != 0) begin
                h_inc_reg: assert(f_int_inc == f_job_di);
                h_start_reg: assert(f_int_start == f_acc + f_bias);
            end
        end
    end
end
`endif

endmodule
