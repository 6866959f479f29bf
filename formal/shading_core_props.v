// SPDX-License-Identifier: Apache-2.0
/*
 * Formal properties of the shading core's stream protocol (rtl/shading_core.v, docs/core.md),
 * for SymbiYosys (read_verilog -formal; model/hw/formal_core.py holds the jobs, docs/formal.md
 * lists every property beside the sentence it proves).
 *
 * shading_core_formal wraps one shading_core (instance "dut", the job's reduced
 * configuration: model.hw.formal_core CONFIGS, its highlight path the specular unit's or a
 * BRDF form's) with every input free and binds
 * formal/axis_props.v to both ports: s_axis as the design's input (the source's rules
 * assumed), m_axis as its output (asserted: tvalid_held, tdata_stable,
 * tvalid_low_after_reset).  Beside them a model of the stream in shadow registers, driven by
 * the ports only:
 *   f_trk, f_tl       one span beat taken, chosen freely (the input f_pick in the cycle it is
 *                     taken, while no other is tracked), and its l: as the choice is free,
 *                     what is asserted of it holds for every span beat (the "any one
 *                     transaction" form: counters only, no queue of spans);
 *   f_before          the pixel beats of earlier spans still to come before its first one
 *                     (the pixels outstanding when it was taken);
 *   f_tidx            its pixel beats already out;
 *   f_total           the pixels taken and not yet out: the sum of l + 1 over the spans taken,
 *                     less the pixel beats;
 *   f_fresh           no span beat taken since the last cycle with rst_n low;
 *   f_wait            clocks in a row with m_axis_tready high, a pixel outstanding and no
 *                     pixel beat.
 * Properties (one labelled assert each, numbered by the P_* localparams):
 *   beat_of_a_span      m_axis_tvalid only while a pixel is outstanding (f_total != 0);
 *   tlast_exact         on every pixel beat of the tracked span (the f_before + 1-th to the
 *                       f_before + l + 1-th beat after it was taken), tlast = (f_tidx = l): its
 *                       (l + 1)-th beat has tlast and none before it does, so every span beat
 *                       taken gives exactly l + 1 pixel beats, in the order taken;
 *   no_deadlock         f_wait < WAIT_N: with tready held high, a pending pixel leaves within
 *                       WAIT_N clocks (LATENCY + the longest span, 2^LEN_WIDTH pixels);
 *   no_beat_after_reset after a cycle with rst_n low, m_axis_tvalid = 0 until a span beat is
 *                       taken (no beat of a span from before the reset).
 * The ROMs take no part: the job's script removes them and their read data is free in every
 * cycle (the properties are about control, not pixel values).
 * CHECK = 0: the job's set: BOUNDED = 0 (the k-induction job) the interface rules,
 * no_beat_after_reset and the helper; BOUNDED = 1 (the bmc job) beat_of_a_span, tlast_exact
 * and no_deadlock, which hold by bounded model checking only (docs/formal.md, "not proven");
 * n: only number n (the deliberate-error runs); 99: none (covers).
 *
 * Induction helper (`define CORE_INTERNALS, prove and bmc jobs): h_fresh_empty, while f_fresh
 * the core is empty (no valid stage, no pixel in flight, the FIFO and its output register
 * empty); the f_int_* wires are left undriven here and the job's script connects them after
 * `flatten` to the core's registers.  Asserted, never assumed.
 *
 * The one assumption of the wrapper: reset (rst_n = 0) in the first cycle; axis_props adds
 * the source's rules on s_axis.  Everything else is free.
 */

module shading_core_formal #(
    // The core's parameters (model.hw.formal_core CONFIGS; the job sets them all)
    parameter X_WIDTH = 2,
    parameter Y_WIDTH = 2,
    parameter SPECULAR = 1,
    parameter DIFFUSE = 1,
    parameter FIFO_DEPTH = 16,
    parameter A_WIDTH = 5,
    parameter K_WIDTH = 2,
    parameter RECIP_BITS = 4,
    parameter RECIP_ROM_FILE = "recip.hex",
    parameter I_INT = 2,
    parameter I_FRAC = 2,
    parameter LEN_WIDTH = 2,
    parameter C_INT_BITS = 2,
    parameter C_FRAC_BITS = 3,
    parameter Z_INT_BITS = 3,
    parameter Z_FRAC_BITS = 4,
    parameter SPEC_LEN_WIDTH = 2,
    parameter A_INT_BITS = 1,
    parameter A_FRAC_BITS = 4,
    parameter ROM_ADDR_BITS = 3,
    parameter ROM_DATA_BITS = 5,
    parameter OUT_WIDTH = 2,
    parameter NUM_TABLES = 4,
    parameter N_HI0 = 1,
    parameter N_HI1 = 2,
    parameter N_HI2 = 6,
    parameter N_HI3 = 1000,
    parameter K0 = 1,
    parameter K1 = 2,
    parameter K2 = 4,
    parameter K3 = 16,
    parameter [8*10-1:0] ALPHA = "taylor",
    parameter MAG_INT_BITS = 1,
    parameter N_FIRST = 1,
    parameter N_LAST = 8,
    parameter A_ROM_FILE = "a.hex",
    parameter COS_ROM_FILE = "cos.hex",
    parameter [8*16-1:0] HIGHLIGHT = "specular",
    parameter COS_ADDR_BITS = 3,
    parameter COS_DATA_BITS = 5,
    parameter COEF_BITS = 18,
    parameter WORK_BITS = 4,
    parameter OUT_BITS = 3,
    parameter LOG_ADDR_BITS = 10,
    parameter LOG_DATA_BITS = 16,
    parameter ANGLE_ROM_FILE = "angle.hex",
    parameter COEF_ROM_FILE = "coef.hex",
    parameter LOG_ROM_FILE = "log.hex",
    // Clocks from a span beat taken to its first pixel beat (model.render.core.latency: 18
    // with the specular unit's highlight path, more with a BRDF form's)
    parameter LATENCY = 18,
    // 0: the k-inductive properties (the prove job); 1: the bounded ones, beat_of_a_span,
    // tlast_exact and no_deadlock (the bmc job); a CHECK of one property overrides it
    parameter BOUNDED = 1,
    // Unused (model.hw.formal sets them for every unit)
    parameter RESET_ALL = 0,
    parameter ARITH = 0,
    parameter CHECK = 0
) (
    input wire                  clk,
    input wire                  rst_n,
    input wire [SPAN_WIDTH-1:0] s_axis_tdata,
    input wire                  s_axis_tvalid,
    input wire                  m_axis_tready,
    // Free: 1 chooses the span beat taken in this cycle as the tracked span (tlast_exact)
    input wire                  f_pick
);

localparam I_W = I_INT + I_FRAC;
localparam C_W = C_INT_BITS + C_FRAC_BITS;
localparam Z_W = Z_INT_BITS + Z_FRAC_BITS;
localparam SPAN_WIDTH = (X_WIDTH + Y_WIDTH + LEN_WIDTH + 2 + 6 * I_W + 4 * C_W + 4 * Z_W + 10
                         + 7) / 8 * 8;
localparam PIX_WIDTH = (X_WIDTH + Y_WIDTH + 24 + 7) / 8 * 8;
localparam O_L = X_WIDTH + Y_WIDTH;  // l in the span beat (model.render.core.SpanFormat)
localparam MAX_PIXELS = 1 << LEN_WIDTH;  // the longest span: l = 2^LEN_WIDTH - 1
localparam WAIT_N = LATENCY + MAX_PIXELS;
// f_total's bits: the core holds at most FIFO_DEPTH pixels in flight and five spans in stages
// A..D and the span register
localparam T_BITS = LEN_WIDTH + 8;
localparam OCC_BITS = (FIFO_DEPTH > 2048) ? 13 : (FIFO_DEPTH > 1024) ? 12
                    : (FIFO_DEPTH > 512) ? 11 : (FIFO_DEPTH > 256) ? 10 : (FIFO_DEPTH > 128) ? 9
                    : (FIFO_DEPTH > 64) ? 8 : (FIFO_DEPTH > 32) ? 7 : (FIFO_DEPTH > 16) ? 6 : 5;
localparam F_ADDR = OCC_BITS - 1;  // the FIFO's ADDR_BITS (FIFO_DEPTH = 2^F_ADDR)
// The core's pixel pipeline S1..S(STAGES) (its v_reg): the latency less the span pipe (6:
// stage A, B..E, the span register) and the FIFO's write and output register (2)
localparam STAGES = LATENCY - 8;

// Property numbers (CHECK selects one)
localparam P_TVALID_HELD = 1;
localparam P_TDATA_STABLE = 2;
localparam P_TVALID_LOW_AFTER_RESET = 3;
localparam P_BEAT_OF_A_SPAN = 4;
localparam P_TLAST_EXACT = 5;
localparam P_NO_DEADLOCK = 6;
localparam P_NO_BEAT_AFTER_RESET = 7;
localparam P_HELPERS = 9;

// The bounded properties (bounded model checking only); the others are proven by k-induction
function bounded_p(input integer p);
    bounded_p = (p == P_BEAT_OF_A_SPAN) || (p == P_TLAST_EXACT) || (p == P_NO_DEADLOCK);
endfunction

// CHECK = n: property n alone; CHECK = 0: the job's set (BOUNDED = 0: the k-inductive
// properties and the helper; 1: the bounded ones)
function check_on(input integer p);
    check_on = (CHECK == p) || (CHECK == 0 && ((BOUNDED != 0) == bounded_p(p)));
endfunction

wire                 s_axis_tready;
wire [PIX_WIDTH-1:0] m_axis_tdata;
wire                 m_axis_tlast;
wire                 m_axis_tuser;
wire                 m_axis_tvalid;

shading_core #(
    .X_WIDTH(X_WIDTH),
    .Y_WIDTH(Y_WIDTH),
    .SPECULAR(SPECULAR),
    .DIFFUSE(DIFFUSE),
    .FIFO_DEPTH(FIFO_DEPTH),
    .A_WIDTH(A_WIDTH),
    .K_WIDTH(K_WIDTH),
    .RECIP_BITS(RECIP_BITS),
    .RECIP_ROM_FILE(RECIP_ROM_FILE),
    .I_INT(I_INT),
    .I_FRAC(I_FRAC),
    .LEN_WIDTH(LEN_WIDTH),
    .C_INT_BITS(C_INT_BITS),
    .C_FRAC_BITS(C_FRAC_BITS),
    .Z_INT_BITS(Z_INT_BITS),
    .Z_FRAC_BITS(Z_FRAC_BITS),
    .SPEC_LEN_WIDTH(SPEC_LEN_WIDTH),
    .A_INT_BITS(A_INT_BITS),
    .A_FRAC_BITS(A_FRAC_BITS),
    .ROM_ADDR_BITS(ROM_ADDR_BITS),
    .ROM_DATA_BITS(ROM_DATA_BITS),
    .OUT_WIDTH(OUT_WIDTH),
    .NUM_TABLES(NUM_TABLES),
    .N_HI0(N_HI0),
    .N_HI1(N_HI1),
    .N_HI2(N_HI2),
    .N_HI3(N_HI3),
    .K0(K0),
    .K1(K1),
    .K2(K2),
    .K3(K3),
    .ALPHA(ALPHA),
    .MAG_INT_BITS(MAG_INT_BITS),
    .N_FIRST(N_FIRST),
    .N_LAST(N_LAST),
    .A_ROM_FILE(A_ROM_FILE),
    .COS_ROM_FILE(COS_ROM_FILE),
    .HIGHLIGHT(HIGHLIGHT),
    .COS_ADDR_BITS(COS_ADDR_BITS),
    .COS_DATA_BITS(COS_DATA_BITS),
    .COEF_BITS(COEF_BITS),
    .WORK_BITS(WORK_BITS),
    .OUT_BITS(OUT_BITS),
    .LOG_ADDR_BITS(LOG_ADDR_BITS),
    .LOG_DATA_BITS(LOG_DATA_BITS),
    .ANGLE_ROM_FILE(ANGLE_ROM_FILE),
    .COEF_ROM_FILE(COEF_ROM_FILE),
    .LOG_ROM_FILE(LOG_ROM_FILE)
) dut (
    .clk(clk),
    .rst_n(rst_n),
    .s_axis_tdata(s_axis_tdata),
    .s_axis_tvalid(s_axis_tvalid),
    .s_axis_tready(s_axis_tready),
    .m_axis_tdata(m_axis_tdata),
    .m_axis_tlast(m_axis_tlast),
    .m_axis_tuser(m_axis_tuser),
    .m_axis_tvalid(m_axis_tvalid),
    .m_axis_tready(m_axis_tready)
);

// ---------------------------------------------------------------- the interface rules
// s_axis: the environment is the source (assumed); tlast and tuser are not part of the span
// stream (held at 0)
axis_props #(
    .DATA_WIDTH(SPAN_WIDTH),
    .USER_WIDTH(1),
    .OUTPUT(0)
) u_s_props (
    .clk(clk),
    .rst_n(rst_n),
    .tdata(s_axis_tdata),
    .tlast(1'b0),
    .tuser(1'b0),
    .tvalid(s_axis_tvalid),
    .tready(s_axis_tready)
);

// m_axis: the core is the source (asserted)
axis_props #(
    .DATA_WIDTH(PIX_WIDTH),
    .USER_WIDTH(1),
    .OUTPUT(1),
    .CHECK_VALID(check_on(P_TVALID_HELD)),
    .CHECK_STABLE(check_on(P_TDATA_STABLE)),
    .CHECK_RESET(check_on(P_TVALID_LOW_AFTER_RESET))
) u_m_props (
    .clk(clk),
    .rst_n(rst_n),
    .tdata(m_axis_tdata),
    .tlast(m_axis_tlast),
    .tuser(m_axis_tuser),
    .tvalid(m_axis_tvalid),
    .tready(m_axis_tready)
);

// ---------------------------------------------------------------- the stream model
wire s_fire = rst_n && s_axis_tvalid && s_axis_tready;
wire m_fire = rst_n && m_axis_tvalid && m_axis_tready;
wire [LEN_WIDTH-1:0] s_l = s_axis_tdata[O_L +: LEN_WIDTH];

reg                  f_past_valid = 1'b0;
reg [T_BITS-1:0]     f_total;
reg                  f_fresh;
reg [5:0]            f_wait;
reg                  f_reset_busy = 1'b0;  // a reset came while pixels were outstanding
// The tracked span: one span beat, chosen freely (f_pick) among those taken
reg                  f_trk;
reg [T_BITS-1:0]     f_before;  // pixel beats of earlier spans still to come before its first
reg [LEN_WIDTH-1:0]  f_tl;      // its l
reg [LEN_WIDTH-1:0]  f_tidx;    // its pixel beats already out
wire                 f_tnow = f_trk && (f_before == 0);  // the beat on m_axis is one of its
wire                 f_tlast_want = (f_tidx == f_tl);

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    if (s_fire) begin
        f_fresh <= 1'b0;
    end
    f_total <= f_total + (s_fire ? {{(T_BITS-LEN_WIDTH){1'b0}}, s_l} + 1'b1 : {T_BITS{1'b0}})
             - {{(T_BITS-1){1'b0}}, m_fire};
    if (f_trk && m_fire) begin
        if (f_before != 0) begin
            f_before <= f_before - 1'b1;
        end else if (f_tlast_want) begin
            f_trk <= 1'b0;  // its last pixel is out: another span may be chosen
        end else begin
            f_tidx <= f_tidx + 1'b1;
        end
    end
    if (s_fire && f_pick && !f_trk) begin
        f_trk <= 1'b1;
        f_before <= f_total - {{(T_BITS-1){1'b0}}, m_fire};
        f_tl <= s_l;
        f_tidx <= {LEN_WIDTH{1'b0}};
    end
    if (!m_axis_tready || m_fire || f_total == 0) begin
        f_wait <= 6'd0;
    end else if (f_wait != 6'h3f) begin
        f_wait <= f_wait + 1'b1;
    end
    if (!rst_n && f_past_valid && f_total != 0) f_reset_busy <= 1'b1;
    if (!rst_n) begin
        f_total <= {T_BITS{1'b0}};
        f_fresh <= 1'b1;
        f_wait <= 6'd0;
        f_trk <= 1'b0;
    end
end

// ---------------------------------------------------------------- the one assumption
always @(*) begin
    if (!f_past_valid) assume(!rst_n);
end

// ---------------------------------------------------------------- properties (ports only)
// Each in a generate block of its own: a property switched off is not built
generate
    if (check_on(P_NO_BEAT_AFTER_RESET)) begin : g_no_beat_after_reset
        always @(*) begin
            // after a cycle with rst_n low, no pixel beat until a span beat is taken
            if (f_past_valid && rst_n && f_fresh) no_beat_after_reset: assert(!m_axis_tvalid);
        end
    end
    if (check_on(P_BEAT_OF_A_SPAN)) begin : g_beat_of_a_span
        always @(*) begin
            // a pixel beat only while a pixel of a span taken is still to come
            if (f_past_valid && rst_n && m_axis_tvalid) beat_of_a_span: assert(f_total != 0);
        end
    end
    if (check_on(P_TLAST_EXACT)) begin : g_tlast_exact
        always @(*) begin
            // tlast exactly on the (l + 1)-th beat of each span, in the order taken (the
            // tracked span's: any span beat taken may be the one tracked)
            if (f_past_valid && rst_n && m_axis_tvalid && f_tnow)
                tlast_exact: assert(m_axis_tlast == f_tlast_want);
        end
    end
    if (check_on(P_NO_DEADLOCK)) begin : g_no_deadlock
        always @(*) begin
            // with tready high, a pending pixel leaves within WAIT_N clocks
            if (f_past_valid && rst_n) no_deadlock: assert(f_wait < WAIT_N);
        end
    end
endgenerate

// ---------------------------------------------------------------- induction helper
`ifdef CORE_INTERNALS
wire                  f_int_va;
wire                  f_int_vb;
wire                  f_int_vc;
wire                  f_int_vd;
wire                  f_int_ve;
wire                  f_int_act;
wire [OCC_BITS-1:0]   f_int_occ;
wire [STAGES-1:0]     f_int_v;
wire [F_ADDR:0]       f_int_wr;
wire [F_ADDR:0]       f_int_rd;
wire                  f_int_out_valid;
always @(*) begin
    if (f_past_valid && check_on(P_HELPERS) && f_fresh) begin  // (CORE_INTERNALS: prove, bmc)
        // since the reset no span beat was taken: the core is empty
        h_fresh_empty: assert(!f_int_va && !f_int_vb && !f_int_vc && !f_int_vd && !f_int_ve
                              && !f_int_act
                              && f_int_occ == 0 && f_int_v == 0 && f_int_wr == f_int_rd
                              && !f_int_out_valid);
    end
end
`endif

// ---------------------------------------------------------------- covers (none is vacuous)
always @(posedge clk) begin
    if (f_past_valid && rst_n) begin
        // a pixel beat waits (tready low), then leaves
        c_stalled_beat: cover($past(m_axis_tvalid && !m_axis_tready && rst_n) && m_fire);
        // the last pixel of a span of the longest length
        c_long_span_last: cover(m_fire && m_axis_tlast && f_tnow && f_tl == MAX_PIXELS - 1);
        // a one-pixel span's pixel right after the last pixel of another span
        c_back_to_back: cover(m_fire && f_tnow && f_tl == 0 && $past(m_fire && m_axis_tlast));
        // the first pixel after the longest wait the bound allows for one span (LATENCY - 1)
        c_first_pixel_latency: cover(m_fire && f_wait == LATENCY - 1);
        // s_axis_tready low while a beat is offered (the core full)
        c_input_stalled: cover(s_axis_tvalid && !s_axis_tready);
        // reset while pixels were outstanding, then a new span's pixel
        c_reset_while_busy: cover(m_fire && f_reset_busy);
    end
end

endmodule
