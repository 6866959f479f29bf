// SPDX-License-Identifier: Apache-2.0
/*
 * A pipelined multiplier for the BRDF unit's wide products: p = a * b, exact, two clock edges
 * after a and b; both operands unsigned (SIGNED = 0) or both two's complement (SIGNED = 1, the
 * cubic's products of its signed tau).  Stage 1: the four partial products of the operands' halves
 * (a = ah 2^AL + al, b = bh 2^BL + bl; al bl, al bh, ah bl, ah bh), each registered: each is
 * at most 13 x 13 bits for 25-bit operands, one multiplier block of an FPGA (18 x 18 on the
 * ECP5, 16 x 16 on the UP5K) with nothing after it in that clock.  Stage 2: their sum,
 * registered.  A product of two 25-bit words in one stage spans several blocks and the adder
 * that joins them, and misses 100 MHz on the ECP5 (docs/brdf_unit.md, "Resources").
 * SIGNED = 1: the high halves ah and bh are two's complement, the low halves unsigned, so the
 * partial products al bh and ah bl are signed (al and bl get a 0 above them: one more bit, 14 x
 * 13 for 25-bit operands) and ah bh is; each is sign-extended to the product's width and the sum
 * taken modulo 2^(A_WIDTH + B_WIDTH), which holds the exact signed product.
 * SPLIT_A = 0 (unsigned only): a is not split, only b: two partial products a bl and a bh, two
 * blocks where an unsigned a of at most 18 bits is one block's operand (ECP5, Gowin: the
 * piecewise form's beta x (r w - 1), 18 x 18 and 18 x 17 at its default widths, two blocks
 * instead of four).
 *
 * Reset: none of these registers is control state; RESET_ALL = 1 resets them all (rst_n is
 * synchronous, active low).
 *
 * Checks: an operand narrower than 2 bits (no halves) is refused at elaboration, by an instance
 * of the module brdf_mul_PARAMETER_ERROR_A_WIDTH_and_B_WIDTH_must_be_at_least_2, which does
 * not exist; so is a SIGNED other than 0 or 1 (brdf_mul_PARAMETER_ERROR_SIGNED_must_be_0_or_1),
 * a SPLIT_A other than 0 or 1 (brdf_mul_PARAMETER_ERROR_SPLIT_A_must_be_0_or_1) and SPLIT_A = 0
 * with SIGNED = 1 (brdf_mul_PARAMETER_ERROR_SPLIT_A_0_needs_SIGNED_0).
 *
 * Sources: this file; instantiated by rtl/brdf_cosine_quadratic.v, rtl/brdf_quadratic.v,
 * rtl/brdf_cubic.v and rtl/brdf_piecewise.v (rtl/brdf_unit.f).  Documentation: docs/brdf_unit.md.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module brdf_mul #(
    // Bits of the operand a
    parameter A_WIDTH = 25,
    // Bits of the operand b
    parameter B_WIDTH = 25,
    // 0: a, b and p unsigned; 1: all three two's complement
    parameter SIGNED = 0,
    // 1: a in halves as b is (four partial products); 0: a whole (two; SIGNED = 0 only)
    parameter SPLIT_A = 1,
    // 0: no register here is reset; 1: rst_n resets every one
    parameter RESET_ALL = 0
) (
    input  wire                       clk,
    input  wire                       rst_n,
    input  wire [A_WIDTH-1:0]         a,
    input  wire [B_WIDTH-1:0]         b,
    output wire [A_WIDTH+B_WIDTH-1:0] p
);

localparam AL = (A_WIDTH + 1) / 2;
localparam AH = A_WIDTH - AL;
localparam BL = (B_WIDTH + 1) / 2;
localparam BH = B_WIDTH - BL;
localparam W = A_WIDTH + B_WIDTH;

generate
    if (A_WIDTH < 2 || B_WIDTH < 2) begin : g_check_width
        brdf_mul_PARAMETER_ERROR_A_WIDTH_and_B_WIDTH_must_be_at_least_2 u_error ();
    end
endgenerate

generate
    if (SIGNED != 0 && SIGNED != 1) begin : g_check_signed
        brdf_mul_PARAMETER_ERROR_SIGNED_must_be_0_or_1 u_error ();
    end
    if (SPLIT_A != 0 && SPLIT_A != 1) begin : g_check_split_a
        brdf_mul_PARAMETER_ERROR_SPLIT_A_must_be_0_or_1 u_error ();
    end
    if (SPLIT_A == 0 && SIGNED == 1) begin : g_check_split_signed
        brdf_mul_PARAMETER_ERROR_SPLIT_A_0_needs_SIGNED_0 u_error ();
    end
endgenerate

reg [W-1:0] p_reg;

assign p = p_reg;

generate
    if (SIGNED == 1) begin : g_signed
        // Stage 1: al bl unsigned; al bh, ah bl, ah bh signed (an unsigned half gets a 0 on top)
        reg        [AL+BL-1:0] ll_reg;
        reg signed [AL+BH:0]   lh_reg;
        reg signed [AH+BL:0]   hl_reg;
        reg signed [AH+BH-1:0] hh_reg;
        // Stage 2: each sign-extended to W bits and aligned; the sum modulo 2^W is the product
        wire [W-1:0] ll_w = {{(W-AL-BL){1'b0}}, ll_reg};
        wire [W-1:0] lh_w = {{(W-AL-BH-1){lh_reg[AL+BH]}}, lh_reg} << BL;
        wire [W-1:0] hl_w = {{(W-AH-BL-1){hl_reg[AH+BL]}}, hl_reg} << AL;
        wire [W-1:0] hh_w = {{(W-AH-BH){hh_reg[AH+BH-1]}}, hh_reg} << (AL + BL);

        always @(posedge clk) begin
            ll_reg <= a[AL-1:0] * b[BL-1:0];
            lh_reg <= $signed({1'b0, a[AL-1:0]}) * $signed(b[B_WIDTH-1:BL]);
            hl_reg <= $signed(a[A_WIDTH-1:AL]) * $signed({1'b0, b[BL-1:0]});
            hh_reg <= $signed(a[A_WIDTH-1:AL]) * $signed(b[B_WIDTH-1:BL]);
            p_reg <= ll_w + lh_w + hl_w + hh_w;

            if (RESET_ALL != 0 && !rst_n) begin
                ll_reg <= {(AL+BL){1'b0}};
                lh_reg <= {(AL+BH+1){1'b0}};
                hl_reg <= {(AH+BL+1){1'b0}};
                hh_reg <= {(AH+BH){1'b0}};
                p_reg <= {W{1'b0}};
            end
        end
    end else if (SPLIT_A == 0) begin : g_unsigned_a_whole
        // Stage 1: a bl and a bh; stage 2: their sum (each fits W bits: the exact product)
        reg [A_WIDTH+BL-1:0] l_reg;
        reg [A_WIDTH+BH-1:0] h_reg;
        wire [W-1:0] l_w = {{BH{1'b0}}, l_reg};
        wire [W-1:0] h_w = {{BL{1'b0}}, h_reg} << BL;

        always @(posedge clk) begin
            l_reg <= a * b[BL-1:0];
            h_reg <= a * b[B_WIDTH-1:BL];
            p_reg <= l_w + h_w;

            if (RESET_ALL != 0 && !rst_n) begin
                l_reg <= {(A_WIDTH+BL){1'b0}};
                h_reg <= {(A_WIDTH+BH){1'b0}};
                p_reg <= {W{1'b0}};
            end
        end
    end else begin : g_unsigned
        reg [AL+BL-1:0] ll_reg;
        reg [AL+BH-1:0] lh_reg;
        reg [AH+BL-1:0] hl_reg;
        reg [AH+BH-1:0] hh_reg;

        // Stage 2: the partial products aligned (each fits W bits: the sum is the exact product)
        wire [W-1:0] ll_w = {{(W-AL-BL){1'b0}}, ll_reg};
        wire [W-1:0] lh_w = {{(W-AL-BH){1'b0}}, lh_reg} << BL;
        wire [W-1:0] hl_w = {{(W-AH-BL){1'b0}}, hl_reg} << AL;
        wire [W-1:0] hh_w = {{(W-AH-BH){1'b0}}, hh_reg} << (AL + BL);

        always @(posedge clk) begin
            ll_reg <= a[AL-1:0] * b[BL-1:0];
            lh_reg <= a[AL-1:0] * b[B_WIDTH-1:BL];
            hl_reg <= a[A_WIDTH-1:AL] * b[BL-1:0];
            hh_reg <= a[A_WIDTH-1:AL] * b[B_WIDTH-1:BL];
            p_reg <= ll_w + lh_w + hl_w + hh_w;

            if (RESET_ALL != 0 && !rst_n) begin
                ll_reg <= {(AL+BL){1'b0}};
                lh_reg <= {(AL+BH){1'b0}};
                hl_reg <= {(AH+BL){1'b0}};
                hh_reg <= {(AH+BH){1'b0}};
                p_reg <= {W{1'b0}};
            end
        end
    end
endgenerate

endmodule

`resetall
