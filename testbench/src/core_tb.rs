//! The RustHDL core (`pixelproc_rtl::core_top::PixelprocCore`) against its cycle-level
//! golden model (`pixelproc_sim::core_model::CoreModel`), clock by clock: the same
//! inputs (a frame's command stream with seeded random gaps, random output
//! back-pressure) go into both, and after every rising edge every control register
//! (both FIFOs' pointers, the tile and readout-job registers, the readout pipeline's
//! tracking flags, the in-flight count, the error flag) and, before every edge, every
//! output port (`s_axis_tready`, `m_axis_tvalid`, `m_axis_tdata`, `m_axis_tuser`,
//! `m_axis_tlast`, `proto_err`) must agree. The pixels collected are then placed into
//! the frame and compared with the golden renderer's image by the caller.

use crate::TbError;
use pixelproc_formats::core_stream::CoreRegs;
use pixelproc_rtl::core_top::PixelprocCore;
use pixelproc_sim::core_model::{
    Beat, CoreInputs, CoreModel, CoreOutputs, FrameCycles, PixelBeat, Stalls,
};
use rust_hdl::prelude::*;

/// The core the RustHDL comparison builds: an 8-beat input FIFO, so that back-pressure
/// reaches the source often.
pub type SmallCore = PixelprocCore<3, 4>;
/// Input FIFO address bits of [`SmallCore`].
pub const SMALL_IN_ABITS: u32 = 3;

/// The first disagreement between the RustHDL core and the model.
#[derive(Clone, Debug)]
pub struct CoreMismatch {
    /// Rising edges before the disagreement (0 = the reset edge).
    pub cycle: u64,
    /// What differed.
    pub what: String,
}

/// Outcome of a clock-by-clock core run.
#[derive(Clone, Debug)]
pub struct CoreComparison {
    /// Pixels taken from the RTL's output stream, in order, each with the clock it was
    /// taken on (edges after reset, from 0).
    pub pixels: Vec<(PixelBeat, u64)>,
    /// Cycle accounting (from the model; the RTL agreed on every clock).
    pub cycles: FrameCycles,
    /// The first disagreement, if any.
    pub mismatch: Option<CoreMismatch>,
    /// Wall seconds.
    pub seconds: f64,
}

fn set_beat<const IA: usize, const IA1: usize>(u: &mut PixelprocCore<IA, IA1>, b: &Beat) {
    let mut d: Bits<256> = Bits::default();
    for (i, limb) in b.data.iter().enumerate() {
        d.set_bits::<64>(64 * i, limb.to_bits());
    }
    u.s_axis_tdata.next = d;
    u.s_axis_tuser.next = (b.kind as u64).to_bits();
}

fn outputs<const IA: usize, const IA1: usize>(u: &PixelprocCore<IA, IA1>) -> CoreOutputs {
    CoreOutputs {
        s_ready: u.s_axis_tready.val(),
        m_valid: u.m_axis_tvalid.val(),
        m_pixel: PixelBeat {
            rgb: u.m_axis_tdata.val().to_u32(),
            user: u.m_axis_tuser.val().to_u64(),
            last: u.m_axis_tlast.val(),
        },
        err: u.proto_err.val(),
        hazard_stall: false,
        issued: false,
    }
}

/// The parts of the model's outputs the RTL ports show (the pixel only when valid).
fn visible(o: &CoreOutputs) -> CoreOutputs {
    CoreOutputs {
        m_pixel: if o.m_valid {
            o.m_pixel
        } else {
            PixelBeat::default()
        },
        hazard_stall: false,
        issued: false,
        ..*o
    }
}

/// Runs `beats` through the RustHDL core `uut` and the model `model` side by side until
/// `expect_pixels` pixels are out (or `max_cycles`), comparing every clock.
pub fn compare_core<const IA: usize, const IA1: usize>(
    uut: &mut PixelprocCore<IA, IA1>,
    model: &mut CoreModel,
    beats: &[Beat],
    expect_pixels: usize,
    stalls: &mut Stalls,
    max_cycles: u64,
) -> Result<CoreComparison, TbError> {
    let t0 = std::time::Instant::now();
    let mut next = 0usize;
    let mut pixels = Vec::with_capacity(expect_pixels);
    let mut c = FrameCycles {
        beats: beats.len() as u64,
        ..Default::default()
    };
    let mut mismatch = None;
    let mut cycle = 0u64;
    let mut first = true;
    while pixels.len() < expect_pixels {
        if cycle > max_cycles {
            mismatch = Some(CoreMismatch {
                cycle,
                what: format!(
                    "no progress: {} of {expect_pixels} pixels after {max_cycles} cycles",
                    pixels.len()
                ),
            });
            break;
        }
        let inp = if first {
            CoreInputs {
                rst: true,
                ..Default::default()
            }
        } else {
            let (valid, ready) = stalls.next(next < beats.len());
            CoreInputs {
                rst: false,
                s_valid: valid,
                s_beat: beats.get(next).copied().unwrap_or_default(),
                m_ready: ready,
            }
        };
        uut.rst.next = inp.rst;
        uut.s_axis_tvalid.next = inp.s_valid;
        set_beat(uut, &inp.s_beat);
        uut.m_axis_tready.next = inp.m_ready;
        if !simulate(uut, 200) {
            return Err(TbError::NoConvergence);
        }
        let got = outputs(uut);
        let want = model.step(&inp);
        crate::sim_tools::clock_cycle(uut, |u| &mut u.clock)?;
        if visible(&want) != visible(&got) {
            mismatch = Some(CoreMismatch {
                cycle,
                what: format!("outputs before the edge: golden {want:?}, rtl {got:?}"),
            });
            break;
        }
        let (g, r): (CoreRegs, CoreRegs) = (model.regs(), uut.probe());
        if g != r {
            mismatch = Some(CoreMismatch {
                cycle,
                what: format!("registers after the edge: golden {g:?}, rtl {r:?}"),
            });
            break;
        }
        if model.overflow {
            mismatch = Some(CoreMismatch {
                cycle,
                what: "a pixel reached a full output FIFO".into(),
            });
            break;
        }
        if !first {
            c.cycles += 1;
            if inp.s_valid && got.s_ready {
                next += 1;
                stalls.taken();
            }
            c.in_stall += (inp.s_valid && !got.s_ready) as u64;
            c.hazard_stall += want.hazard_stall as u64;
            c.out_stall += (got.m_valid && !inp.m_ready) as u64;
            c.issued += want.issued as u64;
            if got.m_valid && inp.m_ready {
                pixels.push((got.m_pixel, c.cycles - 1));
            }
        }
        first = false;
        cycle += 1;
    }
    Ok(CoreComparison {
        pixels,
        cycles: c,
        mismatch,
        seconds: t0.elapsed().as_secs_f64(),
    })
}
