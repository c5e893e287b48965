// Behavioural model of the subset of the Lattice ECP5 MULT18X18D multiplier that
// synth/ecp5/pixelproc_mul_reg.v uses, for simulation only (Icarus Verilog). Written for
// this project from Lattice's documentation of the ECP5 sysDSP block (ECP5 and ECP5-5G
// sysDSP Usage Guide); it is not Lattice's simulation model and was not compared with it
// or with hardware. Neither Yosys's ECP5 cell library nor the PyPI build's has a
// simulation model of MULT18X18D (they declare its ports and parameters only).
//
// Modelled:
// - P = A x B, 18 x 18 bits to 36, each operand signed when its SIGNEDA / SIGNEDB input
//   is 1 (two's complement), else unsigned;
// - the input registers of A and B (REG_INPUTA_CLK, REG_INPUTB_CLK), the pipeline
//   register (REG_PIPELINE_CLK) and the output register (REG_OUTPUT_CLK), each "NONE"
//   (bypassed) or "CLK0": loaded at a rising edge of CLK0 while CE0 = 1, cleared at that
//   edge while RST0 = 1 (RESETMODE "SYNC"); the signedness inputs travel with their
//   operands through the input registers;
// - every register starts at zero.
// Anything else (other clocks, clock enables or resets for a register, MULT_BYPASS,
// SOURCEA / SOURCEB = 1, asynchronous reset, HIGHSPEED_CLK) stops the simulation at time
// 0; the C input and the cascade ports are not modelled (C is accepted and ignored).
module MULT18X18D(
    A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0,
    B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0,
    C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3, C2, C1, C0,
    SIGNEDA, SIGNEDB, SOURCEA, SOURCEB,
    CLK0, CLK1, CLK2, CLK3, CE0, CE1, CE2, CE3, RST0, RST1, RST2, RST3,
    P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0
);
    input wire A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0;
    input wire B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0;
    input wire C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3, C2, C1, C0;
    input wire SIGNEDA, SIGNEDB, SOURCEA, SOURCEB;
    input wire CLK0, CLK1, CLK2, CLK3, CE0, CE1, CE2, CE3, RST0, RST1, RST2, RST3;
    output wire P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0;

    parameter REG_INPUTA_CLK = "NONE";
    parameter REG_INPUTA_CE = "CE0";
    parameter REG_INPUTA_RST = "RST0";
    parameter REG_INPUTB_CLK = "NONE";
    parameter REG_INPUTB_CE = "CE0";
    parameter REG_INPUTB_RST = "RST0";
    parameter REG_INPUTC_CLK = "NONE";
    parameter REG_PIPELINE_CLK = "NONE";
    parameter REG_PIPELINE_CE = "CE0";
    parameter REG_PIPELINE_RST = "RST0";
    parameter REG_OUTPUT_CLK = "NONE";
    parameter REG_OUTPUT_CE = "CE0";
    parameter REG_OUTPUT_RST = "RST0";
    parameter CLK0_DIV = "ENABLED";
    parameter HIGHSPEED_CLK = "NONE";
    parameter GSR = "ENABLED";
    parameter CAS_MATCH_REG = "FALSE";
    parameter SOURCEB_MODE = "B_SHIFT";
    parameter MULT_BYPASS = "DISABLED";
    parameter RESETMODE = "SYNC";

    wire [17:0] a = {A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0};
    wire [17:0] b = {B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0};

    // Input registers (operand and its signedness).
    reg [17:0] a_r = 18'h0, b_r = 18'h0;
    reg sa_r = 1'b0, sb_r = 1'b0;
    wire [17:0] a_s = (REG_INPUTA_CLK == "CLK0") ? a_r : a;
    wire [17:0] b_s = (REG_INPUTB_CLK == "CLK0") ? b_r : b;
    wire sa = (REG_INPUTA_CLK == "CLK0") ? sa_r : SIGNEDA;
    wire sb = (REG_INPUTB_CLK == "CLK0") ? sb_r : SIGNEDB;
    // The product, each operand extended by its signedness.
    wire [35:0] a_x = {{18{sa & a_s[17]}}, a_s};
    wire [35:0] b_x = {{18{sb & b_s[17]}}, b_s};
    wire [35:0] prod = a_x * b_x;
    // Pipeline and output registers.
    reg [35:0] pipe_r = 36'h0, out_r = 36'h0;
    wire [35:0] pipe_s = (REG_PIPELINE_CLK == "CLK0") ? pipe_r : prod;
    wire [35:0] out_s = (REG_OUTPUT_CLK == "CLK0") ? out_r : pipe_s;
    assign {P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0} = out_s;

    always @(posedge CLK0) begin
        if (RST0) begin
            a_r <= 18'h0; b_r <= 18'h0; sa_r <= 1'b0; sb_r <= 1'b0;
            pipe_r <= 36'h0; out_r <= 36'h0;
        end else if (CE0) begin
            a_r <= a; b_r <= b; sa_r <= SIGNEDA; sb_r <= SIGNEDB;
            pipe_r <= prod;
            out_r <= pipe_s;
        end
    end

    initial begin
        if ((REG_INPUTA_CLK != "NONE" && REG_INPUTA_CLK != "CLK0")
            || (REG_INPUTB_CLK != "NONE" && REG_INPUTB_CLK != "CLK0")
            || (REG_PIPELINE_CLK != "NONE" && REG_PIPELINE_CLK != "CLK0")
            || (REG_OUTPUT_CLK != "NONE" && REG_OUTPUT_CLK != "CLK0")
            || REG_INPUTC_CLK != "NONE"
            || REG_INPUTA_CE != "CE0" || REG_INPUTB_CE != "CE0" || REG_PIPELINE_CE != "CE0"
            || REG_OUTPUT_CE != "CE0"
            || REG_INPUTA_RST != "RST0" || REG_INPUTB_RST != "RST0"
            || REG_PIPELINE_RST != "RST0" || REG_OUTPUT_RST != "RST0"
            || MULT_BYPASS != "DISABLED" || RESETMODE != "SYNC" || HIGHSPEED_CLK != "NONE") begin
            $display("MULT18X18D model: a setting outside the modelled subset");
            $finish;
        end
    end

    always @(SOURCEA or SOURCEB) begin
        if (SOURCEA === 1'b1 || SOURCEB === 1'b1) begin
            $display("MULT18X18D model: SOURCEA / SOURCEB = 1 is not modelled");
            $finish;
        end
    end
endmodule
