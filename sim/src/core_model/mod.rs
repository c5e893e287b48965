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
//! then an END beat. [`unbinned_cycles`] times feeding every tile the whole row instead (the
//! old array testbench's stream), to show what binning saves.
//!
//! **The model** ([`CoreModel::step`]): one call per rising edge, with the values on the
//! core's inputs before the edge; it returns the outputs the core showed before the edge
//! (so `s_ready`/`m_valid` are the handshake of that edge) and applies the edge. The
//! array inside is the golden [`PixelArray`]: commands take effect when issued, and a
//! tile-line's pixels are the array state at the TILE or END that ends it. That is what
//! the RTL sweep reads, because its timing ([`READOUT_WAIT`]) is chosen so that every
//! read follows the CLEAR_LINE wavefront (proof in `pixelproc_rtl::core_top`). A TABLE
//! write lands one edge after its beat issues ([`TABLE_WRITE_DELAY`]: the shading step
//! registers it on its way to the block RAMs), after that edge's table read.

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
    /// Exact shading with more shadowing lights than the core's shade registers.
    #[error("exact shading of {0} shadowing lights needs {0} shade registers per processor; the core has 1 (use --shading table, or one shadowing light)")]
    TooManyChannels(usize),
    /// A span word does not fit its fields.
    #[error(transparent)]
    Field(#[from] FieldRangeError),
    /// A CHECK range beyond the span word's columns.
    #[error("a CHECK range {0}..={1} does not fit the span word")]
    Check(u16, u16),
}

mod fifo;
mod model;
mod run;
mod stream;

pub use fifo::Fifo;
pub use model::{CoreInputs, CoreModel, CoreOutputs};
pub use run::{run_frame, run_frame_iter, FrameCycles, FrameRun, Stalls};
pub use stream::{table_beats, unbinned_cycles, Beat, CoreStream, PixelBeat};

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
        let s = SceneStream::of_scene(&ls, &fx.shadow_lights, fx.shadow_form, fx.shading).unwrap();
        let lights = crate::shadow::shadow_lights(&ls, &fx.shadow_lights).unwrap();
        let table = FactorTable::for_mode(&ls, &lights, fx.shading);
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
                assert_eq!(
                    p.state(),
                    frame.px[i].without_shade_channel(),
                    "N {n} pixel ({x}, {y})"
                );
                assert_eq!(p.sof(), k == 0);
                assert_eq!(p.last, x == cs.width - 1 || (x + 1) % n as u32 == 0);
            }
        }
    }
}
