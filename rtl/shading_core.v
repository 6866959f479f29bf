// SPDX-License-Identifier: Apache-2.0
/*
 * The shading core: spans in, RGB pixels out, one pixel per clock (docs/core.md).
 *
 * s_axis: one beat per span (model.render.core.SpanFormat, low bits first): x, y, l (the span
 * has l + 1 pixels), spec (the highlight through the highlight unit), diff (the diffuse term
 * through the specular unit at n = 1), i_start0..2 and i_end0..2 (Gouraud registers, unsigned
 * Q(I_INT).(I_FRAC)), c, dz, z0, n (the highlight unit's registers), diff_c0..2, diff_dz,
 * diff_z0 (the diffuse jobs: one C per channel, one angle per span).
 * m_axis: one beat per pixel (model.render.core.PixelFormat): x, y, R, G, B; tlast on the
 * span's last pixel; tuser = 1 on every pixel of a span whose highlight the core cannot make
 * (n outside N_FIRST..N_LAST or 1..1000 for the specular unit, outside 1..1000 for a BRDF
 * unit: the highlight is 0, as the unit's n_err says; or a flag set for a path this core was
 * built without: that term is 0).
 *
 * Per pixel and channel what model.render.pipeline.assemble does: the divider's quotient for
 * dI (rtl/shading_increment.v: a * round(2^N / l), rounded), the Gouraud lane i0 + bias + x dI
 * truncated and saturated, the highlight (HIGHLIGHT = "specular": the specular unit's
 * C cos^k(a |z0 + x dz|), rtl/shading_specular_pipe.v; a BRDF form: the BRDF unit's
 * C F_n(|z0 + x dz|), rtl/shading_brdf_pipe.v), each channel's diffuse term (the specular unit
 * at n = 1, three channels sharing one angle: rtl/shading_specular_pipe.v), then
 * min(gouraud + diffuse + specular, 255).  Every pixel equals model.render.core.core_pixels.
 *
 * Structure: the input register and the ROM reads (stage A: ROM 9's a and decoder 10, or the
 * BRDF form's word of n, rtl/shading_brdf_word.v; the reciprocal of l), the three products
 * (stages B to E), the span register (the issuer: Gouraud, angle and diffuse-angle
 * accumulators, the pixel counter), the pixel pipeline (the highlight's stages S1..S(STAGES),
 * 10 for the specular unit, 7 + the form's for a BRDF form, beside the delayed Gouraud values
 * and diffuse terms), the sum into the output FIFO.  A span beat
 * is taken while stage E is empty or moves into the span register; the span register takes the
 * next span in the clock that issues the last pixel of the current one, so spans follow each
 * other with no gap.  The issuer issues a pixel only while the pixels in flight and in the
 * FIFO leave room in it (a credit count), so output backpressure stalls the issuer and never
 * drops, duplicates or reorders a pixel; the pixel pipeline itself never stalls.
 *
 * Reset: rst_n (synchronous, active low) empties the core: no beat after reset belongs to a
 * span from before it.  It resets the control state (valid flags, counters, the FIFO); the
 * data path is loaded before it is read.
 *
 * Parameters: the model's configuration fields in upper case (divider, Gouraud and specular
 * unit; the specular unit's LEN_WIDTH as SPEC_LEN_WIDTH; a BRDF unit's own fields after
 * HIGHLIGHT, its angle formats being the specular unit's); SPECULAR and DIFFUSE build the
 * highlight path and the diffuse path, HIGHLIGHT chooses the highlight's unit.  The Gouraud
 * unit's P does not change a pixel (every lane holds i0 + bias + x dI exactly): the core makes
 * one pixel per clock.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module shading_core #(
    // Pixel column bits (the span beat's and the pixel beat's x)
    parameter X_WIDTH = 12,
    // Pixel row bits
    parameter Y_WIDTH = 12,
    // 1: the highlight path (the specular unit) is built
    parameter SPECULAR = 1,
    // 1: the diffuse path (the specular unit at n = 1, three channels) is built
    parameter DIFFUSE = 1,
    // Output FIFO words (a power of two, 16 or more: the pixels in flight fit)
    parameter FIFO_DEPTH = 32,
    // Divider: dividend bits (at least I_INT + I_FRAC + 1)
    parameter A_WIDTH = 21,
    // Divider: divisor bits (k = l up to 2^K_WIDTH - 1)
    parameter K_WIDTH = 11,
    // Divider: reciprocal fraction bits N
    parameter RECIP_BITS = 20,
    // Divider: the reciprocal ROM image
    parameter RECIP_ROM_FILE = {`SHADING_ROM_DIR, "/divider_recip_k11_n20.hex"},
    // Gouraud: intensity integer bits
    parameter I_INT = 8,
    // Gouraud: intensity fraction bits
    parameter I_FRAC = 12,
    // Gouraud: line length bits (spans of 1 .. 2^LEN_WIDTH - 1 pixels)
    parameter LEN_WIDTH = 11,
    // Specular: C integer bits
    parameter C_INT_BITS = 8,
    // Specular: C fraction bits
    parameter C_FRAC_BITS = 8,
    // Specular: dz, z0 integer bits including the sign
    parameter Z_INT_BITS = 3,
    // Specular: dz, z0 fraction bits
    parameter Z_FRAC_BITS = 26,
    // Specular: interval counter bits of the unit (l up to 2^SPEC_LEN_WIDTH - 1)
    parameter SPEC_LEN_WIDTH = 11,
    // Specular: ROM 9 word integer bits
    parameter A_INT_BITS = 3,
    // Specular: ROM 9 word fraction bits
    parameter A_FRAC_BITS = 14,
    // Specular: ROM 12 address bits per table
    parameter ROM_ADDR_BITS = 12,
    // Specular: ROM 12 word bits
    parameter ROM_DATA_BITS = 16,
    // Specular: intensity bits
    parameter OUT_WIDTH = 8,
    // Specular: cos^k tables, 1..4
    parameter NUM_TABLES = 4,
    // Specular: largest n of each k range (1000 if unused)
    parameter N_HI0 = 1,
    parameter N_HI1 = 2,
    parameter N_HI2 = 6,
    parameter N_HI3 = 1000,
    // Specular: k of each table (0 if unused)
    parameter K0 = 1,
    parameter K1 = 2,
    parameter K2 = 4,
    parameter K3 = 16,
    // Specular: how ROM 9's a was chosen, "taylor" or "inflection"
    parameter [8*10-1:0] ALPHA = "taylor",
    // Specular: |zeta| integer bits (the model's mag_int_bits)
    parameter MAG_INT_BITS = 1,
    // Specular: the kept range of n
    parameter N_FIRST = 1,
    parameter N_LAST = 1000,
    // Specular: ROM 9 and ROM 12 images
    parameter A_ROM_FILE = {`SHADING_ROM_DIR,
                            "/specular_a_taylor_n1k1_n2k2_n3-6k4_n7-1000k16_q3.14.hex"},
    parameter COS_ROM_FILE = {`SHADING_ROM_DIR, "/specular_cos_k1-2-4-16_a12_d16.hex"},
    // The highlight path's unit: "specular" (the patent's) or a BRDF form, "cosine_quadratic",
    // "quadratic", "cubic", "log2" or "piecewise" (its angle formats: C_INT_BITS,
    // C_FRAC_BITS, Z_INT_BITS, Z_FRAC_BITS, SPEC_LEN_WIDTH, OUT_WIDTH)
    parameter [8*16-1:0] HIGHLIGHT = "specular",
    // BRDF: angle-table address bits
    parameter COS_ADDR_BITS = 12,
    // BRDF: angle-table word bits
    parameter COS_DATA_BITS = 20,
    // BRDF: coefficient word bits (quadratic, cubic and piecewise forms)
    parameter COEF_BITS = 18,
    // BRDF: fraction bits of the form's intermediate values
    parameter WORK_BITS = 24,
    // BRDF: fraction bits of the form's output word
    parameter OUT_BITS = 16,
    // BRDF: the log2 form's second table, address bits
    parameter LOG_ADDR_BITS = 10,
    // BRDF: the log2 form's second table, word bits
    parameter LOG_DATA_BITS = 16,
    // BRDF: the angle table's, the coefficient table's and the log2 table's images
    parameter ANGLE_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_w_a12_d20.hex"},
    parameter COEF_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_quadratic_coef_c18_q10.8.hex"},
    parameter LOG_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_log2_a10_d16.hex"},
    // s_axis_tdata bits (derived: the span beat's fields rounded up to whole bytes; another
    // value is refused)
    parameter SPAN_WIDTH = (X_WIDTH + Y_WIDTH + LEN_WIDTH + 2 + 6 * (I_INT + I_FRAC)
                            + 4 * (C_INT_BITS + C_FRAC_BITS) + 4 * (Z_INT_BITS + Z_FRAC_BITS)
                            + 10 + 7) / 8 * 8,
    // m_axis_tdata bits (derived: x, y and RGB888 rounded up to whole bytes)
    parameter PIX_WIDTH = (X_WIDTH + Y_WIDTH + 24 + 7) / 8 * 8
) (
    input  wire                  clk,
    input  wire                  rst_n,

    input  wire [SPAN_WIDTH-1:0] s_axis_tdata,
    input  wire                  s_axis_tvalid,
    output wire                  s_axis_tready,

    output wire [PIX_WIDTH-1:0]  m_axis_tdata,
    output wire                  m_axis_tlast,
    output wire                  m_axis_tuser,
    output wire                  m_axis_tvalid,
    input  wire                  m_axis_tready
);

// ---------------------------------------------------------------- widths and the beats
localparam CH = 3;
localparam N_WIDTH = 10;
localparam I_WIDTH = I_INT + I_FRAC;
localparam DI_WIDTH = I_WIDTH + 1;
localparam C_WIDTH = C_INT_BITS + C_FRAC_BITS;
localparam Z_WIDTH = Z_INT_BITS + Z_FRAC_BITS;
localparam ACC_WIDTH = Z_WIDTH + LEN_WIDTH;
localparam G_WIDTH = I_WIDTH + LEN_WIDTH + 2;
localparam AW = A_INT_BITS + A_FRAC_BITS;
localparam TSEL_BITS = (NUM_TABLES > 2) ? 2 : 1;
localparam G_MAX = (1 << I_INT) - 1;

// The highlight's unit
localparam [8*16-1:0] UNIT_SPECULAR = "specular";
localparam [8*16-1:0] FORM_COSINE_QUADRATIC = "cosine_quadratic";
localparam [8*16-1:0] FORM_QUADRATIC = "quadratic";
localparam [8*16-1:0] FORM_CUBIC = "cubic";
localparam [8*16-1:0] FORM_LOG2 = "log2";
localparam [8*16-1:0] FORM_PIECEWISE = "piecewise";
localparam IS_SPEC = (HIGHLIGHT == UNIT_SPECULAR);
localparam IS_BRDF = (HIGHLIGHT == FORM_COSINE_QUADRATIC) || (HIGHLIGHT == FORM_QUADRATIC)
                     || (HIGHLIGHT == FORM_CUBIC) || (HIGHLIGHT == FORM_LOG2)
                     || (HIGHLIGHT == FORM_PIECEWISE);
// The BRDF form's word of n (rtl/shading_brdf_word.v) and its pipeline stages
// (model.units.brdf.form_latency: the piecewise form's max(14, OUT_BITS + 8))
localparam BRDF_K_WIDTH = (HIGHLIGHT == FORM_QUADRATIC) ? COEF_BITS
                        : (HIGHLIGHT == FORM_CUBIC) ? 4 * COEF_BITS
                        : (HIGHLIGHT == FORM_LOG2) ? 10
                        : (HIGHLIGHT == FORM_PIECEWISE) ? 6 * COEF_BITS : 13;
localparam BRDF_FORM_STAGES = (HIGHLIGHT == FORM_QUADRATIC) ? 6 : (HIGHLIGHT == FORM_CUBIC) ? 13
                            : (HIGHLIGHT == FORM_LOG2) ? 7
                            : (HIGHLIGHT == FORM_PIECEWISE) ? ((OUT_BITS + 8 > 14) ? OUT_BITS + 8
                                                                                   : 14)
                            : 5;
// The highlight's word of the span: the specular unit's table and a, or the form's word
localparam HW_WIDTH = IS_BRDF ? BRDF_K_WIDTH : TSEL_BITS + AW;
// The diffuse jobs' a (ROM 9's word of n = 1) is 1.0 when n = 1's k is 1 (a = sqrt(n/k)) or a
// is inflection-matched (1 for n = 1 whatever k): then the diffuse pipe shifts, no
// multiplier 11 and no ROM 9 read (model.units.specular alpha_value)
localparam [8*10-1:0] ALPHA_INFLECTION = "inflection";
localparam DIFF_A_ONE = (K0 == 1) || (ALPHA == ALPHA_INFLECTION);
// The pixel pipeline: S1..S(STAGES), the highlight's (the diffuse terms wait for it)
localparam SPEC_STAGES = 10;
localparam STAGES = (SPECULAR != 0 && IS_BRDF) ? 7 + BRDF_FORM_STAGES : SPEC_STAGES;
// Clocks from a pixel issued to its beat on m_axis: STAGES, the FIFO's write and its output
// register (model.render.core.pixel_pipe)
localparam PIXEL_PIPE = STAGES + 2;

// The span beat, low bits first (model.render.core.SpanFormat)
localparam O_X = 0;
localparam O_Y = O_X + X_WIDTH;
localparam O_L = O_Y + Y_WIDTH;
localparam O_SPEC = O_L + LEN_WIDTH;
localparam O_DIFF = O_SPEC + 1;
localparam O_IS = O_DIFF + 1;
localparam O_IE = O_IS + CH * I_WIDTH;
localparam O_C = O_IE + CH * I_WIDTH;
localparam O_DZ = O_C + C_WIDTH;
localparam O_Z0 = O_DZ + Z_WIDTH;
localparam O_N = O_Z0 + Z_WIDTH;
localparam O_DC = O_N + N_WIDTH;
localparam O_DDZ = O_DC + CH * C_WIDTH;
localparam O_DZ0 = O_DDZ + Z_WIDTH;
localparam SPAN_BITS = O_DZ0 + Z_WIDTH;
localparam SPAN_WIDTH_DERIVED = (SPAN_BITS + 7) / 8 * 8;
// The pixel beat: x, y, R, G, B
localparam PIX_BITS = X_WIDTH + Y_WIDTH + 3 * 8;
localparam PIX_WIDTH_DERIVED = (PIX_BITS + 7) / 8 * 8;

// ---------------------------------------------------------------- parameter check
// The rules the core adds to the units' (the pipeline configuration's cross-checks,
// model.render.pipeline.PipelineConfig; the units' own rules: "the units' own rules" below);
// each ROM checks its image against the parameters.
localparam LEN_MAX = (1 << LEN_WIDTH) - 1;
generate
    if (X_WIDTH < 1 || X_WIDTH > 16) begin : g_check_x_width
        shading_core_PARAMETER_ERROR_X_WIDTH_must_be_1_to_16 u_error ();
    end
    if (Y_WIDTH < 1 || Y_WIDTH > 16) begin : g_check_y_width
        shading_core_PARAMETER_ERROR_Y_WIDTH_must_be_1_to_16 u_error ();
    end
    if (SPECULAR != 0 && SPECULAR != 1) begin : g_check_specular
        shading_core_PARAMETER_ERROR_SPECULAR_must_be_0_or_1 u_error ();
    end
    if (DIFFUSE != 0 && DIFFUSE != 1) begin : g_check_diffuse
        shading_core_PARAMETER_ERROR_DIFFUSE_must_be_0_or_1 u_error ();
    end
    if (FIFO_DEPTH < 16 || FIFO_DEPTH > 4096 || (FIFO_DEPTH & (FIFO_DEPTH - 1)) != 0)
    begin : g_check_fifo_depth
        shading_core_PARAMETER_ERROR_FIFO_DEPTH_must_be_a_power_of_2_from_16_to_4096 u_error ();
    end
    if (I_INT < 1 || I_INT > 16) begin : g_check_i_int
        shading_core_PARAMETER_ERROR_I_INT_must_be_1_to_16 u_error ();
    end
    if (I_FRAC < 1 || I_FRAC > 24) begin : g_check_i_frac
        shading_core_PARAMETER_ERROR_I_FRAC_must_be_1_to_24 u_error ();
    end
    if (LEN_WIDTH < 2 || LEN_WIDTH > 16) begin : g_check_len_width
        shading_core_PARAMETER_ERROR_LEN_WIDTH_must_be_2_to_16 u_error ();
    end
    if (RECIP_BITS < 1 || RECIP_BITS > 40 || K_WIDTH < 1 || K_WIDTH > RECIP_BITS + 1)
    begin : g_check_divider
        shading_core_PARAMETER_ERROR_K_WIDTH_must_be_1_to_RECIP_BITS_plus_1 u_error ();
    end
    if (A_WIDTH < DI_WIDTH) begin : g_check_a_width
        shading_core_PARAMETER_ERROR_A_WIDTH_must_hold_the_difference_of_two_intensities
            u_error ();
    end
    if ((1 << K_WIDTH) - 1 < LEN_MAX - 1) begin : g_check_k_width
        shading_core_PARAMETER_ERROR_K_WIDTH_must_reach_the_longest_span_s_intervals u_error ();
    end
    if ((1 << SPEC_LEN_WIDTH) - 1 < LEN_MAX - 1) begin : g_check_spec_len_width
        shading_core_PARAMETER_ERROR_SPEC_LEN_WIDTH_must_reach_the_longest_span_s_intervals
            u_error ();
    end
    if (DIFFUSE == 1 && N_FIRST != 1) begin : g_check_diffuse_n
        shading_core_PARAMETER_ERROR_DIFFUSE_needs_N_FIRST_1 u_error ();
    end
    if (!IS_SPEC && !IS_BRDF) begin : g_check_highlight
        shading_core_PARAMETER_ERROR_HIGHLIGHT_must_be_specular_or_a_BRDF_form u_error ();
    end
    if (FIFO_DEPTH <= PIXEL_PIPE) begin : g_check_fifo_pipe
        shading_core_PARAMETER_ERROR_FIFO_DEPTH_must_exceed_the_pixels_in_flight u_error ();
    end
    if (SPAN_WIDTH != SPAN_WIDTH_DERIVED) begin : g_check_span_width
        shading_core_PARAMETER_ERROR_SPAN_WIDTH_must_be_the_span_beat_s_bits_rounded_to_bytes
            u_error ();
    end
    if (PIX_WIDTH != PIX_WIDTH_DERIVED) begin : g_check_pix_width
        shading_core_PARAMETER_ERROR_PIX_WIDTH_must_be_X_WIDTH_plus_Y_WIDTH_plus_24_rounded_to_bytes
            u_error ();
    end
endgenerate

// ---------------------------------------------------------------- the units' own rules
// The divider's, the specular unit's and the BRDF unit's legal parameter sets (the k ranges
// and ALPHA, MAG_INT_BITS as the model derives it, the largest a in A_INT_BITS, a BRDF form's
// widths, ...) and their ROM images' checks (ROM 9's kept range among them) are the units'
// own: an instance of each unit the core's paths use, at the core's parameters, its clock and
// inputs tied to 0 and its outputs unread, makes every tool refuse what that unit refuses, by
// the same error names, and simulation check the images as the unit does.  It drives nothing
// and its clock never ticks: synthesis removes it, and it costs simulation nothing.
// verilator lint_off UNUSEDSIGNAL
wire                              rules_div_busy;
wire                              rules_div_valid;
wire [A_WIDTH+RECIP_BITS-1:0]     rules_div_q;
wire                              rules_div_zero;
wire                              rules_spec_busy;
wire                              rules_spec_valid;
wire [OUT_WIDTH-1:0]              rules_spec_intensity;
wire                              rules_spec_n_err;
wire                              rules_brdf_busy;
wire                              rules_brdf_valid;
wire [OUT_WIDTH-1:0]              rules_brdf_intensity;
wire                              rules_brdf_n_err;
// verilator lint_on UNUSEDSIGNAL
divider_shift #(
    .A_WIDTH(A_WIDTH),
    .K_WIDTH(K_WIDTH),
    .RECIP_BITS(RECIP_BITS),
    .ROM_FILE(RECIP_ROM_FILE)
) u_divider_rules (
    .clk(1'b0),
    .rst_n(1'b0),
    .a_in({A_WIDTH{1'b0}}),
    .a_we(1'b0),
    .k_in({K_WIDTH{1'b0}}),
    .k_we(1'b0),
    .start(1'b0),
    .busy(rules_div_busy),
    .valid(rules_div_valid),
    .q(rules_div_q),
    .div_zero(rules_div_zero)
);
generate
    if ((SPECULAR != 0 && IS_SPEC) || DIFFUSE != 0) begin : g_specular_rules
        specular_unit #(
            .C_INT_BITS(C_INT_BITS), .C_FRAC_BITS(C_FRAC_BITS), .Z_INT_BITS(Z_INT_BITS),
            .Z_FRAC_BITS(Z_FRAC_BITS), .LEN_WIDTH(SPEC_LEN_WIDTH), .A_INT_BITS(A_INT_BITS),
            .A_FRAC_BITS(A_FRAC_BITS), .ROM_ADDR_BITS(ROM_ADDR_BITS),
            .ROM_DATA_BITS(ROM_DATA_BITS), .OUT_WIDTH(OUT_WIDTH), .NUM_TABLES(NUM_TABLES),
            .N_HI0(N_HI0), .N_HI1(N_HI1), .N_HI2(N_HI2), .N_HI3(N_HI3), .K0(K0), .K1(K1),
            .K2(K2), .K3(K3), .ALPHA(ALPHA), .MAG_INT_BITS(MAG_INT_BITS), .N_FIRST(N_FIRST),
            .N_LAST(N_LAST), .A_ROM_FILE(A_ROM_FILE), .COS_ROM_FILE(COS_ROM_FILE)
        ) u_specular_rules (
            .clk(1'b0),
            .rst_n(1'b0),
            .c_in({(C_INT_BITS+C_FRAC_BITS){1'b0}}),
            .c_we(1'b0),
            .dz_in({(Z_INT_BITS+Z_FRAC_BITS){1'b0}}),
            .dz_we(1'b0),
            .z0_in({(Z_INT_BITS+Z_FRAC_BITS){1'b0}}),
            .z0_we(1'b0),
            .n_in(10'd0),
            .n_we(1'b0),
            .len_in({SPEC_LEN_WIDTH{1'b0}}),
            .len_we(1'b0),
            .start(1'b0),
            .busy(rules_spec_busy),
            .valid(rules_spec_valid),
            .intensity(rules_spec_intensity),
            .n_err(rules_spec_n_err)
        );
    end else begin : g_no_specular_rules
        assign rules_spec_busy = 1'b0;
        assign rules_spec_valid = 1'b0;
        assign rules_spec_intensity = {OUT_WIDTH{1'b0}};
        assign rules_spec_n_err = 1'b0;
    end
    if (SPECULAR != 0 && IS_BRDF) begin : g_brdf_rules
        brdf_unit #(
            .FORM(HIGHLIGHT), .C_INT_BITS(C_INT_BITS), .C_FRAC_BITS(C_FRAC_BITS),
            .Z_INT_BITS(Z_INT_BITS), .Z_FRAC_BITS(Z_FRAC_BITS), .LEN_WIDTH(SPEC_LEN_WIDTH),
            .OUT_WIDTH(OUT_WIDTH), .COS_ADDR_BITS(COS_ADDR_BITS), .COS_DATA_BITS(COS_DATA_BITS),
            .COEF_BITS(COEF_BITS), .WORK_BITS(WORK_BITS), .OUT_BITS(OUT_BITS),
            .LOG_ADDR_BITS(LOG_ADDR_BITS), .LOG_DATA_BITS(LOG_DATA_BITS),
            .ANGLE_ROM_FILE(ANGLE_ROM_FILE), .COEF_ROM_FILE(COEF_ROM_FILE),
            .LOG_ROM_FILE(LOG_ROM_FILE)
        ) u_brdf_rules (
            .clk(1'b0),
            .rst_n(1'b0),
            .c_in({(C_INT_BITS+C_FRAC_BITS){1'b0}}),
            .c_we(1'b0),
            .dz_in({(Z_INT_BITS+Z_FRAC_BITS){1'b0}}),
            .dz_we(1'b0),
            .z0_in({(Z_INT_BITS+Z_FRAC_BITS){1'b0}}),
            .z0_we(1'b0),
            .n_in(10'd0),
            .n_we(1'b0),
            .len_in({SPEC_LEN_WIDTH{1'b0}}),
            .len_we(1'b0),
            .start(1'b0),
            .busy(rules_brdf_busy),
            .valid(rules_brdf_valid),
            .intensity(rules_brdf_intensity),
            .n_err(rules_brdf_n_err)
        );
    end else begin : g_no_brdf_rules
        assign rules_brdf_busy = 1'b0;
        assign rules_brdf_valid = 1'b0;
        assign rules_brdf_intensity = {OUT_WIDTH{1'b0}};
        assign rules_brdf_n_err = 1'b0;
    end
endgenerate

// ---------------------------------------------------------------- stage A: input, ROM reads
wire ce;              // stage A and B move
wire take;            // the span register takes stage B
reg  va_reg;
reg  vb_reg;
wire s_fire = s_axis_tvalid && s_axis_tready;
assign s_axis_tready = rst_n && ce;

wire [LEN_WIDTH-1:0] in_l = s_axis_tdata[O_L +: LEN_WIDTH];
wire [N_WIDTH-1:0]   in_n = s_axis_tdata[O_N +: N_WIDTH];

// Decoder 10 (as in rtl/specular_unit.v): the table of n and whether n is kept
localparam [N_WIDTH-1:0] HI0 = N_HI0[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] HI1 = N_HI1[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] HI2 = N_HI2[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] HI3 = N_HI3[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] NFIRST = N_FIRST[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] NLAST = N_LAST[N_WIDTH-1:0];
localparam A_DEPTH = N_LAST - N_FIRST + 1;
localparam A_ADDR_BITS = (A_DEPTH > 512) ? 10 : (A_DEPTH > 256) ? 9 : (A_DEPTH > 128) ? 8
                       : (A_DEPTH > 64) ? 7 : (A_DEPTH > 32) ? 6 : (A_DEPTH > 16) ? 5
                       : (A_DEPTH > 8) ? 4 : (A_DEPTH > 4) ? 3 : (A_DEPTH > 2) ? 2 : 1;
wire [3:0] dec_line;
assign dec_line[0] = (in_n != {N_WIDTH{1'b0}}) && (in_n <= HI0);
assign dec_line[1] = (NUM_TABLES > 1) && (in_n > HI0) && (in_n <= HI1);
assign dec_line[2] = (NUM_TABLES > 2) && (in_n > HI1) && (in_n <= HI2);
assign dec_line[3] = (NUM_TABLES > 3) && (in_n > HI2) && (in_n <= HI3);
wire n_kept = (in_n >= NFIRST) && (in_n <= NLAST);
// The highlight's n refused: the specular unit's decoder and kept range, or a BRDF unit's
// 1..1000
wire brdf_n_ok = (in_n != {N_WIDTH{1'b0}}) && (in_n <= 10'd1000);
wire dec_err = IS_BRDF ? !brdf_n_ok : (dec_line == 4'b0000) || !n_kept;
wire [N_WIDTH-1:0] n_off = in_n - NFIRST;
wire [A_ADDR_BITS-1:0] a_addr = n_kept ? n_off[A_ADDR_BITS-1:0] : {A_ADDR_BITS{1'b0}};
wire [1:0] dec_index = {dec_line[3] | dec_line[2], dec_line[3] | dec_line[1]};

reg [X_WIDTH-1:0]      xa_reg;
reg [Y_WIDTH-1:0]      ya_reg;
reg [LEN_WIDTH-1:0]    la_reg;
reg                    speca_reg;
reg                    diffa_reg;
reg [CH*I_WIDTH-1:0]   ia_reg;
reg [CH*DI_WIDTH-1:0]  da_reg;     // i_end - i_start per channel
reg [C_WIDTH-1:0]      ca_reg;
reg [Z_WIDTH-1:0]      dza_reg;
reg [Z_WIDTH-1:0]      z0a_reg;
reg [TSEL_BITS-1:0]    tsela_reg;
reg                    nerra_reg;
reg [CH*C_WIDTH-1:0]   dca_reg;
reg [Z_WIDTH-1:0]      ddza_reg;
reg [Z_WIDTH-1:0]      dz0a_reg;

integer c;
always @(posedge clk) begin
    if (ce) begin
        xa_reg <= s_axis_tdata[O_X +: X_WIDTH];
        ya_reg <= s_axis_tdata[O_Y +: Y_WIDTH];
        la_reg <= in_l;
        speca_reg <= s_axis_tdata[O_SPEC];
        diffa_reg <= s_axis_tdata[O_DIFF];
        ia_reg <= s_axis_tdata[O_IS +: CH * I_WIDTH];
        for (c = 0; c < CH; c = c + 1) begin
            da_reg[c*DI_WIDTH +: DI_WIDTH] <= {1'b0, s_axis_tdata[O_IE + c*I_WIDTH +: I_WIDTH]}
                                            - {1'b0, s_axis_tdata[O_IS + c*I_WIDTH +: I_WIDTH]};
        end
        ca_reg <= s_axis_tdata[O_C +: C_WIDTH];
        dza_reg <= s_axis_tdata[O_DZ +: Z_WIDTH];
        z0a_reg <= s_axis_tdata[O_Z0 +: Z_WIDTH];
        tsela_reg <= dec_index[TSEL_BITS-1:0];
        nerra_reg <= dec_err;
        dca_reg <= s_axis_tdata[O_DC +: CH * C_WIDTH];
        ddza_reg <= s_axis_tdata[O_DDZ +: Z_WIDTH];
        dz0a_reg <= s_axis_tdata[O_DZ0 +: Z_WIDTH];
    end
end

// The reciprocal ROM (read with l: round(2^N / l), the divider's word), ROM 9 (a of n, for
// the specular highlight; port B: a of n = 1, the diffuse jobs' word, read every clock unless
// it is 1.0) or the BRDF form's word of n
wire [RECIP_BITS:0] recip_q;
// verilator lint_off UNUSEDSIGNAL
wire [RECIP_BITS:0] recip_unused_b;  // the reciprocal ROM has one port
// verilator lint_on UNUSEDSIGNAL
wire [K_WIDTH-1:0]  recip_addr;
generate
    if (K_WIDTH > LEN_WIDTH) begin : g_recip_pad
        assign recip_addr = {{(K_WIDTH-LEN_WIDTH){1'b0}}, in_l};
    end else begin : g_recip_fit
        assign recip_addr = in_l[K_WIDTH-1:0];
    end
endgenerate
shading_rom #(
    .WIDTH(RECIP_BITS + 1),
    .DEPTH(1 << K_WIDTH),
    .ADDR_BITS(K_WIDTH),
    .PORTS(1),
    .FILE(RECIP_ROM_FILE),
    .NAME("RECIP_ROM_FILE"),
    .MAGIC("DIVR"),
    .NUM_FIELDS(2),
    .FIELD_0(K_WIDTH), .FIELD_1(RECIP_BITS),
    .FIELD_NAMES({"K_WIDTH         ", "RECIP_BITS      ", {(8*16*10){1'b0}}})
) u_recip_rom (
    .clk(clk),
    .rd_en_a(ce),
    .addr_a(recip_addr),
    .q_a(recip_q),
    .rd_en_b(1'b0),
    .addr_b({K_WIDTH{1'b0}}),
    .q_b(recip_unused_b)
);

localparam ALPHA_INDEX = (ALPHA == ALPHA_INFLECTION) ? 1 : 0;
localparam ROM9_A = (SPECULAR != 0 && IS_SPEC);       // port A: the highlight's a
localparam ROM9_B = (DIFFUSE != 0 && !DIFF_A_ONE);    // port B: the diffuse jobs' a
wire [AW-1:0] a_q;       // a of the span's n (stage B)
wire [AW-1:0] a_diff_q;  // a of n = 1
generate
    if (ROM9_A || ROM9_B) begin : g_rom9
        shading_rom #(
            .WIDTH(AW),
            .DEPTH(A_DEPTH),
            .ADDR_BITS(A_ADDR_BITS),
            .PORTS(ROM9_B ? 2 : 1),
            .FILE(A_ROM_FILE),
            .NAME("A_ROM_FILE"),
            .MAGIC("SR09"),
            .NUM_FIELDS(12),
            .FIELD_0(A_INT_BITS), .FIELD_1(A_FRAC_BITS), .FIELD_2(ALPHA_INDEX),
            .FIELD_3(NUM_TABLES), .FIELD_4(N_HI0), .FIELD_5(N_HI1), .FIELD_6(N_HI2),
            .FIELD_7(N_HI3), .FIELD_8(K0), .FIELD_9(K1), .FIELD_10(K2), .FIELD_11(K3),
            .FIELD_NAMES({"A_INT_BITS      ", "A_FRAC_BITS     ", "ALPHA           ",
                          "NUM_TABLES      ", "N_HI0           ", "N_HI1           ",
                          "N_HI2           ", "N_HI3           ", "K0              ",
                          "K1              ", "K2              ", "K3              "})
        ) u_rom9 (
            .clk(clk),
            .rd_en_a(ce),
            .addr_a(a_addr),
            .q_a(a_q),
            .rd_en_b(ROM9_B ? 1'b1 : 1'b0),
            .addr_b({A_ADDR_BITS{1'b0}}),
            .q_b(a_diff_q)
        );
    end else begin : g_no_rom9
        assign a_q = {AW{1'b0}};
        assign a_diff_q = {AW{1'b0}};
    end
endgenerate

// The BRDF form's word of n (7n, the coefficients or n), read with the span beat as ROM 9 is
wire [BRDF_K_WIDTH-1:0] k_q;
generate
    if (SPECULAR != 0 && IS_BRDF) begin : g_brdf_word
        shading_brdf_word #(
            .FORM(HIGHLIGHT),
            .COEF_BITS(COEF_BITS),
            .COEF_ROM_FILE(COEF_ROM_FILE),
            .K_WIDTH(BRDF_K_WIDTH)
        ) u_brdf_word (
            .clk(clk),
            .en(ce),
            .n(in_n),
            .k(k_q)
        );
    end else begin : g_no_brdf_word
        assign k_q = {BRDF_K_WIDTH{1'b0}};
    end
endgenerate

// The highlight's word of the span in stage A: the specular unit's table and a, or the form's
wire [HW_WIDTH-1:0] hw_a;
generate
    if (IS_BRDF) begin : g_hw_brdf
        assign hw_a = k_q;
    end else begin : g_hw_specular
        assign hw_a = {tsela_reg, a_q};
    end
endgenerate

// ---------------------------------------------------------------- stage B: the products
reg [X_WIDTH-1:0]      xb_reg;
reg [Y_WIDTH-1:0]      yb_reg;
reg [LEN_WIDTH-1:0]    lb_reg;
reg                    specb_reg;
reg                    diffb_reg;
reg [CH*I_WIDTH-1:0]   ib_reg;
reg [C_WIDTH-1:0]      cb_reg;
reg [Z_WIDTH-1:0]      dzb_reg;
reg [Z_WIDTH-1:0]      z0b_reg;
reg                    nerrb_reg;
reg [HW_WIDTH-1:0]     hwb_reg;
reg [CH*C_WIDTH-1:0]   dcb_reg;
reg [Z_WIDTH-1:0]      ddzb_reg;
reg [Z_WIDTH-1:0]      dz0b_reg;
wire [CH*DI_WIDTH-1:0] di_b;  // the increments of the span in stage E

genvar g;
generate
    for (g = 0; g < CH; g = g + 1) begin : g_increment
        shading_increment #(
            .A_WIDTH(DI_WIDTH),
            .RECIP_BITS(RECIP_BITS),
            .DI_WIDTH(DI_WIDTH)
        ) u_increment (
            .clk(clk),
            .ce(ce),
            .a(da_reg[g*DI_WIDTH +: DI_WIDTH]),
            .r(recip_q),
            .di(di_b[g*DI_WIDTH +: DI_WIDTH])
        );
    end
endgenerate

// Stages C, D and E: stage B's fields wait while the products finish (shading_increment's
// pipeline: di belongs to the span in stage E)
localparam FB_WIDTH = X_WIDTH + Y_WIDTH + LEN_WIDTH + 2 + CH * I_WIDTH + C_WIDTH + 2 * Z_WIDTH
                    + 1 + HW_WIDTH + CH * C_WIDTH + 2 * Z_WIDTH;
reg  [FB_WIDTH-1:0] fc_reg;
reg  [FB_WIDTH-1:0] fd_reg;
reg  [FB_WIDTH-1:0] fe_reg;
reg                 vc_reg;
reg                 vd_reg;
reg                 ve_reg;
wire [X_WIDTH-1:0]     xd;
wire [Y_WIDTH-1:0]     yd;
wire [LEN_WIDTH-1:0]   ld;
wire                   specd;
wire                   diffd;
wire [CH*I_WIDTH-1:0]  id;
wire [C_WIDTH-1:0]     cd;
wire [Z_WIDTH-1:0]     dzd;
wire [Z_WIDTH-1:0]     z0d;
wire                   nerrd;
wire [HW_WIDTH-1:0]    hwd;
wire [CH*C_WIDTH-1:0]  dcd;
wire [Z_WIDTH-1:0]     ddzd;
wire [Z_WIDTH-1:0]     dz0d;
assign {xd, yd, ld, specd, diffd, id, cd, dzd, z0d, nerrd, hwd, dcd, ddzd, dz0d} = fe_reg;

always @(posedge clk) begin
    if (ce) begin
        fc_reg <= {xb_reg, yb_reg, lb_reg, specb_reg, diffb_reg, ib_reg, cb_reg, dzb_reg, z0b_reg,
                   nerrb_reg, hwb_reg, dcb_reg, ddzb_reg, dz0b_reg};
        fd_reg <= fc_reg;
        fe_reg <= fd_reg;
    end
end

always @(posedge clk) begin
    if (ce) begin
        xb_reg <= xa_reg;
        yb_reg <= ya_reg;
        lb_reg <= la_reg;
        specb_reg <= speca_reg;
        diffb_reg <= diffa_reg;
        ib_reg <= ia_reg;
        cb_reg <= ca_reg;
        dzb_reg <= dza_reg;
        z0b_reg <= z0a_reg;
        nerrb_reg <= nerra_reg;
        hwb_reg <= hw_a;
        dcb_reg <= dca_reg;
        ddzb_reg <= ddza_reg;
        dz0b_reg <= dz0a_reg;
    end
end

// ---------------------------------------------------------------- the span register (issuer)
localparam OCC_BITS = (FIFO_DEPTH > 2048) ? 13 : (FIFO_DEPTH > 1024) ? 12
                    : (FIFO_DEPTH > 512) ? 11 : (FIFO_DEPTH > 256) ? 10 : (FIFO_DEPTH > 128) ? 9
                    : (FIFO_DEPTH > 64) ? 8 : (FIFO_DEPTH > 32) ? 7 : (FIFO_DEPTH > 16) ? 6 : 5;
localparam [OCC_BITS-1:0] OCC_MAX = FIFO_DEPTH[OCC_BITS-1:0];

reg                    act_reg;
reg [LEN_WIDTH-1:0]    cnt_reg;
reg [X_WIDTH-1:0]      x_reg;
reg [Y_WIDTH-1:0]      y_reg;
reg [CH*G_WIDTH-1:0]   gacc_reg;
reg [CH*DI_WIDTH-1:0]  di_reg;
reg [ACC_WIDTH-1:0]    zacc_reg;
reg [Z_WIDTH-1:0]      dz_reg;
reg [ACC_WIDTH-1:0]    dacc_reg;
reg [Z_WIDTH-1:0]      ddz_reg;
reg [C_WIDTH-1:0]      c_reg;
reg [HW_WIDTH-1:0]     hw_reg;     // the highlight's word: {table, a} or the BRDF form's
reg                    szero_reg;  // the highlight is 0 (no highlight job, or n refused)
reg                    dzero_reg;  // the diffuse terms are 0 (no diffuse jobs)
reg                    err_reg;    // tuser of the span's pixels
reg [CH*C_WIDTH-1:0]   dc_reg;
reg [OCC_BITS-1:0]     occ_reg;

wire out_fire = m_axis_tvalid && m_axis_tready;
wire issue = act_reg && (occ_reg < OCC_MAX);
wire last_px = (cnt_reg == {LEN_WIDTH{1'b0}});
assign take = ve_reg && (!act_reg || (issue && last_px));
assign ce = !ve_reg || take;

localparam [G_WIDTH-1:0] G_BIAS = 1 << (I_FRAC - 1);
integer ci;

always @(posedge clk) begin
    if (take) begin
        cnt_reg <= ld;
        x_reg <= xd;
        y_reg <= yd;
        for (ci = 0; ci < CH; ci = ci + 1) begin
            gacc_reg[ci*G_WIDTH +: G_WIDTH] <= {{(G_WIDTH-I_WIDTH){1'b0}},
                                                id[ci*I_WIDTH +: I_WIDTH]} + G_BIAS;
            di_reg[ci*DI_WIDTH +: DI_WIDTH] <= (ld == {LEN_WIDTH{1'b0}}) ? {DI_WIDTH{1'b0}}
                                               : di_b[ci*DI_WIDTH +: DI_WIDTH];
        end
        zacc_reg <= {{LEN_WIDTH{z0d[Z_WIDTH-1]}}, z0d};
        dz_reg <= dzd;
        dacc_reg <= {{LEN_WIDTH{dz0d[Z_WIDTH-1]}}, dz0d};
        ddz_reg <= ddzd;
        c_reg <= cd;
        hw_reg <= hwd;
        szero_reg <= !specd || nerrd || SPECULAR == 0;
        dzero_reg <= !diffd || DIFFUSE == 0;
        err_reg <= (specd && (nerrd || SPECULAR == 0)) || (diffd && DIFFUSE == 0);
        dc_reg <= dcd;
    end else if (issue) begin
        cnt_reg <= cnt_reg - {{(LEN_WIDTH-1){1'b0}}, 1'b1};
        x_reg <= x_reg + {{(X_WIDTH-1){1'b0}}, 1'b1};
        for (ci = 0; ci < CH; ci = ci + 1) begin
            gacc_reg[ci*G_WIDTH +: G_WIDTH] <= gacc_reg[ci*G_WIDTH +: G_WIDTH]
                + {{(G_WIDTH-DI_WIDTH){di_reg[ci*DI_WIDTH+DI_WIDTH-1]}},
                   di_reg[ci*DI_WIDTH +: DI_WIDTH]};
        end
        zacc_reg <= zacc_reg + {{LEN_WIDTH{dz_reg[Z_WIDTH-1]}}, dz_reg};
        dacc_reg <= dacc_reg + {{LEN_WIDTH{ddz_reg[Z_WIDTH-1]}}, ddz_reg};
    end
end

// Control state
always @(posedge clk) begin
    if (ce) begin
        va_reg <= s_fire;
        vb_reg <= va_reg;
        vc_reg <= vb_reg;
        vd_reg <= vc_reg;
        ve_reg <= vd_reg;
    end
    if (take) begin
        act_reg <= 1'b1;
    end else if (issue && last_px) begin
        act_reg <= 1'b0;
    end
    occ_reg <= occ_reg + {{(OCC_BITS-1){1'b0}}, issue} - {{(OCC_BITS-1){1'b0}}, out_fire};
    if (!rst_n) begin
        va_reg <= 1'b0;
        vb_reg <= 1'b0;
        vc_reg <= 1'b0;
        vd_reg <= 1'b0;
        ve_reg <= 1'b0;
        act_reg <= 1'b0;
        occ_reg <= {OCC_BITS{1'b0}};
    end
end

// ---------------------------------------------------------------- the pixel pipeline
// S0 is the span register (the accumulators); S1..S(STAGES) the highlight's stages
// (rtl/shading_specular_pipe.v, 10; rtl/shading_brdf_pipe.v, 7 + the form's).  Beside
// them: the Gouraud values (truncated and saturated from S0), x, y, tlast and tuser, and the
// diffuse terms (rtl/shading_specular_pipe.v, 10 stages, then held to S(STAGES)).
localparam SIDE = X_WIDTH + Y_WIDTH + CH * I_INT + 2;

reg [STAGES:1]        v_reg;
reg [STAGES*SIDE-1:0] side_reg;  // S1 in the low bits, S10 in the high

wire [CH*I_INT-1:0] g_val;
generate
    for (g = 0; g < CH; g = g + 1) begin : g_gouraud
        wire [G_WIDTH-1:0] acc = gacc_reg[g*G_WIDTH +: G_WIDTH];
        wire [G_WIDTH-I_FRAC-1:0] whole = acc[G_WIDTH-1:I_FRAC];
        wire neg = acc[G_WIDTH-1];
        wire over = |whole[G_WIDTH-I_FRAC-1:I_INT];
        assign g_val[g*I_INT +: I_INT] = neg ? {I_INT{1'b0}} : over ? G_MAX[I_INT-1:0]
                                              : whole[I_INT-1:0];
        // verilator lint_off UNUSEDSIGNAL
        wire unused_frac = &{1'b0, acc[I_FRAC-1:0]};
        // verilator lint_on UNUSEDSIGNAL
    end
endgenerate

always @(posedge clk) begin
    v_reg <= {v_reg[STAGES-1:1], issue};
    side_reg <= {side_reg[0 +: (STAGES-1)*SIDE], err_reg, last_px, g_val, y_reg, x_reg};
    if (!rst_n) begin
        v_reg <= {STAGES{1'b0}};
    end
end

localparam ROM12_ADDR = TSEL_BITS + ROM_ADDR_BITS;
wire [OUT_WIDTH-1:0]    spec_int;
wire [CH*OUT_WIDTH-1:0] diff_int;
wire [CH*OUT_WIDTH-1:0] diff_out;  // the diffuse terms of the pixel in S(STAGES)
wire [ROM12_ADDR-1:0]   spec_addr;
wire [ROM12_ADDR-1:0]   diff_addr;
wire [ROM_DATA_BITS-1:0] spec_q;
wire [ROM_DATA_BITS-1:0] diff_q;
// verilator lint_off UNUSEDSIGNAL
wire [ROM_DATA_BITS-1:0] spec_unused_b;  // the ROMs have one port each
wire [ROM_DATA_BITS-1:0] diff_unused_b;
// verilator lint_on UNUSEDSIGNAL

generate
    // ROM 12: the highlight's port reads every table (a bank per table in synthesis, its word
    // registered before the table is chosen); the diffuse path reads table 0 only (n = 1 is in
    // the first k range), from a ROM of that table alone: neither read runs through a
    // multiplexer over every table's block RAMs before its first register
    if (SPECULAR != 0 && IS_SPEC) begin : g_rom12
        shading_rom #(
            .WIDTH(ROM_DATA_BITS),
            .DEPTH(1 << ROM12_ADDR),
            .ADDR_BITS(ROM12_ADDR),
            .PORTS(1),
            .READ_REGS(2),
            .BANK_BITS(ROM_ADDR_BITS),  // a bank per table
            .FILE(COS_ROM_FILE),
            .NAME("COS_ROM_FILE"),
            .MAGIC("SR12"),
            .NUM_FIELDS(7),
            .FIELD_0(ROM_ADDR_BITS), .FIELD_1(ROM_DATA_BITS), .FIELD_2(NUM_TABLES),
            .FIELD_3(K0), .FIELD_4(K1), .FIELD_5(K2), .FIELD_6(K3),
            .FIELD_NAMES({"ROM_ADDR_BITS   ", "ROM_DATA_BITS   ", "NUM_TABLES      ",
                          "K0              ", "K1              ", "K2              ",
                          "K3              ", {(8*16*5){1'b0}}})
        ) u_rom12 (
            .clk(clk),
            .rd_en_a(1'b1),
            .addr_a(spec_addr),
            .q_a(spec_q),
            .rd_en_b(1'b0),
            .addr_b({ROM12_ADDR{1'b0}}),
            .q_b(spec_unused_b)
        );
    end else begin : g_no_rom12
        assign spec_q = {ROM_DATA_BITS{1'b0}};
        assign spec_unused_b = {ROM_DATA_BITS{1'b0}};
    end
    if (DIFFUSE != 0) begin : g_rom12_diffuse
        shading_rom #(
            .WIDTH(ROM_DATA_BITS),
            .DEPTH(1 << ROM_ADDR_BITS),
            .IMAGE_DEPTH(1 << ROM12_ADDR),
            .ADDR_BITS(ROM_ADDR_BITS),
            .PORTS(1),
            .READ_REGS(2),
            .FILE(COS_ROM_FILE),
            .NAME("COS_ROM_FILE"),
            .MAGIC("SR12"),
            .NUM_FIELDS(7),
            .FIELD_0(ROM_ADDR_BITS), .FIELD_1(ROM_DATA_BITS), .FIELD_2(NUM_TABLES),
            .FIELD_3(K0), .FIELD_4(K1), .FIELD_5(K2), .FIELD_6(K3),
            .FIELD_NAMES({"ROM_ADDR_BITS   ", "ROM_DATA_BITS   ", "NUM_TABLES      ",
                          "K0              ", "K1              ", "K2              ",
                          "K3              ", {(8*16*5){1'b0}}})
        ) u_rom12_diffuse (
            .clk(clk),
            .rd_en_a(1'b1),
            .addr_a(diff_addr[ROM_ADDR_BITS-1:0]),
            .q_a(diff_q),
            .rd_en_b(1'b0),
            .addr_b({ROM_ADDR_BITS{1'b0}}),
            .q_b(diff_unused_b)
        );
    end else begin : g_no_rom12_diffuse
        assign diff_q = {ROM_DATA_BITS{1'b0}};
        assign diff_unused_b = {ROM_DATA_BITS{1'b0}};
    end

    if (SPECULAR != 0 && IS_SPEC) begin : g_highlight
        shading_specular_pipe #(
            .CHANNELS(1),
            .ACC_WIDTH(ACC_WIDTH),
            .Z_FRAC_BITS(Z_FRAC_BITS),
            .MAG_INT_BITS(MAG_INT_BITS),
            .A_WIDTH(AW),
            .A_FRAC_BITS(A_FRAC_BITS),
            .TSEL_BITS(TSEL_BITS),
            .ROM_ADDR_BITS(ROM_ADDR_BITS),
            .ROM_DATA_BITS(ROM_DATA_BITS),
            .C_WIDTH(C_WIDTH),
            .C_FRAC_BITS(C_FRAC_BITS),
            .OUT_WIDTH(OUT_WIDTH)
        ) u_highlight (
            .clk(clk),
            .acc_in(zacc_reg),
            .a_in(hw_reg[AW-1:0]),
            .tsel_in(hw_reg[HW_WIDTH-1:AW]),
            .zero_in(szero_reg),
            .c_in(c_reg),
            .rom_addr(spec_addr),
            .rom_q(spec_q),
            .intensity(spec_int)
        );
    end else if (SPECULAR != 0 && IS_BRDF) begin : g_brdf_highlight
        shading_brdf_pipe #(
            .FORM(HIGHLIGHT),
            .ACC_WIDTH(ACC_WIDTH),
            .Z_FRAC_BITS(Z_FRAC_BITS),
            .COS_ADDR_BITS(COS_ADDR_BITS),
            .COS_DATA_BITS(COS_DATA_BITS),
            .COEF_BITS(COEF_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .LOG_ADDR_BITS(LOG_ADDR_BITS),
            .LOG_DATA_BITS(LOG_DATA_BITS),
            .ANGLE_ROM_FILE(ANGLE_ROM_FILE),
            .LOG_ROM_FILE(LOG_ROM_FILE),
            .C_WIDTH(C_WIDTH),
            .C_FRAC_BITS(C_FRAC_BITS),
            .OUT_WIDTH(OUT_WIDTH),
            .K_WIDTH(BRDF_K_WIDTH),
            .STAGES(STAGES)
        ) u_highlight (
            .clk(clk),
            .acc_in(zacc_reg),
            .k_in(hw_reg),
            .zero_in(szero_reg),
            .c_in(c_reg),
            .intensity(spec_int)
        );
        assign spec_addr = {ROM12_ADDR{1'b0}};
    end else begin : g_no_highlight
        assign spec_int = {OUT_WIDTH{1'b0}};
        assign spec_addr = {ROM12_ADDR{1'b0}};
    end

    if (DIFFUSE != 0) begin : g_diffuse
        shading_specular_pipe #(
            .CHANNELS(CH),
            .ACC_WIDTH(ACC_WIDTH),
            .Z_FRAC_BITS(Z_FRAC_BITS),
            .MAG_INT_BITS(MAG_INT_BITS),
            .A_WIDTH(AW),
            .A_FRAC_BITS(A_FRAC_BITS),
            .TSEL_BITS(TSEL_BITS),
            .ROM_ADDR_BITS(ROM_ADDR_BITS),
            .ROM_DATA_BITS(ROM_DATA_BITS),
            .C_WIDTH(C_WIDTH),
            .C_FRAC_BITS(C_FRAC_BITS),
            .OUT_WIDTH(OUT_WIDTH),
            .A_ONE(DIFF_A_ONE ? 1 : 0)
        ) u_diffuse (
            .clk(clk),
            .acc_in(dacc_reg),
            .a_in(a_diff_q),
            .tsel_in({TSEL_BITS{1'b0}}),  // n = 1 is in the first k range: table 0
            .zero_in(dzero_reg),
            .c_in(dc_reg),
            .rom_addr(diff_addr),
            .rom_q(diff_q),
            .intensity(diff_int)
        );
    end else begin : g_no_diffuse
        assign diff_int = {(CH*OUT_WIDTH){1'b0}};
        assign diff_addr = {ROM12_ADDR{1'b0}};
    end

    // The diffuse terms, made in 10 stages, wait for a longer highlight path
    if (DIFFUSE != 0 && STAGES > SPEC_STAGES + 1) begin : g_diffuse_wait
        localparam DW = STAGES - SPEC_STAGES;
        reg [DW*CH*OUT_WIDTH-1:0] dwait_reg;
        always @(posedge clk) begin
            dwait_reg <= {dwait_reg[0 +: (DW-1)*CH*OUT_WIDTH], diff_int};
        end
        assign diff_out = dwait_reg[(DW-1)*CH*OUT_WIDTH +: CH*OUT_WIDTH];
    end else if (DIFFUSE != 0 && STAGES == SPEC_STAGES + 1) begin : g_diffuse_wait_one
        reg [CH*OUT_WIDTH-1:0] dwait_reg;
        always @(posedge clk) begin
            dwait_reg <= diff_int;
        end
        assign diff_out = dwait_reg;
    end else begin : g_diffuse_now
        assign diff_out = diff_int;
    end
endgenerate

// ---------------------------------------------------------------- the sum, the output FIFO
// Gouraud + highlight + diffuse, wide enough for the three and at least 9 bits (the
// comparison with 255 and the 8-bit select read real bits at every width)
localparam SUM_RAW = ((I_INT > OUT_WIDTH) ? I_INT : OUT_WIDTH) + 2;
localparam SUM_WIDTH = (SUM_RAW > 9) ? SUM_RAW : 9;
wire [SIDE-1:0]   side_out = side_reg[(STAGES-1)*SIDE +: SIDE];
wire [3*8-1:0]    rgb;
generate
    for (g = 0; g < CH; g = g + 1) begin : g_sum
        wire [SUM_WIDTH-1:0] total = {{(SUM_WIDTH-I_INT){1'b0}},
                                      side_out[X_WIDTH + Y_WIDTH + g*I_INT +: I_INT]}
                                   + {{(SUM_WIDTH-OUT_WIDTH){1'b0}}, spec_int}
                                   + {{(SUM_WIDTH-OUT_WIDTH){1'b0}},
                                      diff_out[g*OUT_WIDTH +: OUT_WIDTH]};
        assign rgb[g*8 +: 8] = (total > 255) ? 8'd255 : total[7:0];
    end
endgenerate

wire [PIX_WIDTH-1:0] pix_data;
generate
    if (PIX_WIDTH > PIX_BITS) begin : g_pad
        assign pix_data = {{(PIX_WIDTH-PIX_BITS){1'b0}}, rgb, side_out[X_WIDTH+Y_WIDTH-1:0]};
    end else begin : g_nopad
        assign pix_data = {rgb, side_out[X_WIDTH+Y_WIDTH-1:0]};
    end
endgenerate

// The FIFO always has room for a pixel in S10 (the credit count), so its s_axis_tready is
// not needed
// verilator lint_off UNUSEDSIGNAL
wire fifo_ready;
// verilator lint_on UNUSEDSIGNAL
shading_axis_fifo #(
    .DATA_WIDTH(PIX_WIDTH),
    .USER_WIDTH(1),
    .DEPTH(FIFO_DEPTH)
) u_fifo (
    .clk(clk),
    .rst_n(rst_n),
    .s_axis_tdata(pix_data),
    .s_axis_tlast(side_out[SIDE-2]),
    .s_axis_tuser(side_out[SIDE-1]),
    .s_axis_tvalid(v_reg[STAGES]),
    .s_axis_tready(fifo_ready),
    .m_axis_tdata(m_axis_tdata),
    .m_axis_tlast(m_axis_tlast),
    .m_axis_tuser(m_axis_tuser),
    .m_axis_tvalid(m_axis_tvalid),
    .m_axis_tready(m_axis_tready)
);

// Span-beat bits past the fields, and what a path this core was built without leaves unread
// verilator lint_off UNUSEDSIGNAL
wire unused_in = &{1'b0, s_axis_tdata, a_diff_q, dec_index, n_off, diff_addr, a_addr, c_reg,
                   hw_reg, szero_reg, dzero_reg, dc_reg, spec_addr, spec_q, diff_q, a_q, k_q,
                   tsela_reg};
// verilator lint_on UNUSEDSIGNAL

endmodule

`resetall
