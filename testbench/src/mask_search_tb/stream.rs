//! The stream search units (`MaskSearchIterStream`, `MaskSearchPipeStream`, seed 000) on
//! the whole fragment stream of an A-buffer render, with random input gaps and random
//! output back-pressure, every result compared with the golden model.
//!
//! **Words.** The golden `pixelproc_sim::abuffer::search_stream` lists every search the
//! A-buffer render of a scene runs, in order, each with its golden result. They become
//! `s_tdata` words (`s_data.hex`) and expected `m_tdata` words (`m_expect.hex`), one line
//! per search, in the layouts of `pixelproc_rtl::mask_search::{stream_in_bits,
//! stream_out_bits}`.
//!
//! **Traffic.** One 32-bit xorshift generator seeded from the run's seed decides, after
//! every rising edge, `m_tready` and whether a new search is offered (`s_tvalid`; an
//! offered search is held, data unchanged, until it is taken, as AXI4-Stream requires).
//! The probabilities change every 512 clocks through four phases: (stall %, gap %) =
//! (0, 0), (30, 40), (70, 10), (97, 60), so the stream runs at full rate, with both kinds
//! of bubbles, and with the consumer almost stopped (credits exhausted, input held off).
//! The same generator drives the Verilog testbench and the RustHDL loop.
//!
//! **Checks.** Every hand-over (`m_tvalid && m_tready`) is compared with the next expected
//! word (a lost, repeated or reordered result is a mismatch at its index); while
//! `m_tvalid && !m_tready`, `m_tvalid` and `m_tdata` must stay as they were; after the last
//! result, 40 clocks with `m_tready` high must show no further `m_tvalid`; a run that
//! does not finish within `40·N + 2000` clocks is reported as stuck.

use crate::{SimKind, TbError};
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_rtl::mask_search::{
    mask_search_stream_verilog, stream_in_bits, stream_out_bits, Variant, STREAM_HIT_BIT, Z_BITS,
};
use pixelproc_sim::abuffer::{search_stream, SearchRequest};
use pixelproc_sim::scene::LoadedScene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A bit vector as 64-bit limbs, LSB first.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Word(pub Vec<u64>);

impl Word {
    /// Appends the low `w` bits of `v` above the bits already there (`at` = current width).
    fn put(&mut self, at: &mut usize, v: u64, w: usize) {
        for i in 0..w {
            let n = *at + i;
            if self.0.len() <= n / 64 {
                self.0.resize(n / 64 + 1, 0);
            }
            if (v >> i) & 1 == 1 {
                self.0[n / 64] |= 1 << (n % 64);
            }
        }
        *at += w;
    }

    /// `w` bits (≤ 64) at `off`.
    pub fn get(&self, off: usize, w: usize) -> u64 {
        (0..w).fold(0, |a, i| {
            let n = off + i;
            let b = self.0.get(n / 64).map_or(0, |l| (l >> (n % 64)) & 1);
            a | b << i
        })
    }

    /// Flips bit `n`.
    pub fn flip(&mut self, n: usize) {
        if self.0.len() <= n / 64 {
            self.0.resize(n / 64 + 1, 0);
        }
        self.0[n / 64] ^= 1 << (n % 64);
    }

    /// Hex digits for `bits` bits, most significant first.
    pub fn hex(&self, bits: usize) -> String {
        (0..bits.div_ceil(4))
            .rev()
            .map(|d| char::from_digit(self.get(4 * d, 4) as u32, 16).unwrap_or('0'))
            .collect()
    }

    /// Parses hex digits (most significant first; `x`/`z` read as 0).
    pub fn parse_hex(s: &str) -> Word {
        let mut w = Word::default();
        for (d, c) in s.trim().chars().rev().enumerate() {
            let v = c.to_digit(16).unwrap_or(0) as u64;
            let mut at = 4 * d;
            w.put(&mut at, v, 4);
        }
        w
    }
}

/// The `s_tdata` word of a search.
pub fn input_word(r: &SearchRequest, size: MaskSize) -> Word {
    let m48 = (1u64 << 48) - 1;
    let mut w = Word::default();
    let mut at = 0;
    for f in [r.plane.zc, r.plane.sx, r.plane.sy] {
        w.put(&mut at, f as u64 & m48, 48);
    }
    w.put(&mut at, r.corner.code() as u64, 2);
    w.put(&mut at, r.mask & size.full(), size.bits() as usize);
    w
}

/// The golden `m_tdata` word of a search.
pub fn expected_word(r: &SearchRequest, size: MaskSize) -> Word {
    let zm = (1u64 << Z_BITS) - 1;
    let mut w = Word::default();
    let mut at = 0;
    for z in [r.z1, r.z2, r.zmin(), r.zmax()] {
        w.put(&mut at, z as u64 & zm, Z_BITS);
    }
    let (and, rom) = r.result.hit.map_or((0, 0), |(a, w)| (a, w.pack()));
    w.put(&mut at, rom as u64, 17);
    w.put(&mut at, r.result.steps as u64, 5);
    w.put(&mut at, r.result.hit.is_some() as u64, 1);
    w.put(&mut at, and, size.bits() as usize);
    w
}

/// A result word field by field.
pub fn describe_result(w: &Word, size: MaskSize) -> String {
    let z = |k: usize| {
        let v = w.get(k * Z_BITS, Z_BITS);
        ((v << (64 - Z_BITS)) as i64) >> (64 - Z_BITS)
    };
    format!(
        "hit={} steps={} and={:#x} rom={:#07x} z1={} z2={} zmin={} zmax={}",
        w.get(STREAM_HIT_BIT, 1),
        w.get(STREAM_HIT_BIT - 5, 5),
        w.get(STREAM_HIT_BIT + 1, size.bits() as usize),
        w.get(4 * Z_BITS, 17),
        z(0),
        z(1),
        z(2),
        z(3)
    )
}

/// A search stream as words: what is fed and what must come out.
#[derive(Clone, Debug, Default)]
pub struct StreamWords {
    /// `s_tdata` per search.
    pub input: Vec<Word>,
    /// Expected `m_tdata` per search.
    pub expect: Vec<Word>,
}

/// The words of a stream of searches.
pub fn stream_words(reqs: &[SearchRequest], size: MaskSize) -> StreamWords {
    StreamWords {
        input: reqs.iter().map(|r| input_word(r, size)).collect(),
        expect: reqs.iter().map(|r| expected_word(r, size)).collect(),
    }
}

/// The whole search stream of the A-buffer render of a loaded scene (golden front end;
/// max searches too if the scene declares interpenetrating surfaces).
pub fn scene_requests(ls: &LoadedScene, size: MaskSize) -> Result<Vec<SearchRequest>, TbError> {
    let proj = pixelproc_sim::frontend::project(ls).map_err(|e| TbError::Sim(e.to_string()))?;
    search_stream(
        &proj.tris,
        ls.scene.width,
        ls.scene.height,
        size,
        ls.scene.effects.interpenetrating,
    )
    .map_err(|e| TbError::Sim(e.to_string()))
}

/// Outcome of a stream run.
#[derive(Clone, Debug)]
pub struct StreamSummary {
    /// Variant run.
    pub variant: Variant,
    /// Mask size.
    pub size: MaskSize,
    /// Simulator.
    pub sim: SimKind,
    /// Seed of the traffic generator.
    pub seed: u64,
    /// Searches in the stream.
    pub searches: usize,
    /// Results compared (all of them on success).
    pub results: usize,
    /// Clock cycles simulated.
    pub cycles: u64,
    /// Cycles per second of the run.
    pub cycles_per_second: f64,
    /// Seconds to build the simulator (0 for RustHDL).
    pub build_seconds: f64,
    /// Seconds to run it.
    pub run_seconds: f64,
    /// Every result identical, none missing or extra, data stable under back-pressure.
    pub identical: bool,
    /// The first failure (index, expected and got, field by field), empty on success.
    pub detail: String,
}

impl std::fmt::Display for StreamSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} {} {:?} seed {}: {} of {} results compared, {} cycles, build {:.1} s, run {:.2} s, {:.0} cycles/s, {}",
            self.variant.name(),
            self.size,
            self.sim,
            self.seed,
            self.results,
            self.searches,
            self.cycles,
            self.build_seconds,
            self.run_seconds,
            self.cycles_per_second,
            if self.identical {
                "identical".to_string()
            } else {
                format!("DIFFERENT: {}", self.detail)
            }
        )
    }
}

/// The traffic generator (see the module documentation); the Verilog testbench has the
/// same one.
#[derive(Clone, Copy, Debug)]
pub struct Traffic {
    r: u32,
}

/// (stall %, gap %) per phase of 512 clocks.
const PHASES: [(u32, u32); 4] = [(0, 0), (30, 40), (70, 10), (97, 60)];

impl Traffic {
    /// The generator for `seed` (never zero inside).
    pub fn new(seed: u64) -> Traffic {
        let r = (seed ^ (seed >> 32)) as u32;
        Traffic {
            r: if r == 0 { 0x9E37_79B9 } else { r },
        }
    }

    /// Its 32-bit start state (the Verilog testbench's `r`).
    pub fn state(&self) -> u32 {
        self.r
    }

    fn next(&mut self) -> u32 {
        self.r ^= self.r << 13;
        self.r ^= self.r >> 17;
        self.r ^= self.r << 5;
        self.r
    }

    /// Decisions after edge `cyc`: `(m_tready, offer a new search if none is held)`.
    pub fn step(&mut self, cyc: u64) -> (bool, bool) {
        let (stall, gap) = PHASES[((cyc >> 9) & 3) as usize];
        let ready = self.next() % 100 >= stall;
        let offer = self.next() % 100 >= gap;
        (ready, offer)
    }
}

/// Clocks after which a run counts as stuck.
fn max_cycles(n: usize) -> u64 {
    40 * n as u64 + 2000
}

/// Runs the whole search stream of `scene`'s A-buffer render at `size` through `variant`'s
/// stream unit in `sim` (a temporary work directory, removed after a passing run), with
/// the traffic of `seed`. A missing simulator is an error naming the install command.
pub fn run_search_stream(
    scene: &LoadedScene,
    size: MaskSize,
    variant: Variant,
    sim: SimKind,
    seed: u64,
) -> Result<StreamSummary, TbError> {
    let reqs = scene_requests(scene, size)?;
    let words = stream_words(&reqs, size);
    let dir = std::env::temp_dir().join(format!(
        "pixelproc-search-stream-{}-{}x{}-{}",
        variant.name(),
        size.n(),
        size.m(),
        std::process::id()
    ));
    let s = run_stream_words(&words, size, variant, sim, seed, &dir)?;
    if s.identical {
        std::fs::remove_dir_all(&dir).ok();
    }
    Ok(s)
}

/// Runs prepared words (e.g. [`stream_words`] of a part of a stream, or with an expected
/// word changed on purpose) through `variant`'s stream unit in `sim`; external simulators
/// work in `dir`.
pub fn run_stream_words(
    words: &StreamWords,
    size: MaskSize,
    variant: Variant,
    sim: SimKind,
    seed: u64,
    dir: &Path,
) -> Result<StreamSummary, TbError> {
    if words.input.len() != words.expect.len() {
        return Err(TbError::Sim(format!(
            "{} searches but {} expected results",
            words.input.len(),
            words.expect.len()
        )));
    }
    if size != MaskSize::S4X4 && size != MaskSize::S8X8 {
        return Err(TbError::Sim(format!(
            "the stream units are built for 4x4 and 8x8 masks, not {size}"
        )));
    }
    let mut s = StreamSummary {
        variant,
        size,
        sim,
        seed,
        searches: words.input.len(),
        results: 0,
        cycles: 0,
        cycles_per_second: 0.0,
        build_seconds: 0.0,
        run_seconds: 0.0,
        identical: false,
        detail: String::new(),
    };
    match sim {
        SimKind::RustHdl => super::stream_rusthdl::run(words, size, variant, seed, &mut s)?,
        SimKind::Icarus | SimKind::Verilator => {
            run_external(words, size, variant, sim, dir, &mut s)?
        }
    }
    s.cycles_per_second = if s.run_seconds > 0.0 {
        s.cycles as f64 / s.run_seconds
    } else {
        0.0
    };
    Ok(s)
}

/// A failure report: index, expected and got, field by field.
pub(crate) fn mismatch_detail(
    index: usize,
    cycle: u64,
    expected: &Word,
    got: &Word,
    size: MaskSize,
) -> String {
    let ow = stream_out_bits(size.bits() as usize);
    format!(
        "result {index} (clock {cycle}) differs:\n  expected {} ({})\n  got      {} ({})",
        expected.hex(ow),
        describe_result(expected, size),
        got.hex(ow),
        describe_result(got, size)
    )
}

fn run_external(
    words: &StreamWords,
    size: MaskSize,
    variant: Variant,
    sim: SimKind,
    dir: &Path,
    s: &mut StreamSummary,
) -> Result<(), TbError> {
    let ext = match sim {
        SimKind::Icarus => crate::external::ExternalSim::Icarus,
        _ => crate::external::ExternalSim::Verilator,
    };
    if !crate::external::tool_available(ext.tool()) {
        // Never a silent pass: a missing simulator is an error with the install command.
        return Err(TbError::ToolMissing(ext.tool().to_string()));
    }
    std::fs::create_dir_all(dir)?;
    let dir: PathBuf = dir.canonicalize()?;
    let (name, text) =
        mask_search_stream_verilog(variant, size).map_err(|e| TbError::Sim(e.to_string()))?;
    let vfile = dir.join(format!("{name}.v"));
    std::fs::write(&vfile, text)?;
    write_hex(words, size, &dir)?;
    let b = size.bits() as usize;
    let (iw, ow) = (stream_in_bits(b), stream_out_bits(b));
    let n = words.input.len();
    std::fs::write(
        dir.join("tb_search_stream.v"),
        stream_testbench_verilog(&name, iw, ow, n, Traffic::new(s.seed).state()),
    )?;
    let (out, build, run) = crate::external::build_and_run(ext, &dir, "tb_search_stream", &vfile)?;
    s.build_seconds = build;
    s.run_seconds = run;
    parse_log(&out, words, size, s);
    Ok(())
}

/// Writes `s_data.hex` and `m_expect.hex` into `dir`.
fn write_hex(words: &StreamWords, size: MaskSize, dir: &Path) -> Result<(), TbError> {
    let b = size.bits() as usize;
    let (iw, ow) = (stream_in_bits(b), stream_out_bits(b));
    let mut sd = String::with_capacity(words.input.len() * (iw / 4 + 2));
    for w in &words.input {
        sd.push_str(&w.hex(iw));
        sd.push('\n');
    }
    let mut ed = String::with_capacity(words.expect.len() * (ow / 4 + 2));
    for w in &words.expect {
        ed.push_str(&w.hex(ow));
        ed.push('\n');
    }
    std::fs::write(dir.join("s_data.hex"), sd)?;
    std::fs::write(dir.join("m_expect.hex"), ed)?;
    Ok(())
}

/// Runs the Verilator model that [`run_stream_words`] built in `dir` again on new words
/// (the same number of searches and the same seed: both are fixed in the built
/// testbench), without rebuilding. For checks of the checker: a changed expected word
/// must be reported.
pub fn rerun_verilator(
    words: &StreamWords,
    size: MaskSize,
    variant: Variant,
    seed: u64,
    dir: &Path,
) -> Result<StreamSummary, TbError> {
    let tb = std::fs::read_to_string(dir.join("tb_search_stream.v"))?;
    let n = words.input.len();
    let state = Traffic::new(seed).state();
    if !tb.contains(&format!("localparam integer N = {n};"))
        || !tb.contains(&format!("reg [31:0] r = 32'd{state};"))
    {
        return Err(TbError::Sim(format!(
            "the testbench in {} was built for another stream length or seed",
            dir.display()
        )));
    }
    write_hex(words, size, dir)?;
    // The model built for this testbench, from the build cache (the same sources: no
    // rebuild).
    let (name, text) =
        mask_search_stream_verilog(variant, size).map_err(|e| TbError::Sim(e.to_string()))?;
    let files = [
        ("tb_search_stream.v".to_string(), tb),
        (format!("{name}.v"), text),
    ];
    let (exe, _) = crate::external::verilator_build_cached("tb_search_stream", &files, "", &[])?;
    let t0 = std::time::Instant::now();
    let o = std::process::Command::new(exe).current_dir(dir).output()?;
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let mut s = StreamSummary {
        variant,
        size,
        sim: SimKind::Verilator,
        seed,
        searches: n,
        results: 0,
        cycles: 0,
        cycles_per_second: 0.0,
        build_seconds: 0.0,
        run_seconds: t0.elapsed().as_secs_f64(),
        identical: false,
        detail: String::new(),
    };
    parse_log(&out, words, size, &mut s);
    Ok(s)
}

/// Reads the testbench's last report line into the summary.
fn parse_log(out: &str, words: &StreamWords, size: MaskSize, s: &mut StreamSummary) {
    let field = |line: &str, key: &str| -> Option<String> {
        line.split_whitespace()
            .find_map(|t| t.strip_prefix(key).map(str::to_string))
    };
    let num = |line: &str, key: &str| field(line, key).and_then(|v| v.parse::<u64>().ok());
    for line in out.lines() {
        if line.starts_with("PASS ") {
            s.results = num(line, "results=").unwrap_or(0) as usize;
            s.cycles = num(line, "cycles=").unwrap_or(0);
            s.identical = s.results == words.expect.len();
            if !s.identical {
                s.detail = format!("testbench passed with {} results", s.results);
            }
            return;
        }
        if line.starts_with("MISMATCH ") {
            let k = num(line, "index=").unwrap_or(0) as usize;
            s.results = k;
            s.cycles = num(line, "cycle=").unwrap_or(0);
            let got = Word::parse_hex(&field(line, "got=").unwrap_or_default());
            let exp = words.expect.get(k).cloned().unwrap_or_default();
            s.detail = mismatch_detail(k, s.cycles, &exp, &got, size);
            return;
        }
        if line.starts_with("UNSTABLE ") || line.starts_with("EXTRA ") || line.starts_with("STUCK ")
        {
            s.results = num(line, "results=").unwrap_or(0) as usize;
            s.cycles = num(line, "cycle=").unwrap_or(0);
            s.detail = line.to_string();
            return;
        }
    }
    s.detail = format!("no verdict from the testbench:\n{out}");
}

/// The Verilog testbench of a stream unit `dut` (`iw`/`ow`-bit words, `n` searches,
/// traffic generator state `r0`): reads `s_data.hex` and `m_expect.hex`, drives the
/// traffic of [`Traffic`], checks every hand-over and prints `PASS results=N cycles=C`,
/// or `MISMATCH index=K cycle=C expected=.. got=..`, `UNSTABLE ...`, `EXTRA ...` or
/// `STUCK ...`.
pub fn stream_testbench_verilog(dut: &str, iw: usize, ow: usize, n: usize, r0: u32) -> String {
    let mut phases = String::new();
    for (k, (stall, gap)) in PHASES.iter().enumerate() {
        writeln!(
            phases,
            "                2'd{k}: begin stall_pct = 32'd{stall}; gap_pct = 32'd{gap}; end"
        )
        .ok();
    }
    format!(
        r#"// Stream testbench for {dut}: the whole search stream with random input gaps and
// output back-pressure; every result compared with m_expect.hex.
`timescale 1ns/1ps
module tb_search_stream;
    localparam integer N = {n};
    localparam integer MAXCYC = {maxcyc};
    reg clock = 1'b0;
    reg rst = 1'b1;
    reg [{iw1}:0] sdat [0:N-1];
    reg [{ow1}:0] expv [0:N-1];
    reg s_tvalid = 1'b0;
    reg [{iw1}:0] s_tdata = {{{iw}{{1'b0}}}};
    wire s_tready;
    wire m_tvalid;
    reg m_tready = 1'b0;
    wire [{ow1}:0] m_tdata;
    reg [31:0] r = 32'd{r0};
    reg [31:0] stall_pct, gap_pct;
    reg held, offer, take;
    reg [{ow1}:0] held_d;
    integer sent, got, cyc, k;
    {dut} dut (.clock(clock), .rst(rst), .s_tvalid(s_tvalid), .s_tready(s_tready),
        .s_tdata(s_tdata), .m_tvalid(m_tvalid), .m_tready(m_tready), .m_tdata(m_tdata));
    always #5 clock = ~clock;
    task next_r;
        begin
            r = r ^ (r << 13);
            r = r ^ (r >> 17);
            r = r ^ (r << 5);
        end
    endtask
    initial begin
        $readmemh("s_data.hex", sdat);
        $readmemh("m_expect.hex", expv);
        sent = 0; got = 0; cyc = 0; held = 1'b0; take = 1'b0;
        @(posedge clock);
        @(posedge clock);
        #1 rst = 1'b0;
        while (got < N && cyc < MAXCYC) begin
            // After an edge: the searcher's last offer was taken or is held; new decisions.
            if (take) begin
                sent = sent + 1;
                s_tvalid = 1'b0;
            end
            case ((cyc >> 9) & 3)
{phases}            endcase
            next_r;
            m_tready = (r % 100) >= stall_pct;
            next_r;
            offer = (r % 100) >= gap_pct;
            if (!s_tvalid && offer && sent < N) begin
                s_tvalid = 1'b1;
                s_tdata = sdat[sent];
            end
            #4;
            // Settled, before the next edge: what that edge hands over.
            if (held && (!m_tvalid || m_tdata !== held_d)) begin
                $display("UNSTABLE cycle=%0d results=%0d held=%h valid=%b now=%h", cyc, got, held_d, m_tvalid, m_tdata);
                $finish;
            end
            if (m_tvalid && m_tready) begin
                if (m_tdata !== expv[got]) begin
                    $display("MISMATCH index=%0d cycle=%0d expected=%h got=%h", got, cyc, expv[got], m_tdata);
                    $finish;
                end
                got = got + 1;
            end
            held = m_tvalid && !m_tready;
            held_d = m_tdata;
            take = s_tvalid && s_tready;
            @(posedge clock);
            cyc = cyc + 1;
            #1;
        end
        if (got < N) begin
            $display("STUCK cycle=%0d results=%0d sent=%0d of %0d", cyc, got, sent, N);
            $finish;
        end
        s_tvalid = 1'b0;
        m_tready = 1'b1;
        for (k = 0; k < 40; k = k + 1) begin
            #4;
            if (m_tvalid) begin
                $display("EXTRA cycle=%0d results=%0d got=%h", cyc, got, m_tdata);
                $finish;
            end
            @(posedge clock);
            #1;
        end
        $display("PASS results=%0d cycles=%0d", got, cyc);
        $finish;
    end
endmodule
"#,
        maxcyc = max_cycles(n),
        iw1 = iw - 1,
        ow1 = ow - 1,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_round_trip_through_hex() {
        let mut w = Word::default();
        let mut at = 0;
        w.put(&mut at, 0xABC, 12);
        w.put(&mut at, 1, 1);
        w.put(&mut at, u64::MAX, 64);
        assert_eq!(at, 77);
        let h = w.hex(77);
        assert_eq!(Word::parse_hex(&h), w);
        assert_eq!(w.get(12, 1), 1);
        assert_eq!(w.get(13, 64), u64::MAX);
    }
}
