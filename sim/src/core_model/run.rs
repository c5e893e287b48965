//! Whole frames through the model: the seeded stall pattern and the cycle accounting.

use super::*;

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
