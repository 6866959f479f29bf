// SPDX-License-Identifier: Apache-2.0
/*
 * Segment Gouraud unit (Romanyuk): P pixels of a scan line per clock, I0 + i*dI, i = 0..P-1.
 *
 * Increment block: on start the increment dI is copied into inc_reg; hard-wired shifts give
 * 2^w*dI (w = 0..log2 P) and a few adders the other multiples i*dI, i = 1..P.  Which
 * multiples each adder adds or subtracts is derived from P by constant functions, the same
 * rule as model.gouraud.increment_network: the lowest adder level, an addition before a
 * subtraction, the smallest second operand (P = 8: 3 = 2+1, 5 = 4+1, 6 = 4+2, 7 = 8-1;
 * P = 16 adds a second level for 11 = 10+1 and 13 = 12+1).
 *
 * Segment block: lane 0 is the start register itself, lanes 1..P-1 add i*dI to it, and one
 * more adder makes the next segment's start I0 + P*dI, written back every clock.  The start
 * register is loaded with i0 + 2^(I_FRAC-1) (the rounding bias, one adder), so each lane only
 * drops its I_FRAC fraction bits to round to nearest (ties up) and clamps to 0..2^I_INT-1.
 *
 * Formats: i0 unsigned Q(I_INT).(I_FRAC); di signed Q(I_INT+1).(I_FRAC); len unsigned, pixels
 * in the line; pixels: P lanes of I_INT bits, lane 0 (leftmost pixel) in the low bits; mask:
 * bit j = 1 when lane j belongs to the line (the last segment's lanes past the end are 0).
 *
 * Timing: busy is high for ceil(len/P) cycles after an accepted start; segment s is out
 * (valid) s+1 cycles after the start edge, the last one with last = 1 and busy = 0, when a new
 * start is already accepted.  len = 0 gives one empty segment: valid with mask = 0, last = 1.
 * Every output equals model.gouraud.unit_results() bit for bit.
 *
 * Protocol (docs/architecture.md, "The protocol every unit follows"): operands are sampled
 * with their write strobes while busy = 0;
 * a start accepted in the same cycle as a write runs on the values held before it.
 *
 * Reset: rst_n is synchronous, active low; no register has an initial value.  RESET_ALL = 0
 * (default) resets busy, valid, last, mask, the segment counter and the operand registers (a
 * start right after reset is an empty line); the data path (increment, start register, the
 * last segment's mask, pixels) is loaded by every start, so pixels is defined from the first
 * segment on.  RESET_ALL = 1 resets every register (pixels = 0 after reset)
 * (docs/fpga.md, "Reset", "Parameters").
 *
 * Portability: plain Verilog-2005 (Icarus -g2005, Verilator --language 1364-2005, Yosys
 * read_verilog; make lint); log2 P comes from the constant function clog2, not $clog2.
 *
 * Checks: a parameter set model.gouraud.GouraudConfig refuses, or a RESET_ALL other than 0 and
 * 1, is refused at elaboration (an instance of a module that does not exist, named after the
 * rule, e.g. gouraud_segment_PARAMETER_ERROR_P_must_be_2_4_8_or_16).
 *
 * Documentation: docs/gouraud.md (ports, formats, parameters, timing, accuracy, the contract
 * and its tests); docs/architecture.md (the protocol, the benches).
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module gouraud_segment #(
    // Integer bits of the intensities (output pixel width)
    parameter I_INT = 8,
    // Fraction bits of i0 and di
    parameter I_FRAC = 12,
    // Lanes: pixels per segment (2, 4, 8 or 16)
    parameter P = 8,
    // Width of the line length (lines of 1 .. 2^LEN_WIDTH-1 pixels), more than log2(P)
    parameter LEN_WIDTH = 11,
    // 0: rst_n resets the control state and the operand registers; 1: every register
    parameter RESET_ALL = 0
) (
    input  wire                       clk,
    input  wire                       rst_n,

    input  wire [I_INT+I_FRAC-1:0]    i0_in,
    input  wire                       i0_we,
    input  wire [I_INT+I_FRAC:0]      di_in,
    input  wire                       di_we,
    input  wire [LEN_WIDTH-1:0]       len_in,
    input  wire                       len_we,
    input  wire                       start,

    output wire                       busy,
    output wire                       valid,
    output wire [P*I_INT-1:0]         pixels,
    output wire [P-1:0]               mask,
    output wire                       last
);

// ceil(log2(v)) for v >= 1: $clog2 came with IEEE 1364-2005 and some Verilog tools lack it
function integer clog2(input integer v);
    integer r;
    begin
        clog2 = 0;
        for (r = 1; r < v; r = r * 2) begin
            clog2 = clog2 + 1;
        end
    end
endfunction

localparam I_WIDTH = I_INT + I_FRAC;
localparam DI_WIDTH = I_WIDTH + 1;
localparam LOG2P = clog2(P);
// Multiples i*dI, i <= P: signed, no wrap
localparam INC_WIDTH = DI_WIDTH + LOG2P;
// Start register and lane adders: I0 + bias + i*dI for i up to 2^LEN_WIDTH never wraps
// (model.gouraud.GouraudConfig.acc_width)
localparam ACC_WIDTH = LEN_WIDTH + I_WIDTH + 1 + ((I_WIDTH >= LEN_WIDTH) ? 1 : 0);
localparam EXT_WIDTH = ACC_WIDTH - INC_WIDTH;

// ---------------------------------------------------------------- parameter check
// Exactly the sets model.gouraud.GouraudConfig refuses (Verilog-2005 has no elaboration-time
// $error: a failing rule instantiates a module that does not exist, named after the rule, and
// every tool stops with an error naming it).
generate
    if (I_INT < 1 || I_INT > 16) begin : g_check_i_int
        gouraud_segment_PARAMETER_ERROR_I_INT_must_be_1_to_16 u_error ();
    end
    if (I_FRAC < 1 || I_FRAC > 24) begin : g_check_i_frac
        gouraud_segment_PARAMETER_ERROR_I_FRAC_must_be_1_to_24 u_error ();
    end
    if (P != 2 && P != 4 && P != 8 && P != 16) begin : g_check_p
        gouraud_segment_PARAMETER_ERROR_P_must_be_2_4_8_or_16 u_error ();
    end
    if (LEN_WIDTH <= LOG2P || LEN_WIDTH > 16) begin : g_check_len_width
        // A line must be able to span more than one segment
        gouraud_segment_PARAMETER_ERROR_LEN_WIDTH_must_be_log2_P_plus_1_to_16 u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        gouraud_segment_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
endgenerate

// ---------------------------------------------------------------- the network, derived from P

// Adder level of the multiple v: 0 = a wired shift, 1 = one adder of two shifts, 2 = one
// adder of two level-0/1 multiples (enough for every v <= 16)
function integer mult_level(input integer v, input integer p);
    integer y;
    begin
        // (x & (x - 1)) == 0: x (> 0 here) is a power of two
        if (v > 0 && (v & (v - 1)) == 0 && v <= p) begin
            mult_level = 0;
        end else begin
            mult_level = 2;
            for (y = 1; y <= p; y = y * 2) begin
                if ((v - y >= y && ((v - y) & (v - y - 1)) == 0)
                        || (v + y <= p && ((v + y) & (v + y - 1)) == 0)) begin
                    mult_level = 1;
                end
            end
        end
    end
endfunction

// Smallest y with i = (i-y) + y, both of a lower level (0 if there is none)
function integer add_y(input integer i, input integer p);
    integer y;
    integer level;
    begin
        add_y = 0;
        level = mult_level(i, p);
        for (y = p; y >= 1; y = y - 1) begin
            if (i - y >= y) begin
                if (mult_level(y, p) < level && mult_level(i - y, p) < level) begin
                    add_y = y;
                end
            end
        end
    end
endfunction

// Smallest y with i = (i+y) - y, both of a lower level (0 if there is none)
function integer sub_y(input integer i, input integer p);
    integer y;
    integer level;
    begin
        sub_y = 0;
        level = mult_level(i, p);
        for (y = p; y >= 1; y = y - 1) begin
            if (i + y <= p) begin
                if (mult_level(y, p) < level && mult_level(i + y, p) < level) begin
                    sub_y = y;
                end
            end
        end
    end
endfunction

// ---------------------------------------------------------------- registers

// No register has an initial value: rst_n (synchronous, active low) sets the control state
// (busy, valid, last, the segment counter), the mask flags and the operand registers; the data
// path (inc_reg, start_reg, last_mask_reg, pixels_reg) is loaded by every start and read only
// while busy or, for pixels, from valid = 1 on.  RESET_ALL = 1 resets it too.

// Operand registers
reg [I_WIDTH-1:0]   i0_reg;
reg [DI_WIDTH-1:0]  di_reg;
reg [LEN_WIDTH-1:0] len_reg;

// Working registers of a line: the increment block's dI, the start register, the segments
// still to come after the current one, the last segment's mask
reg [DI_WIDTH-1:0]  inc_reg;
reg [ACC_WIDTH-1:0] start_reg;
reg [LEN_WIDTH-1:0] seg_reg;
reg [P-1:0]         last_mask_reg;

// Control and outputs
reg                 busy_reg;
reg                 valid_reg;
reg                 last_reg;
reg [P*I_INT-1:0]   pixels_reg;
reg [P-1:0]         mask_reg;

assign busy = busy_reg;
assign valid = valid_reg;
assign pixels = pixels_reg;
assign mask = mask_reg;
assign last = last_reg;

// ---------------------------------------------------------------- increment block

// Multiple i*dI in bits [i*INC_WIDTH +: INC_WIDTH], i = 1..P (slot 0 is 0: lane 0), level by
// level: mult0 holds the wired shifts, mult1 adds the level-1 adders, mult the level-2 ones
wire [INC_WIDTH-1:0]       inc_ext = {{LOG2P{inc_reg[DI_WIDTH-1]}}, inc_reg};
/* verilator lint_off UNUSEDSIGNAL */
// Slots of multiples made at a later level are 0 placeholders, never read
wire [(P+1)*INC_WIDTH-1:0] mult0;
wire [(P+1)*INC_WIDTH-1:0] mult1;
/* verilator lint_on UNUSEDSIGNAL */
wire [(P+1)*INC_WIDTH-1:0] mult;

assign mult0[INC_WIDTH-1:0] = {INC_WIDTH{1'b0}};
assign mult1[INC_WIDTH-1:0] = {INC_WIDTH{1'b0}};
assign mult[INC_WIDTH-1:0] = {INC_WIDTH{1'b0}};

genvar i;
generate
    // (an illegal P is refused above: its network is not built, which would only slow the tools)
    for (i = 1; i <= P && P <= 16; i = i + 1) begin : g_mult
        localparam integer LEVEL = mult_level(i, P);
        localparam integer ADD_Y = add_y(i, P);
        localparam integer SUB_Y = sub_y(i, P);
        localparam integer OP_A = (ADD_Y != 0) ? i - ADD_Y : i + SUB_Y;
        localparam integer OP_B = (ADD_Y != 0) ? ADD_Y : SUB_Y;
        if (LEVEL == 0) begin : g_shift
            // Wired shift 2^w * dI
            assign mult0[i*INC_WIDTH +: INC_WIDTH] = inc_ext << clog2(i);
        end else begin : g_none
            assign mult0[i*INC_WIDTH +: INC_WIDTH] = {INC_WIDTH{1'b0}};
        end
        if (LEVEL == 1 && ADD_Y != 0) begin : g_add1
            assign mult1[i*INC_WIDTH +: INC_WIDTH] =
                mult0[OP_A*INC_WIDTH +: INC_WIDTH] + mult0[OP_B*INC_WIDTH +: INC_WIDTH];
        end else if (LEVEL == 1) begin : g_sub1
            // Two's complement subtraction (P = 8: 7dI = 8dI - dI)
            assign mult1[i*INC_WIDTH +: INC_WIDTH] =
                mult0[OP_A*INC_WIDTH +: INC_WIDTH] - mult0[OP_B*INC_WIDTH +: INC_WIDTH];
        end else begin : g_pass1
            assign mult1[i*INC_WIDTH +: INC_WIDTH] = mult0[i*INC_WIDTH +: INC_WIDTH];
        end
        if (LEVEL == 2 && ADD_Y != 0) begin : g_add2
            assign mult[i*INC_WIDTH +: INC_WIDTH] =
                mult1[OP_A*INC_WIDTH +: INC_WIDTH] + mult1[OP_B*INC_WIDTH +: INC_WIDTH];
        end else if (LEVEL == 2) begin : g_sub2
            assign mult[i*INC_WIDTH +: INC_WIDTH] =
                mult1[OP_A*INC_WIDTH +: INC_WIDTH] - mult1[OP_B*INC_WIDTH +: INC_WIDTH];
        end else begin : g_pass2
            assign mult[i*INC_WIDTH +: INC_WIDTH] = mult1[i*INC_WIDTH +: INC_WIDTH];
        end
    end
endgenerate

// ---------------------------------------------------------------- segment block

// Lane adders and output conversion: drop the fraction bits (the bias made it a rounding),
// clamp to 0 .. 2^I_INT-1
wire [P*I_INT-1:0] lane_pixels;

genvar j;
generate
    for (j = 0; j < P; j = j + 1) begin : g_lane
        wire [INC_WIDTH-1:0] m = mult[j*INC_WIDTH +: INC_WIDTH];
        /* verilator lint_off UNUSEDSIGNAL */
        // The low I_FRAC bits only carry into the kept ones
        wire [ACC_WIDTH-1:0] sum = start_reg + {{EXT_WIDTH{m[INC_WIDTH-1]}}, m};
        /* verilator lint_on UNUSEDSIGNAL */
        wire negative = sum[ACC_WIDTH-1];
        wire overflow = |sum[ACC_WIDTH-2:I_FRAC+I_INT];
        // negative ? 0 : overflow ? 2^I_INT-1 : the kept bits, as gates: written as a
        // multiplexer, Yosys turns the clamp to 0 into a synchronous reset that the enable
        // gates, which ECP5 flip-flops lack (synth_ecp5: 380 LUT4 instead of 161 at P = 8)
        assign lane_pixels[j*I_INT +: I_INT] = {I_INT{~negative}}
                                              & (sum[I_FRAC+I_INT-1:I_FRAC] | {I_INT{overflow}});
    end
endgenerate

// The next segment's start, I0 + P*dI (+ bias)
wire [INC_WIDTH-1:0] mult_p = mult[P*INC_WIDTH +: INC_WIDTH];
wire [ACC_WIDTH-1:0] next_start = start_reg + {{EXT_WIDTH{mult_p[INC_WIDTH-1]}}, mult_p};

// Loading a line: the biased start, the segment count and the last segment's mask
wire [ACC_WIDTH-1:0] round_bias = {{(ACC_WIDTH-1){1'b0}}, 1'b1} << (I_FRAC - 1);
wire [ACC_WIDTH-1:0] first_start = {{(ACC_WIDTH-I_WIDTH){1'b0}}, i0_reg} + round_bias;

wire                 len_zero = (len_reg == {LEN_WIDTH{1'b0}});
wire [LEN_WIDTH-1:0] len_m1 = len_reg - {{(LEN_WIDTH-1){1'b0}}, 1'b1};
// Segments after the first: ceil(len/P) - 1 = (len-1) >> log2 P; 0 for the empty line
wire [LEN_WIDTH-1:0] seg_first = len_zero ? {LEN_WIDTH{1'b0}} : (len_m1 >> LOG2P);
// Pixels in the last segment: the low bits of len (0 = a full segment)
wire [LOG2P-1:0]     len_rem = len_reg[LOG2P-1:0];
wire [P-1:0]         last_mask = len_zero ? {P{1'b0}} :
                                 (len_rem == {LOG2P{1'b0}}) ? {P{1'b1}} :
                                 ~({P{1'b1}} << len_rem);

always @(posedge clk) begin
    valid_reg <= 1'b0;
    last_reg <= 1'b0;

    if (!busy_reg) begin
        if (i0_we) begin
            i0_reg <= i0_in;
        end
        if (di_we) begin
            di_reg <= di_in;
        end
        if (len_we) begin
            len_reg <= len_in;
        end
        if (start) begin
            busy_reg <= 1'b1;
            inc_reg <= di_reg;
            start_reg <= first_start;
            seg_reg <= seg_first;
            last_mask_reg <= last_mask;
        end
    end else begin
        // One segment per clock
        valid_reg <= 1'b1;
        pixels_reg <= lane_pixels;
        start_reg <= next_start;
        if (seg_reg == {LEN_WIDTH{1'b0}}) begin
            busy_reg <= 1'b0;
            last_reg <= 1'b1;
            mask_reg <= last_mask_reg;
        end else begin
            seg_reg <= seg_reg - {{(LEN_WIDTH-1){1'b0}}, 1'b1};
            mask_reg <= {P{1'b1}};
        end
    end

    if (!rst_n) begin
        // Control state, flags and operand registers
        i0_reg <= {I_WIDTH{1'b0}};
        di_reg <= {DI_WIDTH{1'b0}};
        len_reg <= {LEN_WIDTH{1'b0}};
        seg_reg <= {LEN_WIDTH{1'b0}};
        busy_reg <= 1'b0;
        valid_reg <= 1'b0;
        last_reg <= 1'b0;
        mask_reg <= {P{1'b0}};
    end
    if (!rst_n && RESET_ALL != 0) begin
        // Data path
        inc_reg <= {DI_WIDTH{1'b0}};
        start_reg <= {ACC_WIDTH{1'b0}};
        last_mask_reg <= {P{1'b0}};
        pixels_reg <= {P*I_INT{1'b0}};
    end
end

endmodule

`resetall
