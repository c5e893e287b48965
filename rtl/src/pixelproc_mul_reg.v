// pixelproc_mul_reg: an unsigned 16 x 16 bit multiplier with registered operands and a
// registered product. The operands at `a` and `b` before edge E are multiplied; the
// product is on `p` after edge E + 1. All registers are 0 at power-on.
//
// This is the generic (behavioural) implementation, the one the exported core carries
// and every simulator and generic synthesis reads. The ECP5 flow replaces it with
// synth/ecp5/pixelproc_mul_reg.v (one MULT18X18D whose own input and output registers
// are the two registers here), which behaves the same.
module pixelproc_mul_reg(clock, a, b, p);
    input wire clock;
    input wire [15:0] a;
    input wire [15:0] b;
    output reg [31:0] p;

    // The operand registers.
    reg [15:0] a_r;
    reg [15:0] b_r;

    initial begin
        a_r = 16'h0;
        b_r = 16'h0;
        p = 32'h0;
    end

    always @(posedge clock) begin
        a_r <= a;
        b_r <= b;
        p <= {16'h0, a_r} * {16'h0, b_r};
    end
endmodule // pixelproc_mul_reg
