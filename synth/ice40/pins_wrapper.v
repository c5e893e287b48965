// Pin-reduced wrapper for placing the pixelproc core on an iCE40 HX8K (CT256, 206 I/O):
// the core's 256-bit command word and 51-bit pixel tuser do not fit the package, and
// nextpnr-ice40 has no out-of-context mode. The command word is loaded through an 8-bit
// shift port (`cmd_shift`: word := word << 8 | cmd_byte) and presented as s_axis_tdata;
// the pixel tuser is folded to one pin (XOR). Everything else is the core's own port.
// Only for measuring resources and Fmax (synth/flow_ice40.sh); adds 256 flip-flops.
`default_nettype none
module pixelproc_ice40_pins (
    input wire clock,
    input wire rst,
    input wire [7:0] cmd_byte,
    input wire cmd_shift,
    input wire [3:0] s_kind,
    input wire s_valid,
    output wire s_ready,
    output wire m_valid,
    input wire m_ready,
    output wire [23:0] m_data,
    output wire m_user,
    output wire m_last,
    output wire proto_err
);
    reg [255:0] word = 256'd0;
    always @(posedge clock) if (cmd_shift) word <= {word[247:0], cmd_byte};
    wire [50:0] tuser;
    pixelproc_top core (
        .clock(clock), .rst(rst),
        .s_axis_tvalid(s_valid), .s_axis_tready(s_ready), .s_axis_tdata(word), .s_axis_tuser(s_kind),
        .m_axis_tvalid(m_valid), .m_axis_tready(m_ready), .m_axis_tdata(m_data),
        .m_axis_tuser(tuser), .m_axis_tlast(m_last), .proto_err(proto_err),
        .in_level()
    );
    assign m_user = ^tuser;
endmodule
