// SPDX-License-Identifier: Apache-2.0
/*
 * Formal properties of the shift-add divider (rtl/divider_shift.v), for SymbiYosys
 * (read_verilog -formal; model/hw/formal.py writes the .sby jobs, docs/formal.md lists every
 * property beside the contract row of docs/divider.md it proves).
 *
 * divider_shift_formal wraps one divider_shift (instance "dut") with every input free and holds
 * a reference model of the protocol in shadow registers, driven by the ports only:
 *   f_a, f_k         the operand registers as the contract says they behave (written with their
 *                    strobes while busy = 0, cleared by reset: k = 0);
 *   f_job_a, f_job_k the operands of the running division (the values held *before* the start
 *                    cycle's writes, contract row 10);
 *   f_left           busy cycles still to come: loaded with cycles(k) = N + 1 - ctz(r) (1 for
 *                    k = 0) at an accepted start, r = round(2^N / k) = (2^(N+1) + k) / (2k)
 *                    computed here from the formula, not read from the ROM;
 *   f_valid, f_dz    the expected valid strobe and div_zero flag;
 *   f_q              (ARITH = 1) the expected quotient f_job_a * r.
 * The properties compare the ports with it: one labelled assert each (busy_exact, ...; the
 * labels are the names in docs/formal.md and in the table of make formal), numbered by the
 * P_* localparams.  Every assert is on,
 * or only the one whose number is CHECK (CHECK = 0: all; the deliberate-error runs check one
 * property on a broken copy of the RTL), or none (CHECK = 99, the cover runs).
 *
 * Induction helpers (`ifdef DIVIDER_INTERNALS): k-induction needs the unit's internal registers
 * tied to the reference model.  They are read without changing the RTL: the f_int_* wires
 * below are left undriven here and the job's Yosys script connects them after `flatten` to
 * the flattened registers (connect -nounset -set f_int_bits \dut.bits_reg, ...).  The
 * helpers are asserted (proven with the rest), never assumed.
 *
 * The one assumption: reset (rst_n = 0) in the first cycle.  Everything else is free.
 *
 * The unit is read as synthesis reads it (-DSYNTHESIS: the ROM image by $readmemh, no image
 * check) and its ROM is made constant logic (memory_map -rom-only): as a memory its contents
 * would be free state in the induction step.  Since the reference model computes r from the
 * formula, the proofs check the ROM image of the configuration proven word for word.
 */

module divider_shift_formal #(
    parameter A_WIDTH = 21,
    parameter K_WIDTH = 11,
    parameter RECIP_BITS = 20,
    parameter ROM_FILE = "divider_recip_k11_n20.hex",
    parameter RESET_ALL = 0,
    // 1: also prove the quotient (P_QUOTIENT and its helpers; small configurations)
    parameter ARITH = 0,
    // 0: every property; n: only P number n (the deliberate-error runs); 99: none (the cover
    // runs: reachable from reset with no assert acting as a constraint)
    parameter CHECK = 0
) (
    input wire                 clk,
    input wire                 rst_n,
    input wire [A_WIDTH-1:0]   a_in,
    input wire                 a_we,
    input wire [K_WIDTH-1:0]   k_in,
    input wire                 k_we,
    input wire                 start
);

localparam Q_WIDTH = A_WIDTH + RECIP_BITS;
localparam R_WIDTH = RECIP_BITS + 1;
localparam C_WIDTH = 7;  // counts up to N + 1 <= 41 (and a little beyond for the bound check)
localparam D_WIDTH = RECIP_BITS + 3;  // 2^(N+1) + k and 2k fit

// Property numbers (CHECK selects one)
localparam P_BUSY_EXACT = 1;
localparam P_VALID_ONE_CYCLE = 2;
localparam P_DIV_ZERO = 3;
localparam P_Q_HELD = 4;
localparam P_RESET_IDLE = 5;
localparam P_BUSY_BOUNDED = 6;
localparam P_QUOTIENT = 7;
localparam P_HELPERS = 8;

wire                 busy;
wire                 valid;
wire [Q_WIDTH-1:0]   q;
wire                 div_zero;

divider_shift #(
    .A_WIDTH(A_WIDTH),
    .K_WIDTH(K_WIDTH),
    .RECIP_BITS(RECIP_BITS),
    .RESET_ALL(RESET_ALL),
    .ROM_FILE(ROM_FILE)
) dut (
    .clk(clk),
    .rst_n(rst_n),
    .a_in(a_in),
    .a_we(a_we),
    .k_in(k_in),
    .k_we(k_we),
    .start(start),
    .busy(busy),
    .valid(valid),
    .q(q),
    .div_zero(div_zero)
);

// ---------------------------------------------------------------- the contract's formulas
// r = round(2^N / k), round half up: (2^(N+1) + k) / (2k); 0 for k = 0 (never used)
function [R_WIDTH-1:0] recip_of(input [K_WIDTH-1:0] k);
    reg [D_WIDTH-1:0] num;
    reg [D_WIDTH-1:0] den;
    reg [D_WIDTH-1:0] quo;
    begin
        num = ({{(D_WIDTH-1){1'b0}}, 1'b1} << (RECIP_BITS + 1)) + k;
        den = {{(D_WIDTH-K_WIDTH){1'b0}}, k} << 1;
        quo = (k == {K_WIDTH{1'b0}}) ? {D_WIDTH{1'b0}} : num / den;
        recip_of = quo[R_WIDTH-1:0];
    end
endfunction

// Busy cycles of a run on reciprocal bits r (MSB = the 2^0 term first): R_WIDTH - ctz(r), 1 for
// r = 0.  With r = recip_of(k) this is cycles(k) = N + 1 - ctz(r) of docs/divider.md.
function [C_WIDTH-1:0] cycles_of(input [R_WIDTH-1:0] r);
    integer i;
    reg found;
    begin
        cycles_of = 1;
        found = 1'b0;
        for (i = 0; i < R_WIDTH; i = i + 1) begin
            if (!found && r[i]) begin
                cycles_of = R_WIDTH - i;
                found = 1'b1;
            end
        end
    end
endfunction

function check_on(input integer p);
    check_on = (CHECK == 0) || (CHECK == p);
endfunction

// ---------------------------------------------------------------- reference model
reg                 f_past_valid = 1'b0;
reg [A_WIDTH-1:0]   f_a;
reg [K_WIDTH-1:0]   f_k;
reg [A_WIDTH-1:0]   f_job_a;
reg [K_WIDTH-1:0]   f_job_k;
reg [C_WIDTH-1:0]   f_left;
reg [C_WIDTH-1:0]   f_done;  // busy cycles of the running division so far
reg                 f_valid;
reg                 f_dz;
reg [Q_WIDTH-1:0]   f_q;
reg [C_WIDTH-1:0]   f_run;   // consecutive busy cycles seen at the port (in the valid cycle:
                             // the length of the run that ended)

wire [R_WIDTH-1:0]  f_job_r = (f_job_k == {K_WIDTH{1'b0}}) ? {R_WIDTH{1'b0}} : recip_of(f_job_k);
wire [R_WIDTH-1:0]  f_k_r = (f_k == {K_WIDTH{1'b0}}) ? {R_WIDTH{1'b0}} : recip_of(f_k);
wire                f_accept = rst_n && (f_left == {C_WIDTH{1'b0}}) && start;

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    f_valid <= 1'b0;
    if (f_left == {C_WIDTH{1'b0}}) begin
        if (a_we) f_a <= a_in;
        if (k_we) f_k <= k_in;
        if (start) begin
            f_job_a <= f_a;
            f_job_k <= f_k;
            f_left <= cycles_of(f_k_r);
            f_done <= {C_WIDTH{1'b0}};
            f_q <= $signed(f_a) * $signed({1'b0, f_k_r});
        end
    end else begin
        f_left <= f_left - 1'b1;
        f_done <= f_done + 1'b1;
        if (f_left == 1) begin
            f_valid <= 1'b1;
            f_dz <= (f_job_k == {K_WIDTH{1'b0}});
        end
    end
    f_run <= busy ? f_run + 1'b1 : {C_WIDTH{1'b0}};
    if (!rst_n) begin
        f_a <= {A_WIDTH{1'b0}};
        f_k <= {K_WIDTH{1'b0}};
        f_left <= {C_WIDTH{1'b0}};
        f_valid <= 1'b0;
        f_dz <= 1'b0;
        f_run <= {C_WIDTH{1'b0}};
    end
end

// ---------------------------------------------------------------- the one assumption
always @(*) begin
    if (!f_past_valid) assume(!rst_n);
end

// ---------------------------------------------------------------- properties (ports only)
always @(*) begin
    if (f_past_valid) begin
        // P_BUSY_EXACT: busy is high for exactly cycles(k) cycles after an accepted start, and
        // only then (a start while busy, or a k write while busy, changes nothing)
        if (check_on(P_BUSY_EXACT)) busy_exact: assert(busy == (f_left != {C_WIDTH{1'b0}}));
        // P_VALID_ONE_CYCLE: valid for one cycle, in the first cycle busy is 0 again
        if (check_on(P_VALID_ONE_CYCLE)) valid_one_cycle: assert(valid == f_valid);
        // P_DIV_ZERO: div_zero is that of the k the division ran on (the value held before the
        // start cycle's write), held until the next result; 0 after reset
        if (check_on(P_DIV_ZERO)) div_zero_of_the_job: assert(div_zero == f_dz);
        // P_BUSY_BOUNDED: never more than N + 1 busy cycles in a row
        if (check_on(P_BUSY_BOUNDED)) busy_bounded: assert(f_run <= R_WIDTH);
        // P_QUOTIENT: the result is q = a * round(2^N / k) (0 for k = 0), exactly
        if (ARITH != 0 && check_on(P_QUOTIENT) && valid) quotient: assert(q == f_q);
        // Invariants of the reference model itself (for induction; ports and shadows only)
        if (check_on(P_HELPERS)) begin
            if (busy) h_run_length: assert(f_run == f_done && f_left + f_done == cycles_of(f_job_r));
            else h_run_idle: assert(f_run == {C_WIDTH{1'b0}} || f_run == f_done);
        end
    end
end

always @(posedge clk) begin
    if (f_past_valid) begin
        // P_Q_HELD: q changes only with valid, or at a reset edge (with RESET_ALL = 0 the data
        // path is not reset, and a reset in a division's last cycle may load q: "the data
        // outputs are defined again from the next result")
        if (check_on(P_Q_HELD) && !valid && $past(rst_n))
            q_held: assert(q == $past(q));
        // P_RESET_IDLE: a cycle with rst_n low, from any state, leaves busy = valid =
        // div_zero = 0 (and q = 0 with RESET_ALL = 1)
        if (check_on(P_RESET_IDLE) && !$past(rst_n)) begin
            reset_idle: assert(!busy && !valid && !div_zero);
            if (RESET_ALL != 0) reset_q_zero: assert(q == {Q_WIDTH{1'b0}});
        end
    end
end

// ---------------------------------------------------------------- covers (none is vacuous)
always @(posedge clk) begin
    if (f_past_valid && rst_n) begin
        // c_idle, c_busy: both control states
        c_idle: cover(!busy && !valid);
        c_busy: cover(busy);
        // c_valid_k0, c_valid_nonzero: a result of each kind
        c_valid_k0: cover(valid && div_zero);
        c_valid_nonzero: cover(valid && !div_zero && f_job_k != {K_WIDTH{1'b0}});
        // c_longest_run, c_shortest_run: a run of N + 1 cycles and a 1-cycle run with k != 0 (k = 1)
        c_longest_run: cover(valid && f_run == R_WIDTH);
        c_shortest_run: cover(valid && f_run == 1 && !div_zero);
        // c_back_to_back: a start accepted in the valid cycle
        c_back_to_back: cover(valid && start);
        // c_write_in_start: the div_zero class: a k write in the start cycle, and the result
        // shows the flag of the k held before it while the register now holds the other
        c_write_in_start: cover(valid && div_zero != (f_k == {K_WIDTH{1'b0}}));
        // c_strobes_while_busy: both writes and start in a busy cycle
        c_strobes_while_busy: cover(busy && a_we && k_we && start);
        // c_reset_while_busy: reset in the middle of a division
        c_reset_while_busy: cover($past(busy) && !$past(rst_n));
        // c_negative_quotient: a negative quotient
        c_negative_quotient: cover(valid && q[Q_WIDTH-1]);
    end
end

// ---------------------------------------------------------------- induction helpers
`ifdef DIVIDER_INTERNALS
// Driven after flatten by the job's script (connect -nounset -set f_int_x \dut.x); see the header.
wire [A_WIDTH-1:0]  f_int_a;
wire [R_WIDTH-1:0]  f_int_recip;
wire                f_int_k_zero;
wire [R_WIDTH-1:0]  f_int_bits;
wire                f_int_run_zero;
wire                f_int_busy;
wire [Q_WIDTH-1:0]  f_int_shift;
wire [Q_WIDTH-1:0]  f_int_acc;

wire [Q_WIDTH-1:0]  f_job_a_q = {f_job_a, {RECIP_BITS{1'b0}}};
wire [R_WIDTH-1:0]  f_used_mask = ~({R_WIDTH{1'b1}} >> f_done);
// (each a wire of its own: a signed operand inside an unsigned comparison would be zero-extended)
wire [Q_WIDTH-1:0]  f_acc_want = $signed(f_job_a) * $signed({1'b0, f_job_r & f_used_mask});
wire [Q_WIDTH-1:0]  f_shift_want = $signed(f_job_a_q) >>> f_done;
wire [Q_WIDTH-1:0]  f_q_want = $signed(f_job_a) * $signed({1'b0, f_job_r});

always @(*) begin
    if (f_past_valid && check_on(P_HELPERS)) begin
        // operand registers: what the contract says was written (row 9: not while busy)
        h_a_reg: assert(f_int_a == f_a);
        h_k_zero_reg: assert(f_int_k_zero == (f_k == {K_WIDTH{1'b0}}));
        if (f_k != {K_WIDTH{1'b0}}) h_recip_reg: assert(f_int_recip == f_k_r);
        h_busy_reg: assert(f_int_busy == busy);
        if (busy) begin
            h_bits_reg: assert(f_int_bits == (f_job_r << f_done));
            h_run_zero_reg: assert(f_int_run_zero == (f_job_k == {K_WIDTH{1'b0}}));
            if (ARITH != 0) begin
                h_shift_reg: assert(f_int_shift == f_shift_want);
                h_acc_reg: assert(f_int_acc == f_acc_want);
                h_job_quotient: assert(f_q == f_q_want);
            end
        end
    end
end
`endif

endmodule
