//! The stream search units in RustHDL's direct `simulate` loop, with the traffic and the
//! checks of the Verilog stream testbench ([`super::stream`]). For short streams: the
//! result words are wider than 128 bits, so each clock costs big-integer arithmetic.

use super::stream::{mismatch_detail, StreamSummary, StreamWords, Traffic, Word};
use crate::TbError;
use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use pixelproc_rtl::mask_search::{
    MaskSearchIterStream4x4, MaskSearchIterStream8x8, MaskSearchPipeStream4x4,
    MaskSearchPipeStream8x8, Variant,
};
use rust_hdl::prelude::*;

/// `w` as a `Bits<N>`.
fn to_bits<const N: usize>(w: &Word) -> Bits<N> {
    let mut b = Bits::<N>::default();
    for (i, &l) in w.0.iter().enumerate() {
        if 64 * i < N {
            b = b | (bit_cast::<N, 64>(l.to_bits()) << (64 * i as u64));
        }
    }
    b
}

/// `b` as a [`Word`].
fn from_bits<const N: usize>(b: Bits<N>) -> Word {
    Word(
        (0..N.div_ceil(64))
            .map(|i| bit_cast::<64, N>(b >> (64 * i as u64)).to_u64())
            .collect(),
    )
}

/// The loop over one stream unit type.
macro_rules! stream_loop {
    ($ty:ty, $words:expr, $size:expr, $seed:expr, $s:expr) => {{
        let words: &StreamWords = $words;
        let s: &mut StreamSummary = $s;
        let mut u =
            <$ty>::new($size, SearchFamily::DIAGONAL).map_err(|e| TbError::Sim(e.to_string()))?;
        u.connect_all();
        let clock = |u: &mut $ty| crate::sim_tools::clock_cycle(u, |u| &mut u.clock);
        let n = words.input.len();
        let t0 = std::time::Instant::now();
        u.rst.next = true;
        clock(&mut u)?;
        clock(&mut u)?;
        u.rst.next = false;
        let mut traffic = Traffic::new($seed);
        let (mut sent, mut got, mut cyc) = (0usize, 0usize, 0u64);
        let mut held: Option<Word> = None;
        let mut valid_in = false;
        let mut verdict = None;
        while got < n && cyc < 40 * n as u64 + 2000 {
            let (ready, offer) = traffic.step(cyc);
            u.m_tready.next = ready;
            if !valid_in && offer && sent < n {
                valid_in = true;
                u.s_tdata.next = to_bits(&words.input[sent]);
            }
            u.s_tvalid.next = valid_in;
            if !simulate(&mut u, 200) {
                return Err(TbError::NoConvergence);
            }
            let now = from_bits(u.m_tdata.val());
            if let Some(h) = &held {
                if !u.m_tvalid.val() || &now != h {
                    verdict = Some(format!(
                        "UNSTABLE cycle={cyc} results={got}: held result changed or withdrawn"
                    ));
                    break;
                }
            }
            if u.m_tvalid.val() && ready {
                if now != words.expect[got] {
                    verdict = Some(mismatch_detail(got, cyc, &words.expect[got], &now, $size));
                    break;
                }
                got += 1;
            }
            held = (u.m_tvalid.val() && !ready).then_some(now);
            let take = valid_in && u.s_tready.val();
            clock(&mut u)?;
            cyc += 1;
            if take {
                sent += 1;
                valid_in = false;
            }
        }
        if verdict.is_none() && got < n {
            verdict = Some(format!(
                "STUCK cycle={cyc} results={got} sent={sent} of {n}"
            ));
        }
        if verdict.is_none() {
            u.s_tvalid.next = false;
            u.m_tready.next = true;
            for _ in 0..40 {
                if !simulate(&mut u, 200) {
                    return Err(TbError::NoConvergence);
                }
                if u.m_tvalid.val() {
                    verdict = Some(format!("EXTRA cycle={cyc} results={got}"));
                    break;
                }
                clock(&mut u)?;
            }
        }
        s.run_seconds = t0.elapsed().as_secs_f64();
        s.cycles = cyc;
        s.results = got;
        s.identical = verdict.is_none();
        s.detail = verdict.unwrap_or_default();
        Ok(())
    }};
}

/// Runs `words` through `variant`'s stream unit at `size` (4×4 or 8×8) in RustHDL.
pub(crate) fn run(
    words: &StreamWords,
    size: MaskSize,
    variant: Variant,
    seed: u64,
    s: &mut StreamSummary,
) -> Result<(), TbError> {
    match (variant, size.bits()) {
        (Variant::Iterative, 16) => stream_loop!(MaskSearchIterStream4x4, words, size, seed, s),
        (Variant::Iterative, 64) => stream_loop!(MaskSearchIterStream8x8, words, size, seed, s),
        (Variant::Pipelined, 16) => stream_loop!(MaskSearchPipeStream4x4, words, size, seed, s),
        (Variant::Pipelined, 64) => stream_loop!(MaskSearchPipeStream8x8, words, size, seed, s),
        _ => Err(TbError::Sim(format!("no stream unit for {size}"))),
    }
}
