// Smoke testbench for the exported core (FuseSoC target `sim`, Icarus Verilog): two
// background-only tile-lines through pixelproc_top (N = 8), with the sink stalling every
// third clock. Expected from docs/core.md alone: a TILE beat (BG, BASE = 0, LAST = 7,
// SOF) and an END beat stream out 8 pixels of BG with tlast on the 8th and SOF on the
// first; a beat of an unknown kind sets proto_err. Prints PASS or FAIL and the first
// difference. The whole-frame checks against the golden model are the cocotb bench
// (testbench/cocotb) and `pixelproc testbench --frame`.
`default_nettype none
module tb_pixelproc_top;
    localparam [3:0] TILE = 4'd8, END_ = 4'd9, BAD = 4'd7;
    localparam [23:0] BG1 = 24'h3366cc, BG2 = 24'hf0a050;
    reg clock = 1'b0, rst = 1'b1;
    reg s_tvalid = 1'b0, m_tready = 1'b0;
    reg [255:0] s_tdata = 256'd0;
    reg [3:0] s_tuser = 4'd0;
    wire s_tready, m_tvalid, m_tlast, proto_err;
    wire [23:0] m_tdata;
    wire [50:0] m_tuser;
    wire [5:0] in_level;
    pixelproc_top dut (.clock(clock), .rst(rst), .s_axis_tvalid(s_tvalid),
        .s_axis_tready(s_tready), .s_axis_tdata(s_tdata), .s_axis_tuser(s_tuser),
        .m_axis_tvalid(m_tvalid), .m_axis_tready(m_tready), .m_axis_tdata(m_tdata),
        .m_axis_tuser(m_tuser), .m_axis_tlast(m_tlast), .proto_err(proto_err),
        .in_level(in_level));
    always #5 clock = ~clock;

    integer errors = 0, pixels = 0, cycles = 0;

    task send(input [3:0] kind, input [255:0] data);
        begin
            @(negedge clock);
            s_tvalid = 1'b1; s_tuser = kind; s_tdata = data;
            @(posedge clock);
            while (!s_tready) @(posedge clock);
            @(negedge clock);
            s_tvalid = 1'b0;
        end
    endtask

    // TILE fields: BG [23:0], BASE [35:24], LAST [47:36], SOF [48].
    function [255:0] tile(input [23:0] bg, input sof);
        tile = {207'd0, sof, 12'd7, 12'd0, bg};
    endfunction

    // Sink: stall every third clock; check each pixel.
    always @(posedge clock) begin
        cycles <= cycles + 1;
        if (!rst && m_tvalid && m_tready) begin
            if (m_tdata !== (pixels < 8 ? BG1 : BG2) || m_tlast !== (pixels % 8 == 7)
                || m_tuser[0] !== (pixels == 0)) begin
                errors = errors + 1;
                $display("FAIL: pixel %0d: rgb %h tlast %b sof %b", pixels, m_tdata, m_tlast, m_tuser[0]);
            end
            pixels = pixels + 1;
        end
    end
    always @(negedge clock) m_tready = (cycles % 3) != 0;

    initial begin
        repeat (3) @(posedge clock);
        if (s_tready !== 1'b0) begin errors = errors + 1; $display("FAIL: s_axis_tready high during reset"); end
        @(negedge clock) rst = 1'b0;
        send(TILE, tile(BG1, 1'b1));
        send(TILE, tile(BG2, 1'b0));
        send(END_, {232'd0, 24'h000000});
        repeat (200) @(posedge clock);
        if (pixels != 16) begin errors = errors + 1; $display("FAIL: %0d pixels, expected 16", pixels); end
        if (proto_err !== 1'b0) begin errors = errors + 1; $display("FAIL: proto_err set by valid beats"); end
        send(BAD, 256'd0);
        repeat (4) @(posedge clock);
        if (proto_err !== 1'b1) begin errors = errors + 1; $display("FAIL: an unknown beat kind did not set proto_err"); end
        if (errors == 0) $display("PASS: 16 pixels, framing and proto_err as in docs/core.md");
        else $fatal(1, "FAIL: %0d errors", errors);
        $finish;
    end
endmodule
