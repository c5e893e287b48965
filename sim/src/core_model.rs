//! The pixelproc core, golden and cycle by cycle: its command stream (the driver's side)
//! and a register-for-register model of its controller (input FIFO occupancy, the
//! readout hazard that stalls the input, the readout sweep, the shading step of seed 001
//! section 2 / section 6, the output FIFO), so that the RTL core
//! (`pixelproc_rtl::core_top::PixelprocCore`) can be compared with it after every rising
//! edge, and so that cycle counts come from one place. Formats:
//! `pixelproc_formats::core_stream`; protocol: `docs/core.md`.
//!
//! **The stream** ([`CoreStream::of_scene`]): the shading table as TABLE beats (shadows
//! only), then for every scanline and every tile a TILE beat followed by the commands
//! that touch the tile ([`SceneStream::tile`]: the binning the renderer itself uses),
//! then an END beat. [`CoreStream::unbinned`] feeds every tile the whole row instead (the
//! old array testbench's stream), to show what binning saves.
//!
//! **The model** ([`CoreModel::step`]): one call per rising edge, with the values on the
//! core's inputs before the edge; it returns the outputs the core showed before the edge
//! (so `s_ready`/`m_valid` are the handshake of that edge) and applies the edge. The
//! array inside is the golden [`PixelArray`]: commands take effect when issued, and a
//! tile-line's pixels are the array state at the TILE or END that ends it. That is what
//! the RTL sweep reads, because its timing ([`READOUT_WAIT`]) is chosen so that every
//! read follows the CLEAR_LINE wavefront (proof in `pixelproc_rtl::core_top`).

use crate::pixel_array::{Command, PixelArray, ProcState};
use crate::rng::XorShift64Star;
use crate::shadow::FactorTable;
use crate::stream::SceneStream;
use pixelproc_formats::core_stream::*;
use pixelproc_formats::{FieldRangeError, SpanWord, Z_FAR};
use thiserror::Error;

/// Clocks a readout job waits before its first address (the RTL's `READOUT_WAIT`).
pub const READOUT_WAIT: u32 = 4;
/// Address bits of the output FIFO.
pub const OUT_FIFO_ABITS: u32 = 4;
/// Input FIFO address bits of the exported core (32 beats).
pub const DEFAULT_IN_ABITS: u32 = 5;

/// Why a scene cannot go through the core.
#[derive(Debug, Error)]
pub enum CoreError {
    /// The array width is outside 1..=4096.
    #[error("--array-width {0}: the core takes 1..=4096 processors")]
    Width(usize),
    /// More shadowing point lights than the shading table's mask bits.
    #[error("{0} shadowing point lights: the core's shading table takes at most {SHADE_MASK_BITS} (light-mask bits of its address)")]
    TooManyLights(u32),
    /// An area light with more samples than the shading table's counter bits.
    #[error("area light with {0} samples: the core's shading table takes at most {} (counter bits of its address)", (1u32 << SHADE_COUNT_BITS) - 1)]
    TooManySamples(u32),
    /// A span word does not fit its fields.
    #[error(transparent)]
    Field(#[from] FieldRangeError),
    /// A CHECK range beyond the span word's columns.
    #[error("a CHECK range {0}..={1} does not fit the span word")]
    Check(u16, u16),
}

/// One command beat: `s_axis_tuser` (kind) and `s_axis_tdata` as four 64-bit limbs
/// (limb 0 = bits 63:0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Beat {
    /// Beat kind (`KIND_*`).
    pub kind: u8,
    /// Data.
    pub data: [u64; 4],
}

impl Beat {
    /// A beat of kind `kind` whose data has the given fields set.
    pub fn with_fields(kind: u64, fields: &[(pixelproc_formats::Field, u64)]) -> Beat {
        let mut data = [0u64; 4];
        for (f, v) in fields {
            f.put(&mut data, *v);
        }
        Beat {
            kind: kind as u8,
            data,
        }
    }

    /// The beat of an array command (`ClearLine` is not one: the core issues it for TILE
    /// and END beats).
    pub fn of_command(c: &Command) -> Result<Beat, CoreError> {
        let word = |w: &SpanWord| -> Result<[u64; 4], CoreError> { Ok(w.pack()?) };
        Ok(match c {
            Command::Span(w) => Beat {
                kind: KIND_SPAN as u8,
                data: word(w)?,
            },
            Command::Check { xl, xr } => {
                if *xl > pixelproc_formats::MAX_X || *xr > pixelproc_formats::MAX_X {
                    return Err(CoreError::Check(*xl, *xr));
                }
                Beat {
                    kind: KIND_CHECK as u8,
                    data: word(&SpanWord {
                        xl: *xl,
                        xr: *xr,
                        ..Default::default()
                    })?,
                }
            }
            Command::ClearFlags => Beat::with_fields(KIND_CLEAR_FLAGS, &[]),
            Command::AccumulateShadow => Beat::with_fields(KIND_ACCUMULATE, &[]),
            Command::LatchShadow { bit } => {
                Beat::with_fields(KIND_LATCH_SHADOW, &[(LATCH_BIT, (*bit & 7) as u64)])
            }
            Command::Nop => Beat::with_fields(KIND_NOP, &[]),
            Command::ClearLine { bg } => Beat::with_fields(
                KIND_TILE,
                &[(TILE_BG, *bg as u64), (TILE_LAST, 0), (TILE_SOF, 0)],
            ),
        })
    }

    /// The array command this beat issues (`None` for TABLE and unknown kinds); TILE and
    /// END issue `ClearLine` with the beat's background.
    pub fn command(&self) -> Option<Command> {
        let d = &self.data;
        Some(match self.kind as u64 {
            KIND_NOP => Command::Nop,
            KIND_SPAN => Command::Span(SpanWord::unpack(d)),
            KIND_CLEAR_FLAGS => Command::ClearFlags,
            KIND_ACCUMULATE => Command::AccumulateShadow,
            KIND_LATCH_SHADOW => Command::LatchShadow {
                bit: LATCH_BIT.get(d) as u8,
            },
            KIND_CHECK => {
                let w = SpanWord::unpack(d);
                Command::Check { xl: w.xl, xr: w.xr }
            }
            KIND_TILE | KIND_END => Command::ClearLine {
                bg: TILE_BG.get(d) as u32,
            },
            _ => return None,
        })
    }
}

/// A whole frame's command stream for the core, with the geometry needed to place its
/// output.
#[derive(Clone, Debug)]
pub struct CoreStream {
    /// The beats, in order.
    pub beats: Vec<Beat>,
    /// Screen width.
    pub width: u32,
    /// Screen height.
    pub height: u32,
    /// Array width `N`.
    pub array_width: u32,
    /// TABLE beats at the start.
    pub table_beats: usize,
}

impl CoreStream {
    /// The binned stream of `s` for an array of `n` processors, with the shading table
    /// `table` (shadows) first.
    pub fn of_scene(
        s: &SceneStream,
        n: usize,
        table: Option<&FactorTable>,
    ) -> Result<CoreStream, CoreError> {
        Self::build(s, n, table)
    }

    fn build(
        s: &SceneStream,
        n: usize,
        table: Option<&FactorTable>,
    ) -> Result<CoreStream, CoreError> {
        if n == 0 || n > pixelproc_formats::MAX_SCREEN as usize {
            return Err(CoreError::Width(n));
        }
        let mut beats = Vec::new();
        if let Some(t) = table {
            beats.extend(table_beats(t)?);
        }
        let table_beats = beats.len();
        let (w, h, nn) = (s.width(), s.height(), n as u32);
        for j in 0..h {
            for base in (0..w).step_by(n) {
                beats.push(tile_beat(s, j, base, nn));
                for c in &s.tile(j, base, nn)[1..] {
                    beats.push(Beat::of_command(c)?);
                }
            }
        }
        beats.push(Beat::with_fields(
            KIND_END,
            &[(TILE_BG, s.bg_packed() as u64)],
        ));
        Ok(CoreStream {
            beats,
            width: w,
            height: h,
            array_width: nn,
            table_beats,
        })
    }

    /// Pixels the frame streams out (`width × height`).
    pub fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Screen position of the `k`-th output pixel: tile-lines in row order, tiles left
    /// to right, processors in order, which is row-major order.
    pub fn position(&self, k: usize) -> (u32, u32) {
        let w = self.width as usize;
        ((k % w) as u32, (k / w) as u32)
    }
}

/// The TILE beat of row `j`'s tile at column `base` on an `n`-processor array.
fn tile_beat(s: &SceneStream, j: u32, base: u32, n: u32) -> Beat {
    let last = (s.width() - base).min(n) - 1;
    Beat::with_fields(
        KIND_TILE,
        &[
            (TILE_BG, s.bg_packed() as u64),
            (TILE_BASE, base as u64),
            (TILE_LAST, last as u64),
            (TILE_SOF, (j == 0 && base == 0) as u64),
        ],
    )
}

/// The model's cycles, with no stalls, for the same frame **unbinned**: every tile fed its
/// whole row (what a source without the golden model's binning would send). The stream is
/// generated row by row, never held whole.
pub fn unbinned_cycles(
    s: &SceneStream,
    n: usize,
    table: Option<&FactorTable>,
    debug: bool,
    in_abits: u32,
) -> Result<FrameCycles, CoreError> {
    let mut m = CoreModel::new(n, table.is_some(), debug, in_abits)?;
    let (w, h, nn) = (s.width(), s.height(), n as u32);
    let head = match table {
        Some(t) => table_beats(t)?,
        None => Vec::new(),
    };
    // Every command converts (the same check the binned stream makes), so the lazy
    // conversion below drops none.
    for j in 0..h {
        for c in s.row(j) {
            Beat::of_command(&c)?;
        }
    }
    let row_beats = |j: u32| -> Vec<Beat> {
        s.row(j)
            .iter()
            .filter_map(|c| Beat::of_command(c).ok())
            .collect()
    };
    let beats = head.into_iter().chain((0..h).flat_map(move |j| {
        let body = row_beats(j);
        (0..w)
            .step_by(n)
            .flat_map(move |base| std::iter::once(tile_beat(s, j, base, nn)).chain(body.clone()))
    }));
    let beats = beats.chain(std::iter::once(Beat::with_fields(
        KIND_END,
        &[(TILE_BG, s.bg_packed() as u64)],
    )));
    let pixels = w as usize * h as usize;
    let max = 1u64 << 40;
    run_frame_iter(&mut m, beats, pixels, &mut Stalls::new(1, 0, 0), max)
        .map(|r| r.cycles)
        .ok_or(CoreError::Width(n))
}

/// The TABLE beats of a factor table; an error if it does not fit the core's address.
pub fn table_beats(t: &FactorTable) -> Result<Vec<Beat>, CoreError> {
    if t.mask_bits() > SHADE_MASK_BITS as u32 {
        return Err(CoreError::TooManyLights(t.mask_bits()));
    }
    if t.counts() > 1 << SHADE_COUNT_BITS {
        return Err(CoreError::TooManySamples(t.counts() - 1));
    }
    Ok(t.entries()
        .map(|(nclass, mask, cnt, f)| {
            Beat::with_fields(
                KIND_TABLE,
                &[
                    (TABLE_ADDR, shade_addr(nclass, mask, cnt) as u64),
                    (TABLE_FACTOR, f as u64),
                ],
            )
        })
        .collect())
}

/// One pixel on the output stream.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelBeat {
    /// RGB888 (`m_axis_tdata`).
    pub rgb: u32,
    /// `m_axis_tuser` ([`OUT_USER_FIELDS`]).
    pub user: u64,
    /// `m_axis_tlast`.
    pub last: bool,
}

impl PixelBeat {
    /// The debug fields as a processor state (RGB taken from `tdata`).
    pub fn state(&self) -> ProcState {
        let u = [self.user, 0, 0, 0];
        ProcState {
            zb: OUT_ZB.get(&u) as u32,
            rgb: self.rgb,
            dsf: OUT_DSF.get(&u) == 1,
            fsf: OUT_FSF.get(&u) == 1,
            count: OUT_COUNT.get(&u) as u8,
            mask: OUT_MASK.get(&u) as u8,
            nclass: OUT_NCLASS.get(&u) as u8,
        }
    }

    /// The start-of-frame bit.
    pub fn sof(&self) -> bool {
        self.user & 1 == 1
    }
}

/// The RTL's first-word-fall-through FIFO (`pixelproc_rtl::stream_fifo`), register for
/// register: write and read pointers of `abits + 1` bits, the head-valid flag, the RAM.
#[derive(Clone, Debug)]
pub struct Fifo<T: Copy + Default> {
    abits: u32,
    wr: u32,
    rd: u32,
    dv: bool,
    mem: Vec<T>,
}

impl<T: Copy + Default> Fifo<T> {
    /// An empty FIFO of `2^abits` entries.
    pub fn new(abits: u32) -> Fifo<T> {
        Fifo {
            abits,
            wr: 0,
            rd: 0,
            dv: false,
            mem: vec![T::default(); 1 << abits],
        }
    }
    fn pmask(&self) -> u32 {
        (2 << self.abits) - 1
    }
    /// Entries held (`wr − rd + dv`).
    pub fn level(&self) -> u32 {
        (self.wr.wrapping_sub(self.rd).wrapping_add(self.dv as u32)) & self.pmask()
    }
    /// `in_ready`.
    pub fn in_ready(&self, rst: bool) -> bool {
        !rst && self.level() != 1 << self.abits
    }
    /// The head entry, when `out_valid`.
    pub fn head(&self) -> Option<T> {
        self.dv
            .then(|| self.mem[(self.rd.wrapping_sub(1) & ((1 << self.abits) - 1)) as usize])
    }
    /// `(wr, rd, dv)`, as the RTL probe reads them.
    pub fn regs(&self) -> (u32, u32, bool) {
        (self.wr, self.rd, self.dv)
    }
    /// One rising edge: `push` is written if `in_ready`, the head is popped if `pop` and
    /// `out_valid`. Returns whether `push` was taken.
    pub fn edge(&mut self, push: Option<T>, pop: bool, rst: bool) -> bool {
        let pop = self.dv && pop;
        let fetch = self.wr != self.rd && (!self.dv || pop);
        let taken = push.is_some() && self.in_ready(rst);
        if fetch {
            self.rd = (self.rd + 1) & self.pmask();
        }
        self.dv = fetch || (self.dv && !pop);
        if let (Some(v), true) = (push, taken) {
            let a = (self.wr & ((1 << self.abits) - 1)) as usize;
            self.mem[a] = v;
            self.wr = (self.wr + 1) & self.pmask();
        }
        if rst {
            (self.wr, self.rd, self.dv) = (0, 0, false);
        }
        taken
    }
}

/// A readout job: the tile-line being streamed out.
#[derive(Clone, Debug, Default)]
struct Job {
    valid: bool,
    wait: u32,
    last: u32,
    sof: bool,
    addr: u32,
    line: Vec<ProcState>,
}

/// A pixel in the readout pipeline: tracking flags and its value.
#[derive(Clone, Copy, Debug, Default)]
struct Track {
    flags: u8,
    px: ProcState,
    factor: u32,
}

/// The core's inputs before one rising edge.
#[derive(Clone, Copy, Debug, Default)]
pub struct CoreInputs {
    /// `rst`.
    pub rst: bool,
    /// `s_axis_tvalid`.
    pub s_valid: bool,
    /// `s_axis_tdata`/`tuser`.
    pub s_beat: Beat,
    /// `m_axis_tready`.
    pub m_ready: bool,
}

/// The core's outputs before one rising edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoreOutputs {
    /// `s_axis_tready`.
    pub s_ready: bool,
    /// `m_axis_tvalid`.
    pub m_valid: bool,
    /// The pixel on `m_axis_*` when `m_valid`.
    pub m_pixel: PixelBeat,
    /// `proto_err`.
    pub err: bool,
    /// The head beat was held back by the readout hazard this clock.
    pub hazard_stall: bool,
    /// The array received a command this clock (`cmd_valid`).
    pub issued: bool,
}

/// The core, cycle by cycle (see the module header).
#[derive(Clone, Debug)]
pub struct CoreModel {
    n: u32,
    shadows: bool,
    debug: bool,
    in_fifo: Fifo<Beat>,
    out_fifo: Fifo<PixelBeat>,
    array: PixelArray,
    base: u32,
    pending: (bool, u32, bool),
    job: Job,
    track: [Track; 3],
    s1: Track,
    s2: Track,
    inflight: u32,
    err: bool,
    table: Vec<u16>,
    /// A pixel reached a full output FIFO (the credit logic failed): never in a correct
    /// design; the testbenches check it.
    pub overflow: bool,
}

impl CoreModel {
    /// The core after reset: `n` processors, shading iff `shadows`, debug fields iff
    /// `debug`, an input FIFO of `2^in_abits` beats.
    pub fn new(n: usize, shadows: bool, debug: bool, in_abits: u32) -> Result<Self, CoreError> {
        if n == 0 || n > pixelproc_formats::MAX_SCREEN as usize {
            return Err(CoreError::Width(n));
        }
        Ok(CoreModel {
            n: n as u32,
            shadows,
            debug,
            in_fifo: Fifo::new(in_abits),
            out_fifo: Fifo::new(OUT_FIFO_ABITS),
            array: PixelArray::new(n, 0),
            base: 0,
            pending: (false, 0, false),
            job: Job::default(),
            track: [Track::default(); 3],
            s1: Track::default(),
            s2: Track::default(),
            inflight: 0,
            err: false,
            table: vec![0; 1 << SHADE_ADDR_BITS],
            overflow: false,
        })
    }

    /// The control registers, as the RTL probe reads them.
    pub fn regs(&self) -> CoreRegs {
        CoreRegs {
            in_fifo: self.in_fifo.regs(),
            out_fifo: self.out_fifo.regs(),
            base: self.base,
            pending: self.pending,
            job: (
                self.job.valid,
                self.job.wait,
                self.job.last,
                self.job.sof,
                self.job.addr,
            ),
            track: [
                self.track[0].flags,
                self.track[1].flags,
                self.track[2].flags,
            ],
            inflight: self.inflight,
            err: self.err,
        }
    }

    /// Input FIFO occupancy.
    pub fn in_level(&self) -> u32 {
        self.in_fifo.level()
    }

    /// The output beat of a shaded pixel.
    fn pixel_beat(&self, t: &Track) -> PixelBeat {
        let p = &t.px;
        let mut u = [((t.flags >> 2) & 1) as u64, 0, 0, 0];
        if self.debug {
            OUT_ZB.put(&mut u, p.zb as u64);
            OUT_DSF.put(&mut u, p.dsf as u64);
            OUT_FSF.put(&mut u, p.fsf as u64);
            OUT_COUNT.put(&mut u, p.count as u64);
            OUT_MASK.put(&mut u, p.mask as u64);
            OUT_NCLASS.put(&mut u, p.nclass as u64);
        }
        PixelBeat {
            rgb: shade_rgb(p.rgb, t.factor),
            user: u[0],
            last: t.flags & 2 != 0,
        }
    }

    /// One rising edge with inputs `inp`; returns the outputs shown before it.
    pub fn step(&mut self, inp: &CoreInputs) -> CoreOutputs {
        let rst = inp.rst;
        // ---- Combinational outputs from the registers.
        let head = self.in_fifo.head();
        let kind = head.map(|b| b.kind as u64).unwrap_or(KIND_NOP);
        let frame = kind == KIND_TILE || kind == KIND_END;
        let arr = kind < 8
            && kind != pixelproc_formats::opcodes::OP_CLEAR_LINE
            && kind != pixelproc_formats::opcodes::OP_RESET;
        let table = kind == KIND_TABLE;
        let can = !(rst || frame && self.job.valid);
        let issue = head.is_some() && can;
        let credit = self.out_fifo.level() + self.inflight < 1 << OUT_FIFO_ABITS;
        let go = self.job.valid && self.job.wait == 0 && credit;
        let out = CoreOutputs {
            s_ready: self.in_fifo.in_ready(rst),
            m_valid: self.out_fifo.head().is_some(),
            m_pixel: self.out_fifo.head().unwrap_or_default(),
            err: self.err,
            hazard_stall: head.is_some() && !can && !rst,
            issued: issue && (arr || frame),
        };
        // ---- The edge.
        let old_table_factor = |t: &Track, tab: &[u16], shadows: bool| -> u32 {
            if !shadows || t.px.zb == Z_FAR {
                256
            } else {
                tab[shade_addr(t.px.nclass, t.px.mask, t.px.count) as usize
                    & ((1 << SHADE_ADDR_BITS) - 1)] as u32
            }
        };
        // Readout pipeline: t1 <- go, t2 <- t1, t3 <- t2, s1 <- t3 (+ table read), s2 <- s1.
        let s2_out = self.s2;
        let mut s1_new = self.track[2];
        s1_new.factor = old_table_factor(&s1_new, &self.table, self.shadows);
        let mut t1_new = Track::default();
        if go {
            let a = self.job.addr;
            t1_new.flags =
                1 | ((a == self.job.last) as u8) << 1 | ((a == 0 && self.job.sof) as u8) << 2;
            t1_new.px = self.job.line.get(a as usize).copied().unwrap_or_default();
        }
        // Output FIFO: the shaded pixel in s2 goes in.
        let push = (s2_out.flags & 1 != 0).then(|| self.pixel_beat(&s2_out));
        if push.is_some() && !self.out_fifo.in_ready(rst) {
            self.overflow |= !rst;
            self.err = true;
        }
        self.out_fifo.edge(push, inp.m_ready, rst);
        // Inflight count.
        match (go, push.is_some()) {
            (true, false) => self.inflight += 1,
            (false, true) => self.inflight -= 1,
            _ => {}
        }
        self.s2 = self.s1;
        self.s1 = s1_new;
        self.track = [t1_new, self.track[0], self.track[1]];
        // Job wait and sweep.
        if self.job.valid && self.job.wait != 0 {
            self.job.wait -= 1;
        }
        if go {
            if self.job.addr == self.job.last {
                self.job.valid = false;
            }
            self.job.addr = (self.job.addr + 1) & 0xFFF;
        }
        // Issue the head beat.
        if issue {
            let b = head.unwrap_or_default();
            if arr || frame {
                if frame {
                    let d = &b.data;
                    if kind == KIND_TILE {
                        self.base = TILE_BASE.get(d) as u32;
                        if TILE_LAST.get(d) as u32 > self.n - 1 {
                            self.err = true;
                        }
                    }
                    if self.pending.0 {
                        self.job = Job {
                            valid: true,
                            wait: READOUT_WAIT,
                            last: self.pending.1,
                            sof: self.pending.2,
                            addr: 0,
                            line: self.array.state().to_vec(),
                        };
                    }
                    self.pending = (
                        kind == KIND_TILE,
                        TILE_LAST.get(d) as u32,
                        TILE_SOF.get(d) == 1,
                    );
                    self.array.set_base(self.base);
                }
                if let Some(c) = b.command() {
                    self.array.step(&c);
                }
            } else if table {
                if self.shadows {
                    let a = TABLE_ADDR.get(&b.data) as usize & ((1 << SHADE_ADDR_BITS) - 1);
                    self.table[a] = TABLE_FACTOR.get(&b.data) as u16;
                }
            } else {
                self.err = true;
            }
        }
        // Input FIFO.
        self.in_fifo
            .edge(inp.s_valid.then_some(inp.s_beat), issue, rst);
        if rst {
            self.pending.0 = false;
            self.job.valid = false;
            self.job.wait = 0;
            self.job.addr = 0;
            self.track = [Track::default(); 3];
            self.s1.flags = 0;
            self.s2.flags = 0;
            self.inflight = 0;
            self.err = false;
            self.base = 0;
            self.array = PixelArray::new(self.n as usize, 0);
        }
        out
    }
}

/// Random stalls on both streams: the source leaves a gap with probability
/// `gap_pct`%, the sink drops `tready` with probability `stall_pct`%, from one seeded
/// xorshift64* sequence (two draws per clock: source, then sink). A source never takes
/// back a beat it offers (AXI4-Stream): once `tvalid` is up it stays up until taken.
#[derive(Clone, Debug)]
pub struct Stalls {
    rng: XorShift64Star,
    gap_pct: u64,
    stall_pct: u64,
    offered: bool,
}

impl Stalls {
    /// Stall pattern from `seed` (0 is replaced by 1) with the two percentages.
    pub fn new(seed: u64, gap_pct: u32, stall_pct: u32) -> Stalls {
        Stalls {
            rng: XorShift64Star(seed.max(1)),
            gap_pct: gap_pct.min(100) as u64,
            stall_pct: stall_pct.min(100) as u64,
            offered: false,
        }
    }

    /// The source's `tvalid` (given it has a beat) and the sink's `tready` for this clock.
    pub fn next(&mut self, have_beat: bool) -> (bool, bool) {
        let a = self.rng.next_u64() % 100;
        let b = self.rng.next_u64() % 100;
        let valid = have_beat && (self.offered || a >= self.gap_pct);
        self.offered = valid;
        (valid, b >= self.stall_pct)
    }

    /// Tell the pattern the offered beat was taken.
    pub fn taken(&mut self) {
        self.offered = false;
    }
}

/// Cycle accounting of one frame through the model.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FrameCycles {
    /// Clocks from the first beat offered to the last pixel taken.
    pub cycles: u64,
    /// Beats sent.
    pub beats: u64,
    /// Clocks the source offered a beat and the core was not ready.
    pub in_stall: u64,
    /// Clocks the head beat waited for a readout to finish (the core stalling itself).
    pub hazard_stall: u64,
    /// Clocks a pixel was offered and the sink was not ready.
    pub out_stall: u64,
    /// Clocks the array received a command.
    pub issued: u64,
}

/// What a frame through the model produced.
#[derive(Clone, Debug)]
pub struct FrameRun {
    /// Output pixels, in stream order.
    pub pixels: Vec<PixelBeat>,
    /// Cycle accounting.
    pub cycles: FrameCycles,
    /// `proto_err` at the end.
    pub err: bool,
    /// The credit logic let a pixel reach a full FIFO.
    pub overflow: bool,
}

/// Runs a whole frame through the model: one reset clock, then the stream with the
/// stall pattern, until `expect_pixels` pixels are out (or `max_cycles`, then `None`).
pub fn run_frame(
    m: &mut CoreModel,
    beats: &[Beat],
    expect_pixels: usize,
    stalls: &mut Stalls,
    max_cycles: u64,
) -> Option<FrameRun> {
    run_frame_iter(m, beats.iter().copied(), expect_pixels, stalls, max_cycles)
}

/// [`run_frame`] with the beats from an iterator (a stream too large to hold).
pub fn run_frame_iter(
    m: &mut CoreModel,
    beats: impl Iterator<Item = Beat>,
    expect_pixels: usize,
    stalls: &mut Stalls,
    max_cycles: u64,
) -> Option<FrameRun> {
    let mut beats = beats.peekable();
    m.step(&CoreInputs {
        rst: true,
        ..Default::default()
    });
    let mut pixels = Vec::with_capacity(expect_pixels);
    let mut c = FrameCycles::default();
    while pixels.len() < expect_pixels {
        if c.cycles >= max_cycles {
            return None;
        }
        let head = beats.peek().copied();
        let (valid, ready) = stalls.next(head.is_some());
        let inp = CoreInputs {
            rst: false,
            s_valid: valid,
            s_beat: head.unwrap_or_default(),
            m_ready: ready,
        };
        let o = m.step(&inp);
        c.cycles += 1;
        if valid && o.s_ready {
            beats.next();
            c.beats += 1;
            stalls.taken();
        }
        c.in_stall += (valid && !o.s_ready) as u64;
        c.hazard_stall += o.hazard_stall as u64;
        c.out_stall += (o.m_valid && !ready) as u64;
        c.issued += o.issued as u64;
        if o.m_valid && ready {
            pixels.push(o.m_pixel);
        }
    }
    Some(FrameRun {
        pixels,
        cycles: c,
        err: m.err,
        overflow: m.overflow,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{Effects, Overrides};
    use crate::scene::load_builtin;

    fn small_default() -> (crate::scene::LoadedScene, Effects) {
        let mut ls = load_builtin("default").unwrap();
        ls.scene.width = 40;
        ls.scene.height = 12;
        let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
        (ls, fx)
    }

    /// The model's output, placed by stream order, is the renderer's no-AA image and
    /// final per-pixel state, under stalls on both sides and with N not dividing the
    /// width; and with an idle sink the output FIFO never overflows.
    #[test]
    fn model_frames_equal_the_rendered_frame() {
        let (ls, fx) = small_default();
        let golden = crate::pipeline::render(&ls, &fx).unwrap();
        let frame = golden.frame.unwrap();
        let s = SceneStream::of_scene(&ls, &fx.shadow_lights, fx.shadow_form).unwrap();
        let lights = crate::shadow::shadow_lights(&ls, &fx.shadow_lights).unwrap();
        let table = FactorTable::new(&ls, &lights);
        for (n, gap, stall) in [(16usize, 0, 0), (16, 30, 40), (7, 50, 50), (64, 10, 80)] {
            let cs = CoreStream::of_scene(&s, n, Some(&table)).unwrap();
            let mut m = CoreModel::new(n, true, true, 3).unwrap();
            let mut st = Stalls::new(42, gap, stall);
            let run = run_frame(&mut m, &cs.beats, cs.pixels(), &mut st, 10_000_000).unwrap();
            assert!(!run.err && !run.overflow);
            for (k, p) in run.pixels.iter().enumerate() {
                let (x, y) = cs.position(k);
                let i = (y * cs.width + x) as usize;
                let g = &golden.image.data[3 * i..3 * i + 3];
                assert_eq!(
                    pixelproc_formats::unpack_rgb(p.rgb),
                    [g[0], g[1], g[2]],
                    "N {n} pixel ({x}, {y})"
                );
                assert_eq!(p.state(), frame.px[i], "N {n} pixel ({x}, {y})");
                assert_eq!(p.sof(), k == 0);
                assert_eq!(p.last, x == cs.width - 1 || (x + 1) % n as u32 == 0);
            }
        }
    }
}
