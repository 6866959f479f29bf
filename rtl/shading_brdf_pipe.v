// SPDX-License-Identifier: Apache-2.0
/*
 * A BRDF unit's per-pixel datapath (rtl/brdf_unit.v from its accumulator on) as a stream: a
 * new pixel every clock, each with its own form word k, zero flag and C, so that the pixels of
 * successive spans follow each other with no gap: the shading core's highlight path when its
 * HIGHLIGHT is a BRDF form.  Every result equals the pixel's value in
 * model.units.brdf.unit_line for the pixel's accumulator value (0 with zero_in).
 *
 * Pipeline: the caller's accumulator register is S0 (acc_in, with k_in, zero_in and c_in of
 * the same pixel); S1..S5 the BRDF family's front (rtl/brdf_front.v, the unit's own: |zeta|
 * in two steps, the angle-table address, the table's read, the w gate); then the form's
 * datapath (rtl/brdf_<form>.v, unchanged: FORM_LATENCY stages, 5 for the cosine-quadratic, 6
 * for the quadratic, 7 for the log2, 13 for the cubic, max(14, OUT_BITS + 8) for the piecewise
 * form; the log2 form's second table read in its pipeline, READ_REGS = 2, as in the unit);
 * then F gated to 0 for zero_in (a multiplexer,
 * as the unit gates an n outside 1..1000), x C (registered), rounding and saturation
 * (registered): intensity holds the pixel that was in S0 STAGES = 7 + FORM_LATENCY clocks
 * before.
 *
 * k per pixel: the form's datapath reads k as its running line's constant, at the stages where
 * it needs each part of it.  Here the word travels with its pixel in a shift register beside
 * the stages, and each part is taken from the stage that puts it beside its own pixel: the
 * whole word with w (S5) for the cosine-quadratic's 7n, the quadratic's a and the log2's n;
 * for the cubic (rtl/brdf_cubic.v) r with w, b2 four clocks later (its b2 x tau), b1 five (its
 * b1 rounded, then + b2 tau) and p0 eight (its p0 rounded, then + tau h); for the piecewise
 * form (rtl/brdf_piecewise.v) the cubic's four where its cubic instance reads them, beta two
 * clocks after w (its register beside the multiplier beta x (r w - 1)) and s2 four (s2
 * rounded, then + that product).  A part taken at the wrong stage mixes the coefficients of
 * neighbouring spans of different n (the stream bench's back-to-back spans show it).  zero_in
 * and C wait likewise for F.
 *
 * The data path has no reset (it is loaded from S0 every clock; the caller's valid flags say
 * which results are pixels); the tables' read registers map onto block RAM.  The angle table
 * and the log2 table are instances of rtl/shading_rom.v, which check their images at time 0.
 *
 * Checks: K_WIDTH and STAGES are derived (another value is refused at elaboration by a module
 * named after the rule, which does not exist: shading_brdf_pipe_PARAMETER_ERROR_<rule>); the
 * BRDF unit's own rules are the core's (its rules instance of rtl/brdf_unit.v).
 *
 * Sources: this file, rtl/brdf_front.v, rtl/brdf_cosine_quadratic.v, rtl/brdf_quadratic.v,
 * rtl/brdf_cubic.v, rtl/brdf_log2.v, rtl/brdf_piecewise.v, rtl/brdf_div.v, rtl/brdf_delay.v,
 * rtl/brdf_mul.v, rtl/brdf_round.v, rtl/shading_rom.v;
 * instantiated by rtl/shading_core.v (rtl/shading_core.f).  Documentation: docs/core.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module shading_brdf_pipe #(
    // The form: "cosine_quadratic", "quadratic", "cubic", "log2" or "piecewise"
    parameter [8*16-1:0] FORM = "cosine_quadratic",
    // Accumulator bits (signed, units of pi/2 with Z_FRAC_BITS fraction bits)
    parameter ACC_WIDTH = 40,
    // Accumulator fraction bits
    parameter Z_FRAC_BITS = 26,
    // Angle-table address bits A
    parameter COS_ADDR_BITS = 12,
    // Angle-table word bits D
    parameter COS_DATA_BITS = 20,
    // Coefficient word bits (the quadratic's a; each of the cubic's four, the piecewise's six)
    parameter COEF_BITS = 18,
    // Fraction bits P of the form's intermediate values
    parameter WORK_BITS = 24,
    // Fraction bits O of the form's output word F
    parameter OUT_BITS = 16,
    // The log2 form's second table: address bits E
    parameter LOG_ADDR_BITS = 10,
    // The log2 form's second table: word bits L
    parameter LOG_DATA_BITS = 16,
    // $readmemh image of the angle table (w = 1 - cos; the log2 form: -log2 cos)
    parameter ANGLE_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_w_a12_d20.hex"},
    // $readmemh image of the log2 form's second table (log2(1 + f))
    parameter LOG_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_log2_a10_d16.hex"},
    // C bits (unsigned)
    parameter C_WIDTH = 16,
    // C fraction bits
    parameter C_FRAC_BITS = 8,
    // Output intensity bits
    parameter OUT_WIDTH = 8,
    // k bits (derived: 13, COEF_BITS, 4 COEF_BITS, 10 or 6 COEF_BITS by the form; another
    // value is refused)
    parameter K_WIDTH = (FORM == "quadratic") ? COEF_BITS : (FORM == "cubic") ? 4 * COEF_BITS
                        : (FORM == "log2") ? 10 : (FORM == "piecewise") ? 6 * COEF_BITS : 13,
    // Clocks from S0 to intensity (derived: 7 + the form's stages; another value is refused)
    parameter STAGES = 7 + ((FORM == "quadratic") ? 6 : (FORM == "cubic") ? 13
                            : (FORM == "log2") ? 7
                            : (FORM == "piecewise") ? ((OUT_BITS + 8 > 14) ? OUT_BITS + 8 : 14)
                            : 5)
) (
    input  wire                 clk,
    input  wire [ACC_WIDTH-1:0] acc_in,
    input  wire [K_WIDTH-1:0]   k_in,
    input  wire                 zero_in,
    input  wire [C_WIDTH-1:0]   c_in,
    output wire [OUT_WIDTH-1:0] intensity
);

localparam [8*16-1:0] FORM_COSINE_QUADRATIC = "cosine_quadratic";
localparam [8*16-1:0] FORM_QUADRATIC = "quadratic";
localparam [8*16-1:0] FORM_CUBIC = "cubic";
localparam [8*16-1:0] FORM_LOG2 = "log2";
localparam [8*16-1:0] FORM_PIECEWISE = "piecewise";
localparam IS_COSINE_QUADRATIC = (FORM == FORM_COSINE_QUADRATIC);
localparam IS_QUADRATIC = (FORM == FORM_QUADRATIC);
localparam IS_CUBIC = (FORM == FORM_CUBIC);
localparam IS_LOG2 = (FORM == FORM_LOG2);
localparam IS_PIECEWISE = (FORM == FORM_PIECEWISE);
localparam K_DERIVED = IS_QUADRATIC ? COEF_BITS : IS_CUBIC ? 4 * COEF_BITS : IS_LOG2 ? 10
                       : IS_PIECEWISE ? 6 * COEF_BITS : 13;
// The form's pipeline stages (model.units.brdf.form_latency: the piecewise form's divider takes
// one stage per quotient bit, rtl/brdf_piecewise.v)
localparam PIECEWISE_LATENCY = (OUT_BITS + 8 > 14) ? OUT_BITS + 8 : 14;
localparam FORM_LATENCY = IS_QUADRATIC ? 6 : IS_CUBIC ? 13 : IS_LOG2 ? 7
                          : IS_PIECEWISE ? PIECEWISE_LATENCY : 5;
// The front's stages S1..S5: w is the word of the pixel that was in S0 five clocks before
localparam FRONT = 5;
// The form's output word F is the word of the pixel in stage Y of this pipe
localparam Y = FRONT + FORM_LATENCY;
// The cubic's coefficients, taken this many clocks after its pixel's w (rtl/brdf_cubic.v; the
// piecewise form's cubic instance reads them so too)
localparam CUBIC_B2_AT = 4;
localparam CUBIC_B1_AT = 5;
localparam CUBIC_P0_AT = 8;
// The piecewise form's own two (rtl/brdf_piecewise.v): beta into beta_reg, read by the
// multiplier beta x (r w - 1) at the next edge; s2 rounded into s2r_reg, read by den's adder
localparam PIECEWISE_BETA_AT = 2;
localparam PIECEWISE_S2_AT = 4;
// The stages the k shift register reaches (S1 .. S(KD))
localparam KD = FRONT + ((IS_CUBIC || IS_PIECEWISE) ? CUBIC_P0_AT : 0);
localparam QUADRATIC_A_INT_BITS = 10;
localparam OP_WIDTH = C_WIDTH + OUT_BITS;
localparam OSHIFT = C_FRAC_BITS + OUT_BITS;
localparam OFULL_WIDTH = OP_WIDTH - OSHIFT + 1;

generate
    if (!IS_COSINE_QUADRATIC && !IS_QUADRATIC && !IS_CUBIC && !IS_LOG2 && !IS_PIECEWISE)
    begin : g_check_form
        shading_brdf_pipe_PARAMETER_ERROR_FORM_must_be_a_form_of_the_family u_error ();
    end
    if (K_WIDTH != K_DERIVED) begin : g_check_k_width
        shading_brdf_pipe_PARAMETER_ERROR_K_WIDTH_must_be_the_form_s_word_bits u_error ();
    end
    if (STAGES != 7 + FORM_LATENCY) begin : g_check_stages
        shading_brdf_pipe_PARAMETER_ERROR_STAGES_must_be_7_plus_the_form_s_stages u_error ();
    end
endgenerate

// ---------------------------------------------------------------- S1..S5: the front
wire [COS_DATA_BITS:0] w;

brdf_front #(
    .ACC_WIDTH(ACC_WIDTH),
    .Z_FRAC_BITS(Z_FRAC_BITS),
    .COS_ADDR_BITS(COS_ADDR_BITS),
    .COS_DATA_BITS(COS_DATA_BITS),
    .TABLE(IS_LOG2 ? 1 : 0),
    .ANGLE_ROM_FILE(ANGLE_ROM_FILE),
    .RESET_ALL(0)
) u_front (
    .clk(clk),
    .rst_n(1'b1),
    .acc(acc_in),
    .w(w)
);

// ---------------------------------------------------------------- the pixels' side data
// Shift registers, stage s in slice s - 1 (S1 in the low bits): k to S(KD), zero_in and C
// to S(Y), where F of their pixel is
reg [KD*K_WIDTH-1:0] k_reg;
reg [Y-1:0]          zero_reg;
reg [Y*C_WIDTH-1:0]  c_reg;

always @(posedge clk) begin
    k_reg <= {k_reg[0 +: (KD-1)*K_WIDTH], k_in};
    zero_reg <= {zero_reg[Y-2:0], zero_in};
    c_reg <= {c_reg[0 +: (Y-1)*C_WIDTH], c_in};
end

// The word of the pixel in stage s
`define SHADING_BRDF_K_AT(s) k_reg[((s)-1)*K_WIDTH +: K_WIDTH]

// What the form reads of k in this clock
wire [K_WIDTH-1:0] form_k;

generate
    if (IS_CUBIC) begin : g_cubic_k
        // {r, p0, b1, b2}, each COEF_BITS: r of the pixel whose w enters, b2 of the pixel
        // four clocks into the form, b1 five, p0 eight
        localparam C = COEF_BITS;
        wire [K_WIDTH-1:0] k_r = `SHADING_BRDF_K_AT(FRONT);
        wire [K_WIDTH-1:0] k_b2 = `SHADING_BRDF_K_AT(FRONT + CUBIC_B2_AT);
        wire [K_WIDTH-1:0] k_b1 = `SHADING_BRDF_K_AT(FRONT + CUBIC_B1_AT);
        wire [K_WIDTH-1:0] k_p0 = `SHADING_BRDF_K_AT(FRONT + CUBIC_P0_AT);
        assign form_k = {k_r[4*C-1:3*C], k_p0[3*C-1:2*C], k_b1[2*C-1:C], k_b2[C-1:0]};
        // The parts of each tap the form does not read there
        // verilator lint_off UNUSEDSIGNAL
        wire unused_k = &{1'b0, k_r[3*C-1:0], k_b2[4*C-1:C], k_b1[4*C-1:2*C], k_b1[C-1:0],
                          k_p0[4*C-1:3*C], k_p0[2*C-1:0]};
        // verilator lint_on UNUSEDSIGNAL
    end else if (IS_PIECEWISE) begin : g_piecewise_k
        // {r, p0, b1, b2, s2, beta}, each COEF_BITS: the cubic's four as the cubic takes them,
        // beta of the pixel two clocks into the form, s2 four
        localparam C = COEF_BITS;
        wire [K_WIDTH-1:0] k_r = `SHADING_BRDF_K_AT(FRONT);
        wire [K_WIDTH-1:0] k_beta = `SHADING_BRDF_K_AT(FRONT + PIECEWISE_BETA_AT);
        wire [K_WIDTH-1:0] k_b2 = `SHADING_BRDF_K_AT(FRONT + CUBIC_B2_AT);
        wire [K_WIDTH-1:0] k_s2 = `SHADING_BRDF_K_AT(FRONT + PIECEWISE_S2_AT);
        wire [K_WIDTH-1:0] k_b1 = `SHADING_BRDF_K_AT(FRONT + CUBIC_B1_AT);
        wire [K_WIDTH-1:0] k_p0 = `SHADING_BRDF_K_AT(FRONT + CUBIC_P0_AT);
        assign form_k = {k_r[6*C-1:5*C], k_p0[5*C-1:4*C], k_b1[4*C-1:3*C],
                         k_b2[3*C-1:2*C], k_s2[2*C-1:C], k_beta[C-1:0]};
        // The parts of each tap the form does not read there
        // verilator lint_off UNUSEDSIGNAL
        wire unused_k = &{1'b0, k_r[5*C-1:0], k_beta[6*C-1:C], k_b2[6*C-1:3*C], k_b2[2*C-1:0],
                          k_s2[6*C-1:2*C], k_s2[C-1:0], k_b1[6*C-1:4*C], k_b1[3*C-1:0],
                          k_p0[6*C-1:5*C], k_p0[4*C-1:0]};
        // verilator lint_on UNUSEDSIGNAL
    end else begin : g_k
        assign form_k = `SHADING_BRDF_K_AT(FRONT);
    end
endgenerate

`undef SHADING_BRDF_K_AT

// ---------------------------------------------------------------- the form
wire [OUT_BITS-1:0] form_y;

generate
    if (IS_QUADRATIC) begin : g_quadratic
        brdf_quadratic #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .COEF_BITS(COEF_BITS),
            .COEF_FRAC_BITS(COEF_BITS - QUADRATIC_A_INT_BITS),
            .RESET_ALL(0)
        ) u_form (
            .clk(clk),
            .rst_n(1'b1),
            .w(w),
            .k(form_k),
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
            .RESET_ALL(0)
        ) u_form (
            .clk(clk),
            .rst_n(1'b1),
            .w(w),
            .k(form_k),
            .y(form_y),
            .rw_prod(rw_unused)
        );
    end else if (IS_PIECEWISE) begin : g_piecewise
        brdf_piecewise #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .COEF_BITS(COEF_BITS),
            .RESET_ALL(0)
        ) u_form (
            .clk(clk),
            .rst_n(1'b1),
            .w(w),
            .k(form_k),
            .y(form_y)
        );
    end else if (IS_LOG2) begin : g_log2
        // The datapath and its second table, log2(1 + f), read in the form's third stage and
        // registered twice (READ_REGS = 2), as in rtl/brdf_unit.v
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
            .RESET_ALL(0)
        ) u_form (
            .clk(clk),
            .rst_n(1'b1),
            .w(w),
            .k(form_k),
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
    end else begin : g_cosine_quadratic
        brdf_cosine_quadratic #(
            .COS_DATA_BITS(COS_DATA_BITS),
            .WORK_BITS(WORK_BITS),
            .OUT_BITS(OUT_BITS),
            .RESET_ALL(0)
        ) u_form (
            .clk(clk),
            .rst_n(1'b1),
            .w(w),
            .k(form_k),
            .y(form_y)
        );
    end
endgenerate

// ---------------------------------------------------------------- x C, rounding, saturation
reg [OP_WIDTH-1:0]  out_prod_reg;
reg [OUT_WIDTH-1:0] intensity_reg;

// S(Y): F, or 0 for a pixel with zero_in (a multiplexer, not a multiply by 0)
wire [OUT_BITS-1:0]  form_gated = zero_reg[Y-1] ? {OUT_BITS{1'b0}} : form_y;
wire [C_WIDTH-1:0]   c_y = c_reg[(Y-1)*C_WIDTH +: C_WIDTH];
// S(Y + 1) -> S(Y + 2): C x F rounded to OUT_WIDTH bits (add half, slice), saturated
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

always @(posedge clk) begin
    out_prod_reg <= c_y * form_gated;
    intensity_reg <= out_sat;
end

assign intensity = intensity_reg;

// Bits the output rounding drops on purpose (below the output LSB)
// verilator lint_off UNUSEDSIGNAL
wire unused_rnd = &{1'b0, out_rnd[OSHIFT-1:0]};
// verilator lint_on UNUSEDSIGNAL

endmodule

`resetall
