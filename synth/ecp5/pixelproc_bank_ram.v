// pixelproc_bank_ram for the ECP5: one bank of the core's shading table (1024 words of
// 18 bits) as one DP16KD block RAM whose read port uses the block RAM's own output
// register (REGMODE_B = "OUTREG") as the second register of the read.
//
// Same ports and behaviour as the generic module the exported core carries (the last
// module of pixelproc_top.v): the word at `read_address` before edge E is on `read_data`
// after edge E + 1. Exception: a read of a word written at the same edge (port A writing
// the word port B reads in the same clock), treated here as undefined; the generic module
// returns the old value. The core writes the table with TABLE beats, before the frames
// that read it.
//
// Read by synth/flow_ecp5.sh (and the other ECP5 scripts) after the export, with
// `read_verilog -overwrite`, in place of the generic definition. Yosys's ECP5 library
// has no simulation model of DP16KD; synth/ecp5/sim/ holds a model of the subset used
// here, written for this project from Lattice's documentation, and the test that
// compares this module with the generic one in Icarus Verilog
// (testbench/tests/ecp5_bank_ram.rs).
//
// Port A writes, port B reads; both 18 bits wide (DATA_WIDTH 18: the word address is
// AD[13:4], AD[3:2] are unused, and on the writing port AD[1:0] are the byte enables of
// DI[8:0] and DI[17:9]). Chip selects are tied to 0 and decoded as 0b000 (always
// selected); clock enables and the output register's clock enable (OCE) are 1; the
// resets are tied off.
module pixelproc_bank_ram(clock, write_enable, write_address, write_data, read_address, read_data);
    input wire clock;
    input wire write_enable;
    input wire [9:0] write_address;
    input wire [17:0] write_data;
    input wire [9:0] read_address;
    output wire [17:0] read_data;

    // DP16KD address buses (x18): word address in [13:4].
    wire [13:0] ada = {write_address, 2'b00, 2'b11};
    wire [13:0] adb = {read_address, 4'b0000};
    wire [17:0] dob;
    assign read_data = dob;

    DP16KD #(
        .DATA_WIDTH_A(18),
        .DATA_WIDTH_B(18),
        .REGMODE_A("NOREG"),
        .REGMODE_B("OUTREG"),
        .RESETMODE("SYNC"),
        .ASYNC_RESET_RELEASE("SYNC"),
        .CSDECODE_A("0b000"),
        .CSDECODE_B("0b000"),
        .WRITEMODE_A("NORMAL"),
        .WRITEMODE_B("NORMAL"),
        .GSR("DISABLED")
    ) bram (
        .DIA0(write_data[0]), .DIA1(write_data[1]), .DIA2(write_data[2]),
        .DIA3(write_data[3]), .DIA4(write_data[4]), .DIA5(write_data[5]),
        .DIA6(write_data[6]), .DIA7(write_data[7]), .DIA8(write_data[8]),
        .DIA9(write_data[9]), .DIA10(write_data[10]), .DIA11(write_data[11]),
        .DIA12(write_data[12]), .DIA13(write_data[13]), .DIA14(write_data[14]),
        .DIA15(write_data[15]), .DIA16(write_data[16]), .DIA17(write_data[17]),
        .ADA0(ada[0]), .ADA1(ada[1]), .ADA2(ada[2]), .ADA3(ada[3]), .ADA4(ada[4]),
        .ADA5(ada[5]), .ADA6(ada[6]), .ADA7(ada[7]), .ADA8(ada[8]), .ADA9(ada[9]),
        .ADA10(ada[10]), .ADA11(ada[11]), .ADA12(ada[12]), .ADA13(ada[13]), .CLKA(clock),
        .CEA(1'b1), .OCEA(1'b1), .WEA(write_enable), .RSTA(1'b0), .CSA0(1'b0), .CSA1(1'b0),
        .CSA2(1'b0), .DOA0(), .DOA1(), .DOA2(), .DOA3(), .DOA4(), .DOA5(), .DOA6(), .DOA7(),
        .DOA8(), .DOA9(), .DOA10(), .DOA11(), .DOA12(), .DOA13(), .DOA14(), .DOA15(),
        .DOA16(), .DOA17(), .DIB0(1'b0), .DIB1(1'b0), .DIB2(1'b0), .DIB3(1'b0), .DIB4(1'b0),
        .DIB5(1'b0), .DIB6(1'b0), .DIB7(1'b0), .DIB8(1'b0), .DIB9(1'b0), .DIB10(1'b0),
        .DIB11(1'b0), .DIB12(1'b0), .DIB13(1'b0), .DIB14(1'b0), .DIB15(1'b0), .DIB16(1'b0),
        .DIB17(1'b0), .ADB0(adb[0]), .ADB1(adb[1]), .ADB2(adb[2]), .ADB3(adb[3]),
        .ADB4(adb[4]), .ADB5(adb[5]), .ADB6(adb[6]), .ADB7(adb[7]), .ADB8(adb[8]),
        .ADB9(adb[9]), .ADB10(adb[10]), .ADB11(adb[11]), .ADB12(adb[12]), .ADB13(adb[13]),
        .CLKB(clock), .CEB(1'b1), .OCEB(1'b1), .WEB(1'b0), .RSTB(1'b0), .CSB0(1'b0),
        .CSB1(1'b0), .CSB2(1'b0), .DOB0(dob[0]), .DOB1(dob[1]), .DOB2(dob[2]),
        .DOB3(dob[3]), .DOB4(dob[4]), .DOB5(dob[5]), .DOB6(dob[6]), .DOB7(dob[7]),
        .DOB8(dob[8]), .DOB9(dob[9]), .DOB10(dob[10]), .DOB11(dob[11]), .DOB12(dob[12]),
        .DOB13(dob[13]), .DOB14(dob[14]), .DOB15(dob[15]), .DOB16(dob[16]), .DOB17(dob[17])
    );
endmodule // pixelproc_bank_ram
