// SPDX-License-Identifier: Apache-2.0
/*
 * BRDF unit of the thesis's family (docs/brdf.md, docs/brdf_unit.md): I = C * F_n(|zeta|) per
 * pixel along a scan line, zeta(0) = z0, zeta(i) = zeta(i-1) + dz, for the l + 1 pixels of a
 * line of l intervals, F one of the thesis's approximations of cos^n chosen by FORM
 * ("cosine_quadratic": (1 - (7n/16)(1 - cos))^2, "quadratic": a cos^2 + (1 - a) cos, "cubic":
 * c P(c), P a cubic about the match point in tau = 1 - r w, "piecewise": the cubic where
 * tau > 0, the bloom part c / (alpha - beta c) beyond, "log2": 2^(n log2 cos) as
 * 1 - log2(1 + n (-log2 cos)) / 2).  Every result equals model.units.brdf.unit_line() bit for
 * bit.
 *
 * Formats (model/units/brdf/, FixedConfig and its angle SpecularConfig):
 *   c_in   unsigned Q(C_INT_BITS).(C_FRAC_BITS), output LSBs
 *   dz_in, z0_in  signed Q(Z_INT_BITS).(Z_FRAC_BITS), units of pi/2
 *   n_in   10 bits, 1..1000; any other n gives intensity 0 and n_err = 1 on every pixel
 *   len_in l, the number of intervals: l + 1 pixels (l = 0: one pixel)
 *   intensity  unsigned OUT_WIDTH bits, saturated
 *
 * Blocks: the patent specular unit's front (rtl/specular_unit.v: operand registers, the
 * interval counter, the accumulator of ACC_WIDTH bits, which never wraps, and the control),
 * |zeta|, the angle-table address (|zeta| rounded to COS_ADDR_BITS fraction bits of pi/2, add
 * half, slice; an address of 2^COS_ADDR_BITS or more is pi/2 or beyond and reads as
 * w = 2^COS_DATA_BITS, cos = 0), the angle table (w = 1 - cos, synchronous read; the log2
 * form's holds -log2 cos), for the quadratic, cubic and piecewise forms the coefficient table
 * (a, r p0 b1 b2, or r p0 b1 b2 s2 beta, per n, read when n is written, like ROM 9), for the
 * log2 form its second table
 * (log2(1 + f), read in its pipeline), the form's datapath (rtl/brdf_<form>.v: the output word
 * F in OUT_BITS fraction bits), then C * F rounded to the output LSB and saturated (as
 * multiplier 13 is).
 *
 * Pipeline (one pixel per clock, 7 + FORM_LATENCY stages): S0 accumulator, S1 |zeta| without
 * its carry (sign, one's complement, "too big" flag), S2 |zeta| saturated below 2 (pi: every
 * clamped value still reads pi/2 or more), S3 the rounded address, S4 the angle-table read and
 * the overflow flag, S5 w (the overflow gate on the registered table word; S1..S5 are
 * rtl/brdf_front.v), then the form's
 * stages (5 for the cosine-quadratic, 6 for the quadratic, 7 for the log2, 13 for the cubic:
 * each wide product in two, rtl/brdf_mul.v; the piecewise form's max(14, OUT_BITS + 8), one
 * stage per quotient bit of its divider), then C * F (F gated to 0 for an n outside 1..1000)
 * and rounding + saturation -> output.  After the edge that accepts start, busy is high for F + l cycles and
 * valid is high in cycles F .. F + l, F = 7 + FORM_LATENCY (the last one together with busy =
 * 0, when a new start is already accepted): model.units.brdf.cycles and valid_offsets.
 *
 * Reset (RESET_ALL): rst_n always resets the control state, the flags and the operand
 * registers; RESET_ALL = 1 also resets the data path.  The table read registers are never
 * reset (they must map onto block RAM); see "Tables" at the end for why none needs it.
 * ROM images: ANGLE_ROM_FILE, COEF_ROM_FILE and LOG_ROM_FILE default to files in `SHADING_ROM_DIR ("rom"
 * unless defined on the command line); the Python flows pass absolute paths instead.
 *
 * Protocol (docs/architecture.md, "The protocol every unit follows"): operands are sampled
 * with their write strobes while busy = 0; a start accepted in the same cycle as a write runs
 * on the values held before it (the run copies the registers at the start edge).  rst_n is
 * synchronous and aborts a line.
 *
 * Checks: a parameter set model.units.brdf refuses (FixedConfig, and check_unit: the
 * quadratic's, the cubic's and the piecewise form's coefficient width, the cubic's and the
 * piecewise form's product widths) is refused at elaboration (an instance of a module that does
 * not exist, named after the rule, e.g. brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_4_to_32).
 * In simulation every table image is checked at time 0 by the ROM module (rtl/shading_rom.v):
 * a missing, short, malformed or wrong-configuration file ends the run with a message and a
 * non-zero exit status.
 *
 * Sources: this file, rtl/brdf_front.v (S1..S5, shared with the shading core's BRDF
 * highlight path), rtl/brdf_cosine_quadratic.v, rtl/brdf_quadratic.v, rtl/brdf_cubic.v,
 * rtl/brdf_log2.v, rtl/brdf_piecewise.v, rtl/brdf_div.v, rtl/brdf_delay.v, rtl/brdf_mul.v,
 * rtl/brdf_round.v and rtl/shading_rom.v (rtl/brdf_unit.f lists them).
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

// Folder of the ROM images for the default ROM file parameters: the Python flows pass absolute
// paths as parameters; to compile without them define it, e.g.
// iverilog -DSHADING_ROM_DIR=\"/abs/path/rtl/rom\" (the default "rom" is relative to the
// folder the tool runs in)
`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module brdf_unit #(
    // The form: "cosine_quadratic", "quadratic", "cubic", "log2" or "piecewise"
    parameter [8*16-1:0] FORM = "cosine_quadratic",
    // C register integer bits (output LSBs), 1..16
    parameter C_INT_BITS = 8,
    // C register fraction bits, 0..16
    parameter C_FRAC_BITS = 8,
    // dz, z0 integer bits including the sign (units of pi/2), 3..8
    parameter Z_INT_BITS = 3,
    // dz, z0 and accumulator fraction bits, 2..40 (at least COS_ADDR_BITS)
    parameter Z_FRAC_BITS = 26,
    // Interval counter width: l = 0 .. 2^LEN_WIDTH - 1, 1..16
    parameter LEN_WIDTH = 11,
    // Output intensity bits, 1..16
    parameter OUT_WIDTH = 8,
    // Angle-table address bits A (fraction bits of |zeta|, units of pi/2), 2..min(16, Z_FRAC_BITS)
    parameter COS_ADDR_BITS = 12,
    // Angle-table word bits D (w = 1 - cos, D fraction bits; the log2 form: -log2 cos, D - 2), 4..24
    parameter COS_DATA_BITS = 20,
    // Coefficient word bits, 4..32 (the quadratic form: 10..32, a up to 786.44 needs 10; the
    // cubic: 11..32, r up to 1443.2 needs 11, and at most 56 - WORK_BITS; the piecewise: 11..21,
    // three coefficients a ROM word of at most 64 bits)
    parameter COEF_BITS = 18,
    // Fraction bits P of the form's intermediate values, 4..28 (the cubic and piecewise: 4..25)
    parameter WORK_BITS = 24,
    // Fraction bits O of the form's output word, 1..24
    parameter OUT_BITS = 16,
    // The log2 form's second table: address bits E (f in [0, 1) rounded to E bits), 2..16
    parameter LOG_ADDR_BITS = 10,
    // The log2 form's second table: word bits L (log2(1 + f), L fraction bits), 4..24
    parameter LOG_DATA_BITS = 16,
    // $readmemh image of the angle table (w = 1 - cos), by model.units.brdf (make roms)
    parameter ANGLE_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_w_a12_d20.hex"},
    // $readmemh image of the coefficient table (quadratic, cubic, piecewise), by model.units.brdf
    parameter COEF_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_quadratic_coef_c18_q10.8.hex"},
    // $readmemh image of the log2 form's second table (log2(1 + f)), by model.units.brdf
    parameter LOG_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_log2_a10_d16.hex"},
    // 0: rst_n resets the control state and the operand registers only; 1: also every
    // data-path register (the table read registers never: they must map onto block RAM)
    parameter RESET_ALL = 0
) (
    input  wire                              clk,
    input  wire                              rst_n,

    input  wire [C_INT_BITS+C_FRAC_BITS-1:0] c_in,
    input  wire                              c_we,
    input  wire [Z_INT_BITS+Z_FRAC_BITS-1:0] dz_in,
    input  wire                              dz_we,
    input  wire [Z_INT_BITS+Z_FRAC_BITS-1:0] z0_in,
    input  wire                              z0_we,
    input  wire [9:0]                        n_in,
    input  wire                              n_we,
    input  wire [LEN_WIDTH-1:0]              len_in,
    input  wire                              len_we,
    input  wire                              start,

    output wire                              busy,
    output wire                              valid,
    output wire [OUT_WIDTH-1:0]              intensity,
    output wire                              n_err
);

localparam N_WIDTH = 10;
localparam [N_WIDTH-1:0] N_MAX = 10'd1000;
localparam C_WIDTH = C_INT_BITS + C_FRAC_BITS;
localparam Z_WIDTH = Z_INT_BITS + Z_FRAC_BITS;
localparam ACC_WIDTH = Z_WIDTH + LEN_WIDTH;
localparam OP_WIDTH = C_WIDTH + OUT_BITS;
localparam OSHIFT = C_FRAC_BITS + OUT_BITS;
// Rounded output before saturation: C_INT_BITS + 1 bits (C * 1.0 rounds up to 2^C_INT_BITS)
localparam OFULL_WIDTH = OP_WIDTH - OSHIFT + 1;

// ---------------------------------------------------------------- parameter check
// Exactly the sets model.units.brdf refuses (FixedConfig with its angle SpecularConfig at its
// defaults but for the six fields above, and check_unit).  Verilog-2005 has no
// elaboration-time $error: a failing rule instantiates a module that does not exist, named
// after the rule, and every tool stops with an error naming it.  62 is the model's
// fixed.MAX_KERNEL_WIDTH: the cubic's products (FixedConfig.product_widths) reach it,
// tau x (b1 + b2 tau) at 2 (WORK_BITS + 5) + 2 bits and b2 x tau at COEF_BITS + WORK_BITS + 6,
// and so do the piecewise form's (the cubic's; its beta x (r w - 1), COEF_BITS + WORK_BITS + 13
// bits, stays within 62 for COEF_BITS <= 21 and WORK_BITS <= 25); no product of the other
// forms comes near it.
localparam [8*16-1:0] FORM_COSINE_QUADRATIC = "cosine_quadratic";
localparam [8*16-1:0] FORM_QUADRATIC = "quadratic";
localparam [8*16-1:0] FORM_CUBIC = "cubic";
localparam [8*16-1:0] FORM_PIECEWISE = "piecewise";
localparam [8*16-1:0] FORM_LOG2 = "log2";
localparam IS_COSINE_QUADRATIC = (FORM == FORM_COSINE_QUADRATIC);
localparam IS_QUADRATIC = (FORM == FORM_QUADRATIC);
localparam IS_CUBIC = (FORM == FORM_CUBIC);
localparam IS_LOG2 = (FORM == FORM_LOG2);
localparam IS_PIECEWISE = (FORM == FORM_PIECEWISE);
localparam FORM_KNOWN = IS_COSINE_QUADRATIC || IS_QUADRATIC || IS_CUBIC || IS_PIECEWISE
                        || IS_LOG2;
// The quadratic's a (786.44 at n = 1000) needs 10 integer bits (model QUADRATIC_A_INT_BITS;
// the coefficient image's COEF_FRAC_BITS field carries the model's value)
localparam QUADRATIC_A_INT_BITS = 10;
// The cubic's r (1443.2 at n = 1000) needs 11 integer bits (model CUBIC_R_INT_BITS; its p0 is
// Q1, b1 and b2 Q0: the image's fraction-bit fields carry the model's values); the piecewise
// form's too, and its three coefficients a ROM word fit 64 bits up to 21 bits each (model
// PIECEWISE_COEF_BITS_MAX; its s2 and beta are Q1)
localparam CUBIC_R_INT_BITS = 11;
localparam PIECEWISE_COEF_BITS_MAX = 21;

localparam BAD_FORM = !FORM_KNOWN;
localparam BAD_C_INT_BITS = (C_INT_BITS < 1 || C_INT_BITS > 16);
localparam BAD_C_FRAC_BITS = (C_FRAC_BITS < 0 || C_FRAC_BITS > 16);
localparam BAD_Z_INT_BITS = (Z_INT_BITS < 3 || Z_INT_BITS > 8);
localparam BAD_Z_FRAC_BITS = (Z_FRAC_BITS < 1 || Z_FRAC_BITS > 40);
localparam BAD_LEN_WIDTH = (LEN_WIDTH < 1 || LEN_WIDTH > 16);
localparam BAD_OUT_WIDTH = (OUT_WIDTH < 1 || OUT_WIDTH > 16);
localparam BAD_COS_ADDR_BITS = (COS_ADDR_BITS < 2 || COS_ADDR_BITS > 16
                                || COS_ADDR_BITS > Z_FRAC_BITS);
localparam BAD_COS_DATA_BITS = (COS_DATA_BITS < 4 || COS_DATA_BITS > 24);
localparam BAD_COEF_BITS = (COEF_BITS < 4 || COEF_BITS > 32);
localparam BAD_COEF_BITS_QUADRATIC = !BAD_COEF_BITS && IS_QUADRATIC
                                     && COEF_BITS < QUADRATIC_A_INT_BITS;
localparam BAD_COEF_BITS_CUBIC = !BAD_COEF_BITS && IS_CUBIC && COEF_BITS < CUBIC_R_INT_BITS;
localparam BAD_COEF_BITS_PIECEWISE = !BAD_COEF_BITS && IS_PIECEWISE
                                     && (COEF_BITS < CUBIC_R_INT_BITS
                                         || COEF_BITS > PIECEWISE_COEF_BITS_MAX);
localparam BAD_WORK_BITS = (WORK_BITS < 4 || WORK_BITS > 28);
// The cubic's tau x (b1 + b2 tau), 2 (P + 5) + 2 bits, and b2 x tau, C + P + 6 bits, within 62
// (the piecewise form's too: it has the cubic's products)
localparam BAD_WORK_BITS_CUBIC = !BAD_WORK_BITS && IS_CUBIC && WORK_BITS > 25;
localparam BAD_WORK_BITS_PIECEWISE = !BAD_WORK_BITS && IS_PIECEWISE && WORK_BITS > 25;
localparam BAD_COEF_WORK_CUBIC = !BAD_COEF_BITS && !BAD_WORK_BITS && !BAD_WORK_BITS_CUBIC
                                 && IS_CUBIC && COEF_BITS + WORK_BITS > 56;
localparam BAD_OUT_BITS = (OUT_BITS < 1 || OUT_BITS > 24);
// The log2 table's widths are checked for every form, as the model's FixedConfig checks them
localparam BAD_LOG_ADDR_BITS = (LOG_ADDR_BITS < 2 || LOG_ADDR_BITS > 16);
localparam BAD_LOG_DATA_BITS = (LOG_DATA_BITS < 4 || LOG_DATA_BITS > 24);

generate
    if (BAD_FORM) begin : g_check_form
        brdf_unit_PARAMETER_ERROR_FORM_must_be_a_form_of_the_family u_error ();
    end
    if (BAD_C_INT_BITS) begin : g_check_c_int_bits
        brdf_unit_PARAMETER_ERROR_C_INT_BITS_must_be_1_to_16 u_error ();
    end
    if (BAD_C_FRAC_BITS) begin : g_check_c_frac_bits
        brdf_unit_PARAMETER_ERROR_C_FRAC_BITS_must_be_0_to_16 u_error ();
    end
    if (BAD_Z_INT_BITS) begin : g_check_z_int_bits
        brdf_unit_PARAMETER_ERROR_Z_INT_BITS_must_be_3_to_8 u_error ();
    end
    if (BAD_Z_FRAC_BITS) begin : g_check_z_frac_bits
        brdf_unit_PARAMETER_ERROR_Z_FRAC_BITS_must_be_1_to_40 u_error ();
    end
    if (BAD_LEN_WIDTH) begin : g_check_len_width
        brdf_unit_PARAMETER_ERROR_LEN_WIDTH_must_be_1_to_16 u_error ();
    end
    if (BAD_OUT_WIDTH) begin : g_check_out_width
        brdf_unit_PARAMETER_ERROR_OUT_WIDTH_must_be_1_to_16 u_error ();
    end
    if (ACC_WIDTH > 62) begin : g_check_acc_width
        brdf_unit_PARAMETER_ERROR_Z_INT_BITS_plus_Z_FRAC_BITS_plus_LEN_WIDTH_above_62 u_error ();
    end
    if (BAD_COS_ADDR_BITS) begin : g_check_cos_addr_bits
        brdf_unit_PARAMETER_ERROR_COS_ADDR_BITS_must_be_2_to_16_and_at_most_Z_FRAC_BITS
            u_error ();
    end
    if (BAD_COS_DATA_BITS) begin : g_check_cos_data_bits
        brdf_unit_PARAMETER_ERROR_COS_DATA_BITS_must_be_4_to_24 u_error ();
    end
    if (BAD_COEF_BITS) begin : g_check_coef_bits
        brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_4_to_32 u_error ();
    end
    if (BAD_COEF_BITS_QUADRATIC) begin : g_check_coef_bits_quadratic
        brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_10_to_32_for_the_quadratic_form u_error ();
    end
    if (BAD_COEF_BITS_CUBIC) begin : g_check_coef_bits_cubic
        brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_11_to_32_for_the_cubic_form u_error ();
    end
    if (BAD_COEF_BITS_PIECEWISE) begin : g_check_coef_bits_piecewise
        brdf_unit_PARAMETER_ERROR_COEF_BITS_must_be_11_to_21_for_the_piecewise_form u_error ();
    end
    if (BAD_WORK_BITS) begin : g_check_work_bits
        brdf_unit_PARAMETER_ERROR_WORK_BITS_must_be_4_to_28 u_error ();
    end
    if (BAD_WORK_BITS_CUBIC) begin : g_check_work_bits_cubic
        brdf_unit_PARAMETER_ERROR_WORK_BITS_must_be_4_to_25_for_the_cubic_form u_error ();
    end
    if (BAD_WORK_BITS_PIECEWISE) begin : g_check_work_bits_piecewise
        brdf_unit_PARAMETER_ERROR_WORK_BITS_must_be_4_to_25_for_the_piecewise_form u_error ();
    end
    if (BAD_COEF_WORK_CUBIC) begin : g_check_coef_work_cubic
        brdf_unit_PARAMETER_ERROR_COEF_BITS_plus_WORK_BITS_above_56_for_the_cubic_form
            u_error ();
    end
    if (BAD_OUT_BITS) begin : g_check_out_bits
        brdf_unit_PARAMETER_ERROR_OUT_BITS_must_be_1_to_24 u_error ();
    end
    if (BAD_LOG_ADDR_BITS) begin : g_check_log_addr_bits
        brdf_unit_PARAMETER_ERROR_LOG_ADDR_BITS_must_be_2_to_16 u_error ();
    end
    if (BAD_LOG_DATA_BITS) begin : g_check_log_data_bits
        brdf_unit_PARAMETER_ERROR_LOG_DATA_BITS_must_be_4_to_24 u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        brdf_unit_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
endgenerate

// What the form reads of n (register 4's form part): the quadratic's coefficient word a, the
// cubic's four {r, p0, b1, b2}, the piecewise form's six {r, p0, b1, b2, s2, beta}, the log2's
// n itself (10 bits), the cosine-quadratic's 7n (13 bits: n up to 1023)
localparam K_WIDTH = IS_QUADRATIC ? COEF_BITS : IS_CUBIC ? 4 * COEF_BITS
                   : IS_PIECEWISE ? 6 * COEF_BITS : IS_LOG2 ? N_WIDTH : 13;
// The form's pipeline stages (model.units.brdf.form_latency: the piecewise form's divider
// takes one stage per quotient bit, OUT_BITS + 1 of them, rtl/brdf_piecewise.v)
localparam PIECEWISE_LATENCY = (OUT_BITS + 8 > 14) ? OUT_BITS + 8 : 14;
localparam FORM_LATENCY = IS_QUADRATIC ? 6 : IS_CUBIC ? 13 : IS_LOG2 ? 7
                        : IS_PIECEWISE ? PIECEWISE_LATENCY : 5;
localparam LAST_STAGE = 6 + FORM_LATENCY;

// ---------------------------------------------------------------- operand registers
// No register has an initial value.  rst_n (synchronous, active low) sets the control state
// (busy, valid, the counter, the stage valid and last-pixel flags), the flags (n_err and the
// run's n error) and the operand registers; the data path (the run copies, the accumulator
// and every pipeline register) is loaded by each start and by the stage before it, so it is
// read only once defined; RESET_ALL = 1 resets it too.  The coefficient table's read register
// is never reset: see "Tables" at the end.
reg [C_WIDTH-1:0]   c_reg;
reg [Z_WIDTH-1:0]   dz_reg;
reg [Z_WIDTH-1:0]   z0_reg;
// Register 4 holds n as what the unit uses of it: the form's word (k_word) and the error flag
wire [K_WIDTH-1:0]  k_word;
reg                 nerr_reg;
reg [LEN_WIDTH-1:0] len_reg;

// n = 1..1000 is the unit's; the coefficient table's address is n - 1 (0 for any other n:
// the gate before x C discards its word)
wire n_ok = (n_in != {N_WIDTH{1'b0}}) && (n_in <= N_MAX);
wire [N_WIDTH-1:0] n_addr = n_ok ? n_in - {{(N_WIDTH-1){1'b0}}, 1'b1} : {N_WIDTH{1'b0}};

// Copies taken at the start edge: the line runs on them
reg [C_WIDTH-1:0]   c_run_reg;
reg [Z_WIDTH-1:0]   dz_run_reg;
reg [K_WIDTH-1:0]   k_run_reg;
reg                 nerr_run_reg;

// ---------------------------------------------------------------- pipeline
// S0 acc_reg, S1..S5 the front (rtl/brdf_front.v: |zeta| in two steps, the rounded address,
// the angle table's read, w on w_reg), S6..S9 the form (its y on form_y), S10 out_prod_reg
// (C * F), S11 intensity_reg (the stage numbers of the cosine-quadratic: each form's own
// stages come between S5 and C * F).  v_reg[s] marks a pixel in stage s.
reg [LEN_WIDTH-1:0]     cnt_reg;
reg [ACC_WIDTH-1:0]     acc_reg;
wire [COS_DATA_BITS:0]  w_reg;
wire [OUT_BITS-1:0]     form_y;
reg [OP_WIDTH-1:0]      out_prod_reg;
// Stage valid and last-pixel flags
reg [LAST_STAGE:0]      v_reg;
reg [LAST_STAGE:1]      last_reg;

// Control and outputs
reg                     busy_reg;
reg                     valid_reg;
reg [OUT_WIDTH-1:0]     intensity_reg;
reg                     n_err_reg;

assign busy = busy_reg;
assign valid = valid_reg;
assign intensity = intensity_reg;
assign n_err = n_err_reg;

// S0 -> S5: the front, from the accumulator to w (the table word, or 2^COS_DATA_BITS from
// pi/2 on); its angle table holds w = 1 - cos, or -log2 cos for the log2 form (TABLE = 1)
brdf_front #(
    .ACC_WIDTH(ACC_WIDTH),
    .Z_FRAC_BITS(Z_FRAC_BITS),
    .COS_ADDR_BITS(COS_ADDR_BITS),
    .COS_DATA_BITS(COS_DATA_BITS),
    .TABLE(IS_LOG2 ? 1 : 0),
    .ANGLE_ROM_FILE(ANGLE_ROM_FILE),
    .RESET_ALL(RESET_ALL)
) u_front (
    .clk(clk),
    .rst_n(rst_n),
    .acc(acc_reg),
    .w(w_reg)
);

// S9 -> S10: F, or 0 for an n outside 1..1000 (a mux, not a multiply by 0: an undefined
// coefficient word of a never written n cannot reach a result)
wire [OUT_BITS-1:0]  form_gated = nerr_run_reg ? {OUT_BITS{1'b0}} : form_y;

// S10 -> S11: round C * F to OUT_WIDTH bits, saturate
wire [OP_WIDTH:0]    out_rnd = {1'b0, out_prod_reg} + ({{OP_WIDTH{1'b0}}, 1'b1} << (OSHIFT - 1));
wire [OFULL_WIDTH-1:0] out_full = out_rnd[OP_WIDTH:OSHIFT];
wire [OUT_WIDTH-1:0] out_sat;

generate
    if (OFULL_WIDTH > OUT_WIDTH) begin : g_sat
        assign out_sat = (|out_full[OFULL_WIDTH-1:OUT_WIDTH]) ? {OUT_WIDTH{1'b1}}
                                                              : out_full[OUT_WIDTH-1:0];
    end else if (OFULL_WIDTH == OUT_WIDTH) begin : g_fit
        assign out_sat = out_full;
    end else begin : g_pad
        assign out_sat = {{(OUT_WIDTH-OFULL_WIDTH){1'b0}}, out_full};
    end
endgenerate

// Bits the output rounding drops on purpose (below the output LSB), and n - 1's bits a form
// without a coefficient table does not use
// verilator lint_off UNUSEDSIGNAL
wire unused_bits = &{1'b0, out_rnd[OSHIFT-1:0], n_addr};
// verilator lint_on UNUSEDSIGNAL

wire start_ok = start && !busy_reg;
wire last0 = (cnt_reg == {LEN_WIDTH{1'b0}});

// Control state and operand registers (reset by rst_n whatever RESET_ALL)
always @(posedge clk) begin
    valid_reg <= 1'b0;

    // Operand registers: written only while the unit is idle
    if (!busy_reg) begin
        if (c_we) begin
            c_reg <= c_in;
        end
        if (dz_we) begin
            dz_reg <= dz_in;
        end
        if (z0_we) begin
            z0_reg <= z0_in;
        end
        if (n_we) begin
            nerr_reg <= !n_ok;
        end
        if (len_we) begin
            len_reg <= len_in;
        end
    end

    // Control, stage S0: the interval counter and the pixel flags
    if (start_ok) begin
        busy_reg <= 1'b1;
        nerr_run_reg <= nerr_reg;
        cnt_reg <= len_reg;
        v_reg[0] <= 1'b1;
    end else if (v_reg[0]) begin
        if (last0) begin
            v_reg[0] <= 1'b0;  // the counter's borrow: the line's last pixel has been issued
        end else begin
            cnt_reg <= cnt_reg - {{(LEN_WIDTH-1){1'b0}}, 1'b1};
        end
    end
    v_reg[LAST_STAGE:1] <= v_reg[LAST_STAGE-1:0];
    last_reg <= {last_reg[LAST_STAGE-1:1], v_reg[0] && last0};

    // Stage S11: the result
    if (v_reg[LAST_STAGE]) begin
        valid_reg <= 1'b1;
        n_err_reg <= nerr_run_reg;
        if (last_reg[LAST_STAGE]) begin
            busy_reg <= 1'b0;
        end
    end

    if (!rst_n) begin
        c_reg <= {C_WIDTH{1'b0}};
        dz_reg <= {Z_WIDTH{1'b0}};
        z0_reg <= {Z_WIDTH{1'b0}};
        nerr_reg <= 1'b1;
        len_reg <= {LEN_WIDTH{1'b0}};
        nerr_run_reg <= 1'b0;
        cnt_reg <= {LEN_WIDTH{1'b0}};
        v_reg <= {(LAST_STAGE+1){1'b0}};
        last_reg <= {LAST_STAGE{1'b0}};
        busy_reg <= 1'b0;
        valid_reg <= 1'b0;
        n_err_reg <= 1'b0;
    end
end

// Data path: reset by rst_n only when RESET_ALL = 1.  Every register here is written before a
// result depends on it (the run copies at the start edge, each stage from the one before), so
// without the reset no X or stale value reaches a result after reset.
always @(posedge clk) begin
    // The accumulator: z0 for the first pixel, acc + dz after
    if (start_ok) begin
        c_run_reg <= c_reg;
        dz_run_reg <= dz_reg;
        k_run_reg <= k_word;
        acc_reg <= {{LEN_WIDTH{z0_reg[Z_WIDTH-1]}}, z0_reg};
    end else if (v_reg[0] && !last0) begin
        acc_reg <= acc_reg + {{LEN_WIDTH{dz_run_reg[Z_WIDTH-1]}}, dz_run_reg};
    end

    // Stage S10
    out_prod_reg <= c_run_reg * form_gated;

    // Stage S11: the result
    if (v_reg[LAST_STAGE]) begin
        intensity_reg <= out_sat;
    end

    if (RESET_ALL != 0 && !rst_n) begin
        c_run_reg <= {C_WIDTH{1'b0}};
        dz_run_reg <= {Z_WIDTH{1'b0}};
        k_run_reg <= {K_WIDTH{1'b0}};
        acc_reg <= {ACC_WIDTH{1'b0}};
        out_prod_reg <= {OP_WIDTH{1'b0}};
        intensity_reg <= {OUT_WIDTH{1'b0}};
    end
end

// ---------------------------------------------------------------- the form
generate
    if (IS_QUADRATIC) begin : g_quadratic
        brdf_quadratic #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .COEF_BITS(COEF_BITS),
            .COEF_FRAC_BITS(COEF_BITS - QUADRATIC_A_INT_BITS),
            .RESET_ALL(RESET_ALL)
        ) u_form (
            .clk(clk),
            .rst_n(rst_n),
            .w(w_reg),
            .k(k_run_reg),
            .y(form_y)
        );
    end else if (IS_CUBIC) begin : g_cubic
        // The product r w, which the piecewise form shares, is not read here
        // verilator lint_off UNUSEDSIGNAL
        wire [COEF_BITS+COS_DATA_BITS:0] rw_unused;
        // verilator lint_on UNUSEDSIGNAL

        brdf_cubic #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .COEF_BITS(COEF_BITS),
            .RESET_ALL(RESET_ALL)
        ) u_form (
            .clk(clk),
            .rst_n(rst_n),
            .w(w_reg),
            .k(k_run_reg),
            .y(form_y),
            .rw_prod(rw_unused)
        );
    end else if (IS_PIECEWISE) begin : g_piecewise
        brdf_piecewise #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .COEF_BITS(COEF_BITS),
            .RESET_ALL(RESET_ALL)
        ) u_form (
            .clk(clk),
            .rst_n(rst_n),
            .w(w_reg),
            .k(k_run_reg),
            .y(form_y)
        );
    end else if (IS_LOG2) begin : g_log2
        // The datapath and its second table (the log2 device of fig. 9b): log2(1 + f) for
        // f = j 2^-LOG_ADDR_BITS, read every cycle at the address of the pixel in the form's
        // third stage; its word registered twice (READ_REGS = 2: the block RAM's register,
        // then one in the fabric, the form's fourth and fifth stages), so that the form's
        // subtraction does not follow the block RAM's slow output in the same clock (in one:
        // 94.7 MHz on the ECP5-25F); see "Tables" below
        wire [LOG_ADDR_BITS-1:0] log_addr;
        wire [LOG_DATA_BITS-1:0] log_q;
        // verilator lint_off UNUSEDSIGNAL
        wire [LOG_DATA_BITS-1:0] log_unused_b;  // one read port
        // verilator lint_on UNUSEDSIGNAL

        brdf_log2 #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .LOG_ADDR_BITS(LOG_ADDR_BITS),
            .LOG_DATA_BITS(LOG_DATA_BITS),
            .OUT_BITS(OUT_BITS),
            .RESET_ALL(RESET_ALL)
        ) u_form (
            .clk(clk),
            .rst_n(rst_n),
            .w(w_reg),
            .k(k_run_reg),
            .log_addr(log_addr),
            .log_q(log_q),
            .y(form_y)
        );

        shading_rom #(
            .WIDTH(LOG_DATA_BITS),
            .DEPTH(2 ** LOG_ADDR_BITS),
            .ADDR_BITS(LOG_ADDR_BITS),
            .PORTS(1),
            .READ_REGS(2),
            .BANK_BITS(LOG_ADDR_BITS),  // one bank
            .FILE(LOG_ROM_FILE),
            .NAME("LOG_ROM_FILE"),
            .MAGIC("BRDL"),
            .NUM_FIELDS(2),
            .FIELD_0(LOG_ADDR_BITS), .FIELD_1(LOG_DATA_BITS),
            .FIELD_NAMES({"LOG_ADDR_BITS   ", "LOG_DATA_BITS   ", {(8*16*10){1'b0}}})
        ) u_log_rom (
            .clk(clk),
            .rd_en_a(1'b1),
            .addr_a(log_addr),
            .q_a(log_q),
            .rd_en_b(1'b0),
            .addr_b({LOG_ADDR_BITS{1'b0}}),
            .q_b(log_unused_b)
        );
    end else if (IS_COSINE_QUADRATIC) begin : g_cosine_quadratic
        brdf_cosine_quadratic #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .RESET_ALL(RESET_ALL)
        ) u_form (
            .clk(clk),
            .rst_n(rst_n),
            .w(w_reg),
            .k(k_run_reg),
            .y(form_y)
        );
    end else begin : g_no_form
        // Refused above (FORM_must_be_a_form_of_the_family)
        assign form_y = {OUT_BITS{1'b0}};
        // verilator lint_off UNUSEDSIGNAL
        wire unused_form = &{1'b0, w_reg, k_run_reg};
        // verilator lint_on UNUSEDSIGNAL
    end
endgenerate

// ---------------------------------------------------------------- tables
// The angle table (stage S4, every cycle, in the front: rtl/brdf_front.v), for the quadratic,
// cubic and piecewise forms the coefficient table (read with n while idle, like the specular
// unit's ROM 9) and for the log2 form its second table (in g_log2 above, every cycle):
// instances of the ROM module (rtl/shading_rom.v), which checks each image at time 0 in
// simulation: magic ("BRDA", "BRDC", the cubic's "BRD3", the piecewise form's "BRDP", the log2
// table's "BRDL"), depth, width, the parameters the contents depend on (the angle table:
// COS_ADDR_BITS, COS_DATA_BITS, TABLE = 0 (w = 1 - cos) or, for the log2 form, 1 (-log2 cos);
// the coefficient table: FORM as its index in model.units.brdf.FORMS, COEF_BITS, and
// COEF_FRAC_BITS, or the cubic's R_FRAC_BITS, P0_FRAC_BITS, B1_FRAC_BITS, B2_FRAC_BITS, and the
// piecewise form's S2_FRAC_BITS and BETA_FRAC_BITS after those; the log2 table: LOG_ADDR_BITS,
// LOG_DATA_BITS), the checksum of the data words and the end mark; a
// bad image prints the file, the field, what it holds and what this instance needs, and ends
// the run with a non-zero exit status.  Their read registers are never reset, in either
// RESET_ALL mode, so that they map onto block RAM.  None needs one: the angle table's and the
// log2 table's (both of its registers) are rewritten every cycle from the address of the pixel in the stage before;
// after reset nerr_reg = 1 (n = 0), so until n is written every pixel's F is gated to 0 before
// x C (an undefined coefficient word cannot reach a result).
generate
    if (IS_QUADRATIC) begin : g_coef_rom
        // verilator lint_off UNUSEDSIGNAL
        wire [K_WIDTH-1:0] coef_unused_b;  // one read port
        // verilator lint_on UNUSEDSIGNAL

        shading_rom #(
            .WIDTH(K_WIDTH),
            .DEPTH(1000),
            .ADDR_BITS(N_WIDTH),
            .PORTS(1),
            .FILE(COEF_ROM_FILE),
            .NAME("COEF_ROM_FILE"),
            .MAGIC("BRDC"),
            .NUM_FIELDS(3),
            .FIELD_0(0), .FIELD_1(COEF_BITS), .FIELD_2(COEF_BITS - QUADRATIC_A_INT_BITS),
            .FIELD_NAMES({"FORM            ", "COEF_BITS       ", "COEF_FRAC_BITS  ",
                          {(8*16*9){1'b0}}})
        ) u_coef_rom (
            .clk(clk),
            .rd_en_a(!busy_reg && n_we),
            .addr_a(n_addr),
            .q_a(k_word),
            .rd_en_b(1'b0),
            .addr_b({N_WIDTH{1'b0}}),
            .q_b(coef_unused_b)
        );
    end else if (IS_CUBIC) begin : g_coef_rom_cubic
        // The cubic's word of n, 4 COEF_BITS wide, as two words of the image (the ROM module
        // holds words of 64 bits at most): {r, p0} at 2 (n - 1), {b1, b2} at 2 (n - 1) + 1,
        // both read in the same clock by the ROM's two ports
        wire [2*COEF_BITS-1:0] coef_hi;
        wire [2*COEF_BITS-1:0] coef_lo;

        shading_rom #(
            .WIDTH(2 * COEF_BITS),
            .DEPTH(2000),
            .ADDR_BITS(N_WIDTH + 1),
            .PORTS(2),
            .FILE(COEF_ROM_FILE),
            .NAME("COEF_ROM_FILE"),
            .MAGIC("BRD3"),
            .NUM_FIELDS(6),
            .FIELD_0(1), .FIELD_1(COEF_BITS), .FIELD_2(COEF_BITS - CUBIC_R_INT_BITS),
            .FIELD_3(COEF_BITS - 1), .FIELD_4(COEF_BITS), .FIELD_5(COEF_BITS),
            .FIELD_NAMES({"FORM            ", "COEF_BITS       ", "R_FRAC_BITS     ",
                          "P0_FRAC_BITS    ", "B1_FRAC_BITS    ", "B2_FRAC_BITS    ",
                          {(8*16*6){1'b0}}})
        ) u_coef_rom (
            .clk(clk),
            .rd_en_a(!busy_reg && n_we),
            .addr_a({n_addr, 1'b0}),
            .q_a(coef_hi),
            .rd_en_b(!busy_reg && n_we),
            .addr_b({n_addr, 1'b1}),
            .q_b(coef_lo)
        );
        assign k_word = {coef_hi, coef_lo};
    end else if (IS_PIECEWISE) begin : g_coef_rom_piecewise
        // The piecewise form's word of n, 6 COEF_BITS wide, as two words of the image, three
        // coefficients each (the ROM module holds words of 64 bits at most: COEF_BITS <= 21):
        // {r, p0, b1} at 2 (n - 1), {b2, s2, beta} at 2 (n - 1) + 1, both read in the same
        // clock by the ROM's two ports
        wire [3*COEF_BITS-1:0] coef_hi;
        wire [3*COEF_BITS-1:0] coef_lo;

        shading_rom #(
            .WIDTH(3 * COEF_BITS),
            .DEPTH(2000),
            .ADDR_BITS(N_WIDTH + 1),
            .PORTS(2),
            .FILE(COEF_ROM_FILE),
            .NAME("COEF_ROM_FILE"),
            .MAGIC("BRDP"),
            .NUM_FIELDS(8),
            .FIELD_0(2), .FIELD_1(COEF_BITS), .FIELD_2(COEF_BITS - CUBIC_R_INT_BITS),
            .FIELD_3(COEF_BITS - 1), .FIELD_4(COEF_BITS), .FIELD_5(COEF_BITS),
            .FIELD_6(COEF_BITS - 1), .FIELD_7(COEF_BITS - 1),
            .FIELD_NAMES({"FORM            ", "COEF_BITS       ", "R_FRAC_BITS     ",
                          "P0_FRAC_BITS    ", "B1_FRAC_BITS    ", "B2_FRAC_BITS    ",
                          "S2_FRAC_BITS    ", "BETA_FRAC_BITS  ", {(8*16*4){1'b0}}})
        ) u_coef_rom (
            .clk(clk),
            .rd_en_a(!busy_reg && n_we),
            .addr_a({n_addr, 1'b0}),
            .q_a(coef_hi),
            .rd_en_b(!busy_reg && n_we),
            .addr_b({n_addr, 1'b1}),
            .q_b(coef_lo)
        );
        assign k_word = {coef_hi, coef_lo};
    end else if (IS_LOG2) begin : g_n_word
        // The log2 form's factor is n itself (10 bits), registered when n is written
        reg [N_WIDTH-1:0] k_reg;
        always @(posedge clk) begin
            if (!busy_reg && n_we) begin
                k_reg <= n_in;
            end
            if (!rst_n) begin
                k_reg <= {N_WIDTH{1'b0}};
            end
        end
        assign k_word = k_reg;
    end else begin : g_seven_n
        // The cosine-quadratic's m = 7n/16: 7n (8n - n) registered when n is written
        reg [12:0] k_reg;
        always @(posedge clk) begin
            if (!busy_reg && n_we) begin
                k_reg <= {n_in, 3'b000} - {3'b000, n_in};
            end
            if (!rst_n) begin
                k_reg <= 13'd0;
            end
        end
        assign k_word = k_reg[K_WIDTH-1:0];
    end
endgenerate

endmodule

`resetall
