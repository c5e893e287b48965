//! External simulation of the exported Verilog (Icarus Verilog, Verilator).
//!
//! The golden model writes two `$readmemh` files, one line per clock:
//! - `stim.hex`, 80 hex digits (320 bits): `cmd_word[255:0]`, `cmd_bg` at `[279:256]`,
//!   `cmd_op` at `[282:280]`, `cmd_valid` `[283]`, `rst` `[284]`, `tile_base`
//!   `[296:285]`, `rd_addr` `[308:297]`, zero above (the span word is `SpanWord::to_hex`;
//!   the ports above it are one field table, `STIM_FIELDS`, that both the Rust writer
//!   and the Verilog reader follow);
//! - `expect.hex`, 32 hex digits (128 bits): `{check, 28'b0, readout[98:0]}` expected
//!   after that clock's rising edge, the readout word in the layout of
//!   `pixelproc_formats::regs::READOUT_FIELDS` (`{rd_won, rd_sh, rd_nclass, rd_mask, rd_zb, rd_rgb,
//!   rd_dsf, rd_fsf, rd_count}`); `check` (bit 127) is 0 where the port shows a processor the reset token
//!   has not reached yet (power-up values) and on lines 0 and 1.
//!
//! Expected values come from the golden `PixelArray` only: after edge `t` the readout
//! port shows processor `a = rd_addr(t − 2)`'s readout registers after edge `t − 1`,
//! i.e. the golden state before the latest `ClearLine` among the first
//! `t − 1 − LATENCY_PROC0 − a` commands. `tb_pixelproc.v` drives the vectors, compares
//! every output after every clock, prints the first mismatch (cycle, inputs, both
//! outputs), dumps a VCD of the top-level ports, and prints `PASS cycles=N`.

use crate::compare::{port_vectors, without_shadow_regs, PortVector};
use crate::{Outcome, TbError};
use pixelproc_formats::fields::Field;
use pixelproc_formats::opcodes::OP_BITS;
use pixelproc_formats::regs::{READOUT_BITS, READOUT_FIELDS, RGB_BITS};
use pixelproc_formats::{SPAN_WORD_BITS, X_BITS};
use pixelproc_rtl::pixel_array::LATENCY_PROC0;
use pixelproc_sim::pixel_array::{Command, PixelArray, ProcState};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command as Proc;

/// An external simulator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExternalSim {
    /// Icarus Verilog (`iverilog` + `vvp`).
    Icarus,
    /// Verilator (`verilator --binary`).
    Verilator,
}

impl ExternalSim {
    /// The simulator's program.
    pub fn tool(self) -> &'static str {
        match self {
            ExternalSim::Icarus => "iverilog",
            ExternalSim::Verilator => "verilator",
        }
    }
}

/// The install command printed when a tool is missing.
pub const INSTALL_HINT: &str =
    "apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y iverilog verilator yosys";

/// True if `tool` runs. Under `CI=true` a missing tool is an error; otherwise the caller
/// should report the test as skipped (see [`skip_or_fail`]).
pub fn tool_available(tool: &str) -> bool {
    Proc::new(tool)
        .arg(if tool == "iverilog" {
            "-V"
        } else {
            "--version"
        })
        .output()
        .map(|o| o.status.success() || !o.stdout.is_empty())
        .unwrap_or(false)
}

/// For a missing `tool`: `Err` under `CI=true`, otherwise prints and returns the
/// [`Outcome::Skipped`] outcome.
pub fn skip_or_fail(tool: &str) -> Result<Outcome, TbError> {
    let skipped = Outcome::missing(tool);
    if std::env::var("CI").map(|v| v == "true").unwrap_or(false) {
        Err(TbError::ToolMissing(tool.to_string()))
    } else {
        println!("{skipped}");
        Ok(skipped)
    }
}

/// Whether every tool of `tools` is available; for the first missing one, what
/// [`skip_or_fail`] does (prints `SKIPPED: ...`, or panics under `CI=true`), and `false`.
pub fn tools_or_skip(tools: &[&str]) -> bool {
    match tools.iter().find(|t| !tool_available(t)) {
        Some(t) => {
            skip_or_fail(t).unwrap();
            false
        }
        None => true,
    }
}

/// A mutant of Verilog `text` for a test that must catch it: `from` replaced by `to`.
/// Panics (naming the mutant `what`) unless `from` occurs exactly once, so a mutant that
/// silently stops applying after an export change fails the test instead of passing it.
pub fn mutant(text: &str, what: &str, from: &str, to: &str) -> String {
    assert_eq!(
        text.matches(from).count(),
        1,
        "{what}: `{from}` not found once"
    );
    text.replace(from, to)
}

/// Compiles `sources` with Icarus Verilog (`iverilog -g2012 -Wall`, in `dir`, to
/// `tb.vvp`) and runs the result with `plusargs`; the simulator's output. Panics, with the
/// compiler's output, if the compile fails or warns: for the tests that compare a module
/// with its reference (`PASS` / `MISMATCH` lines).
pub fn icarus_run(dir: &Path, sources: &[PathBuf], plusargs: &[String]) -> String {
    let c = Proc::new("iverilog")
        .current_dir(dir)
        .args(["-g2012", "-Wall", "-o", "tb.vvp"])
        .args(sources)
        .output()
        .expect("iverilog runs");
    let text = String::from_utf8_lossy(&c.stdout).to_string() + &String::from_utf8_lossy(&c.stderr);
    assert!(c.status.success(), "iverilog failed:\n{text}");
    assert!(!text.contains("warning"), "iverilog warnings:\n{text}");
    let r = Proc::new("vvp")
        .current_dir(dir)
        .args(["-n", "tb.vvp"])
        .args(plusargs)
        .output()
        .expect("vvp runs");
    String::from_utf8_lossy(&r.stdout).to_string() + &String::from_utf8_lossy(&r.stderr)
}

/// The numbers of a testbench's `PASS key=N key=M ...` line, in order, or `None` without
/// one.
pub fn pass_counts(text: &str) -> Option<Vec<u64>> {
    let line = text.lines().find(|l| l.starts_with("PASS "))?;
    line.split_whitespace()
        .skip(1)
        .map(|kv| kv.split_once('=').and_then(|(_, n)| n.parse::<u64>().ok()))
        .collect()
}

/// A module the export carries in a generic definition and the ECP5 flow replaces with
/// its own (`synth/ecp5/<module>.v` on a vendor primitive), with the Icarus testbench that
/// compares the two (`synth/ecp5/sim/`, instantiating the generic one renamed
/// `generic_...` for `pixelproc_...`) and our model of the primitive.
pub struct Ecp5Module {
    /// The module's name (`pixelproc_...`).
    pub module: &'static str,
    /// Its generic Verilog, as the export appends it.
    pub generic: &'static str,
    /// The testbench under `synth/ecp5/sim/`.
    pub testbench: &'static str,
    /// The primitive's model under `synth/ecp5/sim/`.
    pub model: &'static str,
}

impl Ecp5Module {
    /// Runs the comparison in `dir` with `ecp5` as the ECP5 definition's text (the
    /// committed file or a mutant of it), `+seed=seed +cycles=20000`; the simulator's
    /// output.
    pub fn compare(&self, dir: &Path, ecp5: &str, seed: u32) -> String {
        let renamed = self.module.replacen("pixelproc_", "generic_", 1);
        std::fs::write(
            dir.join("generic.v"),
            self.generic.replace(self.module, &renamed),
        )
        .expect("write generic.v");
        std::fs::write(dir.join("ecp5.v"), ecp5).expect("write ecp5.v");
        let sim = Path::new(env!("CARGO_MANIFEST_DIR")).join("../synth/ecp5/sim");
        let sources = [
            sim.join(self.testbench),
            dir.join("generic.v"),
            dir.join("ecp5.v"),
            sim.join(self.model),
        ];
        icarus_run(
            dir,
            &sources,
            &[format!("+seed={seed}"), "+cycles=20000".into()],
        )
    }

    /// The whole check, in `dir`: the committed ECP5 definition (`synth/ecp5/<module>.v`)
    /// matches the generic one for seeds 1, 2 and 3, with at least `min_compared` clocks
    /// compared and the output changing on more than 15,000 of them; then each wiring
    /// mistake `(what, text in the module, replacement)` must make the comparison report a
    /// `MISMATCH`. Panics with the simulator's output otherwise.
    pub fn check(&self, dir: &Path, min_compared: u64, mutants: &[(&str, &str, &str)]) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../synth/ecp5")
            .join(format!("{}.v", self.module));
        let ecp5 = std::fs::read_to_string(&path).expect("the ECP5 module");
        let passed = |text: &str| match pass_counts(text).as_deref() {
            Some(&[compared, changes]) => Some((compared, changes)),
            _ => None,
        };
        for seed in [1, 2, 3] {
            let text = self.compare(dir, &ecp5, seed);
            let (compared, changes) =
                passed(&text).unwrap_or_else(|| panic!("seed {seed}: no PASS:\n{text}"));
            // Every clock compared, and the output moving on most of them.
            assert!(
                compared >= min_compared && changes > 15_000,
                "seed {seed}: {text}"
            );
        }
        for &(what, from, to) in mutants {
            let text = self.compare(dir, &mutant(&ecp5, what, from, to), 1);
            assert!(
                passed(&text).is_none() && text.contains("MISMATCH"),
                "{what}: the comparison did not fail:\n{text}"
            );
        }
    }
}

/// The port fields of a `stim.hex` line above the span word (`cmd_word[255:0]`), named
/// as the array's input ports.
const STIM_BG: Field = Field {
    name: "cmd_bg",
    lsb: SPAN_WORD_BITS as usize,
    width: RGB_BITS,
};
const STIM_OP: Field = STIM_BG.then("cmd_op", OP_BITS);
const STIM_VALID: Field = STIM_OP.then("cmd_valid", 1);
const STIM_RST: Field = STIM_VALID.then("rst", 1);
const STIM_BASE: Field = STIM_RST.then("tile_base", X_BITS as usize);
const STIM_RD: Field = STIM_BASE.then("rd_addr", X_BITS as usize);
const STIM_FIELDS: [Field; 6] = [STIM_BG, STIM_OP, STIM_VALID, STIM_RST, STIM_BASE, STIM_RD];

/// The limb above the span word of a `stim.hex` line (bits 319:256).
fn stim_high_limb(v: &PortVector) -> u64 {
    let values = [
        v.bg as u64,
        v.op as u64,
        v.valid as u64,
        v.rst as u64,
        v.base as u64,
        v.rd_addr as u64,
    ];
    let mut l = [0u64; 5];
    for (f, x) in STIM_FIELDS.iter().zip(values) {
        f.put(&mut l, x);
    }
    l[4]
}

/// The Verilog statements that take one stimulus line apart, one per port.
fn stim_assignments() -> String {
    let mut out = format!(
        "            cmd_word = stim[t][{}:0];\n",
        SPAN_WORD_BITS - 1
    );
    for f in STIM_FIELDS {
        let bits = if f.width == 1 {
            format!("{}", f.lsb)
        } else {
            format!("{}:{}", f.msb(), f.lsb)
        };
        writeln!(out, "            {} = stim[t][{bits}];", f.name).ok();
    }
    out
}

/// Bit 127 of an `expect.hex` line: compare this cycle.
const CHECK_BIT: u32 = 127;

fn pack_state(s: &ProcState) -> u128 {
    (1u128 << CHECK_BIT) | s.pack_readout()
}

/// The Verilog concatenation of the readout ports in the readout word's layout, most
/// significant field first: `{rd_nclass, rd_mask, ...}`.
fn readout_concat() -> String {
    let ports: Vec<String> = READOUT_FIELDS
        .iter()
        .rev()
        .map(|f| format!("rd_{}", f.name.to_lowercase()))
        .collect();
    format!("{{{}}}", ports.join(", "))
}

/// Writes `stim.hex` and `expect.hex` for `cmds` on an `n`-processor array into `dir`;
/// returns the number of cycles.
pub fn write_vectors(
    dir: &Path,
    cmds: &[(u32, Command)],
    n: usize,
    shadows: bool,
) -> Result<usize, TbError> {
    let vecs = port_vectors(cmds, n)?;
    // Golden readout registers after k commands, k = 0..=len.
    let mut arr = PixelArray::new(n, 0);
    let mut cap = arr.state().to_vec();
    let mut caps: Vec<Vec<ProcState>> = vec![cap.clone()];
    for (b, c) in cmds {
        if let Command::ClearLine { .. } = c {
            cap = arr.state().to_vec();
        }
        arr.set_base(*b);
        arr.step(c);
        caps.push(cap.clone());
    }
    let mut stim = String::new();
    let mut exp = String::new();
    for (t, v) in vecs.iter().enumerate() {
        let hi = stim_high_limb(v);
        writeln!(
            stim,
            "{:016x}{:016x}{:016x}{:016x}{:016x}",
            hi, v.word[3], v.word[2], v.word[1], v.word[0]
        )
        .ok();
        let e = if t < 2 {
            0
        } else {
            let a = vecs[t - 2].rd_addr as usize;
            let kk = t as i64 - 1 - LATENCY_PROC0 as i64 - a as i64;
            if kk < 0 {
                0
            } else {
                let s = caps[kk.min(cmds.len() as i64) as usize][a];
                pack_state(&if shadows { s } else { without_shadow_regs(s) })
            }
        };
        writeln!(exp, "{e:032x}").ok();
    }
    std::fs::write(dir.join("stim.hex"), stim)?;
    std::fs::write(dir.join("expect.hex"), exp)?;
    Ok(vecs.len())
}

/// The Verilog testbench for module `dut` over `cycles` vector lines.
pub fn testbench_verilog(dut: &str, cycles: usize) -> String {
    let got = readout_concat();
    let top = READOUT_BITS - 1;
    let unpack = stim_assignments();
    format!(
        r#"// Vector testbench for {dut}: drives stim.hex, checks every output against expect.hex.
`timescale 1ns/1ps
module tb_pixelproc;
    localparam integer NCYC = {cycles};
    reg clock = 1'b0;
    reg [319:0] stim [0:NCYC-1];
    reg [127:0] expv [0:NCYC-1];
    reg rst, cmd_valid;
    reg [2:0] cmd_op;
    reg [23:0] cmd_bg;
    reg [255:0] cmd_word;
    reg [11:0] tile_base, rd_addr;
    wire [23:0] rd_zb, rd_rgb, rd_sh;
    wire rd_dsf, rd_fsf, rd_won;
    wire [7:0] rd_count, rd_mask, rd_nclass;
    wire [{top}:0] got = {got};
    integer t;
    {dut} dut (.clock(clock), .rst(rst), .cmd_valid(cmd_valid), .cmd_op(cmd_op),
        .cmd_bg(cmd_bg), .cmd_word(cmd_word), .tile_base(tile_base), .rd_addr(rd_addr),
        .rd_zb(rd_zb), .rd_rgb(rd_rgb), .rd_dsf(rd_dsf), .rd_fsf(rd_fsf), .rd_count(rd_count),
        .rd_mask(rd_mask), .rd_nclass(rd_nclass), .rd_sh(rd_sh), .rd_won(rd_won));
{tail}"#,
        tail = crate::sim_tools::vector_loop(
            "tb_pixelproc",
            &unpack,
            &format!("expv[t][{CHECK_BIT}] && got !== expv[t][{top}:0]")
        )
    )
}

/// Result of an external run.
#[derive(Clone, Debug)]
pub struct ExternalRun {
    /// Cycles simulated (vector lines).
    pub cycles: usize,
    /// True if the testbench printed `PASS`.
    pub pass: bool,
    /// The simulator's output (first mismatch line on failure).
    pub log: String,
    /// Seconds to build the simulator (only the cache look-up if `build_cached`).
    pub build_seconds: f64,
    /// True if Verilator's model came from the build cache ([`verilator_build_cached`]).
    pub build_cached: bool,
    /// Seconds to run it.
    pub run_seconds: f64,
    /// The VCD of the top-level ports.
    pub vcd: PathBuf,
}

fn run(cmd: &mut Proc, what: &str) -> Result<String, TbError> {
    let o = cmd.output()?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    if !o.status.success() {
        return Err(TbError::Sim(format!("{what} failed:\n{text}")));
    }
    Ok(text)
}

/// Compiles the vector testbench `TB.v` (top module `TB`) with the design file `dut` in
/// `dir` and runs it in `sim`. Returns the simulator's output, the build seconds and the
/// run seconds. Shared by every block's external simulation. Verilator models come from
/// [`verilator_build_cached`] (0 build seconds when cached).
pub(crate) fn build_and_run(
    sim: ExternalSim,
    dir: &Path,
    tb: &str,
    dut: &Path,
) -> Result<(String, f64, f64), TbError> {
    let (out, build, run_seconds) = build_and_run_info(sim, dir, tb, dut)?;
    Ok((out, build.seconds, run_seconds))
}

/// [`build_and_run`], with the build's [`BuildInfo`].
fn build_and_run_info(
    sim: ExternalSim,
    dir: &Path,
    tb: &str,
    dut: &Path,
) -> Result<(String, BuildInfo, f64), TbError> {
    let tb_file = format!("{tb}.v");
    let t0 = std::time::Instant::now();
    match sim {
        ExternalSim::Icarus => {
            run(
                Proc::new("iverilog")
                    .current_dir(dir)
                    .args(["-g2012", "-o", "tb.vvp", "-s", tb, &tb_file])
                    .arg(dut),
                "iverilog",
            )?;
            let build = BuildInfo {
                seconds: t0.elapsed().as_secs_f64(),
                cached: false,
                dir: dir.to_path_buf(),
            };
            let t1 = std::time::Instant::now();
            let out = run(
                Proc::new("vvp").current_dir(dir).args(["-n", "tb.vvp"]),
                "vvp",
            )?;
            Ok((out, build, t1.elapsed().as_secs_f64()))
        }
        ExternalSim::Verilator => {
            let dut_name = dut
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| "dut.v".to_string());
            let files = [
                (
                    tb_file.clone(),
                    std::fs::read_to_string(dir.join(&tb_file))?,
                ),
                (dut_name, std::fs::read_to_string(dir.join(dut))?),
            ];
            let (exe, build) = verilator_build_cached(tb, &files, "", &[])?;
            let t1 = std::time::Instant::now();
            let out = run(Proc::new(exe).current_dir(dir), "verilated model")?;
            Ok((out, build, t1.elapsed().as_secs_f64()))
        }
    }
}

mod vcache;

pub use vcache::{
    verilator_build_cached, verilator_build_cached_in, verilator_cache_dir, BuildInfo,
    VERILATOR_FLAGS,
};

/// Exports the `n`-processor array, writes vectors for `cmds` and runs them in `sim`
/// inside `dir`. Returns `Ok(None)` (after printing `SKIPPED: ...`) if the tool is
/// missing and `CI` is not `true`.
pub fn run_external(
    sim: ExternalSim,
    dir: &Path,
    cmds: &[(u32, Command)],
    n: usize,
    shadows: bool,
) -> Result<Option<ExternalRun>, TbError> {
    if !tool_available(sim.tool()) {
        skip_or_fail(sim.tool())?;
        return Ok(None);
    }
    std::fs::create_dir_all(dir)?;
    let dir = dir.canonicalize()?;
    let (name, text) = pixelproc_rtl::verilog::array_verilog(n, shadows)?;
    let vfile = dir.join(format!("{name}.v"));
    std::fs::write(&vfile, text)?;
    let cycles = write_vectors(&dir, cmds, n, shadows)?;
    std::fs::write(dir.join("tb_pixelproc.v"), testbench_verilog(&name, cycles))?;
    let (log, build, run_seconds) = build_and_run_info(sim, &dir, "tb_pixelproc", &vfile)?;
    let pass = log.contains(&format!("PASS cycles={cycles}")) && !log.contains("MISMATCH");
    Ok(Some(ExternalRun {
        cycles,
        pass,
        log,
        build_seconds: build.seconds,
        build_cached: build.cached,
        run_seconds,
        vcd: dir.join("tb_pixelproc.vcd"),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readout_compare_follows_the_readout_table() {
        let tb = testbench_verilog("dut_x", 3);
        assert!(tb.contains(
            "wire [98:0] got = {rd_won, rd_sh, rd_nclass, rd_mask, rd_zb, rd_rgb, rd_dsf, rd_fsf, rd_count};"
        ));
        assert!(tb.contains("if (expv[t][127] && got !== expv[t][98:0]) begin"));
        assert!(tb.contains(
            "            cmd_word = stim[t][255:0];
            cmd_bg = stim[t][279:256];
            cmd_op = stim[t][282:280];
            cmd_valid = stim[t][283];
            rst = stim[t][284];
            tile_base = stim[t][296:285];
            rd_addr = stim[t][308:297];
            @(posedge clock);"
        ));
        let v = PortVector {
            rst: true,
            valid: true,
            op: 5,
            bg: 0x1_23456,
            word: [0; 4],
            base: 0x1abc,
            rd_addr: 0xfed,
        };
        let old = (v.bg as u64 & 0xff_ffff)
            | ((v.op as u64 & 7) << 24)
            | ((v.valid as u64) << 27)
            | ((v.rst as u64) << 28)
            | ((v.base as u64 & 0xfff) << 29)
            | ((v.rd_addr as u64 & 0xfff) << 41);
        assert_eq!(stim_high_limb(&v), old);
        let s = ProcState {
            sh: 0,
            won: false,
            zb: 0x1_ABCDEF,
            rgb: 0x123456,
            dsf: true,
            fsf: true,
            count: 3,
            mask: 0x80,
            nclass: 9,
        };
        let old = (1u128 << 127)
            | (9u128 << 66)
            | (0x80u128 << 58)
            | (0xABCDEFu128 << 34)
            | (0x123456u128 << 10)
            | (1u128 << 9)
            | (1u128 << 8)
            | 3;
        assert_eq!(pack_state(&s), old);
    }
}
