//! Pieces shared by the testbenches: the clock cycle of a RustHDL block driven with the
//! direct `simulate()` loop ([`clock_cycle`]), and for the Verilog vector testbenches of
//! the external simulators (Icarus Verilog, Verilator) the replay loop: the golden model
//! writes `stim.hex` and `expect.hex`, one line per clock, and a generated testbench
//! replays them against the exported module.

use crate::TbError;
use rust_hdl::prelude::*;

/// One clock cycle of a RustHDL block whose clock input is `clk(u)`: a rising edge, then
/// a falling one, each settled with the direct `simulate()` loop.
pub fn clock_cycle<B: Block>(
    u: &mut B,
    clk: fn(&mut B) -> &mut Signal<In, Clock>,
) -> Result<(), TbError> {
    for level in [true, false] {
        clk(u).next = Clock { clk: level };
        if !simulate(u, 200) {
            return Err(TbError::NoConvergence);
        }
    }
    Ok(())
}

/// The end of a vector testbench module: the clock, loading of `stim.hex` and
/// `expect.hex`, a VCD of the testbench `tb`, then for every cycle `t` the `drive`
/// statements (whole lines, applying `stim[t]`), a rising edge and the check: where the
/// Verilog condition `mismatch` holds, the cycle, inputs, expected and `got` are shown and
/// the run stops; otherwise `PASS cycles=N` ends it. Expects `clock`, `stim`, `expv`, `got`,
/// `t` and `NCYC` declared by the caller's part of the module.
pub fn vector_loop(tb: &str, drive: &str, mismatch: &str) -> String {
    format!(
        r#"    always #5 clock = ~clock;
    initial begin
        $readmemh("stim.hex", stim);
        $readmemh("expect.hex", expv);
        $dumpfile("{tb}.vcd");
        $dumpvars(1, {tb});
        for (t = 0; t < NCYC; t = t + 1) begin
{drive}            @(posedge clock);
            #1;
            if ({mismatch}) begin
                $display("MISMATCH cycle=%0d inputs=%h expected=%h got=%h", t, stim[t], expv[t], got);
                $finish;
            end
        end
        $display("PASS cycles=%0d", NCYC);
        $finish;
    end
endmodule
"#
    )
}

/// One line on an external run's speed: `label`, cycles, build and run seconds, cycles
/// per second of the run, and whether it passed.
pub fn speed_line(label: &str, r: &crate::external::ExternalRun) -> String {
    format!(
        "{label}: {} cycles, build {:.1} s, run {:.2} s, {:.0} cycles/s, pass {}",
        r.cycles,
        r.build_seconds,
        r.run_seconds,
        r.cycles as f64 / r.run_seconds,
        r.pass
    )
}
