//! Clock-by-clock comparison of the RustHDL `PixelProcessorArray` with the golden
//! `PixelArray::step`.
//!
//! Alignment (see `pixelproc_rtl::pixel_array`): the reset is sampled at edge 0 and the
//! commands at edges 1, 2, ...; what is sampled at edge `t` reaches processor `p`'s
//! registers at edge `t + L + p`, `L = LATENCY_PROC0`. So after edge `T ≥ L + p`,
//! processor `p` must equal the golden state of processor `p` after the first
//! `T − L − p` commands (before that it holds power-up values and is not compared).
//! Every processor's `ZB`, `RGB`, `DSF`, `FSF`, `COUNT`, `MASK`, `NCLASS` and readout
//! registers are checked after every edge, and the readout port (`rd_addr` sweeping the
//! processors) after edge `T` against the readout registers after edge `T − 1` of the
//! processor addressed at edge `T − 2`.

use crate::stimulus::LineStream;
use crate::TbError;
use pixelproc_formats::opcodes::*;
use pixelproc_formats::{SpanWord, MAX_X};
use pixelproc_rtl::pixel_array::{PixelProcessorArray, LATENCY_PROC0};
use pixelproc_sim::pixel_array::{Command, PixelArray, ProcState};
use rust_hdl::prelude::*;
use std::collections::VecDeque;
use std::path::PathBuf;

/// The per-clock port values for one command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PortVector {
    /// `rst`.
    pub rst: bool,
    /// `cmd_valid`.
    pub valid: bool,
    /// `cmd_op`.
    pub op: u8,
    /// `cmd_bg`.
    pub bg: u32,
    /// `cmd_word`, 64-bit limbs, limb 0 = bits 63:0.
    pub word: [u64; 4],
    /// `tile_base`.
    pub base: u32,
    /// `rd_addr`.
    pub rd_addr: u32,
}

/// Encodes a golden command for the array's command port.
pub fn encode(base: u32, cmd: &Command) -> Result<PortVector, TbError> {
    let mut v = PortVector {
        rst: false,
        valid: true,
        op: OP_NOP as u8,
        bg: 0,
        word: [0; 4],
        base,
        rd_addr: 0,
    };
    match cmd {
        Command::Nop => v.valid = false,
        Command::ClearLine { bg } => {
            v.op = OP_CLEAR_LINE as u8;
            v.bg = *bg;
        }
        Command::Span(w) => {
            v.op = OP_SPAN as u8;
            v.word = w.pack()?;
        }
        Command::ClearFlags => v.op = OP_CLEAR_FLAGS as u8,
        Command::AccumulateShadow => v.op = OP_ACCUMULATE as u8,
        Command::LatchShadow { bit } => {
            // The golden model uses `bit & 7`; the port carries the same three bits.
            v.op = OP_LATCH_SHADOW as u8;
            v.bg = (*bit & 7) as u32;
        }
        Command::Check { xl, xr } => {
            // The range travels in the span word's XL/XR fields (12 bits each).
            if *xl > MAX_X || *xr > MAX_X {
                return Err(TbError::Unsupported(format!(
                    "{cmd:?}: check range beyond column {MAX_X}"
                )));
            }
            v.op = OP_CHECK as u8;
            v.word = SpanWord {
                xl: *xl,
                xr: *xr,
                ..Default::default()
            }
            .pack()?;
        }
    }
    Ok(v)
}

/// Reads every register (`ZB`, RGB, DSF, FSF, COUNT, MASK, NCLASS) of every processor.
pub fn probe_all(uut: &PixelProcessorArray) -> Vec<ProcState> {
    uut.procs.iter().map(|p| p.probe()).collect()
}

fn probe_cap(uut: &PixelProcessorArray, p: usize) -> ProcState {
    uut.procs[p].probe_capture()
}

/// Clears the shadow registers (what an array built without shadows reads).
pub fn without_shadow_regs(s: ProcState) -> ProcState {
    s.without_shadow_regs()
}

/// Puts one port vector on the array's inputs (the clock is left alone).
fn set_ports(uut: &mut PixelProcessorArray, v: &PortVector) {
    uut.rst.next = v.rst;
    uut.cmd_valid.next = v.valid;
    uut.cmd_op.next = (v.op as u64).to_bits();
    uut.cmd_bg.next = (v.bg as u64).to_bits();
    let mut w: Bits<{ pixelproc_rtl::layout::SPAN_W }> = Bits::default();
    for (i, limb) in v.word.iter().enumerate() {
        w.set_bits::<64>(64 * i, limb.to_bits());
    }
    uut.cmd_word.next = w;
    uut.tile_base.next = (v.base as u64).to_bits();
    uut.rd_addr.next = (v.rd_addr as u64).to_bits();
}

/// Drives one clock cycle of the RustHDL model with the direct `simulate()` loop.
pub fn drive(uut: &mut PixelProcessorArray, v: &PortVector) -> Result<(), TbError> {
    set_ports(uut, v);
    crate::sim_tools::clock_cycle(uut, |u| &mut u.clock)
}

/// The first disagreement between RTL and golden model.
#[derive(Clone, Debug)]
pub struct Mismatch {
    /// Rising edge (cycle) after which the states differ; edge 0 samples the reset.
    pub cycle: u64,
    /// Processor index.
    pub processor: usize,
    /// What was compared (`"state"`, `"readout register"`, `"readout port"`).
    pub what: &'static str,
    /// Index of the last command applied to that processor (if any).
    pub command_index: Option<usize>,
    /// That command, as text.
    pub command: String,
    /// The port values of the cycles that command was sampled in.
    pub inputs: String,
    /// Golden value.
    pub expected: ProcState,
    /// RTL value.
    pub got: ProcState,
    /// VCD trace of the run up to the mismatch, when written.
    pub vcd: Option<PathBuf>,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "first mismatch after cycle {} at processor {} ({}): command #{:?} {} [inputs {}]\n  golden {:?}\n  rtl    {:?}",
            self.cycle, self.processor, self.what, self.command_index, self.command, self.inputs,
            self.expected, self.got
        )?;
        if let Some(p) = &self.vcd {
            write!(f, "\n  trace: {}", p.display())?;
        }
        Ok(())
    }
}

/// Outcome of a clock-by-clock run.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Commands fed (including `ClearLine`s and the final one).
    pub commands: usize,
    /// Span words fed (counting each tile).
    pub span_words: usize,
    /// Clock cycles simulated (reset, commands, drain).
    pub cycles: u64,
    /// Processor-state comparisons made (processors × cycles × 2, plus readout port).
    pub comparisons: u64,
    /// Wall-clock seconds of the simulation loop.
    pub seconds: f64,
    /// The first mismatch, if any.
    pub mismatch: Option<Mismatch>,
}

impl Comparison {
    /// True if every compared value was identical.
    pub fn bit_exact(&self) -> bool {
        self.mismatch.is_none()
    }
}

/// The port vectors of a run: one reset cycle, the commands, then `N + L + 2` NOPs so
/// the last command reaches every processor; `rd_addr` sweeps `0..N`.
pub fn port_vectors(cmds: &[(u32, Command)], n: usize) -> Result<Vec<PortVector>, TbError> {
    let mut v = Vec::with_capacity(cmds.len() + n + LATENCY_PROC0 + 3);
    let mut r = encode(0, &Command::Nop)?;
    r.rst = true;
    v.push(r);
    for (base, c) in cmds {
        v.push(encode(*base, c)?);
    }
    for _ in 0..n + LATENCY_PROC0 + 2 {
        v.push(encode(0, &Command::Nop)?);
    }
    for (t, x) in v.iter_mut().enumerate() {
        x.rd_addr = (t % n) as u32;
    }
    Ok(v)
}

/// Golden per-step states in a sliding window: `state(k)` is the array after the first
/// `k` commands, `cap(k)` the readout registers (state before the latest `ClearLine`).
struct GoldenWindow {
    arr: PixelArray,
    states: VecDeque<(Vec<ProcState>, Vec<ProcState>)>,
    first: usize,
    applied: usize,
    cap: Vec<ProcState>,
}

impl GoldenWindow {
    fn new(n: usize, keep: usize) -> Self {
        let arr = PixelArray::new(n, 0);
        let init = arr.state().to_vec();
        let mut states = VecDeque::with_capacity(keep + 1);
        states.push_back((init.clone(), init.clone()));
        GoldenWindow {
            arr,
            states,
            first: 0,
            applied: 0,
            cap: init,
        }
    }
    fn push(&mut self, base: u32, c: &Command, keep: usize) {
        if let Command::ClearLine { .. } = c {
            self.cap = self.arr.state().to_vec();
        }
        self.arr.set_base(base);
        self.arr.step(c);
        self.applied += 1;
        self.states
            .push_back((self.arr.state().to_vec(), self.cap.clone()));
        while self.states.len() > keep {
            self.states.pop_front();
            self.first += 1;
        }
    }
    fn get(&self, k: usize) -> &(Vec<ProcState>, Vec<ProcState>) {
        &self.states[k - self.first]
    }
}

/// Runs `stream` through an `n`-processor RTL array (with or without shadow logic) and
/// the golden model, comparing every processor after every clock. On a mismatch, if
/// `vcd_dir` is given, re-runs the stimulus up to it in the traced simulator and writes
/// `mismatch.vcd` there.
pub fn compare_stream(
    stream: &LineStream,
    n: usize,
    shadows: bool,
    vcd_dir: Option<&std::path::Path>,
) -> Result<Comparison, TbError> {
    compare_commands(&stream.flatten(n), n, shadows, vcd_dir)
}

/// As [`compare_stream`], for an explicit list of `(tile base, command)` per clock.
pub fn compare_commands(
    cmds: &[(u32, Command)],
    n: usize,
    shadows: bool,
    vcd_dir: Option<&std::path::Path>,
) -> Result<Comparison, TbError> {
    compare_commands_checked(cmds, n, shadows, !shadows, vcd_dir)
}

/// As [`compare_commands`]; `ignore_flags` stops DSF/FSF/COUNT from being compared (an
/// array built without shadows reads them as 0). Exposed so a test can show that a
/// shadow stream on a shadow-less array is reported as a mismatch.
pub fn compare_commands_checked(
    cmds: &[(u32, Command)],
    n: usize,
    shadows: bool,
    ignore_flags: bool,
    vcd_dir: Option<&std::path::Path>,
) -> Result<Comparison, TbError> {
    let vecs = port_vectors(cmds, n)?;
    let mut uut = PixelProcessorArray::new(n, shadows)?;
    uut.connect_all();
    let keep = n + LATENCY_PROC0 + 4;
    let mut check = Checker {
        cmds,
        vecs: &vecs,
        gold: GoldenWindow::new(n, keep),
        keep,
        ignore_flags,
        comparisons: 0,
        prev_cap: None,
    };
    let start = std::time::Instant::now();
    let mut mismatch = None;
    for (t, v) in vecs.iter().enumerate() {
        drive(&mut uut, v)?;
        mismatch = check.after_edge(&uut, t);
        if mismatch.is_some() {
            break;
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    if let (Some(m), Some(dir)) = (mismatch.as_mut(), vcd_dir) {
        std::fs::create_dir_all(dir)?;
        let path = dir.join("mismatch.vcd");
        write_vcd(&vecs[..=(m.cycle as usize)], n, shadows, &path)?;
        m.vcd = Some(path);
    }
    let span_words = cmds
        .iter()
        .filter(|(_, c)| matches!(c, Command::Span(_)))
        .count();
    Ok(Comparison {
        commands: cmds.len(),
        span_words,
        cycles: vecs.len() as u64,
        comparisons: check.comparisons,
        seconds,
        mismatch,
    })
}

/// The checks of one clock-by-clock run: the commands, their port vectors and the golden
/// states they lead to.
struct Checker<'a> {
    cmds: &'a [(u32, Command)],
    vecs: &'a [PortVector],
    gold: GoldenWindow,
    keep: usize,
    ignore_flags: bool,
    comparisons: u64,
    /// The readout registers of `rd_addr` after the previous edge, if that processor had
    /// been reached by the reset token (before, it holds its power-up values).
    prev_cap: Option<ProcState>,
}

impl Checker<'_> {
    /// Compares everything after edge `t` (vector `t` was just driven); the first
    /// mismatch, if any.
    fn after_edge(&mut self, uut: &PixelProcessorArray, t: usize) -> Option<Mismatch> {
        // Golden: commands are vector indices 1..=cmds.len(); feed the one sampled now.
        if t >= 1 && t <= self.cmds.len() {
            let (b, c) = &self.cmds[t - 1];
            self.gold.push(*b, c, self.keep);
        }
        if let Some(m) = self.check_processors(uut, t) {
            return Some(m);
        }
        if let Some(m) = self.check_port(uut, t) {
            return Some(m);
        }
        // After edge t the port shows, at edge t + 1, the readout registers (as now) of
        // the processor whose address was sampled at edge t − 1.
        self.prev_cap = None;
        if t >= 1 {
            let a = self.vecs[t - 1].rd_addr as usize;
            if t >= LATENCY_PROC0 + a {
                self.prev_cap = Some(probe_cap(uut, a));
            }
        }
        None
    }

    /// Every processor's state and readout registers against the golden model.
    fn check_processors(&mut self, uut: &PixelProcessorArray, t: usize) -> Option<Mismatch> {
        let rtl = probe_all(uut);
        for (p, got) in rtl.iter().enumerate() {
            // The reset (edge 0) reaches processor p at edge L + p; commands sampled at
            // edges 1..=t−L−p have been applied.
            let kk = t as i64 - LATENCY_PROC0 as i64 - p as i64;
            if kk < 0 {
                continue;
            }
            let k = kk.min(self.cmds.len() as i64) as usize;
            let (st, cap) = self.gold.get(k);
            let mut exp = st[p];
            let mut exp_cap = cap[p];
            if self.ignore_flags {
                exp = without_shadow_regs(exp);
                exp_cap = without_shadow_regs(exp_cap);
            }
            let got_cap = probe_cap(uut, p);
            self.comparisons += 2;
            let bad = if *got != exp {
                Some(("state", exp, *got))
            } else if got_cap != exp_cap {
                Some(("readout register", exp_cap, got_cap))
            } else {
                None
            };
            if let Some((what, expected, got)) = bad {
                return Some(make_mismatch(
                    t, p, what, k, self.cmds, self.vecs, expected, got,
                ));
            }
        }
        None
    }

    /// Readout port: the readout registers after edge t − 1 of the processor whose
    /// address was sampled at edge t − 2.
    fn check_port(&mut self, uut: &PixelProcessorArray, t: usize) -> Option<Mismatch> {
        let exp = self.prev_cap?;
        if t < 1 {
            return None;
        }
        let got = port_state(uut);
        self.comparisons += 1;
        if got == exp {
            return None;
        }
        let p = self.vecs[t - 2].rd_addr as usize;
        Some(make_mismatch(
            t,
            p,
            "readout port",
            0,
            self.cmds,
            self.vecs,
            exp,
            got,
        ))
    }
}

/// The readout port's current values.
fn port_state(uut: &PixelProcessorArray) -> ProcState {
    ProcState {
        sh: uut.rd_sh.val().to_u32(),
        won: uut.rd_won.val(),
        zb: uut.rd_zb.val().to_u32(),
        rgb: uut.rd_rgb.val().to_u32(),
        dsf: uut.rd_dsf.val(),
        fsf: uut.rd_fsf.val(),
        count: uut.rd_count.val().to_u8(),
        mask: uut.rd_mask.val().to_u8(),
        nclass: uut.rd_nclass.val().to_u8(),
    }
}

#[allow(clippy::too_many_arguments)]
fn make_mismatch(
    t: usize,
    p: usize,
    what: &'static str,
    k: usize,
    cmds: &[(u32, Command)],
    vecs: &[PortVector],
    expected: ProcState,
    got: ProcState,
) -> Mismatch {
    let (command_index, command, inputs) = if k >= 1 {
        let (b, c) = &cmds[k - 1];
        let text = match c {
            Command::Span(w) => format!("Span {:?} (hex {})", w, w.to_hex().unwrap_or_default()),
            other => format!("{other:?}"),
        };
        (
            Some(k - 1),
            format!("{text} at tile base {b}"),
            format!("{:?}", vecs[k]),
        )
    } else {
        (None, "reset".to_string(), format!("{:?}", vecs[0]))
    };
    Mismatch {
        cycle: t as u64,
        processor: p,
        what,
        command_index,
        command,
        inputs,
        expected,
        got,
        vcd: None,
    }
}

/// Replays `vecs` in the traced (threaded) RustHDL simulator and writes a VCD.
pub fn write_vcd(
    vecs: &[PortVector],
    n: usize,
    shadows: bool,
    path: &std::path::Path,
) -> Result<(), TbError> {
    const HALF_PS: u64 = 5_000;
    let vecs = vecs.to_vec();
    let count = vecs.len() as u64;
    let mut sim = Simulation::new();
    sim.add_clock(HALF_PS, |x: &mut Box<PixelProcessorArray>| {
        x.clock.next = !x.clock.val()
    });
    sim.add_testbench(move |mut ep: Sim<PixelProcessorArray>| {
        let mut x = ep.init()?;
        for v in &vecs {
            set_ports(&mut x, v);
            wait_clock_cycle!(ep, clock, x);
        }
        ep.done(x)
    });
    let uut = PixelProcessorArray::new(n, shadows)?;
    let path_s = path.to_string_lossy().to_string();
    sim.run_to_file(Box::new(uut), (count + 4) * 2 * HALF_PS, &path_s)
        .map_err(|e| TbError::Sim(format!("{e:?}")))
}

/// Golden expectation helper for tests: the state after all of `cmds`.
pub fn golden_final(cmds: &[(u32, Command)], n: usize) -> Vec<ProcState> {
    let mut a = PixelArray::new(n, 0);
    for (b, c) in cmds {
        a.set_base(*b);
        a.step(c);
    }
    a.state().to_vec()
}
