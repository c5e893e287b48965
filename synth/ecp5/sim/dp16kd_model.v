// Behavioural model of the subset of the Lattice ECP5 DP16KD block RAM that
// synth/ecp5/pixelproc_bank_ram.v uses, for simulation only (Icarus Verilog). Written for
// this project from Lattice's documentation of the ECP5 sysMEM block RAM (ECP5 and
// ECP5-5G Memory Usage Guide); it is not Lattice's simulation model and was not compared
// with it or with hardware. Neither Yosys's ECP5 cell library nor the PyPI
// build's has a simulation model of DP16KD (they declare its ports and parameters only).
//
// Modelled:
// - both ports DATA_WIDTH 18 (1024 words): word address AD[13:4]; on a write, AD[0] and
//   AD[1] enable the bytes DI[8:0] and DI[17:9];
// - a port acts at a rising edge of its clock when CE = 1 and its chip selects CS[2:0]
//   equal CSDECODE; then it writes (WE = 1) or reads (WE = 0): the address and data are
//   registered at the edge and the word appears on DO after it (REGMODE "NOREG");
// - REGMODE "OUTREG": DO is the output register, loaded at the next rising edge while
//   OCE = 1 with what NOREG would show, so the word appears one edge later;
// - WRITEMODE of a port that writes: "NORMAL" (its DO keeps the last read),
//   "WRITETHROUGH" (DO shows the word written), "READBEFOREWRITE" (DO shows the word's
//   old value);
// - RST with RESETMODE "SYNC": at a rising edge, clears the port's read latch and output
//   register;
// - contents and output registers start at zero (no INITVAL_* parameters: they are not
//   declared, so setting one is an error);
// - one port reading a word the other port writes at the same time (both clocks rising
//   together): the read gives X (treated as undefined, not relied on).
// Other widths, REGMODE, WRITEMODE or RESETMODE values stop the simulation at time 0;
// parameters not declared here (the *MUX inversion settings, INITVAL_*) do not compile.
module DP16KD(
    DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7, DIA6, DIA5, DIA4, DIA3, DIA2, DIA1, DIA0,
    ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2, ADA1, ADA0,
    CEA, OCEA, CLKA, WEA, RSTA, CSA2, CSA1, CSA0,
    DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6, DOA5, DOA4, DOA3, DOA2, DOA1, DOA0,
    DIB17, DIB16, DIB15, DIB14, DIB13, DIB12, DIB11, DIB10, DIB9, DIB8, DIB7, DIB6, DIB5, DIB4, DIB3, DIB2, DIB1, DIB0,
    ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2, ADB1, ADB0,
    CEB, OCEB, CLKB, WEB, RSTB, CSB2, CSB1, CSB0,
    DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6, DOB5, DOB4, DOB3, DOB2, DOB1, DOB0
);
    input wire DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7, DIA6, DIA5, DIA4, DIA3, DIA2, DIA1, DIA0;
    input wire ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2, ADA1, ADA0;
    input wire CEA, OCEA, CLKA, WEA, RSTA, CSA2, CSA1, CSA0;
    output wire DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6, DOA5, DOA4, DOA3, DOA2, DOA1, DOA0;
    input wire DIB17, DIB16, DIB15, DIB14, DIB13, DIB12, DIB11, DIB10, DIB9, DIB8, DIB7, DIB6, DIB5, DIB4, DIB3, DIB2, DIB1, DIB0;
    input wire ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2, ADB1, ADB0;
    input wire CEB, OCEB, CLKB, WEB, RSTB, CSB2, CSB1, CSB0;
    output wire DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6, DOB5, DOB4, DOB3, DOB2, DOB1, DOB0;

    parameter DATA_WIDTH_A = 18;
    parameter DATA_WIDTH_B = 18;
    parameter REGMODE_A = "NOREG";
    parameter REGMODE_B = "NOREG";
    parameter RESETMODE = "SYNC";
    parameter ASYNC_RESET_RELEASE = "SYNC";
    parameter CSDECODE_A = "0b000";
    parameter CSDECODE_B = "0b000";
    parameter WRITEMODE_A = "NORMAL";
    parameter WRITEMODE_B = "NORMAL";
    parameter GSR = "ENABLED";

    wire [17:0] dia = {DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7, DIA6, DIA5, DIA4, DIA3, DIA2, DIA1, DIA0};
    wire [13:0] ada = {ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2, ADA1, ADA0};
    wire [2:0] csa = {CSA2, CSA1, CSA0};
    wire [17:0] dib = {DIB17, DIB16, DIB15, DIB14, DIB13, DIB12, DIB11, DIB10, DIB9, DIB8, DIB7, DIB6, DIB5, DIB4, DIB3, DIB2, DIB1, DIB0};
    wire [13:0] adb = {ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2, ADB1, ADB0};
    wire [2:0] csb = {CSB2, CSB1, CSB0};

    // CSDECODE is a string "0bXYZ": its last three characters are the bits (the low bit of
    // '0' and '1' is the digit).
    wire [2:0] dec_a = {CSDECODE_A[16], CSDECODE_A[8], CSDECODE_A[0]};
    wire [2:0] dec_b = {CSDECODE_B[16], CSDECODE_B[8], CSDECODE_B[0]};
    wire act_a = CEA && csa == dec_a;
    wire act_b = CEB && csb == dec_b;

    reg [17:0] mem [0:1023];
    reg [17:0] lat_a, lat_b;   // what DO shows with REGMODE "NOREG"
    reg [17:0] out_a, out_b;   // the output registers (REGMODE "OUTREG")
    integer i;

    initial begin
        for (i = 0; i < 1024; i = i + 1) mem[i] = 18'h0;
        lat_a = 18'h0; lat_b = 18'h0; out_a = 18'h0; out_b = 18'h0;
        if (DATA_WIDTH_A != 18 || DATA_WIDTH_B != 18
            || (REGMODE_A != "NOREG" && REGMODE_A != "OUTREG")
            || (REGMODE_B != "NOREG" && REGMODE_B != "OUTREG")
            || RESETMODE != "SYNC"
            || (WRITEMODE_A != "NORMAL" && WRITEMODE_A != "WRITETHROUGH" && WRITEMODE_A != "READBEFOREWRITE")
            || (WRITEMODE_B != "NORMAL" && WRITEMODE_B != "WRITETHROUGH" && WRITEMODE_B != "READBEFOREWRITE")
            || CSDECODE_A[39:24] != "0b" || CSDECODE_B[39:24] != "0b") begin
            $display("DP16KD model: configuration outside the modelled subset");
            $finish;
        end
    end

    // The word a port writes: the enabled bytes of DI over the old word.
    function [17:0] merged(input [17:0] old, input [17:0] di, input [1:0] be);
        merged = {be[1] ? di[17:9] : old[17:9], be[0] ? di[8:0] : old[8:0]};
    endfunction

    always @(posedge CLKA) begin
        if (act_a && WEA) mem[ada[13:4]] <= merged(mem[ada[13:4]], dia, ada[1:0]);
        if (RSTA) begin
            lat_a <= 18'h0;
            out_a <= 18'h0;
        end else begin
            if (OCEA) out_a <= lat_a;
            if (act_a && WEA) begin
                if (WRITEMODE_A == "WRITETHROUGH") lat_a <= merged(mem[ada[13:4]], dia, ada[1:0]);
                else if (WRITEMODE_A == "READBEFOREWRITE") lat_a <= mem[ada[13:4]];
            end else if (act_a) begin
                // The other port writing this word at the same edge: not defined.
                if (CLKB === 1'b1 && act_b && WEB && adb[13:4] == ada[13:4]) lat_a <= 18'hx;
                else lat_a <= mem[ada[13:4]];
            end
        end
    end

    always @(posedge CLKB) begin
        if (act_b && WEB) mem[adb[13:4]] <= merged(mem[adb[13:4]], dib, adb[1:0]);
        if (RSTB) begin
            lat_b <= 18'h0;
            out_b <= 18'h0;
        end else begin
            if (OCEB) out_b <= lat_b;
            if (act_b && WEB) begin
                if (WRITEMODE_B == "WRITETHROUGH") lat_b <= merged(mem[adb[13:4]], dib, adb[1:0]);
                else if (WRITEMODE_B == "READBEFOREWRITE") lat_b <= mem[adb[13:4]];
            end else if (act_b) begin
                // The other port writing this word at the same edge: not defined.
                if (CLKA === 1'b1 && act_a && WEA && ada[13:4] == adb[13:4]) lat_b <= 18'hx;
                else lat_b <= mem[adb[13:4]];
            end
        end
    end

    wire [17:0] doa = REGMODE_A == "OUTREG" ? out_a : lat_a;
    assign {DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6, DOA5, DOA4, DOA3, DOA2, DOA1, DOA0} = doa;
    wire [17:0] dob = REGMODE_B == "OUTREG" ? out_b : lat_b;
    assign {DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6, DOB5, DOB4, DOB3, DOB2, DOB1, DOB0} = dob;
endmodule // DP16KD
