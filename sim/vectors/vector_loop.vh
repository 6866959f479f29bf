// SPDX-License-Identifier: Apache-2.0
// Shared body of the vector benches (sim/vectors/tb_<unit>.v), included inside the module.
//
// The including bench declares the parameters CYCLES, STIM_FILE, EXPECT_FILE, MASK_FILE and
// RESET_MODES, the localparams STIM_W and OUT_W, the register stim_word (whose fields drive
// the units' inputs) and the wire got_words: the output word of the instance with RESET_ALL = 0
// in bits [OUT_W-1:0], of the one with RESET_ALL = 1 in [2*OUT_W-1:OUT_W] (RESET_MODES bit r
// set: that instance exists and is checked).  Each cycle i puts stim[i] on the inputs, waits
// for the rising edge, and 1 ns later compares, in every instance, every output bit whose mask
// bit is 1 with expect[i]: every output, in every cycle it is defined.  X or Z where a value is
// due is a mismatch.
//
// Output: a line "MISMATCH cycle <i> RESET_ALL=<r> got <hex> expected <hex> mask <hex>" per
// mismatch (the first 20), then "VECTORS <n> cycles <m> mismatches" and a PASS or FAIL line.
// A mismatch, or a vector file that is missing or short, ends the run with a non-zero exit
// status: $fatal under Icarus (vvp exits with 1), $stop elsewhere (a Verilator binary aborts,
// exit 134; a vendor simulator stops with an error).  Written by sim/soak.py and
// sim/vector_sets.py (make vectors); replayed by sim/vectors/replay.sh.

reg clk = 1'b0;
always #5 clk <= ~clk;

reg [STIM_W-1:0] stim_mem [0:CYCLES-1];
reg [OUT_W-1:0]  expect_mem [0:CYCLES-1];
reg [OUT_W-1:0]  mask_mem [0:CYCLES-1];
reg [OUT_W-1:0]  got_word;
integer          cycle;
integer          inst;
integer          mismatches;

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
    $readmemh(STIM_FILE, stim_mem);
    $readmemh(EXPECT_FILE, expect_mem);
    $readmemh(MASK_FILE, mask_mem);
    mismatches = 0;
    // busy and valid are defined in every cycle: a mask word without them is a word the file
    // did not provide (missing or short file, X under Icarus, 0 under a two-state simulator).
    if (mask_mem[CYCLES-1][OUT_W-1:OUT_W-2] !== 2'b11 || ^stim_mem[CYCLES-1] === 1'bx
            || ^expect_mem[CYCLES-1] === 1'bx) begin
        $display("FAIL %m: %0s, %0s or %0s is missing or has fewer than CYCLES = %0d words",
                 STIM_FILE, EXPECT_FILE, MASK_FILE, CYCLES);
        vector_fail;
    end
    for (cycle = 0; cycle < CYCLES; cycle = cycle + 1) begin
        stim_word = stim_mem[cycle];
        @(posedge clk);
        #1;
        for (inst = 0; inst < 2; inst = inst + 1) begin
            if (((RESET_MODES >> inst) & 1) == 1) begin
                got_word = got_words[inst*OUT_W +: OUT_W];
                if (((got_word ^ expect_mem[cycle]) & mask_mem[cycle]) !== {OUT_W{1'b0}}) begin
                    mismatches = mismatches + 1;
                    if (mismatches <= 20) begin
                        $display("MISMATCH cycle %0d RESET_ALL=%0d got %h expected %h mask %h",
                                 cycle, inst, got_word, expect_mem[cycle], mask_mem[cycle]);
                    end
                end
            end
        end
    end
    $display("VECTORS %0d cycles %0d mismatches", CYCLES, mismatches);
    if (mismatches != 0) begin
        $display("FAIL %m: %0d mismatches in %0d cycles (%0s against %0s, mask %0s)",
                 mismatches, CYCLES, STIM_FILE, EXPECT_FILE, MASK_FILE);
        vector_fail;
    end
    $display("PASS %m: %0d cycles, every output of %0s compared in each, 0 mismatches",
             CYCLES, (RESET_MODES == 3) ? "RESET_ALL = 0 and 1" :
                     (RESET_MODES == 2) ? "RESET_ALL = 1" : "RESET_ALL = 0");
    $finish;
end
