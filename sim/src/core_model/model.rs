//! The core's controller, register for register: readout jobs, the readout pipeline,
//! the shading step, one rising edge per [`CoreModel::step`].

use super::*;

// `table_write` holds one write: the model's delay is one edge.
const _: () = assert!(TABLE_WRITE_DELAY == 1);

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
    drop: u32,
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
    /// The shading step's stages: `s[0]` holds the pixel as it arrived, `s[1]` the pixel
    /// and its table entry (read as it enters), the last stage's pixel goes to the output
    /// FIFO.
    s: [Track; SHADE_STAGES],
    inflight: u32,
    pub(super) err: bool,
    table: Vec<(u16, u16)>,
    /// The TABLE write issued at the last edge (address, entry): the shading step's write
    /// registers hold it for one edge (`TABLE_WRITE_DELAY`), and it lands in the table at
    /// the next edge, after that edge's table read.
    table_write: Option<(usize, (u16, u16))>,
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
            s: [Track::default(); SHADE_STAGES],
            inflight: 0,
            err: false,
            table: vec![(0, 0); 1 << SHADE_ADDR_BITS],
            table_write: None,
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
            rgb: shade_rgb(p.rgb, p.sh, t.factor, t.drop),
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
        let old_table_entry = |t: &Track, tab: &[(u16, u16)], shadows: bool| -> (u32, u32) {
            if !shadows || t.px.zb == Z_FAR {
                (256, 0)
            } else {
                let (f, g) = tab[shade_addr(t.px.nclass, t.px.mask, t.px.count) as usize
                    & ((1 << SHADE_ADDR_BITS) - 1)];
                (f as u32, g as u32)
            }
        };
        // Readout pipeline: t1 <- go, t2 <- t1, t3 <- t2, s[0] <- t3, s[1] <- s[0] (+ table
        // read), s[k] <- s[k − 1].
        let s2_out = self.s[SHADE_STAGES - 1];
        let mut s1_new = self.s[0];
        (s1_new.factor, s1_new.drop) = old_table_entry(&s1_new, &self.table, self.shadows);
        // The TABLE write issued at the last edge lands now, after the read: a write issued
        // at edge E is seen by table reads at E + 2 and later (reset does not cancel it).
        if let Some((a, e)) = self.table_write.take() {
            self.table[a] = e;
        }
        let mut t1_new = Track::default();
        if go {
            let a = self.job.addr;
            t1_new.flags =
                1 | ((a == self.job.last) as u8) << 1 | ((a == 0 && self.job.sof) as u8) << 2;
            t1_new.px = self.job.line.get(a as usize).copied().unwrap_or_default();
        }
        // Output FIFO: the shaded pixel in the last stage goes in.
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
        self.s.copy_within(0..SHADE_STAGES - 1, 1);
        self.s[1] = s1_new;
        self.s[0] = self.track[2];
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
                    self.table_write = Some((
                        a,
                        (
                            TABLE_FACTOR.get(&b.data) as u16,
                            TABLE_DROP.get(&b.data) as u16,
                        ),
                    ));
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
            for t in self.s.iter_mut() {
                t.flags = 0;
            }
            self.inflight = 0;
            self.err = false;
            self.base = 0;
            self.array = PixelArray::new(self.n as usize, 0);
        }
        out
    }
}
