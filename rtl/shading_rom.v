// SPDX-License-Identifier: Apache-2.0
/*
 * A ROM from a model-generated $readmemh image (model.rom.format_image), with one or two
 * synchronous read ports, and the image check in simulation: the one ROM module of the
 * project.  The divider's reciprocal ROM, the specular unit's ROM 9 and ROM 12, and the
 * shading core's copies of them are instances of it.
 *
 * Image: IMAGE_DEPTH data words of WIDTH bits (the ROM keeps the first DEPTH of them: e.g.
 * one table of several), then the check fields, each a 32-bit value in CHUNKS
 * words of WIDTH bits, low bits first: MAGIC, depth, width, the NUM_FIELDS configuration values
 * FIELD_0.., the FNV-1a checksum of the data words (over 32-bit pieces, low first) and "END!".
 * At time 0 the whole image is read word by word (read_word: not by $readmemh, whose
 * Verilator version aborts on a word past the end of its array before a check could name the
 * field); every word must be there (not in a missing file, past the end of a short one or from
 * a non-hex word on) and defined, no word may follow them, and every field must be this
 * instance's.  CHECK_ENDS = 1 also checks the first and the last data word against FIRST_WORD
 * and LAST_WORD (what a header field cannot say: the specular unit's ROM 9 holds a for a kept
 * range of n, and its header gives the depth only).  A bad image
 * prints the file, the field, what it holds and what this instance needs, and ends the run
 * with a non-zero exit status: $fatal under Icarus, $stop under other simulators (Verilator
 * exits with an error; $fatal is SystemVerilog, which Verilator's 1364-2005 mode refuses).
 * Synthesis (SYNTHESIS defined, as Yosys does) loads the data words only: the check words fall
 * past the end of the array (and so do the data words past DEPTH), which Yosys drops, so the
 * ROM stays DEPTH words of block RAM.
 *
 * Ports: rd_en_a / addr_a -> q_a (q_a <= rom[addr_a] at a rising edge with rd_en_a); port B
 * the same when PORTS = 2 (its outputs are 0 when PORTS = 1).  The read registers have no
 * reset, so that they map onto a block RAM's output registers.
 *
 * READ_REGS = 2 (port A only): the word read at an edge with rd_en_a is registered again in the
 * fabric at the next one, so that no logic follows a block RAM's slow output in the same clock.
 * Synthesis then splits the ROM into banks of 2^BANK_BITS words (one block RAM each on most
 * parts: the read needs no multiplexer between block RAMs before its first register); the
 * banks' words, registered, are selected by the address's high bits two clocks later.  In
 * simulation it is one memory with the same two clocks of latency.
 */

`resetall
`timescale 1ns / 1ps
`default_nettype none

module shading_rom #(
    // Data word bits
    parameter WIDTH = 16,
    // Data words
    parameter DEPTH = 1024,
    // Data words in the image (DEPTH or more: the ROM keeps the first DEPTH)
    parameter IMAGE_DEPTH = DEPTH,
    // Address bits (2^ADDR_BITS >= DEPTH)
    parameter ADDR_BITS = 10,
    // Read ports, 1 or 2
    parameter PORTS = 1,
    // Clocks from an address to its word on q_a: 1, or 2 (registered again in the fabric)
    parameter READ_REGS = 1,
    // READ_REGS = 2: address bits of a bank in synthesis (the ROM in banks of 2^BANK_BITS words)
    parameter BANK_BITS = 10,
    // The $readmemh image
    parameter FILE = "rom.hex",
    // What the ROM is, for the messages
    parameter NAME = "ROM",
    // The image's first check field
    parameter [31:0] MAGIC = "ROM?",
    // Configuration fields after depth and width, 0..12
    parameter NUM_FIELDS = 0,
    // Their values (32 bits each; FIELD_0 comes first in the image)
    parameter FIELD_0 = 0,
    parameter FIELD_1 = 0,
    parameter FIELD_2 = 0,
    parameter FIELD_3 = 0,
    parameter FIELD_4 = 0,
    parameter FIELD_5 = 0,
    parameter FIELD_6 = 0,
    parameter FIELD_7 = 0,
    parameter FIELD_8 = 0,
    parameter FIELD_9 = 0,
    parameter FIELD_10 = 0,
    parameter FIELD_11 = 0,
    // Their names, 16 characters each, field 0 first (in the highest bits)
    parameter [8*16*12-1:0] FIELD_NAMES = {(8*16*12){1'b0}},
    // 1: the first and the last data word must be FIRST_WORD and LAST_WORD
    parameter CHECK_ENDS = 0,
    // What the end words are, for the messages: "<ENDS_NAME> = <FIRST_KEY>" (or LAST_KEY)
    parameter ENDS_NAME = "word",
    parameter FIRST_KEY = 0,
    parameter LAST_KEY = 0,
    // The first and the last data word (CHECK_ENDS = 1; 32 bits: WIDTH at most 32)
    parameter FIRST_WORD = 0,
    parameter LAST_WORD = 0
) (
    input  wire                 clk,
    input  wire                 rd_en_a,
    input  wire [ADDR_BITS-1:0] addr_a,
    output wire [WIDTH-1:0]     q_a,
    input  wire                 rd_en_b,
    input  wire [ADDR_BITS-1:0] addr_b,
    output wire [WIDTH-1:0]     q_b
);

// ---------------------------------------------------------------- parameter check
generate
    if (WIDTH < 1 || WIDTH > 64) begin : g_check_width
        shading_rom_PARAMETER_ERROR_WIDTH_must_be_1_to_64 u_error ();
    end
    if (DEPTH < 1 || DEPTH > (1 << ADDR_BITS)) begin : g_check_depth
        shading_rom_PARAMETER_ERROR_DEPTH_must_be_1_to_2_pow_ADDR_BITS u_error ();
    end
    if (IMAGE_DEPTH < DEPTH) begin : g_check_image_depth
        shading_rom_PARAMETER_ERROR_IMAGE_DEPTH_must_be_at_least_DEPTH u_error ();
    end
    if (ADDR_BITS < 1 || ADDR_BITS > 20) begin : g_check_addr_bits
        shading_rom_PARAMETER_ERROR_ADDR_BITS_must_be_1_to_20 u_error ();
    end
    if (PORTS != 1 && PORTS != 2) begin : g_check_ports
        shading_rom_PARAMETER_ERROR_PORTS_must_be_1_or_2 u_error ();
    end
    if (READ_REGS != 1 && !(READ_REGS == 2 && PORTS == 1)) begin : g_check_read_regs
        shading_rom_PARAMETER_ERROR_READ_REGS_must_be_1_or_2_with_one_port u_error ();
    end
    if (BANK_BITS < 1 || BANK_BITS > 20) begin : g_check_bank_bits
        shading_rom_PARAMETER_ERROR_BANK_BITS_must_be_1_to_20 u_error ();
    end
    if (NUM_FIELDS < 0 || NUM_FIELDS > 12) begin : g_check_num_fields
        shading_rom_PARAMETER_ERROR_NUM_FIELDS_must_be_0_to_12 u_error ();
    end
    if (CHECK_ENDS != 0 && CHECK_ENDS != 1) begin : g_check_check_ends
        shading_rom_PARAMETER_ERROR_CHECK_ENDS_must_be_0_or_1 u_error ();
    end
    if (CHECK_ENDS == 1 && WIDTH > 32) begin : g_check_ends_width
        shading_rom_PARAMETER_ERROR_CHECK_ENDS_needs_WIDTH_at_most_32 u_error ();
    end
endgenerate

reg [WIDTH-1:0] rom [0:DEPTH-1];
reg [WIDTH-1:0] q_a_reg;

`ifdef SYNTHESIS
initial begin
    $readmemh(FILE, rom);
end
`else
// ---------------------------------------------------------------- ROM image check (simulation)
localparam CHUNKS = (32 + WIDTH - 1) / WIDTH;
localparam TOTAL_FIELDS = NUM_FIELDS + 5;
localparam WORDS = IMAGE_DEPTH + TOTAL_FIELDS * CHUNKS;

reg [WIDTH-1:0] image [0:WORDS-1];

// The next word of a $readmemh image from file fd: blank space and // comments skipped; got = 1
// with the word, 0 at the end of the file or at a word that is not hex (reading stops there).
// (Verilator 5.006 counts fd unused.)
// verilator lint_off UNUSEDSIGNAL
task read_word(input integer fd, output reg [WIDTH-1:0] word, output integer got);
    integer ch;
    begin
        got = -1;
        word = {WIDTH{1'b0}};
        while (got < 0) begin
            ch = $fgetc(fd);
            if (ch == -1) begin
                got = 0;
            end else if (ch == "/") begin
                while (ch != -1 && ch != 10) ch = $fgetc(fd);
            end else if (ch != " " && ch != 9 && ch != 10 && ch != 13) begin
                ch = $ungetc(ch, fd);
                got = ($fscanf(fd, "%h", word) == 1) ? 1 : 0;
            end
        end
    end
endtask
// verilator lint_on UNUSEDSIGNAL

// Configuration field i (FIELD_<i>)
function [31:0] field_value(input integer i);
    begin
        case (i)
            0: field_value = FIELD_0;
            1: field_value = FIELD_1;
            2: field_value = FIELD_2;
            3: field_value = FIELD_3;
            4: field_value = FIELD_4;
            5: field_value = FIELD_5;
            6: field_value = FIELD_6;
            7: field_value = FIELD_7;
            8: field_value = FIELD_8;
            9: field_value = FIELD_9;
            10: field_value = FIELD_10;
            default: field_value = FIELD_11;
        endcase
    end
endfunction

function [31:0] expected(input integer f, input [31:0] sum);
    begin
        if (f == 0) begin
            expected = MAGIC;
        end else if (f == 1) begin
            expected = IMAGE_DEPTH;
        end else if (f == 2) begin
            expected = WIDTH;
        end else if (f < 3 + NUM_FIELDS) begin
            expected = field_value(f - 3);
        end else if (f == 3 + NUM_FIELDS) begin
            expected = sum;
        end else begin
            expected = "END!";
        end
    end
endfunction

// Field f's name, its trailing blanks dropped (FIELD_NAMES pads each name to 16 characters)
function [8*16-1:0] field_name(input integer f);
    integer c;
    begin
        if (f == 0) begin
            field_name = "magic";
        end else if (f == 1) begin
            field_name = "depth";
        end else if (f == 2) begin
            field_name = "width";
        end else if (f < 3 + NUM_FIELDS) begin
            field_name = FIELD_NAMES[8*16*(12-1-(f-3)) +: 8*16];
            for (c = 0; c < 15 && field_name[7:0] == " "; c = c + 1) begin
                field_name = field_name >> 8;
            end
        end else if (f == 3 + NUM_FIELDS) begin
            field_name = "checksum";
        end else begin
            field_name = "end mark";
        end
    end
endfunction

reg                     chk_bad;
integer                 chk_fd;
integer                 chk_got;
integer                 chk_n;
reg [WIDTH-1:0]         chk_read;
integer                 chk_i;
integer                 chk_p;
reg [WIDTH+31:0]        chk_word;
// verilator lint_off UNUSEDSIGNAL
reg [WIDTH*CHUNKS-1:0]  chk_found;  // its low 32 bits are the field
// verilator lint_on UNUSEDSIGNAL
reg [31:0]              chk_want;
reg [31:0]              chk_sum;
reg [31:0]              chk_end;
reg [63:0]              chk_found64;

initial begin
    // chk_n: the words the file holds (its first WORDS go into the image)
    chk_n = 0;
    chk_fd = $fopen(FILE, "r");
    if (chk_fd != 0) begin
        chk_got = 1;
        while (chk_got == 1) begin
            read_word(chk_fd, chk_read, chk_got);
            if (chk_got == 1) begin
                if (chk_n < WORDS) image[chk_n] = chk_read;
                chk_n = chk_n + 1;
            end
        end
        $fclose(chk_fd);
    end
    chk_bad = 1'b0;
    for (chk_i = 0; chk_i < WORDS; chk_i = chk_i + 1) begin
        if (!chk_bad && (chk_i >= chk_n || ^image[chk_i] === 1'bx)) begin
            $write("%m: %0s \"%0s\": word %0d is undefined: the file is missing or ", NAME,
                   FILE, chk_i);
            $write("unreadable, has fewer than the %0d words of this image (%0d data + ",
                   WORDS, IMAGE_DEPTH);
            $display("%0d check words of %0d bits) or a non-hex word there; regenerate it "
                     , TOTAL_FIELDS * CHUNKS, WIDTH, "with make roms");
            chk_bad = 1'b1;
        end
    end
    chk_sum = 32'h811c9dc5;
    for (chk_i = 0; chk_i < IMAGE_DEPTH; chk_i = chk_i + 1) begin
        chk_word = {32'd0, image[chk_i]};
        for (chk_p = 0; chk_p < WIDTH; chk_p = chk_p + 32) begin
            chk_sum = (chk_sum ^ chk_word[chk_p +: 32]) * 32'h01000193;
        end
    end
    for (chk_i = 0; chk_i < TOTAL_FIELDS; chk_i = chk_i + 1) begin
        for (chk_p = 0; chk_p < CHUNKS; chk_p = chk_p + 1) begin
            chk_found[chk_p*WIDTH +: WIDTH] = image[IMAGE_DEPTH + chk_i * CHUNKS + chk_p];
        end
        chk_want = expected(chk_i, chk_sum);
        if (!chk_bad && chk_found[31:0] !== chk_want) begin
            $write("%m: %0s \"%0s\": check field %0s is %0d (0x%0h), ", NAME, FILE,
                   field_name(chk_i), chk_found[31:0], chk_found[31:0]);
            $write("this instance needs %0d (0x%0h): %0s ", chk_want, chk_want,
                   (chk_i == 3 + NUM_FIELDS) ? "a data word differs from" : "the file is not");
            $display("the image of this configuration; regenerate it with make roms");
            chk_bad = 1'b1;
        end
    end
    // The first and the last data word (CHECK_ENDS = 1)
    for (chk_i = 0; chk_i < 2 * CHECK_ENDS; chk_i = chk_i + 1) begin
        chk_p = (chk_i == 0) ? 0 : IMAGE_DEPTH - 1;
        chk_end = (chk_i == 0) ? FIRST_WORD : LAST_WORD;
        chk_found64 = 64'd0;
        chk_found64[WIDTH-1:0] = image[chk_p];
        if (!chk_bad && chk_found64 !== {32'd0, chk_end}) begin
            $write("%m: %0s \"%0s\": data word %0d is %0d, this instance needs %0s = %0d ", NAME,
                   FILE, chk_p, chk_found64, ENDS_NAME, (chk_i == 0) ? FIRST_KEY : LAST_KEY);
            $display("(%0d): the file is not the image of this configuration; regenerate it %0s",
                     chk_end, "with make roms");
            chk_bad = 1'b1;
        end
    end
    if (!chk_bad && chk_n > WORDS) begin
        $write("%m: %0s \"%0s\": the file has %0d words, more than the %0d of this image; ", NAME,
               FILE, chk_n, WORDS);
        $display("regenerate it with make roms");
        chk_bad = 1'b1;
    end
    if (chk_bad) begin
        $fflush;
`ifdef __ICARUS__
        $fatal(1, "%m: bad ROM image (see above)");
`else
        $stop;
`endif
    end
    for (chk_i = 0; chk_i < DEPTH; chk_i = chk_i + 1) begin
        rom[chk_i] = image[chk_i];
    end
end
`endif

`ifdef SYNTHESIS
localparam BANKS = (ADDR_BITS > BANK_BITS) ? (1 << (ADDR_BITS - BANK_BITS)) : 1;
localparam HIGH_BITS = (ADDR_BITS > BANK_BITS) ? ADDR_BITS - BANK_BITS : 1;
`endif

generate
    if (READ_REGS == 1) begin : g_read1
        always @(posedge clk) begin
            if (rd_en_a) begin
                q_a_reg <= rom[addr_a];
            end
        end
        assign q_a = q_a_reg;
`ifdef SYNTHESIS
    end else if (BANKS > 1) begin : g_banked
        // One memory per bank (each reads only its own addresses: synthesis keeps those
        // words), its word registered in the fabric, the bank chosen after both registers
        reg [HIGH_BITS-1:0] high1_reg;
        reg [HIGH_BITS-1:0] high2_reg;
        wire [BANKS*WIDTH-1:0] words;
        genvar b;
        for (b = 0; b < BANKS; b = b + 1) begin : g_bank
            reg [WIDTH-1:0] mem [0:DEPTH-1];
            reg [WIDTH-1:0] q1_reg;
            reg [WIDTH-1:0] q2_reg;
            wire [ADDR_BITS-1:0] addr = {b[HIGH_BITS-1:0], addr_a[BANK_BITS-1:0]};
            initial begin
                $readmemh(FILE, mem);
            end
            always @(posedge clk) begin
                if (rd_en_a) begin
                    q1_reg <= mem[addr];
                    q2_reg <= q1_reg;
                end
            end
            assign words[b*WIDTH +: WIDTH] = q2_reg;
        end
        always @(posedge clk) begin
            if (rd_en_a) begin
                high1_reg <= addr_a[ADDR_BITS-1:BANK_BITS];
                high2_reg <= high1_reg;
            end
        end
        assign q_a = words[high2_reg*WIDTH +: WIDTH];
`endif
    end else begin : g_read2
        reg [WIDTH-1:0] q2_reg;
        always @(posedge clk) begin
            if (rd_en_a) begin
                q_a_reg <= rom[addr_a];
                q2_reg <= q_a_reg;
            end
        end
        assign q_a = q2_reg;
    end
endgenerate

generate
    if (PORTS == 2) begin : g_port_b
        reg [WIDTH-1:0] q_b_reg;
        always @(posedge clk) begin
            if (rd_en_b) begin
                q_b_reg <= rom[addr_b];
            end
        end
        assign q_b = q_b_reg;
    end else begin : g_one_port
        // verilator lint_off UNUSEDSIGNAL
        wire unused_b = &{1'b0, rd_en_b, addr_b};
        // verilator lint_on UNUSEDSIGNAL
        assign q_b = {WIDTH{1'b0}};
    end
endgenerate

endmodule

`resetall
