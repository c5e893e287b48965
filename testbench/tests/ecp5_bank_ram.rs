//! The ECP5 shading-table bank (`synth/ecp5/pixelproc_bank_ram.v`: one DP16KD with its
//! output register) behaves like the generic `pixelproc_bank_ram` the exported core
//! carries (`pixelproc_rtl::bank_ram::GENERIC_VERILOG`), clock by clock, in Icarus
//! Verilog: `synth/ecp5/sim/tb_bank_ram.v` under random writes and reads, the DP16KD
//! being our own model of the subset used (`synth/ecp5/sim/dp16kd_model.v`, written from
//! Lattice's documentation; no vendor model is available to the open tools). Then each of
//! a list of wiring mistakes in the ECP5 module (address, data and output bits, byte
//! enables, chip select, output register mode and enable) must make the comparison fail.
//!
//! Needs iverilog. A missing tool prints `SKIPPED: ...`, and fails under `CI=true`.

use pixelproc_rtl::bank_ram::{GENERIC_VERILOG, MODULE};
use pixelproc_testbench::external::{skip_or_fail, tool_available, Ecp5Module};

/// The module, its testbench and the primitive's model.
const UNDER_TEST: Ecp5Module = Ecp5Module {
    module: MODULE,
    generic: GENERIC_VERILOG,
    testbench: "tb_bank_ram.v",
    model: "dp16kd_model.v",
};

#[test]
fn ecp5_bank_ram_matches_the_generic_one() {
    if !tool_available("iverilog") {
        skip_or_fail("iverilog").unwrap();
        return;
    }
    // Wiring mistakes the comparison must catch: (what, text in the module, replacement).
    let mutants: [(&str, &str, &str); 9] = [
        (
            "read address bits 0 and 1 swapped",
            ".ADB4(adb[4]), .ADB5(adb[5])",
            ".ADB4(adb[5]), .ADB5(adb[4])",
        ),
        (
            "write address bits 8 and 9 swapped",
            ".ADA12(ada[12]), .ADA13(ada[13])",
            ".ADA12(ada[13]), .ADA13(ada[12])",
        ),
        (
            "read address one bit low",
            "{read_address, 4'b0000}",
            "{read_address[8:0], 5'b00000}",
        ),
        (
            "write data bits 0 and 1 swapped",
            ".DIA0(write_data[0]), .DIA1(write_data[1])",
            ".DIA0(write_data[1]), .DIA1(write_data[0])",
        ),
        (
            "high byte not enabled",
            "{write_address, 2'b00, 2'b11}",
            "{write_address, 2'b00, 2'b01}",
        ),
        (
            "read data bit 17 from bit 16",
            ".DOB17(dob[17])",
            ".DOB17(dob[16])",
        ),
        (
            "no output register",
            ".REGMODE_B(\"OUTREG\")",
            ".REGMODE_B(\"NOREG\")",
        ),
        (
            "output register never enabled",
            ".OCEB(1'b1)",
            ".OCEB(1'b0)",
        ),
        (
            "read port never selected",
            ".CSDECODE_B(\"0b000\")",
            ".CSDECODE_B(\"0b001\")",
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    UNDER_TEST.check(dir.path(), 21_001, &mutants);
}
