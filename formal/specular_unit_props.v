// SPDX-License-Identifier: Apache-2.0
/*
 * Formal properties of the specular unit (rtl/specular_unit.v), for SymbiYosys
 * (read_verilog -formal; model/hw/formal_specular.py holds the jobs, docs/formal.md lists every
 * property beside the contract sentences of docs/specular.md it proves).
 *
 * Size: about 780 lines, one file on purpose: the protocol model, the per-stage data helpers
 * (one per pipeline register of the nine-stage unit) and the DATA = 1 / 2 forms of the
 * intensity check all read the same shadow registers; split, each part would re-declare them.
 *
 * specular_unit_formal wraps one specular_unit (instance "dut", the job's configuration:
 * model.hw.formal_specular CONFIGS) with every input free and holds a reference model of the
 * protocol in shadow registers, driven by the ports only:
 *   f_len, f_nerr       the operand registers as the contract says they behave (written with
 *                       their strobes while busy = 0, cleared by reset as the RTL does: l = 0
 *                       and n = 0, an invalid n); likewise f_c, f_dz, f_z0, f_n;
 *   f_job_len, f_job_nerr   the running line's l and n error (the values held *before* the
 *                       start cycle's writes); likewise f_job_c, f_job_dz, f_job_z0, f_job_n;
 *   f_left              busy cycles still to come: FILL_LATENCY + l = 8 + l at an accepted start;
 *   f_valid, f_nerr_out the expected valid (offsets 8..8+l after the start edge, i.e. while
 *                       f_left was 1..l+1 in the cycle before) and n_err;
 *   f_zeta              the angle of the next result's pixel: z0 at the start, + dz per result.
 * DATA = 0: the job's script removes both ROMs and leaves their read data free in every cycle,
 * so every property holds whatever the ROM words.  The data output (intensity) is observed
 * only with ARITH = 1, by intensity_zero_on_n_err (every pixel of an invalid n's line is 0);
 * with ARITH = 0 Yosys removes the data path before the run.
 * DATA = 1: also intensity_formula, every intensity equal to specular_unit_ref
 * (formal/specular_unit_datapath.v: the contract's formula) of f_zeta and the line's C and n,
 * with the ROM words from this file's own copies of the committed images (f_a_image,
 * f_cos_image); CLAMP = 1 adds clamp_never_changes_a_result.  DATA = 2 (the bounded check at
 * the default, HELPERS = 0): the same with the words the unit's ROMs returned and the two
 * products computed here from the unit's operand registers (the RTL's expression, which Yosys
 * merges with the unit's $mul), carried to the pixel's result; intensity_formula then also
 * asserts that the ROM addresses and the products' operands were the formula's (f_taken_ok).
 * CHECK 1..5 (a protocol property alone) leave the reference out (D_EFF = 0).
 * One labelled assert per property (busy_exact, ...), numbered by the P_* localparams.
 * CHECK = 0: every assert; n: only number n (the deliberate-error runs); 99: none (covers).
 *
 * Induction helpers: the f_int_* wires are left undriven here and the job's Yosys script
 * connects them after `flatten` to the flattened registers (connect -nounset -set f_int_cnt
 * \dut.cnt_reg, ...); the protocol helpers only with `define SPECULAR_INTERNALS (prove and
 * bmc jobs), the data path's also with DATA (the data mutant at the default reads the
 * connections too, made by its memory script).  They are asserted, never assumed.
 *
 * The one assumption: reset (rst_n = 0) in the first cycle.  Everything else is free.
 */

module specular_unit_formal #(
    // The unit's parameters (model.units.specular SpecularConfig.hdl_parameters(); the RTL's
    // defaults here): the job sets them all
    parameter C_INT_BITS = 8,
    parameter C_FRAC_BITS = 8,
    parameter Z_INT_BITS = 3,
    parameter Z_FRAC_BITS = 26,
    parameter LEN_WIDTH = 11,
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
    parameter A_ROM_FILE = "a.hex",
    parameter COS_ROM_FILE = "cos.hex",
    parameter RESET_ALL = 0,
    // 1: also prove intensity = 0 on the pixels of an invalid n (the data path kept, the ROM
    // words free)
    parameter ARITH = 0,
    // 1: also prove every intensity equal to the reference formula (specular_unit_ref of
    // formal/specular_unit_datapath.v; the ROMs kept, their committed images)
    parameter DATA = 0,
    // 1 (with DATA): also prove clamp_never_changes_a_result
    parameter CLAMP = 0,
    // 0: the induction helpers are not asserted (the bounded check at the default, where they
    // are not needed and cost more solver time than they save)
    parameter HELPERS = 1,
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

localparam FILL = 8;  // FILL_LATENCY of docs/specular.md
localparam LAST_STAGE = 7;
localparam L_WIDTH = LEN_WIDTH + 2;  // f_left: up to 8 + 2^LEN_WIDTH - 1 (LEN_WIDTH >= 2)
localparam C_W = C_INT_BITS + C_FRAC_BITS;
localparam Z_W = Z_INT_BITS + Z_FRAC_BITS;
localparam ACC_W = Z_W + LEN_WIDTH;
localparam A_W = A_INT_BITS + A_FRAC_BITS;
localparam MAG_W = MAG_INT_BITS + Z_FRAC_BITS;
localparam PROD_W = MAG_W + A_W;
localparam SHIFT = Z_FRAC_BITS + A_FRAC_BITS - ROM_ADDR_BITS;
localparam RND_W = PROD_W + 1 - SHIFT;
localparam OP_W = C_W + ROM_DATA_BITS;
localparam TSEL_BITS = (NUM_TABLES > 2) ? 2 : 1;
localparam [OUT_WIDTH-1:0] OUT_MAX = {OUT_WIDTH{1'b1}};

// Property numbers (CHECK selects one)
localparam P_BUSY_EXACT = 1;
localparam P_VALID_EXACT = 2;
localparam P_NERR_OF_THE_LINE = 3;
localparam P_RESET_IDLE = 4;
localparam P_NERR_DARK = 5;
localparam P_INTENSITY = 6;
localparam P_CLAMP = 7;
localparam P_HELPERS = 9;
// DATA as used: 0 in the jobs that check a protocol property alone (CHECK 1..5), so that they
// carry no reference (its disabled asserts would stay in the model)
localparam D_EFF = (CHECK == 0 || CHECK == P_INTENSITY || CHECK == P_CLAMP || CHECK == P_HELPERS
                    || CHECK == 99) ? DATA : 0;

wire                 busy;
wire                 valid;
wire [OUT_WIDTH-1:0] intensity;
wire                 n_err;

specular_unit #(
    .C_INT_BITS(C_INT_BITS),
    .C_FRAC_BITS(C_FRAC_BITS),
    .Z_INT_BITS(Z_INT_BITS),
    .Z_FRAC_BITS(Z_FRAC_BITS),
    .LEN_WIDTH(LEN_WIDTH),
    .A_INT_BITS(A_INT_BITS),
    .A_FRAC_BITS(A_FRAC_BITS),
    .ROM_ADDR_BITS(ROM_ADDR_BITS),
    .ROM_DATA_BITS(ROM_DATA_BITS),
    .OUT_WIDTH(OUT_WIDTH),
    .NUM_TABLES(NUM_TABLES),
    .N_HI0(N_HI0),
    .N_HI1(N_HI1),
    .N_HI2(N_HI2),
    .N_HI3(N_HI3),
    .K0(K0),
    .K1(K1),
    .K2(K2),
    .K3(K3),
    .ALPHA(ALPHA),
    .MAG_INT_BITS(MAG_INT_BITS),
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
    check_on = ((CHECK == 0) || (CHECK == p)) && (p != P_HELPERS || HELPERS != 0);
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
// The data operands (DATA): the registers as written while idle (reset clears C, dz, z0 and
// n), and the running line's copies
reg [C_W-1:0]        f_c;
reg [Z_W-1:0]        f_dz;
reg [Z_W-1:0]        f_z0;
reg [9:0]            f_n;
reg [C_W-1:0]        f_job_c;
reg [Z_W-1:0]        f_job_dz;
reg [Z_W-1:0]        f_job_z0;
reg [9:0]            f_job_n;
// zeta of the pixel of the next valid strobe: z0 at the start, + dz at each result (the
// contract's zeta_0 = z0, zeta_i = zeta_(i-1) + dz, in the accumulator's width)
reg signed [ACC_W-1:0] f_zeta;
wire signed [ACC_W-1:0] f_job_dz_w = $signed(f_job_dz);

wire [L_WIDTH-1:0]   f_job_l = {2'b00, f_job_len};
wire                 f_out_now = (f_left != 0) && (f_left <= f_job_l + 1'b1);

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    f_valid <= 1'b0;
    if (valid) f_nvalid <= f_nvalid + 1'b1;
    if (valid) f_zeta <= f_zeta + f_job_dz_w;
    if (f_left == 0) begin
        if (len_we) f_len <= len_in;
        if (n_we) f_nerr <= nerr_of(n_in);
        if (n_we) f_n <= n_in;
        if (c_we) f_c <= c_in;
        if (dz_we) f_dz <= dz_in;
        if (z0_we) f_z0 <= z0_in;
        if (start) begin
            f_job_c <= f_c;
            f_job_dz <= f_dz;
            f_job_z0 <= f_z0;
            f_job_n <= f_n;
            f_zeta <= $signed(f_z0);
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
        f_c <= {C_W{1'b0}};
        f_dz <= {Z_W{1'b0}};
        f_z0 <= {Z_W{1'b0}};
        f_n <= 10'd0;
    end
end

// The reference's copies of the committed ROM images (the files the unit reads)
localparam A_DEPTH = N_LAST - N_FIRST + 1;
localparam COS_DEPTH = (1 << (TSEL_BITS + ROM_ADDR_BITS));
reg [A_W-1:0]           f_a_image [0:A_DEPTH-1];
reg [ROM_DATA_BITS-1:0] f_cos_image [0:COS_DEPTH-1];
initial begin
    $readmemh(A_ROM_FILE, f_a_image);
    $readmemh(COS_ROM_FILE, f_cos_image);
end

// The expected intensity of the pixel in the valid cycle: pixel f_nvalid of the running line,
// by the contract's formula on the line's operands (formal/specular_unit_datapath.v)
wire                 f_want_nerr;
wire [1:0]           f_want_table;
wire [A_W-1:0]       f_want_a;
wire                 f_want_past_half_pi;
wire [ROM_DATA_BITS-1:0] f_want_word;
wire                 f_want_clamp_matters;
wire [9:0]           f_want_a_index;
wire [31:0]          f_want_cos_index;
wire [31:0]          f_want_cos_index_u;
// ROM 12's word of the pixel of the valid cycle: from the reference's copy of the image, or
// with DATA = 2 the word the unit's ROM returned for it (then intensity_formula also asserts
// that the unit read it at the reference's address)
wire [ROM_DATA_BITS-1:0] f_want_cos_word;
// ROM 9's word of the line: likewise (with DATA = 2 the word the unit read when n was written,
// its address asserted likewise)
wire [A_W-1:0]       f_want_a_word;
wire [MAG_W-1:0]     f_want_mag;
// With DATA = 2 the reference's two products: the property file's own multiplications of the
// unit's operand registers, carried with the pixel to its result (f_o_*: see g_data_helpers),
// the operands asserted equal to the formula's (f_taken_ok, part of intensity_formula)
wire [PROD_W-1:0]    f_o_p;
wire [OP_W-1:0]      f_o_q;
wire                 f_taken_ok;
wire                 f_want_saturated;
wire [OUT_WIDTH-1:0] f_want;
generate
    if (D_EFF != 0) begin : g_ref
        specular_unit_ref #(
            .C_INT_BITS(C_INT_BITS),
            .C_FRAC_BITS(C_FRAC_BITS),
            .Z_INT_BITS(Z_INT_BITS),
            .Z_FRAC_BITS(Z_FRAC_BITS),
            .LEN_WIDTH(LEN_WIDTH),
            .A_INT_BITS(A_INT_BITS),
            .A_FRAC_BITS(A_FRAC_BITS),
            .ROM_ADDR_BITS(ROM_ADDR_BITS),
            .ROM_DATA_BITS(ROM_DATA_BITS),
            .OUT_WIDTH(OUT_WIDTH),
            .NUM_TABLES(NUM_TABLES),
            .N_HI0(N_HI0),
            .N_HI1(N_HI1),
            .N_HI2(N_HI2),
            .MAG_INT_BITS(MAG_INT_BITS),
            .N_FIRST(N_FIRST),
            .N_LAST(N_LAST),
            .EXT_PRODUCTS(D_EFF == 2)
        ) want (
            .c(f_job_c),
            .zeta(f_zeta),
            .n(f_job_n),
            .a_index(f_want_a_index),
            .a_word(f_want_a_word),
            .cos_index(f_want_cos_index),
            .cos_word(f_want_cos_word),
            .cos_index_u(f_want_cos_index_u),
            .cos_word_u(f_cos_image[f_want_cos_index_u]),
            .nerr(f_want_nerr),
            .table_j(f_want_table),
            .a(f_want_a),
            .past_half_pi(f_want_past_half_pi),
            .word(f_want_word),
            .clamp_matters(f_want_clamp_matters),
            .mag(f_want_mag),
            .scaled(),
            .addr(),
            .saturated(f_want_saturated),
            .out(f_want),
            .scaled_in(f_o_p),
            .lit_in({1'b0, f_o_q})
        );
    end
endgenerate

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
            intensity_zero_on_n_err: assert(intensity == 0);
        // every pixel = the contract's formula on the line's operands (C, dz, z0, n held
        // before the start cycle's writes) and its index: the reference specular_unit_ref
        // (DATA = 2: the ROM words and the products the reference took from the unit's reads
        // and operand registers are those of the formula's addresses and operands: f_taken_ok)
        if (D_EFF != 0 && check_on(P_INTENSITY) && valid)
            intensity_formula: assert(intensity == f_want && (D_EFF != 2 || f_taken_ok));
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

generate
    if (D_EFF != 0 && CLAMP != 0 && (CHECK == 0 || CHECK == P_CLAMP)) begin : g_clamp
        // the contract: saturating |zeta| never changes a result (the reference's word with
        // and without it, for the pixel of every valid cycle)
        always @(*) begin
            if (f_past_valid && valid)
                clamp_never_changes_a_result: assert(!f_want_clamp_matters);
        end
    end
endgenerate

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

generate
    if (D_EFF != 0) begin : g_data_covers
        // the data path's events (with DATA): a lit pixel from each of the four tables, a
        // saturated one, one past pi/2, a lit one at a negative angle, one whose |zeta| the
        // unit clamps, a lit third pixel of a line (two additions of dz)
        always @(posedge clk) begin
            if (f_past_valid && rst_n && valid && !n_err) begin
                c_lit_table0: cover(intensity != 0 && f_want_table == 2'd0);
                c_lit_table1: cover(intensity != 0 && f_want_table == 2'd1);
                c_lit_table2: cover(intensity != 0 && f_want_table == 2'd2);
                c_lit_table3: cover(intensity != 0 && f_want_table == 2'd3);
                c_saturated: cover(intensity == OUT_MAX && f_want_saturated);
                c_past_half_pi: cover(intensity == 0 && f_want_past_half_pi && f_job_c != 0);
                c_negative_angle_lit: cover(intensity != 0 && f_zeta < 0);
                c_clamped: cover((f_zeta < 0 ? -f_zeta : f_zeta) >= (1 << MAG_W));
                c_third_pixel_lit: cover(intensity != 0 && f_nvalid == 2 && f_job_dz != 0);
            end
        end
    end
endgenerate

// ---------------------------------------------------------------- induction helpers
// Driven after flatten by the job's script (connect -nounset -set f_int_x \dut.x); see the header.
// (connect -nounset: a plain connect -set would also cut every alias of the wire, such as
// assign w = f_int_x below.)
wire [LEN_WIDTH-1:0]  f_int_len;
wire                  f_int_nerr;
wire                  f_int_nerr_run;
wire                  f_int_busy;
wire [LEN_WIDTH-1:0]  f_int_cnt;
wire [LAST_STAGE:0]   f_int_v;
wire [LAST_STAGE:1]   f_int_last;
wire                  f_int_zero;      // read with ARITH = 1 only
wire [ROM_DATA_BITS-1:0] f_int_rom_d;
wire [OP_W-1:0]       f_int_out_prod;
// read with DATA = 1 only: the operand registers, the line's copies, the pipeline
wire [C_W-1:0]        f_int_c;
wire [Z_W-1:0]        f_int_dz;
wire [Z_W-1:0]        f_int_z0;
wire [A_W-1:0]        f_int_a;
wire [TSEL_BITS-1:0]  f_int_tsel;
wire [C_W-1:0]        f_int_c_run;
wire [Z_W-1:0]        f_int_dz_run;
wire [A_W-1:0]        f_int_a_run;
wire [TSEL_BITS-1:0]  f_int_tsel_run;
wire [ACC_W-1:0]      f_int_acc;
wire [MAG_W-1:0]      f_int_mag_next;
wire [MAG_W-1:0]      f_int_mag;
wire [PROD_W-1:0]     f_int_prod;
wire [RND_W-1:0]      f_int_addr;
wire [ROM_DATA_BITS-1:0] f_int_rom_q;
wire [TSEL_BITS+ROM_ADDR_BITS-1:0] f_int_rom_addr;
localparam A_ADDR_BITS = (A_DEPTH > 512) ? 10 : (A_DEPTH > 256) ? 9 : (A_DEPTH > 128) ? 8
                       : (A_DEPTH > 64) ? 7 : (A_DEPTH > 32) ? 6 : (A_DEPTH > 16) ? 5
                       : (A_DEPTH > 8) ? 4 : (A_DEPTH > 4) ? 3 : (A_DEPTH > 2) ? 2 : 1;
wire [A_ADDR_BITS-1:0] f_int_a_addr;

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

`ifdef SPECULAR_INTERNALS
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

generate
`ifdef SPECULAR_INTERNALS
    if (ARITH != 0) begin : g_data
        // the data path of an invalid n's pixels: the zero gate (S5), the gated word (S6), the
        // product (S7)
        always @(*) begin
            if (f_past_valid && check_on(P_HELPERS) && f_job_nerr && f_left != 0) begin
                if (f_v_want[5]) h_zero_reg: assert(f_int_zero);
                if (f_v_want[6]) h_rom_d_reg: assert(f_int_rom_d == 0);
                if (f_v_want[7]) h_out_prod_reg: assert(f_int_out_prod == 0);
            end
        end
    end
`endif
    if (D_EFF != 0) begin : g_data_helpers
        // The operand registers hold the last write accepted while idle (a and the table as
        // ROM 9 and the decoder give them for a valid n), the line's copies the values of its
        // start, and stage s (0..7) the pixel f_left + s - 8 steps into the line, as the
        // reference computes it: S0 zeta, S1 and S2 |zeta| clamped to MAG_W bits, S3 times a,
        // S4 rounded, S5 the gated word, S6 the word, S7 C times the word.
        wire                 op_nerr;
        wire [1:0]           op_table;
        wire [A_W-1:0]       op_a;
        wire [9:0]           op_a_index;
        wire [A_W-1:0]       op_a_word;  // ROM 9's word of n (DATA = 2: the unit's read)
        if (D_EFF == 2) begin : g_op_unit
            assign op_a_word = f_int_a;
        end else begin : g_op_image
            assign op_a_word = f_a_image[op_a_index];
        end
        specular_unit_ref #(
            .C_INT_BITS(C_INT_BITS), .C_FRAC_BITS(C_FRAC_BITS), .Z_INT_BITS(Z_INT_BITS),
            .Z_FRAC_BITS(Z_FRAC_BITS), .LEN_WIDTH(LEN_WIDTH), .A_INT_BITS(A_INT_BITS),
            .A_FRAC_BITS(A_FRAC_BITS), .ROM_ADDR_BITS(ROM_ADDR_BITS),
            .ROM_DATA_BITS(ROM_DATA_BITS), .OUT_WIDTH(OUT_WIDTH), .NUM_TABLES(NUM_TABLES),
            .N_HI0(N_HI0), .N_HI1(N_HI1), .N_HI2(N_HI2), .MAG_INT_BITS(MAG_INT_BITS),
            .N_FIRST(N_FIRST), .N_LAST(N_LAST)
        ) op_ref (
            .c(f_c), .zeta({ACC_W{1'b0}}), .n(f_n), .a_index(op_a_index),
            .a_word(op_a_word), .cos_index(),
            .cos_word({ROM_DATA_BITS{1'b0}}),
            .cos_index_u(), .cos_word_u({ROM_DATA_BITS{1'b0}}), .nerr(op_nerr),
            .table_j(op_table), .a(op_a),
            .past_half_pi(), .word(), .clamp_matters(),
            .mag(), .scaled(), .addr(), .saturated(), .out(),
            .scaled_in({PROD_W{1'b0}}), .lit_in({(OP_W+1){1'b0}})
        );
        always @(*) begin
            if (f_past_valid && check_on(P_HELPERS)) begin
                // the reference's own n error flags are those of its n
                h_f_nerr: assert(f_nerr == nerr_of(f_n));
                if (f_left != 0) h_f_job_nerr: assert(f_job_nerr == nerr_of(f_job_n));
                h_c_reg: assert(f_int_c == f_c);
                h_dz_reg: assert(f_int_dz == f_dz);
                h_z0_reg: assert(f_int_z0 == f_z0);
                if (!op_nerr) begin
                    h_a_reg: assert(f_int_a == op_a);
                    h_tsel_reg: assert(f_int_tsel == op_table[TSEL_BITS-1:0]);
                end
                if (f_left != 0) begin
                    h_c_run_reg: assert(f_int_c_run == f_job_c);
                    h_dz_run_reg: assert(f_int_dz_run == f_job_dz);
                end
            end
        end
        // zeta of the pixel in each stage, for the helpers: stage 0 starts at z0 and adds dz
        // per clock, each stage takes the one before it
        wire signed [ACC_W-1:0] f_zeta_next = valid ? f_zeta + f_job_dz_w : f_zeta;
        // ROM 12's words: the reference's copy, or with DATA = 2 the unit's reads (rom_q_reg
        // holds the word of the pixel in S5, read at the address f_ra5), delayed with it
        reg [ROM_DATA_BITS-1:0] f_w6;
        reg [ROM_DATA_BITS-1:0] f_w7;
        reg [ROM_DATA_BITS-1:0] f_w8;
        reg [TSEL_BITS+ROM_ADDR_BITS-1:0] f_ra5;
        always @(posedge clk) begin
            f_w6 <= f_int_rom_q;
            f_w7 <= f_w6;
            f_w8 <= f_w7;
            f_ra5 <= f_int_rom_addr;
        end
        genvar g;
        for (g = 0; g <= LAST_STAGE; g = g + 1) begin : g_stage
            // the pixel in stage g (index pix of the line) and its zeta
            wire [L_WIDTH-1:0]       pix = FILL + f_job_l - f_left - g;
            // (one register per stage: stage 0 starts at z0 and adds dz per clock, each other
            // stage takes the one before it)
            reg signed [ACC_W-1:0]   zeta;
            if (g == 0) begin : g_first
                always @(posedge clk) zeta <= (f_left == 0 && start) ? $signed(f_z0)
                                                                     : zeta + f_job_dz_w;
            end else begin : g_next
                always @(posedge clk) zeta <= g_stage[g-1].zeta;
            end
            // DATA = 2: multiplier 11's operands (pm, pa) and product (p) of the pixel in
            // stage g = 3..7: stage 3 takes the unit's operand registers of the cycle before
            // and this file's own product of them, written as the RTL writes it (the same
            // widths and expression on the same registers: after flatten Yosys merges the two
            // $mul cells, so the solver never compares two multipliers); each later stage takes
            // the one before it
            reg [MAG_W-1:0]          pm;
            reg [A_W-1:0]            pa;
            reg [PROD_W-1:0]         p;
            if (D_EFF == 2 && g == 3) begin : g_mul11
                always @(posedge clk) begin
                    pm <= f_int_mag;
                    pa <= f_int_a_run;
                    p <= f_int_mag * f_int_a_run;
                end
            end else if (D_EFF == 2 && g > 3) begin : g_mul11_next
                always @(posedge clk) begin
                    pm <= g_stage[g-1].pm;
                    pa <= g_stage[g-1].pa;
                    p <= g_stage[g-1].p;
                end
            end
            wire [MAG_W-1:0]         mag;
            wire [PROD_W-1:0]        prod;
            wire [PROD_W:0]          rnd;
            wire                     nerr;
            wire [1:0]               table_j;
            wire [A_W-1:0]           a;
            wire [ROM_DATA_BITS-1:0] word;
            wire                     past_half_pi;
            wire [9:0]               a_index;
            wire [31:0]              cos_index;
            wire [ROM_DATA_BITS-1:0] word_in;  // ROM 12's word at cos_index (see f_w)
            wire [A_W-1:0]           a_word;   // ROM 9's word of the line's n
            if (D_EFF == 2 && g >= 5) begin : g_unit
                assign word_in = (g == 5) ? f_int_rom_q
                                          : (g == 6) ? f_w6 : f_w7;
            end else begin : g_image
                assign word_in = f_cos_image[cos_index];
            end
            if (D_EFF == 2) begin : g_a_unit
                assign a_word = f_int_a_run;
            end else begin : g_a_image
                assign a_word = f_a_image[a_index];
            end
            specular_unit_ref #(
                .C_INT_BITS(C_INT_BITS), .C_FRAC_BITS(C_FRAC_BITS), .Z_INT_BITS(Z_INT_BITS),
                .Z_FRAC_BITS(Z_FRAC_BITS), .LEN_WIDTH(LEN_WIDTH), .A_INT_BITS(A_INT_BITS),
                .A_FRAC_BITS(A_FRAC_BITS), .ROM_ADDR_BITS(ROM_ADDR_BITS),
                .ROM_DATA_BITS(ROM_DATA_BITS), .OUT_WIDTH(OUT_WIDTH), .NUM_TABLES(NUM_TABLES),
                .N_HI0(N_HI0), .N_HI1(N_HI1), .N_HI2(N_HI2), .MAG_INT_BITS(MAG_INT_BITS),
                .N_FIRST(N_FIRST), .N_LAST(N_LAST), .EXT_PRODUCTS(D_EFF == 2 && g >= 3)
            ) stage_ref (
                .c(f_job_c), .zeta(zeta), .n(f_job_n), .a_index(a_index),
                .a_word(a_word), .cos_index(cos_index),
                .cos_word(word_in), .cos_index_u(),
                .cos_word_u({ROM_DATA_BITS{1'b0}}), .nerr(nerr), .table_j(table_j), .a(a),
                .past_half_pi(past_half_pi), .word(word), .clamp_matters(), .mag(mag),
                .scaled(prod), .addr(rnd), .saturated(), .out(),
                .scaled_in(p), .lit_in({(OP_W+1){1'b0}})
            );
        end
        // DATA = 2: what the reference takes from the unit, carried to the pixel's result:
        // multiplier 11's operands and product (from stage 7), multiplier 13's (its operand
        // registers c_run_reg and rom_d_reg in stage 6, this file's own product of them as the
        // RTL writes it), the ROM-12 address of the word f_w8 (f_ra5..f_ra8) and ROM 9's
        // address of the line's a (read when n is written while idle, copied at the start,
        // as the unit reads and copies a_reg)
        reg [C_W-1:0]           f_pc7;
        reg [ROM_DATA_BITS-1:0] f_pw7;
        reg [OP_W-1:0]          f_q7;
        reg [MAG_W-1:0]         f_o_pm;
        reg [A_W-1:0]           f_o_pa;
        reg [PROD_W-1:0]        f_o_p_r;
        reg [C_W-1:0]           f_o_pc;
        reg [ROM_DATA_BITS-1:0] f_o_pw;
        reg [OP_W-1:0]          f_o_q_r;
        reg [TSEL_BITS+ROM_ADDR_BITS-1:0] f_ra6;
        reg [TSEL_BITS+ROM_ADDR_BITS-1:0] f_ra7;
        reg [TSEL_BITS+ROM_ADDR_BITS-1:0] f_ra8;
        reg [A_ADDR_BITS-1:0]   f_a_addr_rd;
        reg [A_ADDR_BITS-1:0]   f_a_addr_run;
        if (D_EFF == 2) begin : g_want_unit
            assign f_want_cos_word = f_w8;
            assign f_want_a_word = f_int_a_run;
            always @(posedge clk) begin
                f_o_pm <= g_stage[7].pm;
                f_o_pa <= g_stage[7].pa;
                f_o_p_r <= g_stage[7].p;
                f_pc7 <= f_int_c_run;
                f_pw7 <= f_int_rom_d;
                f_q7 <= f_int_c_run * f_int_rom_d;
                f_o_pc <= f_pc7;
                f_o_pw <= f_pw7;
                f_o_q_r <= f_q7;
                f_ra6 <= f_ra5;
                f_ra7 <= f_ra6;
                f_ra8 <= f_ra7;
                if (!busy && n_we) f_a_addr_rd <= f_int_a_addr;
                if (!busy && start) f_a_addr_run <= f_a_addr_rd;
            end
            assign f_o_p = f_o_p_r;
            assign f_o_q = f_o_q_r;
            // the operands of both products are the formula's (|zeta| saturated and a; C and
            // the gated word), the ROM words were read at the formula's addresses
            assign f_taken_ok = f_o_pm == f_want_mag && f_o_pa == f_want_a
                && f_o_pc == f_job_c && f_o_pw == f_want_word
                && (f_want_nerr || f_want_past_half_pi
                    || f_ra8 == f_want_cos_index[TSEL_BITS+ROM_ADDR_BITS-1:0])
                && (f_want_nerr || f_a_addr_run == f_want_a_index[A_ADDR_BITS-1:0]);
        end else begin : g_want_image
            assign f_want_cos_word = f_cos_image[f_want_cos_index];
            assign f_want_a_word = f_a_image[f_want_a_index];
            // (DATA = 2, where no helper is asserted: a multiplier of other registers)
            always @(*) begin
                if (f_past_valid && check_on(P_HELPERS) && f_left != 0 && !g_stage[0].nerr
                    && f_v_want[7])
                    h_out_prod_word: assert(f_int_out_prod == f_job_c * g_stage[7].word);
            end
        end
        // (hierarchical names: a label inside the loop would repeat per iteration)
        always @(*) begin
            if (f_past_valid && check_on(P_HELPERS) && f_left != 0 && !g_stage[0].nerr) begin
                // the line's a and table, from its start to its last result
                h_a_run_reg: assert(f_int_a_run == g_stage[0].a);
                h_tsel_run_reg: assert(f_int_tsel_run == g_stage[0].table_j[TSEL_BITS-1:0]);
                if (f_v_want[0]) h_acc_reg: assert(f_int_acc == g_stage[0].zeta);
                // before the line's first result f_zeta is z0; the stage of pixel 0 holds z0,
                // neighbouring stages differ by dz, and stage 7's pixel is the next result's
                if (f_left > f_job_l) h_zeta_fill: assert(f_zeta == $signed(f_job_z0));
                if (f_v_want[7])
                    h_zs_out: assert(g_stage[7].zeta == f_zeta_next);
                if (f_v_want[0] && g_stage[0].pix == 0)
                    h_zs_first_0: assert(g_stage[0].zeta == $signed(f_job_z0));
                if (f_v_want[1] && g_stage[1].pix == 0)
                    h_zs_first_1: assert(g_stage[1].zeta == $signed(f_job_z0));
                if (f_v_want[2] && g_stage[2].pix == 0)
                    h_zs_first_2: assert(g_stage[2].zeta == $signed(f_job_z0));
                if (f_v_want[3] && g_stage[3].pix == 0)
                    h_zs_first_3: assert(g_stage[3].zeta == $signed(f_job_z0));
                if (f_v_want[4] && g_stage[4].pix == 0)
                    h_zs_first_4: assert(g_stage[4].zeta == $signed(f_job_z0));
                if (f_v_want[5] && g_stage[5].pix == 0)
                    h_zs_first_5: assert(g_stage[5].zeta == $signed(f_job_z0));
                if (f_v_want[6] && g_stage[6].pix == 0)
                    h_zs_first_6: assert(g_stage[6].zeta == $signed(f_job_z0));
                if (f_v_want[7] && g_stage[7].pix == 0)
                    h_zs_first_7: assert(g_stage[7].zeta == $signed(f_job_z0));
                if (f_v_want[0] && f_v_want[1])
                    h_zs_step_0: assert(g_stage[0].zeta == g_stage[1].zeta + f_job_dz_w);
                if (f_v_want[1] && f_v_want[2])
                    h_zs_step_1: assert(g_stage[1].zeta == g_stage[2].zeta + f_job_dz_w);
                if (f_v_want[2] && f_v_want[3])
                    h_zs_step_2: assert(g_stage[2].zeta == g_stage[3].zeta + f_job_dz_w);
                if (f_v_want[3] && f_v_want[4])
                    h_zs_step_3: assert(g_stage[3].zeta == g_stage[4].zeta + f_job_dz_w);
                if (f_v_want[4] && f_v_want[5])
                    h_zs_step_4: assert(g_stage[4].zeta == g_stage[5].zeta + f_job_dz_w);
                if (f_v_want[5] && f_v_want[6])
                    h_zs_step_5: assert(g_stage[5].zeta == g_stage[6].zeta + f_job_dz_w);
                if (f_v_want[6] && f_v_want[7])
                    h_zs_step_6: assert(g_stage[6].zeta == g_stage[7].zeta + f_job_dz_w);
                if (f_v_want[1]) h_mag_next: assert(f_int_mag_next == g_stage[1].mag);
                if (f_v_want[2]) h_mag_reg: assert(f_int_mag == g_stage[2].mag);
                if (f_v_want[3]) h_prod_reg: assert(f_int_prod == g_stage[3].prod);
                if (f_v_want[4]) h_addr_reg: assert(f_int_addr == g_stage[4].rnd[RND_W-1:0]);
                if (f_v_want[5])
                    h_rom_q_reg: assert((f_int_zero ? 0 : f_int_rom_q) == g_stage[5].word);
                if (f_v_want[6]) h_rom_d_word: assert(f_int_rom_d == g_stage[6].word);
            end
        end
    end
endgenerate

endmodule
