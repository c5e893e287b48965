// Formal properties of the exported stream FIFO (`rtl/src/stream_fifo.rs`, instantiated
// in the exported core as `pixelproc_top$out_fifo` and `pixelproc_top$in_fifo`).
// The DUT module comes from `FIFO_MODULE` (a define set by the .sby file); W, LW and
// DEPTH are its data width, level width and depth.
//
// The source is the environment: any valid, any ready, any reset, under the AXI4-Stream
// source rule (a valid beat stays valid until taken). Its data is a tag of the beat's
// sequence number (`tag(n)`: the 16-bit count of beats accepted since the last reset,
// repeated across the word). The FIFO never looks at its data (it only stores and
// moves it), so by data independence a FIFO that delivers `tag(0), tag(1), ...` in order
// delivers any data in order: nothing dropped, duplicated or reordered.
//
// Properties (checked every clock):
//   A1 level == accepted - delivered       (the count: nothing dropped or duplicated)
//   A2 level <= DEPTH; in_ready == !rst && level != DEPTH (no overflow; ready rule)
//   A3 out_valid implies level != 0
//   A4 out_valid, not out_ready -> next clock out_valid and the same out_data
//      (AXI4-Stream: valid stays up and data is stable until taken)
//   A6 ne == (level != out_valid): the FIFO's registered non-empty flag `ne` (read by
//      its fetch decision) equals `wr != rd` (level = wr - rd + out_valid). The flag is
//      internal state no port shows, so fifo.sby exposes it as a port (`expose`) and
//      the induction needs A6 as an invariant.
//   A7 level == wr - rd + out_valid: the FIFO's level is a register of its own (`lv`,
//      counted up and down; `level` shows it), so the induction needs its relation to
//      the pointers (exposed like `ne`) as an invariant.
//   A5 (DATA) out_valid -> out_data == tag(delivered): the head is the next beat in
//      order, so content and order are right. Memory contents are not visible in the
//      induction's free start state, so A5 is checked bounded only (task `data`).
`default_nettype none
module fifo_formal #(
    parameter integer W = 76,
    parameter integer LW = 5,
    parameter integer DEPTH = 16
) (
    input wire clock
);
    (* anyseq *) wire rst;
    (* anyseq *) wire in_valid;
    (* anyseq *) wire out_ready;
    wire in_ready, out_valid;
    wire [W-1:0] out_data;
    wire [LW-1:0] level;
    wire ne;
    wire [LW-2:0] wa, ra;  // the pointers' addresses; ww, rw their wrap bits
    wire ww, rw;
    reg [15:0] n_in = 16'd0;   // beats accepted since the last reset (mod 2^16)
    reg [15:0] n_out = 16'd0;  // beats delivered since the last reset (mod 2^16)

    function automatic [W-1:0] tag(input [15:0] n);
        tag = {((W + 15) / 16){n}};
    endfunction

    wire [W-1:0] in_data = tag(n_in);

    `FIFO_MODULE dut (
        .clock(clock), .rst(rst),
        .in_valid(in_valid), .in_data(in_data), .in_ready(in_ready),
        .out_valid(out_valid), .out_data(out_data), .out_ready(out_ready),
        .level(level), .\ne$q (ne),
        .\wa$q (wa), .\ww$q (ww), .\ra$q (ra), .\rw$q (rw)
    );

    always @(posedge clock) begin
        if (rst) begin
            n_in <= 16'd0;
            n_out <= 16'd0;
        end else begin
            if (in_valid && in_ready) n_in <= n_in + 16'd1;
`ifndef MUTANT
            if (out_valid && out_ready) n_out <= n_out + 16'd1;
`else
            // Mutant: the checker miscounts a delivered beat; A1 must fail.
            if (out_valid && out_ready) n_out <= n_out + 16'd2;
`endif
        end
    end

    // The run starts with a reset.
    always @(*) if ($initstate) assume (rst);

    // Source rule: a beat offered and not taken is still offered on the next clock (its
    // data is tag(n_in), unchanged because n_in only moves when a beat is taken).
    always @(posedge clock)
        if (!$initstate && !$past(rst) && !rst && $past(in_valid && !in_ready))
            assume (in_valid);

    wire [15:0] held = n_in - n_out;

    always @(*) if (!$initstate) begin
        A1_count: assert (held == {{(16 - LW){1'b0}}, level});
        A2_bound: assert (level <= DEPTH);
        A2_ready: assert (in_ready == (!rst && level != DEPTH));
        A3_valid: assert (!out_valid || level != 0);
        A6_nonempty: assert (ne == (level != {{(LW - 1){1'b0}}, out_valid}));
        A7_level: assert (level == {ww, wa} - {rw, ra} + {{(LW - 1){1'b0}}, out_valid});
`ifdef DATA
        A5_order: assert (!out_valid || out_data == tag(n_out));
`endif
    end

    always @(posedge clock)
        if (!$initstate && !$past(rst) && $past(out_valid && !out_ready)) begin
            A4_valid_held: assert (out_valid);
            A4_data_stable: assert (out_data == $past(out_data));
        end

    // Reachability: the FIFO fills up and drains (not vacuous).
    always @(posedge clock) if (!$initstate && !rst) begin
        C_full: cover (level == DEPTH);
        C_full_then_pop: cover ($past(level == DEPTH) && !$past(rst) && $past(out_valid && out_ready));
    end
endmodule
