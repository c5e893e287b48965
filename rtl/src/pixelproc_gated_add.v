// pixelproc_gated_add: a W-bit adder whose second operand is gated, s = a + (en ? b : 0)
// modulo 2^W. Combinational.
//
// This is the generic (behavioural) implementation, the one the exported core carries
// and every simulator and generic synthesis reads. The ECP5 flow replaces it with
// synth/ecp5/pixelproc_gated_add.v (one carry chain of CCU2C whose LUTs take the gate),
// which behaves the same.
module pixelproc_gated_add #(parameter W = 8) (a, b, en, s);
    input wire [W-1:0] a;
    input wire [W-1:0] b;
    input wire en;
    output wire [W-1:0] s;

    assign s = a + (b & {W{en}});
endmodule // pixelproc_gated_add
