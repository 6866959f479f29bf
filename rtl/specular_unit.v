// SPDX-License-Identifier: Apache-2.0
/*
 * Specular unit of patent UA 71489 (fig. 1): I = C * cos^k(a(n) * |zeta|) per pixel along a
 * scan line, zeta(0) = z0, zeta(i) = zeta(i-1) + dz, for the l + 1 pixels of a line of l
 * intervals.  k is chosen from n by the decoder (block 10), a(n) read from ROM 9, cos^k from
 * ROM 12 (one table per k).  Every result equals model.specular.unit_line() bit for bit.
 *
 * Formats (model/units/specular/, SpecularConfig; docs/specular.md):
 *   c_in   unsigned Q(C_INT_BITS).(C_FRAC_BITS), output LSBs
 *   dz_in, z0_in  signed Q(Z_INT_BITS).(Z_FRAC_BITS), units of pi/2
 *   n_in   10 bits, 1..1000 (the patent's 9-input decoder would alias every n >= 512), or
 *          the kept range N_FIRST..N_LAST; any other n gives intensity 0 and n_err = 1 on
 *          every pixel of the line
 *   len_in l, the number of intervals: l + 1 pixels (l = 0: one pixel)
 *   intensity  unsigned OUT_WIDTH bits, saturated
 *
 * Blocks: registers 1..4 (C, dz, z0, n), the interval counter (len register + down-counter),
 * accumulating adder 6 + multiplexer 7 + register 8 (ACC_WIDTH bits: z0 + l*dz never wraps),
 * decoder 10 (10 bits), ROM 9 (a for the kept n = N_FIRST..N_LAST at address n - N_FIRST,
 * read when n is written), multiplier 11 (|zeta| * a), ROM 12 (synchronous read), multiplier
 * 13 (C * cos^k) and the control unit.
 *
 * Pipeline (one pixel per clock, nine stages): S0 accumulator, S1 |zeta| without its carry
 * (sign, one's complement, "too big" flag), S2 |zeta| saturated to MAG_INT_BITS integer bits
 * (every clamped value already gives cos^k = 0), S3 multiplier 11, S4 address rounding, S5
 * overflow (>= pi/2 -> 0) and ROM-12 read, S6 the zero gate on the registered ROM word, S7
 * multiplier 13, S8 rounding + saturation -> output.  Both ROMs' outputs are registered (ROM 9
 * into rom9_q when n is written, ROM 12 into rom12_q and again into rom_d_reg), so no path
 * runs from a block RAM's output through logic.  After the edge that accepts start, busy is
 * high for 8 + l cycles and valid is high in cycles 8 .. 8 + l (the last one together with
 * busy = 0, when a new start is already accepted).
 *
 * Reset (RESET_ALL): rst_n always resets the control state, the flags and the operand
 * registers; RESET_ALL = 1 also resets the data path.  The ROM read registers are never reset
 * (they must map onto block RAM); see "ROM 9 and ROM 12" at the end for why none needs it.
 * ROM images: A_ROM_FILE and COS_ROM_FILE default to files in `SHADING_ROM_DIR ("rom" unless
 * defined on the command line); the Python flows pass absolute paths instead.
 *
 * Protocol (docs/architecture.md, "The protocol every unit follows"): operands are sampled
 * with their write strobes while busy = 0; a start
 * accepted in the same cycle as a write runs on the values held before it (the run copies the
 * registers at the start edge).  rst_n is synchronous and aborts a line.
 *
 * Checks: a parameter set model.specular.SpecularConfig refuses is refused at elaboration (an
 * instance of a module that does not exist, named after the rule, e.g.
 * specular_unit_PARAMETER_ERROR_A_INT_BITS_too_small_for_the_largest_a).  K0..K3 and ALPHA
 * take part in these checks only (the datapath reads k and a from the ROMs), and MAG_INT_BITS
 * must be the value the model derives from them and the kept range N_FIRST..N_LAST.  In
 * simulation both ROM images are checked at time 0 by the ROM module (rtl/shading_rom.v; see
 * "ROM 9 and ROM 12"): a missing, short, malformed or wrong-configuration file ends the run
 * with a message and a non-zero exit status.
 *
 * Sources: this file and rtl/shading_rom.v (rtl/specular_unit.f lists them).
 *
 * Documentation: docs/specular.md (ports, formats, parameters, timing, accuracy, the contract
 * and its tests); docs/architecture.md (the protocol, the ROM image format, the benches).
 *
 * Why this file is long (about 770 lines; the datapath itself is the last ~300): one module
 * per file, and Verilog-2005 has no packages to put the rest in.  The section "parameter
 * check" (about 280 lines) re-derives the model's legal set at elaboration (the largest and
 * smallest a of the kept n, with constant functions) so that every tool refuses exactly what
 * model.units.specular refuses.
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

module specular_unit #(
    // C register integer bits (output LSBs)
    parameter C_INT_BITS = 8,
    // C register fraction bits
    parameter C_FRAC_BITS = 8,
    // dz, z0 integer bits including the sign (units of pi/2)
    parameter Z_INT_BITS = 3,
    // dz, z0 and accumulator fraction bits
    parameter Z_FRAC_BITS = 26,
    // Interval counter width: l = 0 .. 2^LEN_WIDTH - 1
    parameter LEN_WIDTH = 11,
    // ROM 9 word (the scale a) integer bits
    parameter A_INT_BITS = 3,
    // ROM 9 word fraction bits
    parameter A_FRAC_BITS = 14,
    // ROM 12 address bits per table (fraction bits of the scaled angle, units of pi/2)
    parameter ROM_ADDR_BITS = 12,
    // ROM 12 word bits
    parameter ROM_DATA_BITS = 16,
    // Output intensity bits
    parameter OUT_WIDTH = 8,
    // Number of cos^k tables (decoder outputs used), 1..4
    parameter NUM_TABLES = 4,
    // Largest n of the first k range (the ranges start at n = 1)
    parameter N_HI0 = 1,
    // Largest n of the second k range (1000 if unused)
    parameter N_HI1 = 2,
    // Largest n of the third k range (1000 if unused)
    parameter N_HI2 = 6,
    // Largest n of the fourth k range (1000 if unused)
    parameter N_HI3 = 1000,
    // k of the first decoder output's cos^k table (1..64)
    parameter K0 = 1,
    // k of the second table (0 if unused)
    parameter K1 = 2,
    // k of the third table (0 if unused)
    parameter K2 = 4,
    // k of the fourth table (0 if unused)
    parameter K3 = 16,
    // How ROM 9's a was chosen: "taylor" (a = sqrt(n/k)) or "inflection"
    parameter [8*10-1:0] ALPHA = "taylor",
    // Integer bits |zeta| is saturated to before multiplier 11 (derived: model mag_int_bits)
    parameter MAG_INT_BITS = 1,
    // The kept range of n: ROM 9 holds a for N_FIRST..N_LAST only (1 <= N_FIRST <= N_LAST <=
    // 1000); every other n gives what an invalid n gives (intensity 0, n_err = 1)
    parameter N_FIRST = 1,
    parameter N_LAST = 1000,
    // $readmemh image of ROM 9 (a for n = N_FIRST..N_LAST), by model.specular (make roms)
    parameter A_ROM_FILE = {`SHADING_ROM_DIR,
                            "/specular_a_taylor_n1k1_n2k2_n3-6k4_n7-1000k16_q3.14.hex"},
    // $readmemh image of ROM 12 (the cos^k tables), generated by model.specular (make roms)
    parameter COS_ROM_FILE = {`SHADING_ROM_DIR, "/specular_cos_k1-2-4-16_a12_d16.hex"},
    // 0: rst_n resets the control state and the operand registers only; 1: also every
    // data-path register (the ROM read registers never: they must map onto block RAM)
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
localparam N_MAX = 1000;
localparam C_WIDTH = C_INT_BITS + C_FRAC_BITS;
localparam Z_WIDTH = Z_INT_BITS + Z_FRAC_BITS;
localparam ACC_WIDTH = Z_WIDTH + LEN_WIDTH;
localparam A_WIDTH = A_INT_BITS + A_FRAC_BITS;
localparam MAG_WIDTH = MAG_INT_BITS + Z_FRAC_BITS;
localparam PROD_WIDTH = MAG_WIDTH + A_WIDTH;
// Product bits dropped to form the ROM-12 address (rounded: add half, slice)
localparam SHIFT = Z_FRAC_BITS + A_FRAC_BITS - ROM_ADDR_BITS;
localparam TSEL_BITS = (NUM_TABLES > 2) ? 2 : 1;
localparam OP_WIDTH = C_WIDTH + ROM_DATA_BITS;
localparam OSHIFT = C_FRAC_BITS + ROM_DATA_BITS;
// Rounded output before saturation: C_INT_BITS + 1 bits (C * 1.0 rounds up to 2^C_INT_BITS)
localparam OFULL_WIDTH = OP_WIDTH - OSHIFT + 1;

localparam [N_WIDTH-1:0] HI0 = N_HI0[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] HI1 = N_HI1[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] HI2 = N_HI2[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] HI3 = N_HI3[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] NFIRST = N_FIRST[N_WIDTH-1:0];
localparam [N_WIDTH-1:0] NLAST = N_LAST[N_WIDTH-1:0];

// ---------------------------------------------------------------- parameter check
// Exactly the sets model.specular.SpecularConfig refuses, K0..K3, N_HI0..N_HI3 and NUM_TABLES
// standing for its k_ranges (an unused table has K = 0 and N_HI = 1000, as hdl_parameters()
// gives them) and MAG_INT_BITS for its derived mag_int_bits.  Verilog-2005 has no
// elaboration-time $error: a failing rule instantiates a module that does not exist, named
// after the rule, and every tool stops with an error naming it.  62 is the model's
// fixed.MAX_KERNEL_WIDTH.

localparam [8*10-1:0] ALPHA_TAYLOR = "taylor";
localparam [8*10-1:0] ALPHA_INFLECTION = "inflection";
localparam ALPHA_INDEX = (ALPHA == ALPHA_INFLECTION) ? 1 : 0;

function integer clamp(input integer v, input integer lo, input integer hi);
    begin
        clamp = (v < lo) ? lo : (v > hi) ? hi : v;
    end
endfunction

// Largest n of table j (the n_hi of its k range)
function integer n_hi(input integer j);
    begin
        case (j)
            0: n_hi = N_HI0;
            1: n_hi = N_HI1;
            2: n_hi = N_HI2;
            default: n_hi = N_HI3;
        endcase
    end
endfunction

function integer k_of(input integer j);
    begin
        case (j)
            0: k_of = K0;
            1: k_of = K1;
            2: k_of = K2;
            default: k_of = K3;
        endcase
    end
endfunction

// ROM 9's word for n and k: round(a * 2^frac), a as model.specular.alpha_value computes it
// (the same IEEE double operations, so the same word)
function integer a_word(input integer n, input integer k, input integer inflection,
                        input integer frac);
    begin
        a_word = $rtoi($floor(((inflection == 0) ? $sqrt(n * 1.0 / k)
                               : (n == 1) ? 1.0
                               : $acos($pow((n - 1) * 1.0 / n, n * 1.0 / (2 * k)))
                                 / $atan(1.0 / $sqrt(n - 1.0)))
                              * $pow(2.0, frac) + 0.5));
    end
endfunction

// The largest (want_max = 1) or smallest ROM 9 word over the kept n = N_FIRST..N_LAST (the
// model's a_max and mag_int_bits take the kept range only).  For n >= 2 a grows with n in both
// modes (every k <= 64; inflection's a(1) = 1 is the exception), so per k range, cut to the
// kept range, the extremes are among its first n, the next and its last.  Arguments are
// clamped so that an illegal set (refused by another rule) still evaluates.
function integer a_extreme(input integer want_max);
    integer j;
    integer lo;
    integer hi;
    integer first;
    integer last;
    integer c;
    integer n;
    integer w;
    begin
        a_extreme = (want_max != 0) ? 0 : 32'h7fffffff;
        lo = 1;
        for (j = 0; j < clamp(NUM_TABLES, 1, 4); j = j + 1) begin
            hi = clamp(n_hi(j), lo, N_MAX);
            first = clamp(N_FIRST, lo, N_MAX);
            last = clamp(N_LAST, 1, hi);
            for (c = 0; c < 3 && first <= last; c = c + 1) begin
                n = (c == 0) ? first : (c == 1) ? clamp(first + 1, first, last) : last;
                w = a_word(n, clamp(k_of(j), 1, 64), ALPHA_INDEX, clamp(A_FRAC_BITS, 0, 24));
                if ((want_max != 0) ? (w > a_extreme) : (w < a_extreme)) begin
                    a_extreme = w;
                end
            end
            lo = clamp(hi + 1, 1, N_MAX);
        end
    end
endfunction

// ROM 9's word of the kept n (k from the table whose range holds n): the image check reads
// the first and the last word against it
function integer kept_word(input integer n);
    integer j;
    integer k;
    begin
        k = 0;
        for (j = clamp(NUM_TABLES, 1, 4) - 1; j >= 0; j = j - 1) begin
            if (n <= n_hi(j)) begin
                k = k_of(j);
            end
        end
        kept_word = a_word(clamp(n, 1, N_MAX), clamp(k, 1, 64), ALPHA_INDEX,
                           clamp(A_FRAC_BITS, 0, 24));
    end
endfunction

// model.specular.SpecularConfig.mag_int_bits: the smallest M (at most Z_INT_BITS + LEN_WIDTH
// - 1) with a_min * (2^(M + Z_FRAC_BITS) - 1) >= 2^(Z_FRAC_BITS + A_FRAC_BITS)
function integer mag_bits(input integer a_min, input integer zf, input integer af,
                          input integer cap);
    reg [127:0] one;
    reg [127:0] lhs;
    integer     m;
    begin
        one = 128'd1 << (zf + af);
        m = 0;
        lhs = a_min * ((128'd1 << zf) - 128'd1);
        while (m < cap && lhs < one) begin
            m = m + 1;
            lhs = a_min * ((128'd1 << (m + zf)) - 128'd1);
        end
        mag_bits = m;
    end
endfunction

// The rules on the fields, the k ranges and ALPHA (the model's first checks)
localparam BAD_C_INT_BITS = (C_INT_BITS < 1 || C_INT_BITS > 16);
localparam BAD_C_FRAC_BITS = (C_FRAC_BITS < 0 || C_FRAC_BITS > 16);
localparam BAD_Z_INT_BITS = (Z_INT_BITS < 3 || Z_INT_BITS > 8);
localparam BAD_Z_FRAC_BITS = (Z_FRAC_BITS < 1 || Z_FRAC_BITS > 40);
localparam BAD_LEN_WIDTH = (LEN_WIDTH < 1 || LEN_WIDTH > 16);
localparam BAD_A_INT_BITS = (A_INT_BITS < 1 || A_INT_BITS > 8);
localparam BAD_A_FRAC_BITS = (A_FRAC_BITS < 1 || A_FRAC_BITS > 24);
localparam BAD_ROM_ADDR_BITS = (ROM_ADDR_BITS < 2 || ROM_ADDR_BITS > 16);
localparam BAD_ROM_DATA_BITS = (ROM_DATA_BITS < 2 || ROM_DATA_BITS > 24);
localparam BAD_OUT_WIDTH = (OUT_WIDTH < 1 || OUT_WIDTH > 16);
// k_ranges: 1..4 ranges covering n = 1..1000 in order, k = 1..64 each (the rules on N_HI and
// K apply once NUM_TABLES is legal)
localparam BAD_NUM_TABLES = (NUM_TABLES < 1 || NUM_TABLES > 4);
localparam TABLES_OK = !BAD_NUM_TABLES;
localparam BAD_N_HI0 = TABLES_OK && (N_HI0 < 1);
localparam BAD_N_HI1 = TABLES_OK && (NUM_TABLES > 1 && N_HI1 <= N_HI0);
localparam BAD_N_HI2 = TABLES_OK && (NUM_TABLES > 2 && N_HI2 <= N_HI1);
localparam BAD_N_HI3 = TABLES_OK && (NUM_TABLES > 3 && N_HI3 <= N_HI2);
localparam BAD_N_HI_LAST = TABLES_OK && (n_hi(clamp(NUM_TABLES, 1, 4) - 1) != N_MAX);
localparam BAD_N_HI_UNUSED = TABLES_OK && ((NUM_TABLES < 2 && N_HI1 != N_MAX)
                                           || (NUM_TABLES < 3 && N_HI2 != N_MAX)
                                           || (NUM_TABLES < 4 && N_HI3 != N_MAX));
localparam BAD_K = TABLES_OK && (K0 < 1 || K0 > 64 || (NUM_TABLES > 1 && (K1 < 1 || K1 > 64))
                                 || (NUM_TABLES > 2 && (K2 < 1 || K2 > 64))
                                 || (NUM_TABLES > 3 && (K3 < 1 || K3 > 64)));
localparam BAD_K_UNUSED = TABLES_OK && ((NUM_TABLES < 2 && K1 != 0) || (NUM_TABLES < 3 && K2 != 0)
                                        || (NUM_TABLES < 4 && K3 != 0));
localparam BAD_ALPHA = (ALPHA != ALPHA_TAYLOR && ALPHA != ALPHA_INFLECTION);
// The kept range: 1 <= N_FIRST <= N_LAST <= 1000
localparam BAD_N_FIRST = (N_FIRST < 1 || N_FIRST > N_MAX);
localparam BAD_N_LAST = (N_LAST < clamp(N_FIRST, 1, N_MAX) || N_LAST > N_MAX);
// ROM 9's words, and from them MAG_INT_BITS, are defined once these rules hold
localparam BASE_OK = !(BAD_C_INT_BITS || BAD_C_FRAC_BITS || BAD_Z_INT_BITS || BAD_Z_FRAC_BITS
                       || BAD_LEN_WIDTH || BAD_A_INT_BITS || BAD_A_FRAC_BITS
                       || BAD_ROM_ADDR_BITS || BAD_ROM_DATA_BITS || BAD_OUT_WIDTH
                       || BAD_NUM_TABLES || BAD_N_HI0 || BAD_N_HI1 || BAD_N_HI2 || BAD_N_HI3
                       || BAD_N_HI_LAST || BAD_N_HI_UNUSED || BAD_K || BAD_K_UNUSED
                       || BAD_ALPHA || BAD_N_FIRST || BAD_N_LAST);

localparam A_MAX_WORD = a_extreme(1);
localparam A_MIN_WORD = a_extreme(0);
localparam MAG_DERIVED = mag_bits(A_MIN_WORD, clamp(Z_FRAC_BITS, 1, 40),
                                  clamp(A_FRAC_BITS, 1, 24),
                                  clamp(Z_INT_BITS + LEN_WIDTH - 1, 0, 63));
// The largest word fits A_INT_BITS + A_FRAC_BITS bits (at most 32 once the fields are legal)
localparam A_FITS = (A_INT_BITS + A_FRAC_BITS >= 31) ? 1
                  : (A_MAX_WORD < (1 << clamp(A_INT_BITS + A_FRAC_BITS, 0, 30))) ? 1 : 0;

generate
    if (BAD_C_INT_BITS) begin : g_check_c_int_bits
        specular_unit_PARAMETER_ERROR_C_INT_BITS_must_be_1_to_16 u_error ();
    end
    if (BAD_C_FRAC_BITS) begin : g_check_c_frac_bits
        specular_unit_PARAMETER_ERROR_C_FRAC_BITS_must_be_0_to_16 u_error ();
    end
    if (BAD_Z_INT_BITS) begin : g_check_z_int_bits
        specular_unit_PARAMETER_ERROR_Z_INT_BITS_must_be_3_to_8 u_error ();
    end
    if (BAD_Z_FRAC_BITS) begin : g_check_z_frac_bits
        specular_unit_PARAMETER_ERROR_Z_FRAC_BITS_must_be_1_to_40 u_error ();
    end
    if (BAD_LEN_WIDTH) begin : g_check_len_width
        specular_unit_PARAMETER_ERROR_LEN_WIDTH_must_be_1_to_16 u_error ();
    end
    if (BAD_A_INT_BITS) begin : g_check_a_int_bits
        specular_unit_PARAMETER_ERROR_A_INT_BITS_must_be_1_to_8 u_error ();
    end
    if (BAD_A_FRAC_BITS) begin : g_check_a_frac_bits
        specular_unit_PARAMETER_ERROR_A_FRAC_BITS_must_be_1_to_24 u_error ();
    end
    if (BAD_ROM_ADDR_BITS) begin : g_check_rom_addr_bits
        specular_unit_PARAMETER_ERROR_ROM_ADDR_BITS_must_be_2_to_16 u_error ();
    end
    if (BAD_ROM_DATA_BITS) begin : g_check_rom_data_bits
        specular_unit_PARAMETER_ERROR_ROM_DATA_BITS_must_be_2_to_24 u_error ();
    end
    if (BAD_OUT_WIDTH) begin : g_check_out_width
        specular_unit_PARAMETER_ERROR_OUT_WIDTH_must_be_1_to_16 u_error ();
    end
    if (BAD_NUM_TABLES) begin : g_check_num_tables
        specular_unit_PARAMETER_ERROR_NUM_TABLES_must_be_1_to_4 u_error ();
    end
    if (BAD_N_HI0) begin : g_check_n_hi0
        specular_unit_PARAMETER_ERROR_N_HI0_must_be_at_least_1 u_error ();
    end
    if (BAD_N_HI1) begin : g_check_n_hi1
        specular_unit_PARAMETER_ERROR_N_HI1_must_exceed_N_HI0 u_error ();
    end
    if (BAD_N_HI2) begin : g_check_n_hi2
        specular_unit_PARAMETER_ERROR_N_HI2_must_exceed_N_HI1 u_error ();
    end
    if (BAD_N_HI3) begin : g_check_n_hi3
        specular_unit_PARAMETER_ERROR_N_HI3_must_exceed_N_HI2 u_error ();
    end
    if (BAD_N_HI_LAST) begin : g_check_n_hi_last
        specular_unit_PARAMETER_ERROR_N_HI_of_the_last_table_must_be_1000 u_error ();
    end
    if (BAD_N_HI_UNUSED) begin : g_check_n_hi_unused
        specular_unit_PARAMETER_ERROR_N_HI_of_an_unused_table_must_be_1000 u_error ();
    end
    if (BAD_K) begin : g_check_k
        specular_unit_PARAMETER_ERROR_K_of_a_table_must_be_1_to_64 u_error ();
    end
    if (BAD_K_UNUSED) begin : g_check_k_unused
        specular_unit_PARAMETER_ERROR_K_of_an_unused_table_must_be_0 u_error ();
    end
    if (RESET_ALL != 0 && RESET_ALL != 1) begin : g_check_reset_all
        specular_unit_PARAMETER_ERROR_RESET_ALL_must_be_0_or_1 u_error ();
    end
    if (BAD_ALPHA) begin : g_check_alpha
        specular_unit_PARAMETER_ERROR_ALPHA_must_be_taylor_or_inflection u_error ();
    end
    if (BAD_N_FIRST) begin : g_check_n_first
        specular_unit_PARAMETER_ERROR_N_FIRST_must_be_1_to_1000 u_error ();
    end
    if (BAD_N_LAST) begin : g_check_n_last
        specular_unit_PARAMETER_ERROR_N_LAST_must_be_N_FIRST_to_1000 u_error ();
    end
    // Widths derived from the fields (62: the model's fixed.MAX_KERNEL_WIDTH)
    if (SHIFT < 1) begin : g_check_addr_shift
        specular_unit_PARAMETER_ERROR_Z_FRAC_BITS_plus_A_FRAC_BITS_must_exceed_ROM_ADDR_BITS
            u_error ();
    end
    if (ACC_WIDTH > 62) begin : g_check_acc_width
        specular_unit_PARAMETER_ERROR_Z_INT_BITS_plus_Z_FRAC_BITS_plus_LEN_WIDTH_above_62
            u_error ();
    end
    if (BASE_OK && MAG_DERIVED + Z_FRAC_BITS + A_WIDTH + 1 > 62) begin : g_check_product_width
        specular_unit_PARAMETER_ERROR_MAG_INT_BITS_Z_FRAC_BITS_A_INT_BITS_A_FRAC_BITS_sum_above_61
            u_error ();
    end
    if (C_WIDTH + ROM_DATA_BITS + 1 > 62) begin : g_check_c_product_width
        specular_unit_PARAMETER_ERROR_C_INT_BITS_C_FRAC_BITS_ROM_DATA_BITS_sum_above_61 u_error ();
    end
    // ROM 9's words (from the k ranges and ALPHA): the largest must fit, and MAG_INT_BITS must
    // be where the smallest a already reaches pi/2
    if (BASE_OK && A_FITS == 0) begin : g_check_a_max
        specular_unit_PARAMETER_ERROR_A_INT_BITS_too_small_for_the_largest_a u_error ();
    end
    if (BASE_OK && MAG_INT_BITS != MAG_DERIVED) begin : g_check_mag_int_bits
        specular_unit_PARAMETER_ERROR_MAG_INT_BITS_must_equal_the_model_mag_int_bits u_error ();
    end
endgenerate

// ROM 9 (a per kept n, address n - N_FIRST) and ROM 12 (cos^k tables, address {table, angle})
localparam A_DEPTH = clamp(N_LAST - N_FIRST + 1, 1, 2 ** N_WIDTH);
localparam A_ADDR_BITS = (A_DEPTH > 512) ? 10 : (A_DEPTH > 256) ? 9 : (A_DEPTH > 128) ? 8
                       : (A_DEPTH > 64) ? 7 : (A_DEPTH > 32) ? 6 : (A_DEPTH > 16) ? 5
                       : (A_DEPTH > 8) ? 4 : (A_DEPTH > 4) ? 3 : (A_DEPTH > 2) ? 2 : 1;
localparam COS_DEPTH = 2 ** (TSEL_BITS + ROM_ADDR_BITS);
// ROM 9's first and last word (a of N_FIRST and of N_LAST): the image check compares them
localparam A_FIRST_WORD = kept_word(N_FIRST);
localparam A_LAST_WORD = kept_word(N_LAST);

// ---------------------------------------------------------------- decoder 10 (10 inputs)
// One-hot outputs (the patent's lines 30..33), one per k range; none for n = 0 or n > 1000.
// An n outside the kept range N_FIRST..N_LAST is an error too; ROM 9's address is n - N_FIRST
// for a kept n and 0 (any defined word: the zero gate discards it) for every other.
wire [3:0] dec_line;
assign dec_line[0] = (n_in != {N_WIDTH{1'b0}}) && (n_in <= HI0);
assign dec_line[1] = (NUM_TABLES > 1) && (n_in > HI0) && (n_in <= HI1);
assign dec_line[2] = (NUM_TABLES > 2) && (n_in > HI1) && (n_in <= HI2);
assign dec_line[3] = (NUM_TABLES > 3) && (n_in > HI2) && (n_in <= HI3);
wire n_kept = (n_in >= NFIRST) && (n_in <= NLAST);
wire dec_err = (dec_line == 4'b0000) || !n_kept;
wire [N_WIDTH-1:0] n_off = n_in - NFIRST;
wire [A_ADDR_BITS-1:0] a_addr = n_kept ? n_off[A_ADDR_BITS-1:0] : {A_ADDR_BITS{1'b0}};
// The one-hot lines encoded as the high ROM-12 address bits
wire [1:0] dec_index = {dec_line[3] | dec_line[2], dec_line[3] | dec_line[1]};

// ---------------------------------------------------------------- operand registers
// No register has an initial value.  rst_n (synchronous, active low) sets the control state
// (busy, valid, counter 5, the stage valid and last-pixel flags), the flags (n_err and the
// run's n error) and the operand registers; the data path (the run copies, the accumulator and
// every pipeline register) is loaded by each start and by the stage before it, so it is read
// only once defined; RESET_ALL = 1 resets it too.  ROM 9's and ROM 12's read registers (rom9_q,
// rom12_q) are never reset: see "ROM 9 and ROM 12" at the end.
reg [C_WIDTH-1:0]   c_reg;
reg [Z_WIDTH-1:0]   dz_reg;
reg [Z_WIDTH-1:0]   z0_reg;
// Register 4 holds n as what the unit uses of it: ROM 9's word (rom9_q, the ROM's read
// register, written with n), the table and the error flag
wire [A_WIDTH-1:0]  rom9_q;
reg [TSEL_BITS-1:0] tsel_reg;
reg                 nerr_reg;
// Parallel-load value of counter 5
reg [LEN_WIDTH-1:0] len_reg;

// Copies taken at the start edge: the line runs on them
reg [C_WIDTH-1:0]   c_run_reg;
reg [Z_WIDTH-1:0]   dz_run_reg;
reg [A_WIDTH-1:0]   a_run_reg;
reg [TSEL_BITS-1:0] tsel_run_reg;
reg                 nerr_run_reg;

// ---------------------------------------------------------------- pipeline
// S0 acc_reg, S1 low_reg + neg_reg + big_reg (|zeta| without its carry), S2 mag_reg (|zeta|
// saturated), S3 prod_reg (multiplier 11), S4 addr_reg (rounded address bits), S5 rom12_q +
// zero_reg (ROM 12 read), S6 rom_d_reg (gated word), S7 out_prod_reg (multiplier 13), S8
// intensity_reg (rounding, saturation).  v_reg[s] marks a pixel in stage s.
localparam LAST_STAGE = 7;
// Rounded product bits kept from S4 on: the address and the overflow bits above it
localparam RND_WIDTH = PROD_WIDTH + 1 - SHIFT;

reg [LEN_WIDTH-1:0]  cnt_reg;
reg [ACC_WIDTH-1:0]  acc_reg;
reg [MAG_WIDTH-1:0]  low_reg;
reg                  neg_reg;
reg                  big_reg;
reg [MAG_WIDTH-1:0]  mag_reg;
reg [PROD_WIDTH-1:0] prod_reg;
reg [RND_WIDTH-1:0]  addr_reg;
wire [ROM_DATA_BITS-1:0] rom12_q;
reg                  zero_reg;
reg [ROM_DATA_BITS-1:0] rom_d_reg;
reg [OP_WIDTH-1:0]   out_prod_reg;
// Stage valid and last-pixel flags
reg [LAST_STAGE:0]   v_reg;
reg [LAST_STAGE:1]   last_reg;

// Control and outputs
reg                  busy_reg;
reg                  valid_reg;
reg [OUT_WIDTH-1:0]  intensity_reg;
reg                  n_err_reg;

assign busy = busy_reg;
assign valid = valid_reg;
assign intensity = intensity_reg;
assign n_err = n_err_reg;

// S0 -> S1: |zeta| >= 2^MAG_WIDTH (big) without negating: a negative accumulator is big unless
// its high bits are all ones and its low bits not all zeros; the low bits one's-complemented
// S1 -> S2: |zeta| = low + 1 if negative, saturated to MAG_WIDTH bits
wire                 acc_neg = acc_reg[ACC_WIDTH-1];
wire                 acc_big = acc_neg ? (~&acc_reg[ACC_WIDTH-1:MAG_WIDTH]
                                          || ~|acc_reg[MAG_WIDTH-1:0])
                                       : |acc_reg[ACC_WIDTH-1:MAG_WIDTH];
wire [MAG_WIDTH-1:0] mag_next = big_reg ? {MAG_WIDTH{1'b1}}
                                        : low_reg + {{(MAG_WIDTH-1){1'b0}}, neg_reg};

// S3 -> S4: the scaled angle rounded at the ROM-12 address LSB (add half, slice)
wire [PROD_WIDTH:0]  prod_rnd = {1'b0, prod_reg} + ({{PROD_WIDTH{1'b0}}, 1'b1} << (SHIFT - 1));

// S4 -> S5: the ROM-12 address; >= pi/2 (overflow) or an invalid n reads as 0
wire [ROM_ADDR_BITS-1:0] rom_angle = addr_reg[ROM_ADDR_BITS-1:0];
wire                 rom_ovf = |addr_reg[RND_WIDTH-1:ROM_ADDR_BITS];
wire [TSEL_BITS+ROM_ADDR_BITS-1:0] rom_addr = {tsel_run_reg, rom_angle};

// S7 -> S8: round C * cos^k to OUT_WIDTH bits, saturate
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

// Bits the rounding steps drop on purpose (below the ROM address and the output LSB), the
// table index bit a one- or two-table configuration does not use, and the bits of n - N_FIRST
// above a short ROM 9's address
// verilator lint_off UNUSEDSIGNAL
wire unused_bits = &{1'b0, prod_rnd[SHIFT-1:0], out_rnd[OSHIFT-1:0], dec_index, n_off};
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
            tsel_reg <= dec_index[TSEL_BITS-1:0];
            nerr_reg <= dec_err;
        end
        if (len_we) begin
            len_reg <= len_in;
        end
    end

    // Control unit, stage S0: counter 5 and the pixel flags
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

    // Stage S8: the result
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
        tsel_reg <= {TSEL_BITS{1'b0}};
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
    // Multiplexer 7 selects z0 for the first pixel, adder 6 acc + dz after
    if (start_ok) begin
        c_run_reg <= c_reg;
        dz_run_reg <= dz_reg;
        a_run_reg <= rom9_q;
        tsel_run_reg <= tsel_reg;
        acc_reg <= {{LEN_WIDTH{z0_reg[Z_WIDTH-1]}}, z0_reg};
    end else if (v_reg[0] && !last0) begin
        acc_reg <= acc_reg + {{LEN_WIDTH{dz_run_reg[Z_WIDTH-1]}}, dz_run_reg};
    end

    // Stages S1..S7
    low_reg <= acc_reg[MAG_WIDTH-1:0] ^ {MAG_WIDTH{acc_neg}};
    neg_reg <= acc_neg;
    big_reg <= acc_big;
    mag_reg <= mag_next;
    prod_reg <= mag_reg * a_run_reg;
    addr_reg <= prod_rnd[PROD_WIDTH:SHIFT];
    zero_reg <= rom_ovf || nerr_run_reg;
    rom_d_reg <= zero_reg ? {ROM_DATA_BITS{1'b0}} : rom12_q;
    out_prod_reg <= c_run_reg * rom_d_reg;

    // Stage S8: the result
    if (v_reg[LAST_STAGE]) begin
        intensity_reg <= out_sat;
    end

    if (RESET_ALL != 0 && !rst_n) begin
        c_run_reg <= {C_WIDTH{1'b0}};
        dz_run_reg <= {Z_WIDTH{1'b0}};
        a_run_reg <= {A_WIDTH{1'b0}};
        tsel_run_reg <= {TSEL_BITS{1'b0}};
        acc_reg <= {ACC_WIDTH{1'b0}};
        low_reg <= {MAG_WIDTH{1'b0}};
        neg_reg <= 1'b0;
        big_reg <= 1'b0;
        mag_reg <= {MAG_WIDTH{1'b0}};
        prod_reg <= {PROD_WIDTH{1'b0}};
        addr_reg <= {RND_WIDTH{1'b0}};
        zero_reg <= 1'b0;
        rom_d_reg <= {ROM_DATA_BITS{1'b0}};
        out_prod_reg <= {OP_WIDTH{1'b0}};
        intensity_reg <= {OUT_WIDTH{1'b0}};
    end
end

// ---------------------------------------------------------------- ROM 9 and ROM 12
// ROM 9 (read with n while idle) and ROM 12 (stage S5, every cycle): instances of the ROM
// module (rtl/shading_rom.v), which checks each image at time 0 in simulation: magic ("SR09",
// "SR12"), depth, width, the parameters the contents depend on (ROM 9: A_INT_BITS,
// A_FRAC_BITS, ALPHA as 0 = taylor / 1 = inflection, NUM_TABLES, N_HI0..N_HI3, K0..K3, and
// its first and last words, those of N_FIRST and N_LAST: the header has no field for the kept
// range, its depth only; ROM 12: ROM_ADDR_BITS, ROM_DATA_BITS, NUM_TABLES, K0..K3), the
// checksum of the data words and the end mark; a bad image prints the file, the field, what
// it holds and what this instance needs, and ends the run with a non-zero exit status.
// Their read registers are never reset, in either RESET_ALL mode, so that they map onto block
// RAM (a block RAM's read register has no reset on every family, and where it has one Yosys
// does not always merge it).  Neither needs one: after reset nerr_reg = 1 (n = 0), so until n
// is written every pixel has zero_reg = 1 and its ROM-12 word is gated to 0 (an undefined
// rom9_q cannot reach a result: zero_reg = overflow || n error is 1 whatever the overflow),
// and rom12_q is rewritten every cycle from the address of the pixel in stage S4.
// verilator lint_off UNUSEDSIGNAL
wire [A_WIDTH-1:0]       rom9_unused_b;   // one read port each
wire [ROM_DATA_BITS-1:0] rom12_unused_b;
// verilator lint_on UNUSEDSIGNAL

shading_rom #(
    .WIDTH(A_WIDTH),
    .DEPTH(A_DEPTH),
    .ADDR_BITS(A_ADDR_BITS),
    .PORTS(1),
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
                  "K1              ", "K2              ", "K3              "}),
    .CHECK_ENDS(1),
    .ENDS_NAME("a of n"),
    .FIRST_KEY(N_FIRST),
    .LAST_KEY(N_LAST),
    .FIRST_WORD(A_FIRST_WORD),
    .LAST_WORD(A_LAST_WORD)
) u_rom9 (
    .clk(clk),
    .rd_en_a(!busy_reg && n_we),
    .addr_a(a_addr),
    .q_a(rom9_q),
    .rd_en_b(1'b0),
    .addr_b({A_ADDR_BITS{1'b0}}),
    .q_b(rom9_unused_b)
);

shading_rom #(
    .WIDTH(ROM_DATA_BITS),
    .DEPTH(COS_DEPTH),
    .ADDR_BITS(TSEL_BITS + ROM_ADDR_BITS),
    .PORTS(1),
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
    .addr_a(rom_addr),
    .q_a(rom12_q),
    .rd_en_b(1'b0),
    .addr_b({(TSEL_BITS + ROM_ADDR_BITS){1'b0}}),
    .q_b(rom12_unused_b)
);

endmodule

`resetall
