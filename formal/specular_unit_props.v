// SPDX-License-Identifier: Apache-2.0
/*
 * Formal properties of the specular unit (rtl/specular_unit.v), for SymbiYosys
 * (read_verilog -formal; model/hw/formal_specular.py holds the jobs, docs/formal.md lists every
 * property beside the contract sentences of docs/specular.md it proves).
 *
 * specular_unit_formal wraps one specular_unit (instance "dut", the RTL's default parameters:
 * model.units.specular DEFAULT) with every input free and holds a reference model of the
 * protocol in shadow registers, driven by the ports only:
 *   f_len, f_nerr       the operand registers as the contract says they behave (written with
 *                       their strobes while busy = 0, cleared by reset as the RTL does: l = 0
 *                       and n = 0, an invalid n);
 *   f_job_len, f_job_nerr   the running line's l and n error (the values held *before* the
 *                       start cycle's writes);
 *   f_left              busy cycles still to come: FILL_LATENCY + l = 8 + l at an accepted start;
 *   f_valid, f_nerr_out the expected valid (offsets 8..8+l after the start edge, i.e. while
 *                       f_left was 1..l+1 in the cycle before) and n_err.
 * The job's script removes both ROMs and leaves their read data free in every cycle, so every
 * property holds whatever the ROM words.  The data output (intensity) is observed only with
 * ARITH = 1, by intensity_zero_on_n_err (every pixel of an invalid n's line is 0); with
 * ARITH = 0 Yosys removes the data path before the run.
 * One labelled assert per property (busy_exact, ...), numbered by the P_* localparams.
 * CHECK = 0: every assert; n: only number n (the deliberate-error runs); 99: none (covers).
 *
 * Induction helpers (`ifdef SPECULAR_INTERNALS): the f_int_* wires are left undriven here and
 * the job's Yosys script connects them after `flatten` to the flattened registers
 * (connect -set f_int_cnt \dut.cnt_reg, ...).  They are asserted, never assumed.
 *
 * The one assumption: reset (rst_n = 0) in the first cycle.  Everything else is free.
 */

module specular_unit_formal #(
    parameter A_ROM_FILE = "a.hex",
    parameter COS_ROM_FILE = "cos.hex",
    parameter RESET_ALL = 0,
    // 1: also prove intensity = 0 on the pixels of an invalid n (the data path kept, the ROM
    // words free)
    parameter ARITH = 0,
    parameter CHECK = 0
) (
    input wire         clk,
    input wire         rst_n,
    input wire [15:0]  c_in,
    input wire         c_we,
    input wire [28:0]  dz_in,
    input wire         dz_we,
    input wire [28:0]  z0_in,
    input wire         z0_we,
    input wire [9:0]   n_in,
    input wire         n_we,
    input wire [10:0]  len_in,
    input wire         len_we,
    input wire         start
);

localparam LEN_WIDTH = 11;
localparam FILL = 8;  // FILL_LATENCY of docs/specular.md
localparam LAST_STAGE = 7;
localparam L_WIDTH = LEN_WIDTH + 2;  // f_left: up to 8 + 2^LEN_WIDTH - 1
localparam N_FIRST = 1;
localparam N_LAST = 1000;

// Property numbers (CHECK selects one)
localparam P_BUSY_EXACT = 1;
localparam P_VALID_EXACT = 2;
localparam P_NERR_OF_THE_LINE = 3;
localparam P_RESET_IDLE = 4;
localparam P_NERR_DARK = 5;
localparam P_HELPERS = 9;

wire        busy;
wire        valid;
wire [7:0]  intensity;
wire        n_err;

specular_unit #(
    .LEN_WIDTH(LEN_WIDTH),
    .N_FIRST(N_FIRST),
    .N_LAST(N_LAST),
    .A_ROM_FILE(A_ROM_FILE),
    .COS_ROM_FILE(COS_ROM_FILE),
    .RESET_ALL(RESET_ALL)
) dut (
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

// n outside 1..1000 or the kept range N_FIRST..N_LAST: intensity 0 and n_err = 1
function nerr_of(input [9:0] n);
    nerr_of = (n == 10'd0) || (n > 10'd1000) || (n < N_FIRST) || (n > N_LAST);
endfunction

function check_on(input integer p);
    check_on = (CHECK == 0) || (CHECK == p);
endfunction

// ---------------------------------------------------------------- reference model
reg                  f_past_valid = 1'b0;
reg [LEN_WIDTH-1:0]  f_len;
reg                  f_nerr;
reg [LEN_WIDTH-1:0]  f_job_len;
reg                  f_job_nerr;
reg [L_WIDTH-1:0]    f_left;
reg                  f_valid;
reg                  f_nerr_out;
reg [L_WIDTH-1:0]    f_nvalid;  // valid strobes of the running line so far
reg                  f_n_in_start;  // an n write in the start cycle of the running line

wire [L_WIDTH-1:0]   f_job_l = {2'b00, f_job_len};
wire                 f_out_now = (f_left != 0) && (f_left <= f_job_l + 1'b1);

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    f_valid <= 1'b0;
    if (valid) f_nvalid <= f_nvalid + 1'b1;
    if (f_left == 0) begin
        if (len_we) f_len <= len_in;
        if (n_we) f_nerr <= nerr_of(n_in);
        if (start) begin
            f_job_len <= f_len;
            f_job_nerr <= f_nerr;
            f_left <= FILL + {2'b00, f_len};
            f_nvalid <= 0;
            f_n_in_start <= n_we && nerr_of(n_in) != f_nerr;
        end
    end else begin
        f_left <= f_left - 1'b1;
        if (f_out_now) begin
            f_valid <= 1'b1;
            f_nerr_out <= f_job_nerr;
        end
    end
    if (!rst_n) begin
        f_len <= {LEN_WIDTH{1'b0}};
        f_nerr <= 1'b1;
        f_left <= 0;
        f_valid <= 1'b0;
        f_nerr_out <= 1'b0;
        f_nvalid <= 0;
    end
end

// ---------------------------------------------------------------- the one assumption
always @(*) begin
    if (!f_past_valid) assume(!rst_n);
end

// ---------------------------------------------------------------- properties (ports only)
always @(*) begin
    if (f_past_valid) begin
        // busy exactly 8 + l cycles after an accepted start, l the value held before the start
        // cycle's writes; writes and start while busy change nothing
        if (check_on(P_BUSY_EXACT)) busy_exact: assert(busy == (f_left != 0));
        // valid exactly at offsets 8..8+l after the start edge (l + 1 results, one per clock,
        // the last with busy = 0), never otherwise
        if (check_on(P_VALID_EXACT)) valid_exact: assert(valid == f_valid);
        // n_err = the n error of the line's n (held before the start cycle's writes) on every
        // pixel, held between results, 0 after reset
        if (check_on(P_NERR_OF_THE_LINE)) n_err_of_the_line: assert(n_err == f_nerr_out);
        // every pixel of a line with an invalid n is 0, whatever the ROM words
        if (ARITH != 0 && check_on(P_NERR_DARK) && valid && f_nerr_out)
            intensity_zero_on_n_err: assert(intensity == 8'd0);
        if (check_on(P_HELPERS)) begin
            if (f_left != 0) begin
                h_run_length: assert(f_left <= FILL + f_job_l);
                h_valid: assert(f_valid == (f_left <= f_job_l));
                h_nvalid: assert(f_nvalid == ((f_left <= f_job_l) ? f_job_l - f_left : 0));
            end
        end
    end
end

always @(posedge clk) begin
    if (f_past_valid) begin
        // a cycle with rst_n low, from any state: busy = valid = n_err = 0
        if (check_on(P_RESET_IDLE) && !$past(rst_n))
            reset_idle: assert(!busy && !valid && !n_err);
    end
end

// ---------------------------------------------------------------- covers (none is vacuous)
always @(posedge clk) begin
    if (f_past_valid && rst_n) begin
        c_idle: cover(!busy && !valid);
        c_busy: cover(busy && !valid);
        c_valid_busy: cover(valid && busy);
        c_len_zero: cover(valid && !busy && f_job_len == 0 && f_nvalid == 0);
        c_long_line: cover(valid && !busy && f_job_len >= 4 && f_nvalid == f_job_l);
        c_back_to_back: cover(valid && !busy && start && len_we);
        c_start_while_busy: cover(busy && start && $past(busy) && $past(start));
        c_write_in_start: cover(busy && f_left == FILL + f_job_l && f_len != f_job_len);
        c_strobes_while_busy: cover(busy && c_we && dz_we && z0_we && n_we && len_we);
        // reset in the middle of a line (not the first cycle's reset of an arbitrary state)
        c_reset_while_busy: cover($past(f_past_valid) && $past(busy) && !$past(rst_n));
        c_n_err: cover(valid && n_err);
        c_n_ok: cover(valid && !n_err);
        c_n_write_in_start: cover(valid && !busy && f_n_in_start);
    end
end

// ---------------------------------------------------------------- induction helpers
`ifdef SPECULAR_INTERNALS
// Driven after flatten by the job's script (connect -set f_int_x \dut.x); see the header.
wire [LEN_WIDTH-1:0]  f_int_len;
wire                  f_int_nerr;
wire                  f_int_nerr_run;
wire                  f_int_busy;
wire [LEN_WIDTH-1:0]  f_int_cnt;
wire [LAST_STAGE:0]   f_int_v;
wire [LAST_STAGE:1]   f_int_last;
wire                  f_int_zero;      // read with ARITH = 1 only
wire [15:0]           f_int_rom_d;
wire [31:0]           f_int_out_prod;

// The stage flags: the pixel in stage s left S0 s cycles ago; pixel i (0..l) is in S0 while
// f_left = 8 + l - i, so stage s holds a pixel iff 8 <= f_left + s <= 8 + l
reg [LAST_STAGE:0] f_v_want;
reg [LAST_STAGE:1] f_last_want;
integer s;
always @(*) begin
    for (s = 0; s <= LAST_STAGE; s = s + 1) begin
        f_v_want[s] = (f_left != 0) && (f_left + s >= FILL) && (f_left + s <= FILL + f_job_l);
        if (s > 0) f_last_want[s] = (f_left != 0) && (f_left + s == FILL);
    end
end

always @(*) begin
    if (f_past_valid && check_on(P_HELPERS)) begin
        h_len_reg: assert(f_int_len == f_len);
        h_nerr_reg: assert(f_int_nerr == f_nerr);
        h_busy_reg: assert(f_int_busy == busy);
        h_cnt_reg: assert({2'b00, f_int_cnt} == ((f_left >= FILL) ? f_left - FILL : 0));
        h_v_reg: assert(f_int_v == f_v_want);
        h_last_reg: assert(f_int_last == f_last_want);
        if (f_left != 0) h_nerr_run_reg: assert(f_int_nerr_run == f_job_nerr);
    end
end

generate
    if (ARITH != 0) begin : g_data
        // the data path of an invalid n's pixels: the zero gate (S5), the gated word (S6), the
        // product (S7)
        always @(*) begin
            if (f_past_valid && check_on(P_HELPERS) && f_job_nerr && f_left != 0) begin
                if (f_v_want[5]) h_zero_reg: assert(f_int_zero);
                if (f_v_want[6]) h_rom_d_reg: assert(f_int_rom_d == 16'd0);
                if (f_v_want[7]) h_out_prod_reg: assert(f_int_out_prod == 32'd0);
            end
        end
    end
endgenerate
`endif

endmodule
