// SPDX-License-Identifier: Apache-2.0
/*
 * AXI4-Stream interface properties of one port, for SymbiYosys (read_verilog -formal): the
 * handshake rules of the source (ZipCPU's faxis_master / faxis_slave idea), reusable on any
 * port of any design.  Bound to both ports of the shading core by formal/shading_core_props.v;
 * docs/formal.md lists what each rule proves.
 *
 * OUTPUT = 1: the port is the design's output (the design is the source): the rules are
 * asserted.  OUTPUT = 0: the port is the design's input (the environment is the source): the
 * same rules are assumed, so that the design is checked against every legal source.
 *
 * The rules, in every cycle after the first (rst_n synchronous, active low):
 *   tvalid_held             a beat offered and not taken (tvalid && !tready) is offered again in
 *                           the next cycle, unless that edge was a reset edge (rst_n low in the
 *                           cycle before);
 *   tdata_stable            in that next cycle tdata, tlast and tuser are those of the cycle
 *                           before (the beat does not change while it waits);
 *   tvalid_low_after_reset  in a cycle after one with rst_n low, tvalid is 0 (the source starts
 *                           offering beats no earlier than one clock after reset).
 * The source may raise tvalid whenever it likes, and tready (the sink's) is free: no rule is
 * placed on it.  X values play no part in formal (every bit is 0 or 1).
 *
 * CHECK_VALID, CHECK_STABLE, CHECK_RESET (OUTPUT = 1 only): 0 switches that assert off (the
 * deliberate-error runs keep one property on; covers switch all off).  The assumptions of
 * OUTPUT = 0 are always on.
 */

module axis_props #(
    parameter DATA_WIDTH = 8,
    parameter USER_WIDTH = 1,
    // 1: the design's output (asserted); 0: the design's input (assumed)
    parameter OUTPUT = 1,
    parameter CHECK_VALID = 1,
    parameter CHECK_STABLE = 1,
    parameter CHECK_RESET = 1
) (
    input wire                  clk,
    input wire                  rst_n,
    input wire [DATA_WIDTH-1:0] tdata,
    input wire                  tlast,
    input wire [USER_WIDTH-1:0] tuser,
    input wire                  tvalid,
    input wire                  tready
);

reg f_past_valid = 1'b0;
always @(posedge clk) begin
    f_past_valid <= 1'b1;
end

// The rules' conditions and claims, shared by the assert and the assume forms
wire f_waited;  // the cycle before offered a beat that was not taken, not at a reset edge
wire f_held;    // tvalid is high again
wire f_stable;  // tdata, tlast and tuser are the cycle before's
wire f_reset;   // the cycle before had rst_n low
reg  [DATA_WIDTH-1:0] f_tdata;
reg                   f_tlast;
reg  [USER_WIDTH-1:0] f_tuser;
reg                   f_tvalid;
reg                   f_tready;
reg                   f_rst_n;
always @(posedge clk) begin
    f_tdata <= tdata;
    f_tlast <= tlast;
    f_tuser <= tuser;
    f_tvalid <= tvalid;
    f_tready <= tready;
    f_rst_n <= rst_n;
end
assign f_waited = f_past_valid && f_rst_n && f_tvalid && !f_tready;
assign f_held = tvalid;
assign f_stable = (tdata == f_tdata) && (tlast == f_tlast) && (tuser == f_tuser);
assign f_reset = f_past_valid && !f_rst_n;

generate
    // Each assert in a block of its own: one switched off is not built at all (a disabled
    // assert would keep the logic it reads, e.g. the whole data path behind tdata)
    if (OUTPUT != 0 && CHECK_VALID != 0) begin : g_valid
        always @(*) begin
            if (f_waited) tvalid_held: assert(f_held);
        end
    end
    if (OUTPUT != 0 && CHECK_STABLE != 0) begin : g_stable
        always @(*) begin
            if (f_waited) tdata_stable: assert(f_stable);
        end
    end
    if (OUTPUT != 0 && CHECK_RESET != 0) begin : g_reset
        always @(*) begin
            if (f_reset) tvalid_low_after_reset: assert(!tvalid);
        end
    end
    if (OUTPUT == 0) begin : g_assume
        always @(*) begin
            if (f_waited) src_tvalid_held: assume(f_held);
            if (f_waited) src_tdata_stable: assume(f_stable);
            if (f_reset) src_tvalid_low_after_reset: assume(!tvalid);
        end
    end
endgenerate

endmodule
