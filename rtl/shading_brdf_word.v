// SPDX-License-Identifier: Apache-2.0
/*
 * What a BRDF form reads of n, read per span at the shading core's span intake (stage A, as
 * the core reads the specular unit's ROM 9): the cosine-quadratic's 7n (8n - n, 13 bits), the
 * quadratic's coefficient a (the coefficient table's word of n, COEF_BITS), the cubic's four
 * coefficients {r, p0, b1, b2} (4 COEF_BITS: the table's two words of n, {r, p0} at 2 (n - 1)
 * and {b1, b2} at 2 (n - 1) + 1, read in the same clock by the ROM's two ports), the piecewise
 * form's six {r, p0, b1, b2, s2, beta} (6 COEF_BITS: {r, p0, b1} at 2 (n - 1) and {b2, s2,
 * beta} at 2 (n - 1) + 1, likewise) or the log2 form's n itself (10 bits): the word
 * rtl/brdf_unit.v takes into its register 4 when n is written
 * (model.units.brdf.coefficient_words), for the form's datapath rtl/brdf_<form>.v.
 *
 * Timing: k is the word of the n on the input at the last rising edge with en = 1 (the
 * tables' synchronous read and the registers of 7n and n alike).  An n outside 1..1000 reads
 * the table at address 0 (its word is defined; the core gates that span's highlight to 0), and
 * 7n or n of any 10-bit n.
 *
 * The tables are instances of the ROM module (rtl/shading_rom.v), with the BRDF unit's image
 * checks (magic "BRDC", "BRD3" or "BRDP", FORM as its index in model.units.brdf.FORMS,
 * COEF_BITS and the coefficients' fraction bits): a bad image ends the simulation at time 0
 * naming the file and the field.  Their read registers are not reset (block RAM); the registers of 7n and n
 * need no reset either: the core reads k only with a span that wrote it.
 *
 * Checks: K_WIDTH is derived (another value, or a form without a word here, is refused at
 * elaboration by a module named after the rule, which does not exist:
 * shading_brdf_word_PARAMETER_ERROR_<rule>).
 *
 * Sources: this file and rtl/shading_rom.v; instantiated by rtl/shading_core.v
 * (rtl/shading_core.f).  Documentation: docs/core.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

`ifndef SHADING_ROM_DIR
`define SHADING_ROM_DIR "rom"
`endif

module shading_brdf_word #(
    // The form: "cosine_quadratic", "quadratic", "cubic", "log2" or "piecewise"
    parameter [8*16-1:0] FORM = "cosine_quadratic",
    // Coefficient word bits (the quadratic's a; each of the cubic's four, the piecewise form's six)
    parameter COEF_BITS = 18,
    // $readmemh image of the coefficient table (quadratic, cubic and piecewise forms), by
    // model.units.brdf
    parameter COEF_ROM_FILE = {`SHADING_ROM_DIR, "/brdf_quadratic_coef_c18_q10.8.hex"},
    // k bits (derived: 13, COEF_BITS, 4 COEF_BITS, 10 or 6 COEF_BITS by the form; another value
    // is refused)
    parameter K_WIDTH = (FORM == "quadratic") ? COEF_BITS : (FORM == "cubic") ? 4 * COEF_BITS
                        : (FORM == "log2") ? 10 : (FORM == "piecewise") ? 6 * COEF_BITS : 13
) (
    input  wire               clk,
    input  wire               en,
    input  wire [9:0]         n,
    output wire [K_WIDTH-1:0] k
);

localparam N_WIDTH = 10;
localparam [N_WIDTH-1:0] N_MAX = 10'd1000;
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
localparam K_DERIVED = IS_QUADRATIC ? COEF_BITS : IS_CUBIC ? 4 * COEF_BITS : IS_LOG2 ? N_WIDTH
                       : IS_PIECEWISE ? 6 * COEF_BITS : 13;
// The quadratic's a and the cubic's (and the piecewise form's) r: their integer bits
// (model.units.brdf QUADRATIC_A_INT_BITS, CUBIC_R_INT_BITS; the images' fraction-bit fields
// carry the model's)
localparam QUADRATIC_A_INT_BITS = 10;
localparam CUBIC_R_INT_BITS = 11;

generate
    if (!IS_COSINE_QUADRATIC && !IS_QUADRATIC && !IS_CUBIC && !IS_LOG2 && !IS_PIECEWISE)
    begin : g_check_form
        shading_brdf_word_PARAMETER_ERROR_FORM_must_be_a_form_of_the_family u_error ();
    end
    if (K_WIDTH != K_DERIVED) begin : g_check_k_width
        shading_brdf_word_PARAMETER_ERROR_K_WIDTH_must_be_the_form_s_word_bits u_error ();
    end
endgenerate

// The table's address: n - 1 (0 for an n outside 1..1000)
wire n_ok = (n != {N_WIDTH{1'b0}}) && (n <= N_MAX);
wire [N_WIDTH-1:0] n_addr = n_ok ? n - {{(N_WIDTH-1){1'b0}}, 1'b1} : {N_WIDTH{1'b0}};

generate
    if (IS_QUADRATIC) begin : g_quadratic
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
            .rd_en_a(en),
            .addr_a(n_addr),
            .q_a(k),
            .rd_en_b(1'b0),
            .addr_b({N_WIDTH{1'b0}}),
            .q_b(coef_unused_b)
        );
    end else if (IS_CUBIC) begin : g_cubic
        // {r, p0} at 2 (n - 1) on port A, {b1, b2} at 2 (n - 1) + 1 on port B
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
            .rd_en_a(en),
            .addr_a({n_addr, 1'b0}),
            .q_a(coef_hi),
            .rd_en_b(en),
            .addr_b({n_addr, 1'b1}),
            .q_b(coef_lo)
        );
        assign k = {coef_hi, coef_lo};
    end else if (IS_PIECEWISE) begin : g_piecewise
        // {r, p0, b1} at 2 (n - 1) on port A, {b2, s2, beta} at 2 (n - 1) + 1 on port B
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
            .rd_en_a(en),
            .addr_a({n_addr, 1'b0}),
            .q_a(coef_hi),
            .rd_en_b(en),
            .addr_b({n_addr, 1'b1}),
            .q_b(coef_lo)
        );
        assign k = {coef_hi, coef_lo};
    end else if (IS_LOG2) begin : g_n
        // The log2 form's factor is n itself
        reg [N_WIDTH-1:0] k_reg;
        always @(posedge clk) begin
            if (en) begin
                k_reg <= n;
            end
        end
        assign k = k_reg;
    end else begin : g_seven_n
        // The cosine-quadratic's m = 7n/16: 7n = 8n - n (n up to 1023: 13 bits)
        reg [12:0] k_reg;
        always @(posedge clk) begin
            if (en) begin
                k_reg <= {n, 3'b000} - {3'b000, n};
            end
        end
        assign k = k_reg[K_WIDTH-1:0];
    end
endgenerate

// The address serves the tables only
// verilator lint_off UNUSEDSIGNAL
wire unused_addr = &{1'b0, n_addr};
// verilator lint_on UNUSEDSIGNAL

endmodule

`resetall
