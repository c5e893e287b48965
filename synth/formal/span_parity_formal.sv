// Formal properties of the exported span-parity block (`span_parity`,
// `rtl/src/span_parity.rs`): its flags follow the seed's toggle rule. The rule is written
// out below a second time, independently of the block, from the header of
// `span_parity.rs` (seed 001, sections 4 to 6), and every output must equal it after
// every clock, for any input sequence (any opcode, attribute, range and depth outcome,
// light bit, reset):
//
//   IF attr = IF THEN DSF := NOT DSF                               (every pixel)
//   IF covered AND Z < ZB THEN DSF := NOT DSF                       (range and depth test)
//   IF attr = EV THEN FSF := FSF OR DSF                             (end of one volume)
//   ClearFlags:       DSF := 0; FSF := 0
//   AccumulateShadow: COUNT := min(COUNT + FSF, 255)
//   LatchShadow{bit}: MASK := MASK OR (FSF << bit)
//   Check:            IF covered THEN FSF := FSF OR DSF
//   ClearLine / rst:  DSF := 0; FSF := 0; COUNT := 0; MASK := 0
//   OP spans, NOP and the other opcodes: no change.
`default_nettype none
module span_parity_formal (
    input wire clock
);
    localparam [2:0] CLEAR_LINE = 3'd1, SPAN = 3'd2, CLEAR_FLAGS = 3'd3, ACCUMULATE = 3'd4,
                     LATCH_SHADOW = 3'd5, CHECK = 3'd6;
    localparam [1:0] ATTR_OP = 2'd0, ATTR_EV = 2'd2, ATTR_IF = 2'd3;
    (* anyseq *) wire rst;
    (* anyseq *) wire [2:0] op;
    (* anyseq *) wire [1:0] attr;
    (* anyseq *) wire covered;
    (* anyseq *) wire z_lt;
    (* anyseq *) wire [2:0] light;
    wire dsf, fsf;
    wire [7:0] count, mask;

    span_parity dut (
        .clock(clock), .rst(rst), .op(op), .attr(attr), .covered(covered), .z_lt(z_lt),
        .light(light), .dsf(dsf), .fsf(fsf), .count(count), .mask(mask)
    );

    // The rule (power-on values 0, like the block's registers).
    reg s_dsf = 1'b0, s_fsf = 1'b0;
    reg [7:0] s_count = 8'd0, s_mask = 8'd0;
    reg d;
    always @(posedge clock) begin
        if (rst || op == CLEAR_LINE) begin
            s_dsf <= 1'b0;
            s_fsf <= 1'b0;
            s_count <= 8'd0;
            s_mask <= 8'd0;
        end else begin
            case (op)
                SPAN:
                    if (attr != ATTR_OP) begin
                        d = s_dsf;
                        if (attr == ATTR_IF) d = !d;
                        if (covered && z_lt) d = !d;
                        s_dsf <= d;
`ifndef MUTANT
                        if (attr == ATTR_EV) s_fsf <= s_fsf | d;
`endif
                    end
                CLEAR_FLAGS: begin
                    s_dsf <= 1'b0;
                    s_fsf <= 1'b0;
                end
                ACCUMULATE: if (s_count != 8'd255) s_count <= s_count + {7'd0, s_fsf};
                LATCH_SHADOW: s_mask <= s_mask | ({7'd0, s_fsf} << light);
                CHECK: if (covered) s_fsf <= s_fsf | s_dsf;
                default: ;
            endcase
        end
    end

    always @(*) begin
        P_dsf: assert (dsf == s_dsf);
        P_fsf: assert (fsf == s_fsf);
        P_count: assert (count == s_count);
        P_mask: assert (mask == s_mask);
    end

    // Reachability (not vacuous): a counter of 3 and a full light mask.
    always @(posedge clock) begin
        C_count: cover (count == 8'd3);
        C_mask_full: cover (mask == 8'hff);
    end
endmodule
