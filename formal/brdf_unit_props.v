// SPDX-License-Identifier: Apache-2.0
/*
 * Formal properties of the BRDF unit's protocol (rtl/brdf_unit.v), for SymbiYosys
 * (read_verilog -formal; model/hw/formal_brdf.py holds the jobs, docs/formal.md lists every
 * property).
 *
 * brdf_unit_formal wraps one brdf_unit (instance "dut", the job's configuration:
 * model.hw.formal_brdf CONFIGS) with every input free and holds a reference model of the
 * protocol in shadow registers, driven by the ports only:
 *   f_len, f_nerr       the l and n-error registers as the contract says they behave (written
 *                       with their strobes while busy = 0; reset clears l to 0 and makes n
 *                       invalid, as the RTL does);
 *   f_job_len, f_job_nerr   the running line's l and n error (the values held *before* the
 *                       start cycle's writes);
 *   f_left              busy cycles still to come: FILL + l at an accepted start, FILL = 12
 *                       (cosine-quadratic), 13 (quadratic), 20 (cubic), 14 (log2) or
 *                       7 + max(14, OUT_BITS + 8) (piecewise: 31 at its default widths)
 *                       (model.units.brdf.cycles);
 *   f_valid, f_nerr_out the expected valid (offsets FILL..FILL+l after the start edge) and
 *                       n_err.
 * The job's script removes every table (their read data free in every cycle) and Yosys removes
 * the data path, which no property here observes: the protocol holds whatever the table words.
 * One labelled assert per property (busy_exact, ...), numbered by the P_* localparams.
 * CHECK = 0: every assert; n: only number n (the deliberate-error runs); 99: none (covers).
 *
 * Induction helpers: the f_int_* wires are left undriven here and the job's Yosys script
 * connects them after `flatten` to the flattened registers (connect -nounset -set f_int_cnt
 * \dut.cnt_reg, ...), with `define BRDF_INTERNALS (prove jobs).  They are asserted, never
 * assumed.
 *
 * The one assumption: reset (rst_n = 0) in the first cycle.  Everything else is free.
 */

module brdf_unit_formal #(
    // The unit's parameters (model.units.brdf.hdl_parameters; the RTL's defaults here): the
    // job sets them all
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
    parameter ANGLE_ROM_FILE = "angle.hex",
    parameter COEF_ROM_FILE = "coef.hex",
    parameter LOG_ROM_FILE = "log2.hex",
    parameter RESET_ALL = 0,
    // unused: the protocol jobs observe no data output (model.hw.formal sets it for every unit)
    parameter ARITH = 0,
    parameter CHECK = 0
) (
    input wire                              clk,
    input wire                              rst_n,
    input wire [C_INT_BITS+C_FRAC_BITS-1:0] c_in,
    input wire                              c_we,
    input wire [Z_INT_BITS+Z_FRAC_BITS-1:0] dz_in,
    input wire                              dz_we,
    input wire [Z_INT_BITS+Z_FRAC_BITS-1:0] z0_in,
    input wire                              z0_we,
    input wire [9:0]                        n_in,
    input wire                              n_we,
    input wire [LEN_WIDTH-1:0]              len_in,
    input wire                              len_we,
    input wire                              start
);

// model.units.brdf.fill_latency: 7 front stages + the form's 5 (cosine-quadratic), 6
// (quadratic), 13 (cubic), 7 (log2) or max(14, OUT_BITS + 8) (piecewise: its divider takes
// one stage per quotient bit)
localparam [8*16-1:0] FORM_QUADRATIC = "quadratic";
localparam [8*16-1:0] FORM_CUBIC = "cubic";
localparam [8*16-1:0] FORM_LOG2 = "log2";
localparam [8*16-1:0] FORM_PIECEWISE = "piecewise";
localparam FILL_COSINE_QUADRATIC = 12;
localparam FILL_QUADRATIC = 13;
localparam FILL_CUBIC = 20;
localparam FILL_LOG2 = 14;
localparam FILL_PIECEWISE = 7 + ((OUT_BITS + 8 > 14) ? OUT_BITS + 8 : 14);
localparam FILL = (FORM == FORM_QUADRATIC) ? FILL_QUADRATIC
                : (FORM == FORM_CUBIC) ? FILL_CUBIC
                : (FORM == FORM_LOG2) ? FILL_LOG2
                : (FORM == FORM_PIECEWISE) ? FILL_PIECEWISE : FILL_COSINE_QUADRATIC;
localparam LAST_STAGE = FILL - 1;
// f_left: up to FILL + 2^LEN_WIDTH - 1 (LEN_WIDTH >= 4: FILL is at most 39)
localparam L_WIDTH = LEN_WIDTH + 2;

// Property numbers (CHECK selects one)
localparam P_BUSY_EXACT = 1;
localparam P_VALID_EXACT = 2;
localparam P_NERR_OF_THE_LINE = 3;
localparam P_RESET_IDLE = 4;
localparam P_HELPERS = 9;

wire                 busy;
wire                 valid;
wire [OUT_WIDTH-1:0] intensity;
wire                 n_err;

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

// n outside 1..1000: intensity 0 and n_err = 1
function nerr_of(input [9:0] n);
    nerr_of = (n == 10'd0) || (n > 10'd1000);
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
reg                  f_n_in_start;  // an n write in the start cycle that changes the n error

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
        // busy exactly FILL + l cycles after an accepted start, l the value held before the
        // start cycle's writes; writes and start while busy change nothing
        if (check_on(P_BUSY_EXACT)) busy_exact: assert(busy == (f_left != 0));
        // valid exactly at offsets FILL..FILL+l after the start edge (l + 1 results, one per
        // clock, the last with busy = 0), never otherwise
        if (check_on(P_VALID_EXACT)) valid_exact: assert(valid == f_valid);
        // n_err = the n error of the line's n (held before the start cycle's writes) on every
        // pixel, held between results, 0 after reset
        if (check_on(P_NERR_OF_THE_LINE)) n_err_of_the_line: assert(n_err == f_nerr_out);
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
// Driven after flatten by the job's script (connect -nounset -set f_int_x \dut.x); see the header.
wire [LEN_WIDTH-1:0]  f_int_len;
wire                  f_int_nerr;
wire                  f_int_nerr_run;
wire                  f_int_busy;
wire [LEN_WIDTH-1:0]  f_int_cnt;
wire [LAST_STAGE:0]   f_int_v;
wire [LAST_STAGE:1]   f_int_last;

// The stage flags: the pixel in stage s left S0 s cycles ago; pixel i (0..l) is in S0 while
// f_left = FILL + l - i, so stage s holds a pixel iff FILL <= f_left + s <= FILL + l
reg [LAST_STAGE:0] f_v_want;
reg [LAST_STAGE:1] f_last_want;
integer s;
always @(*) begin
    for (s = 0; s <= LAST_STAGE; s = s + 1) begin
        f_v_want[s] = (f_left != 0) && (f_left + s >= FILL) && (f_left + s <= FILL + f_job_l);
        if (s > 0) f_last_want[s] = (f_left != 0) && (f_left + s == FILL);
    end
end

`ifdef BRDF_INTERNALS
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
`endif

endmodule
