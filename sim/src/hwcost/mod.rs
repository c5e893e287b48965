//! What accuracy costs in hardware: a cycle model per anti-aliasing method, exact where
//! the block has RTL and a stated assumption where it has not.
//!
//! | method | module | exact | stated |
//! |---|---|---|---|
//! | none (the pixel-processor array of seed 001 in the streaming core) | [`array`](mod@array) | cycles: the core's controller timing (`docs/core.md`, "Timing"), equal to [`crate::core_model::CoreModel`]'s count on the same stream | — |
//! | multi-scanning (seed 002 on seed 001's array) | [`multiscan`] | the array's cycles per pass | one pass per sub-scanline; the weighting and the two-row memory |
//! | corner sampling, D3D 4×, ordered 2×2, k×k supersampling (seed 003) | [`sampling`] | the array's cycles per sample row | sample rows per pixel row, samples per row, the row buffer |
//! | post-process (seed 004) | [`postfx`] | the array's frame | a scan-out pass, one pixel per clock, the 5-line window |
//! | A-buffer (seed 000) | [`abuffer`] | the search unit's clocks per fragment ([`crate::mask_search::SearchUnit`], `docs/rtl_mask_search.md`) | fragment generation, packing and resolve, one fragment per clock each |
//!
//! Every model counts integer cycles per frame; [`HwConfig`] turns them into milliseconds
//! and frames per second at a clock. Resources (ECP5 LUT4 and FF) are quoted only for
//! blocks with RTL, from the measured tables ([`Resources`]). [`target`] turns a model
//! around: the clock or the array width a frame rate needs.
//!
//! **Default configuration** ([`HwConfig::DEFAULT`]): `N = 64` processors at 165.21 MHz.
//! 165.21 MHz is the streaming core at `N = 8` without shadows, placed and routed on an
//! ECP5 (`docs/fpga_results/ecp5_n8_noshadow.md`, `docs/fpga.md`); the anti-aliasing
//! methods run without shadows. The test `hwcost_default_clock` reads that report and
//! fails when this constant no longer matches its Fmax. Taking the `N = 8` clock for
//! `N = 64` is an extrapolation, an optimistic one: `N = 64` with shadows routes at
//! 118.43 MHz on pins (`docs/fpga_results/ecp5_n64_pins.md`; 128.35 MHz placed with HeAP's
//! timing weight 40, `docs/fpga_results/ecp5_n64_pins_heap40.md`). With shadows the routed
//! `N = 8` figure is 152.84 MHz (`docs/fpga_results/ecp5_n8.md`).

pub mod abuffer;
pub mod array;
pub mod multiscan;
pub mod postfx;
pub mod sampling;
pub mod target;

use thiserror::Error;

use crate::aa::AaMethod;
use crate::setup::SnappedTri;

/// Why a hardware configuration or a cost cannot be computed.
#[derive(Debug, Error, PartialEq)]
pub enum HwCostError {
    /// The array width is outside `1..=4096` (the core's range).
    #[error("--array-width {0}: the core takes 1..=4096 processors")]
    ArrayWidth(u64),
    /// The clock is not a positive finite frequency up to 2000 MHz.
    #[error("--clock-mhz {0}: expected a frequency above 0 and at most 2000 MHz")]
    Clock(String),
    /// The scene could not be set up or rendered for the model.
    #[error("{0}")]
    Scene(String),
}

/// The hardware a cost is computed for: array width and clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HwConfig {
    /// Processors in the array, `N` (1..=4096).
    pub array_width: u32,
    /// Clock, MHz.
    pub clock_mhz: f64,
}

/// The highest clock [`HwConfig::new`] accepts, MHz (far above anything routed here).
pub const MAX_CLOCK_MHZ: f64 = 2000.0;

impl HwConfig {
    /// `N = 64` at 165.21 MHz, the routed Fmax of the `N = 8` core without shadows
    /// (`docs/fpga_results/ecp5_n8_noshadow.md`): see the module header (an extrapolation
    /// to `N = 64`).
    pub const DEFAULT: HwConfig = HwConfig {
        array_width: 64,
        clock_mhz: 165.21,
    };

    /// A checked configuration: `1 ≤ N ≤ 4096`, `0 < clock ≤ 2000` MHz and finite.
    pub fn new(array_width: u64, clock_mhz: f64) -> Result<HwConfig, HwCostError> {
        if array_width == 0 || array_width > pixelproc_formats::MAX_SCREEN as u64 {
            return Err(HwCostError::ArrayWidth(array_width));
        }
        if !(clock_mhz.is_finite() && clock_mhz > 0.0 && clock_mhz <= MAX_CLOCK_MHZ) {
            return Err(HwCostError::Clock(format!("{clock_mhz}")));
        }
        Ok(HwConfig {
            array_width: array_width as u32,
            clock_mhz,
        })
    }

    /// Milliseconds of `cycles` at this clock.
    pub fn ms(&self, cycles: u64) -> f64 {
        cycles as f64 / (self.clock_mhz * 1e3)
    }

    /// Frames per second when a frame takes `cycles`.
    pub fn fps(&self, cycles: u64) -> f64 {
        self.clock_mhz * 1e6 / cycles.max(1) as f64
    }

    /// Whether the clock is the routed figure this configuration claims: only `N = 8`
    /// was placed and routed.
    pub fn routed(&self) -> bool {
        self.array_width == 8
    }
}

impl Default for HwConfig {
    fn default() -> Self {
        HwConfig::DEFAULT
    }
}

/// ECP5 resources of a block with RTL, from a measured table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resources {
    /// LUT4.
    pub lut4: u64,
    /// Flip-flops.
    pub ff: u64,
    /// Measured as quoted (`true`), or extrapolated from measured figures (`false`).
    pub measured: bool,
    /// Which blocks are counted and where the figures come from.
    pub source: &'static str,
}

/// The cost of one method on one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct HwCost {
    /// Clock cycles per frame.
    pub cycles: u64,
    /// Passes the array makes over the frame's rows: sample rows (or sub-scanlines) per
    /// pixel row, times 1000 (1000 for one pass per row).
    pub passes_per_row_milli: u64,
    /// Samples (or pixels, or fragments) the array or pipeline processes per frame.
    pub samples: u64,
    /// On-chip memory the method adds beyond the core's FIFOs, bits (row buffers, line
    /// windows, accumulation rows); a stated design, no RTL.
    pub extra_memory_bits: u64,
    /// LUT4/FF of the blocks with RTL, if any.
    pub resources: Option<Resources>,
}

/// The scene a cost is computed on: snapped screen-space triangles and the screen size.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Triangles in scene order.
    pub tris: &'a [SnappedTri],
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

/// The hardware cost of `method` on `frame` with `cfg` (the method's own module gives the
/// model and its assumptions). The A-buffer is costed with the pipelined search unit.
pub fn method_cost(
    method: &AaMethod,
    frame: &Frame<'_>,
    cfg: &HwConfig,
) -> Result<HwCost, HwCostError> {
    match method {
        AaMethod::None => array::no_aa_cost(frame, cfg),
        AaMethod::Multiscan(p) => multiscan::cost(frame, cfg, p),
        AaMethod::Corner(p) => sampling::corner_cost(frame, cfg, p),
        AaMethod::Ssaa { k } => sampling::ssaa_cost(frame, cfg, *k),
        AaMethod::PostFx(_) => postfx::cost(frame, cfg),
        AaMethod::Abuffer(p) => abuffer::cost(frame, cfg, p, abuffer::SearchKind::Pipelined),
    }
}

/// `tris` scaled from a `w0`×`h0` screen to `w1`×`h1` (each axis by its own ratio,
/// rounded to the Q8 grid): the same scene drawn at another resolution. Depths, colours
/// and tags are kept (they interpolate linearly, so an affine map keeps the planes).
pub fn rescale(tris: &[SnappedTri], w0: u32, h0: u32, w1: u32, h1: u32) -> Vec<SnappedTri> {
    let sc = |p: [i32; 2]| -> [i32; 2] {
        let f = |v: i32, a: u32, b: u32| -> i32 {
            let n = v as i64 * b as i64;
            let d = a.max(1) as i64;
            (n.div_euclid(d) + (2 * n.rem_euclid(d) >= d) as i64) as i32
        };
        [f(p[0], w0, w1), f(p[1], h0, h1)]
    };
    tris.iter()
        .map(|t| {
            let mut t = *t;
            t.v = t.v.map(sc);
            if let Some(h) = &mut t.host {
                h.v = h.v.map(sc);
            }
            t
        })
        .collect()
}

/// `tris` moved down by `dy_q8` / 256 pixels (negative: up), so that row `j` of the
/// moved scene samples the original at `y = j + 1/2 − dy_q8 / 256`.
pub(crate) fn shift_y(tris: &[SnappedTri], dy_q8: i32) -> Vec<SnappedTri> {
    tris.iter()
        .map(|t| {
            let mut t = *t;
            for p in &mut t.v {
                p[1] += dy_q8;
            }
            if let Some(h) = &mut t.host {
                for p in &mut h.v {
                    p[1] += dy_q8;
                }
            }
            t
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_checks_and_converts() {
        assert!(HwConfig::new(0, 80.0).is_err());
        assert!(HwConfig::new(4097, 80.0).is_err());
        assert!(HwConfig::new(64, 0.0).is_err());
        assert!(HwConfig::new(64, -3.0).is_err());
        assert!(HwConfig::new(64, f64::NAN).is_err());
        assert!(HwConfig::new(64, 1e9).is_err());
        let c = HwConfig::new(64, 100.0).unwrap();
        // 100 MHz: 100,000 cycles per millisecond.
        assert_eq!(c.ms(250_000), 2.5);
        assert_eq!(c.fps(1_000_000), 100.0);
    }
}
