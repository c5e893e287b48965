// pixelproc_gated_add for the ECP5: s = a + (en ? b : 0) modulo 2^W as one carry chain
// of CCU2C cells whose LUTs take the gate, so that no LUT4 per bit gates b (or selects
// the sum) beside the chain.
//
// Same ports and behaviour as the generic module the exported core carries (the end of
// pixelproc_top.v). Read by synth/flow_ecp5.sh (and the other ECP5 scripts) after the
// export, with `read_verilog -overwrite`, in place of the generic definition;
// testbench/tests/ecp5_gated_add.rs proves the two equal with Yosys's SAT solver, on
// Yosys's own simulation model of the CCU2C.
//
// Each half of a CCU2C (Yosys's model, cells_sim.v) computes a propagate bit P with a
// LUT4 of (A, B, C, D) and a generate bit G with a LUT2 of (A, B) taken from the LUT4's
// INIT bits 3:0 (the values at C = D = 0); its carry out is P ? carry in : G, and its
// sum bit P ^ carry in. Here A = a[i], B = b[i], D = en, C = 0:
//   P = A ^ (B & D)          INIT = 16'h66AA (bits 7:0 = A for D = 0, bits 15:8 = A ^ B)
//   G = A                    INIT[3:0] = 4'hA
// Where P = 0, A equals B & D, so G = A is the carry of A + (B & D). The gate is on D,
// the LUT's fastest input. The chain starts with a carry in of 0.
module pixelproc_gated_add #(parameter W = 8) (a, b, en, s);
    input wire [W-1:0] a;
    input wire [W-1:0] b;
    input wire en;
    output wire [W-1:0] s;

    // Two bits per CCU2C; an odd width leaves the last half adding 0 + 0.
    localparam H = (W + 1) / 2;
    wire [2*H-1:0] aa = a;
    wire [2*H-1:0] bb = b;
    wire [2*H-1:0] ss;
    wire [H:0] carry;
    assign carry[0] = 1'b0;
    assign s = ss[W-1:0];

    genvar k;
    generate
        for (k = 0; k < H; k = k + 1) begin : chain
            CCU2C #(
                .INIT0(16'h66AA),
                .INIT1(16'h66AA),
                .INJECT1_0("NO"),
                .INJECT1_1("NO")
            ) ccu (
                .CIN(carry[k]),
                .A0(aa[2*k]), .B0(bb[2*k]), .C0(1'b0), .D0(en),
                .A1(aa[2*k+1]), .B1(bb[2*k+1]), .C1(1'b0), .D1(en),
                .S0(ss[2*k]), .S1(ss[2*k+1]),
                .COUT(carry[k+1])
            );
        end
    endgenerate
endmodule // pixelproc_gated_add
