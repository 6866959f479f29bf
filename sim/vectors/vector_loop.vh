// SPDX-License-Identifier: Apache-2.0
// Shared body of the vector benches (sim/vectors/tb_<unit>.v), included inside the module.
//
// The including bench declares the parameters CYCLES, VECTOR_FILE and RESET_MODES, the
// localparams STIM_W and OUT_W, the register stim_word (whose fields drive the units' inputs)
// and the wire got_words: the output word of the instance with RESET_ALL = 0 in bits
// [OUT_W-1:0], of the one with RESET_ALL = 1 in [2*OUT_W-1:OUT_W] (RESET_MODES bit r set: that
// instance exists and is checked).
//
// The vector file is binary, one record per cycle, read with $fread as the run goes, CHUNK
// records at a time (any length, a fixed memory): the stimulus word in STIM_BYTES =
// ceil(STIM_W / 8) bytes, then the mask and expected words {mask, expect} of the instance with
// RESET_ALL = 0 in OUT_BYTES = ceil(2 * OUT_W / 8) bytes, then those of the instance with
// RESET_ALL = 1 in as many (each instance has its own prediction: after a reset RESET_ALL = 1
// defines the data outputs as 0 where RESET_ALL = 0 leaves them undefined), each big-endian
// and right-aligned (the $fread order); the bits that pad a word to whole bytes are 0.  Mask
// bit 1: compare that output bit; 0: the output is undefined there.  Each cycle i puts the
// stimulus of record i on the inputs, gives a rising clock edge 5 ns later, lets the clock
// fall 4 ns after that and compares 1 ns later, in every instance, every output bit whose mask
// bit is 1 with that instance's expected word: every output, in every cycle it is defined.  X
// or Z where a value is due is a mismatch.  The next record then goes on the inputs.  The
// falling edge comes before the compare and apart from any input change, so a flip-flop
// clocked on the falling edge shows: it has taken record i's inputs half a cycle early (with
// the inputs changing at the falling edge it would take record i + 1's, as the rising edge
// does half a cycle later, and look the same at every compare).
//
// Plusargs override the parameters at run time, so one build replays any set of its
// configuration: +VECTOR_FILE=<path>, +CYCLES=<n>; +OUT_FILE=<path> also writes the output
// word ({busy, valid, outputs} in hex, one line) of the lowest instance RESET_MODES selects in
// every cycle its valid is 1: the RTL's own results (the scene co-simulation reads them).
//
// Output: a line "MISMATCH cycle <i> RESET_ALL=<r> got <hex> expected <hex> mask <hex>" per
// mismatch (the first 20), then "VECTORS <n> cycles <m> mismatches" and a PASS or FAIL line.
// A mismatch, or a vector file that is missing, short, longer than CYCLES records or with
// padding bits set, ends the run with a non-zero exit status: $fatal under Icarus (vvp exits
// with 1), $stop elsewhere (the binary of verilator --binary aborts, exit 134; a vendor
// simulator stops with an error).
// Written by sim/soak.py and sim/vector_sets.py (make vectors); replayed by
// sim/vectors/replay.sh.

localparam STIM_BYTES = (STIM_W + 7) / 8;
// one instance's {mask, expect}
localparam OUT_BYTES = (2 * OUT_W + 7) / 8;
localparam DUMP_INST = (RESET_MODES == 2) ? 1 : 0;
localparam REC_BYTES = STIM_BYTES + 2 * OUT_BYTES;
// records read per $fread call (a call per record costs Icarus about a tenth more run time)
localparam CHUNK = 1024;

reg                      clk = 1'b0;
reg [8*STIM_BYTES-1:0]   stim_rec;
reg [8*OUT_BYTES-1:0]    expect_rec0;
reg [8*OUT_BYTES-1:0]    expect_rec1;
reg [8*OUT_BYTES-1:0]    expect_rec;
reg [8*REC_BYTES-1:0]    vec_rec;
reg [8*REC_BYTES-1:0]    chunk [0:CHUNK-1];
reg [OUT_W-1:0]          expect_word;
reg [OUT_W-1:0]          mask_word;
reg [OUT_W-1:0]          got_word;
reg [8*1024-1:0]         vector_file;
reg [8*1024-1:0]         out_file;
integer                  cycles;
integer                  cycle;
integer                  inst;
integer                  mismatches;
integer                  fd;
integer                  out_fd;
integer                  got_bytes;
integer                  want;

task vector_fail;
    begin
`ifdef __ICARUS__
        $fatal(1, "%m: the vector replay failed (see above)");
`else
        $stop;
`endif
    end
endtask

initial begin
    if (!$value$plusargs("VECTOR_FILE=%s", vector_file)) begin
        // a string parameter into the wider register, zero-extended on the left
        /* verilator lint_off WIDTH */
        vector_file = VECTOR_FILE;
        /* verilator lint_on WIDTH */
    end
    if (!$value$plusargs("CYCLES=%d", cycles)) begin
        cycles = CYCLES;
    end
    out_fd = 0;
    if ($value$plusargs("OUT_FILE=%s", out_file)) begin
        out_fd = $fopen(out_file, "w");
        if (out_fd == 0) begin
            $display("FAIL %m: cannot write %0s", out_file);
            vector_fail;
        end
    end
    fd = $fopen(vector_file, "rb");
    if (fd == 0) begin
        $display("FAIL %m: cannot read the vector file %0s", vector_file);
        vector_fail;
    end
    mismatches = 0;
    for (cycle = 0; cycle < cycles; cycle = cycle + 1) begin
        if (cycle % CHUNK == 0) begin
            want = (cycles - cycle < CHUNK) ? cycles - cycle : CHUNK;
            got_bytes = $fread(chunk, fd, 0, want);
            if (got_bytes != want * REC_BYTES) begin
                $display("FAIL %m: %0s is short: it has fewer than CYCLES = %0d records",
                         vector_file, cycles);
                vector_fail;
            end
        end
        vec_rec = chunk[cycle % CHUNK];
        {stim_rec, expect_rec0, expect_rec1} = vec_rec;
        // the bits that pad a word to whole bytes are 0 in a well-formed file
        if ((stim_rec >> STIM_W) != 0 || (expect_rec0 >> (2 * OUT_W)) != 0 ||
            (expect_rec1 >> (2 * OUT_W)) != 0) begin
            $display("FAIL %m: record %0d of %0s has padding bits set", cycle, vector_file);
            vector_fail;
        end
        stim_word = stim_rec[STIM_W-1:0];
        #5 clk = 1'b1;
        #4 clk = 1'b0;
        #1;
        for (inst = 0; inst < 2; inst = inst + 1) begin
            if (((RESET_MODES >> inst) & 1) == 1) begin
                got_word = got_words[inst*OUT_W +: OUT_W];
                expect_rec = (inst == 1) ? expect_rec1 : expect_rec0;
                {mask_word, expect_word} = expect_rec[2*OUT_W-1:0];
                if (((got_word ^ expect_word) & mask_word) !== {OUT_W{1'b0}}) begin
                    mismatches = mismatches + 1;
                    if (mismatches <= 20) begin
                        $display("MISMATCH cycle %0d RESET_ALL=%0d got %h expected %h mask %h",
                                 cycle, inst, got_word, expect_word, mask_word);
                    end
                end
            end
        end
        if (out_fd != 0 && got_words[DUMP_INST*OUT_W + OUT_W - 2] === 1'b1) begin
            $fwrite(out_fd, "%h\n", got_words[DUMP_INST*OUT_W +: OUT_W]);
        end
    end
    if ($fgetc(fd) != -1) begin
        $display("FAIL %m: %0s has more than CYCLES = %0d records", vector_file, cycles);
        vector_fail;
    end
    $fclose(fd);
    if (out_fd != 0) begin
        $fclose(out_fd);
    end
    $display("VECTORS %0d cycles %0d mismatches", cycles, mismatches);
    if (mismatches != 0) begin
        $display("FAIL %m: %0d mismatches in %0d cycles (%0s)", mismatches, cycles,
                 vector_file);
        vector_fail;
    end
    $display("PASS %m: %0d cycles, every output of %0s compared in each, 0 mismatches",
             cycles, (RESET_MODES == 3) ? "RESET_ALL = 0 and 1" :
                     (RESET_MODES == 2) ? "RESET_ALL = 1" : "RESET_ALL = 0");
    $finish;
end
