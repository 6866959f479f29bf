// Shared body of the vector benches (sim/vectors/tb_<unit>.v), included inside the module.
//
// The including bench declares the parameters CYCLES, STIM_FILE, EXPECT_FILE and MASK_FILE,
// the localparams STIM_W and OUT_W, the register stim_word (whose fields drive the unit's
// inputs) and the wire got_word (the unit's outputs), and instantiates the unit.  Each cycle i
// puts stim[i] on the inputs, waits for the rising edge, and 1 ns later compares every output
// bit whose mask bit is 1 with expect[i]: every output, in every cycle it is defined.  X or Z
// where a value is due is a mismatch.  Written by sim/soak.py (python -m sim.soak to replay).

reg clk = 1'b0;
always #5 clk = ~clk;

reg [STIM_W-1:0] stim_mem [0:CYCLES-1];
reg [OUT_W-1:0]  expect_mem [0:CYCLES-1];
reg [OUT_W-1:0]  mask_mem [0:CYCLES-1];
integer          cycle;
integer          mismatches;

initial begin
    $readmemh(STIM_FILE, stim_mem);
    $readmemh(EXPECT_FILE, expect_mem);
    $readmemh(MASK_FILE, mask_mem);
    mismatches = 0;
    for (cycle = 0; cycle < CYCLES; cycle = cycle + 1) begin
        stim_word = stim_mem[cycle];
        @(posedge clk);
        #1;
        if (((got_word ^ expect_mem[cycle]) & mask_mem[cycle]) !== {OUT_W{1'b0}}) begin
            mismatches = mismatches + 1;
            if (mismatches <= 20) begin
                $display("MISMATCH %0d %h %h %h", cycle, got_word, expect_mem[cycle],
                         mask_mem[cycle]);
            end
        end
    end
    $display("VECTORS %0d cycles %0d mismatches", CYCLES, mismatches);
    $finish;
end
