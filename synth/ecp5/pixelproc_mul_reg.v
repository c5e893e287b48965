// pixelproc_mul_reg for the ECP5: the unsigned 16 x 16 bit multiplier with registered
// operands and product as one MULT18X18D whose own input registers (A and B) and output
// register are the module's two registers, so that no path runs from a fabric register
// through the multiplier to another fabric register.
//
// Same ports and behaviour as the generic module the exported core carries (the end of
// pixelproc_top.v): the operands at `a` and `b` before edge E are multiplied; the
// product is on `p` after edge E + 1.
//
// Read by synth/flow_ecp5.sh (and the other ECP5 scripts) after the export, with
// `read_verilog -overwrite`, in place of the generic definition. Yosys's ECP5 library
// has no simulation model of MULT18X18D; synth/ecp5/sim/ holds a model of the subset used
// here, written for this project from Lattice's documentation, and the test that
// compares this module with the generic one in Icarus Verilog
// (testbench/tests/ecp5_mul_reg.rs).
//
// The operands are unsigned (SIGNEDA = SIGNEDB = 0) and zero-extended to 18 bits; the C
// input and the cascade paths are unused; every register is clocked by CLK0 with CE0 = 1
// and RST0 = 0.
module pixelproc_mul_reg(clock, a, b, p);
    input wire clock;
    input wire [15:0] a;
    input wire [15:0] b;
    output wire [31:0] p;

    wire [35:0] prod;
    assign p = prod[31:0];

    MULT18X18D #(
        .REG_INPUTA_CLK("CLK0"),
        .REG_INPUTA_CE("CE0"),
        .REG_INPUTA_RST("RST0"),
        .REG_INPUTB_CLK("CLK0"),
        .REG_INPUTB_CE("CE0"),
        .REG_INPUTB_RST("RST0"),
        .REG_INPUTC_CLK("NONE"),
        .REG_PIPELINE_CLK("NONE"),
        .REG_OUTPUT_CLK("CLK0"),
        .REG_OUTPUT_CE("CE0"),
        .REG_OUTPUT_RST("RST0"),
        .CLK0_DIV("ENABLED"),
        .HIGHSPEED_CLK("NONE"),
        .GSR("DISABLED"),
        .CAS_MATCH_REG("FALSE"),
        .SOURCEB_MODE("B_SHIFT"),
        .MULT_BYPASS("DISABLED"),
        .RESETMODE("SYNC")
    ) dsp (
        .A0(a[0]), .A1(a[1]), .A2(a[2]), .A3(a[3]), .A4(a[4]), .A5(a[5]), .A6(a[6]),
        .A7(a[7]), .A8(a[8]), .A9(a[9]), .A10(a[10]), .A11(a[11]), .A12(a[12]),
        .A13(a[13]), .A14(a[14]), .A15(a[15]), .A16(1'b0), .A17(1'b0),
        .B0(b[0]), .B1(b[1]), .B2(b[2]), .B3(b[3]), .B4(b[4]), .B5(b[5]), .B6(b[6]),
        .B7(b[7]), .B8(b[8]), .B9(b[9]), .B10(b[10]), .B11(b[11]), .B12(b[12]),
        .B13(b[13]), .B14(b[14]), .B15(b[15]), .B16(1'b0), .B17(1'b0),
        .C0(1'b0), .C1(1'b0), .C2(1'b0), .C3(1'b0), .C4(1'b0), .C5(1'b0), .C6(1'b0),
        .C7(1'b0), .C8(1'b0), .C9(1'b0), .C10(1'b0), .C11(1'b0), .C12(1'b0), .C13(1'b0),
        .C14(1'b0), .C15(1'b0), .C16(1'b0), .C17(1'b0),
        .SIGNEDA(1'b0), .SIGNEDB(1'b0), .SOURCEA(1'b0), .SOURCEB(1'b0),
        .CLK0(clock), .CLK1(1'b0), .CLK2(1'b0), .CLK3(1'b0),
        .CE0(1'b1), .CE1(1'b0), .CE2(1'b0), .CE3(1'b0),
        .RST0(1'b0), .RST1(1'b0), .RST2(1'b0), .RST3(1'b0),
        .P0(prod[0]), .P1(prod[1]), .P2(prod[2]), .P3(prod[3]), .P4(prod[4]),
        .P5(prod[5]), .P6(prod[6]), .P7(prod[7]), .P8(prod[8]), .P9(prod[9]),
        .P10(prod[10]), .P11(prod[11]), .P12(prod[12]), .P13(prod[13]), .P14(prod[14]),
        .P15(prod[15]), .P16(prod[16]), .P17(prod[17]), .P18(prod[18]), .P19(prod[19]),
        .P20(prod[20]), .P21(prod[21]), .P22(prod[22]), .P23(prod[23]), .P24(prod[24]),
        .P25(prod[25]), .P26(prod[26]), .P27(prod[27]), .P28(prod[28]), .P29(prod[29]),
        .P30(prod[30]), .P31(prod[31]), .P32(prod[32]), .P33(prod[33]), .P34(prod[34]),
        .P35(prod[35])
    );
endmodule // pixelproc_mul_reg
