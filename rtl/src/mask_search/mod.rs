//! The A-buffer mask search unit with its offset ROM and depth calculator (seed 000,
//! JP2569952B2, claim 2 and Fig. 6), in two variants.
//!
//! Blocks of Fig. 6 and where they are here: the start corner (2) is an input (the caller
//! picks it from the slope signs, `Corner::of_min`); the search mask generator (3) is a
//! generated constant table per corner and line (`search_mask_table`, line `k` of family
//! `(p, q)` is `{(c, r) : p·c' + q·r' = k}`, the seed's diagonal band is `(1, 1)`); the AND
//! unit (4), zero detector (5) and mover (6) are the per-line logic; the offset reader (7)
//! and ROM (8) are [`OffsetRom`] (compacted, see its module); the depth calculator (10)
//! is [`DepthCalc`], `z = zc + sx·dx + sy·dy` evaluated at the one or two end offsets with
//! min and max.
//!
//! * [`MaskSearchIter`]: one search line per clock, the seed's flowchart. Its step ports
//!   (`active`, `line`, `search_mask`, `and_result`, `zero`, `moved`, `hit`, `done`) are
//!   exactly the golden `SearchUnit::step` output of every clock.
//! * [`MaskSearchPipe`]: one stage per search line, a new mask accepted every clock.
//! * [`MaskSearchIterStream`], [`MaskSearchPipeStream`]: the two units as AXI4-Stream
//!   blocks (`s_tvalid/s_tready/s_tdata` in, `m_tvalid/m_tready/m_tdata` out), a
//!   credit-counted [`ResultFifo`] behind each core; these are what the Verilog export
//!   writes for streaming use ([`mask_search_stream_verilog`]).
//!
//! Both feed the same back end ([`SearchBackEnd`]: ROM, depth calculator, result
//! registers). All arithmetic is on `Bits` (two's complement modulo `2^53`); formats are
//! those of `pixelproc_formats::abuffer`: masks in its bit order, corner code (bit 0 right,
//! bit 1 bottom), plane fields Q.12 48-bit two's complement, ROM word 17 bits, depths Q.12
//! 53-bit two's complement. Every register has a synchronous reset (`rst`, to zero).
//! `docs/rtl_mask_search.md` gives ports, handshakes, latencies and synthesis figures.
//!
//! One block per file: [`iter`] with its [`mask_gen`], [`stage`], [`pipe`], [`back_end`], [`depth_calc`]
//! and [`offset_rom`]; each file carries a short smoke simulation and
//! a Yosys check of its block (the exhaustive comparisons are in the testbench crate);
//! this module holds the widths, latencies and errors they share, and its `ports` macros
//! declare the ports that the two units and the back end have in common.
//!
//! **Literals.** Every sized literal in the kernels is a `Constant` field (`k_zero_*`,
//! `k_one`, ...), never a bare `0`/`1` or a const generic: rust-hdl emits bare literals as
//! 32-bit numbers and const generics by name, which Verilator's WIDTH lint (or the
//! compiler) rejects.

#[macro_use]
mod ports;

pub mod back_end;
pub mod depth_calc;
pub mod iter;
pub mod iter_stream;
pub mod mask_gen;
pub mod offset_rom;
pub mod pipe;
pub mod pipe_stream;
pub mod result_fifo;
pub mod stage;

pub use back_end::SearchBackEnd;
pub use depth_calc::DepthCalc;
pub use iter::MaskSearchIter;
pub use iter_stream::{MaskSearchIterStream, ITER_FIFO_DEPTH};
pub use mask_gen::MaskGen;
pub use offset_rom::{OffsetRom, ROM_LATENCY, WORD_BITS};
pub use pipe::MaskSearchPipe;
pub use pipe_stream::{pipe_fifo_depth, MaskSearchPipeStream};
pub use result_fifo::ResultFifo;
pub use stage::{SearchStage, StageProbe};

use pixelproc_formats::abuffer::{MaskSize, SearchFamily, PLANE_BITS};
use rust_hdl::prelude::*;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Width of a plane field (`zc`, `sx`, `sy`) on the ports.
pub const PB: usize = PLANE_BITS as usize;
/// Width of a computed depth: `|zc| + 7|sx| + 7|sy| < 15·2^47 < 2^51`, plus sign and one
/// bit of headroom for the min/max difference.
pub const Z_BITS: usize = 53;
const _: () = assert!(
    PB == 48 && Z_BITS == 53,
    "DepthCalc uses literal bit 47 and 52"
);
/// Width of the line index and of the step count.
pub const LINE_BITS: usize = 5;
/// Clocks through the depth calculator.
pub const DEPTH_LATENCY: usize = 6;
/// The back end's input register (the search result is registered before the ROM reads
/// it).
pub const IN_LATENCY: usize = 1;
/// Clocks from a search result (the clock its last line is tested) to the result ports.
pub const BACK_LATENCY: usize = IN_LATENCY + ROM_LATENCY + DEPTH_LATENCY;

/// Width of a stream search word (`s_tdata`) for `b`-bit masks. Fields, LSB first:
/// `zc[48]` at 0, `sx[48]` at 48, `sy[48]` at 96, `corner[2]` at 144, `mask[b]` at 146.
pub const fn stream_in_bits(b: usize) -> usize {
    3 * PB + 2 + b
}

/// Width of a stream result word (`m_tdata`) for `b`-bit masks. Fields, LSB first:
/// `z1` at 0, `z2` at 53, `zmin` at 106, `zmax` at 159 (53 bits each), `rom[17]` at 212,
/// `steps[5]` at 229, `hit` at 234, `and[b]` at 235.
pub const fn stream_out_bits(b: usize) -> usize {
    4 * Z_BITS + WORD_BITS + LINE_BITS + 1 + b
}

/// Bit of `hit` in a result word.
pub const STREAM_HIT_BIT: usize = 4 * Z_BITS + WORD_BITS + LINE_BITS;
// The stream kernels (`stream_unit_logic!`) use these offsets as literals.
const _: () = assert!(
    stream_in_bits(0) == 146 && STREAM_HIT_BIT == 234 && WORD_BITS == 17,
    "stream word layout changed: update stream_unit_logic!"
);

/// The iterative stream unit for 4×4 masks.
pub type MaskSearchIterStream4x4 =
    MaskSearchIterStream<16, { stream_in_bits(16) }, { stream_out_bits(16) }>;
/// The iterative stream unit for 8×8 masks.
pub type MaskSearchIterStream8x8 =
    MaskSearchIterStream<64, { stream_in_bits(64) }, { stream_out_bits(64) }>;
/// The pipelined stream unit for 4×4 masks.
pub type MaskSearchPipeStream4x4 =
    MaskSearchPipeStream<16, { stream_in_bits(16) }, { stream_out_bits(16) }>;
/// The pipelined stream unit for 8×8 masks.
pub type MaskSearchPipeStream8x8 =
    MaskSearchPipeStream<64, { stream_in_bits(64) }, { stream_out_bits(64) }>;

/// Checks a stream unit's word widths against its mask width.
pub(crate) fn check_stream(b: usize, iw: usize, ow: usize) -> Result<(), MaskSearchError> {
    if iw != stream_in_bits(b) || ow != stream_out_bits(b) {
        return Err(MaskSearchError::StreamWidth {
            b,
            iw,
            ow,
            want_iw: stream_in_bits(b),
            want_ow: stream_out_bits(b),
        });
    }
    Ok(())
}

/// The `hit` bit of a result word as a constant.
pub(crate) fn hit_bit<const OW: usize>() -> Bits<OW> {
    Bits::<OW>::default().replace_bit(STREAM_HIT_BIT, true)
}

/// Why a search unit cannot be built.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum MaskSearchError {
    /// The mask size does not match the block's mask width `B`.
    #[error("mask size {size} has {bits} subpixels, the block is built for {width}")]
    Width {
        /// The size asked for.
        size: MaskSize,
        /// Its subpixel count.
        bits: u32,
        /// The block's `B`.
        width: usize,
    },
    /// The family has more lines than the 5-bit line counter holds.
    #[error("search family ({p}, {q}) has {lines} lines for {size}; at most 31 supported")]
    TooManyLines {
        /// Column weight.
        p: u8,
        /// Row weight.
        q: u8,
        /// Mask size.
        size: MaskSize,
        /// Lines needed.
        lines: u32,
    },
    /// Verilog export is built for 4×4 (`B = 16`) and 8×8 (`B = 64`) masks only.
    #[error("no Verilog export for mask size {0} (4x4 and 8x8 are built)")]
    NoExport(MaskSize),
    /// A stream unit's word widths do not fit its mask width.
    #[error("stream words of {iw} and {ow} bits for {b}-bit masks; need {want_iw} and {want_ow}")]
    StreamWidth {
        /// Mask width.
        b: usize,
        /// `s_tdata` width asked for.
        iw: usize,
        /// `m_tdata` width asked for.
        ow: usize,
        /// `s_tdata` width needed.
        want_iw: usize,
        /// `m_tdata` width needed.
        want_ow: usize,
    },
    /// Writing a file failed.
    #[error("writing Verilog: {0}")]
    Io(String),
}

pub(crate) fn check(
    size: MaskSize,
    family: SearchFamily,
    b: usize,
) -> Result<u32, MaskSearchError> {
    if size.bits() as usize != b {
        return Err(MaskSearchError::Width {
            size,
            bits: size.bits(),
            width: b,
        });
    }
    let lines = family.lines(size);
    if lines > 31 {
        return Err(MaskSearchError::TooManyLines {
            p: family.p,
            q: family.q,
            size,
            lines,
        });
    }
    Ok(lines)
}

/// The two architectures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// One search line per clock ([`MaskSearchIter`]).
    Iterative,
    /// One stage per line, one mask per clock ([`MaskSearchPipe`]).
    Pipelined,
}

impl Variant {
    /// Both variants.
    pub const ALL: [Variant; 2] = [Variant::Iterative, Variant::Pipelined];
    /// Short name (`iter`, `pipe`).
    pub fn name(self) -> &'static str {
        match self {
            Variant::Iterative => "iter",
            Variant::Pipelined => "pipe",
        }
    }
}

/// `n` default registers.
pub(crate) fn dff_line<T: Synth>(n: usize) -> Vec<DFF<T>> {
    (0..n).map(|_| DFF::default()).collect()
}

/// Verilog module name of a variant for a size, e.g. `mask_search_pipe_4x4`.
pub fn module_name(variant: Variant, size: MaskSize) -> String {
    format!("mask_search_{}_{}x{}", variant.name(), size.n(), size.m())
}

/// Verilog module name of a variant's stream unit for a size, e.g.
/// `mask_search_pipe_stream_4x4`.
pub fn stream_module_name(variant: Variant, size: MaskSize) -> String {
    format!(
        "mask_search_{}_stream_{}x{}",
        variant.name(),
        size.n(),
        size.m()
    )
}

/// Self-contained Verilog of one variant's AXI4-Stream unit ([`MaskSearchIterStream`],
/// [`MaskSearchPipeStream`]) for 4×4 or 8×8 masks (seed diagonal family): `(module name,
/// text)`. The module is [`stream_module_name`].
pub fn mask_search_stream_verilog(
    variant: Variant,
    size: MaskSize,
) -> Result<(String, String), MaskSearchError> {
    let name = stream_module_name(variant, size);
    let fam = SearchFamily::DIAGONAL;
    let text = match (variant, size.bits()) {
        (Variant::Iterative, 16) => {
            crate::verilog::export(MaskSearchIterStream4x4::new(size, fam)?, &name)
        }
        (Variant::Iterative, 64) => {
            crate::verilog::export(MaskSearchIterStream8x8::new(size, fam)?, &name)
        }
        (Variant::Pipelined, 16) => {
            crate::verilog::export(MaskSearchPipeStream4x4::new(size, fam)?, &name)
        }
        (Variant::Pipelined, 64) => {
            crate::verilog::export(MaskSearchPipeStream8x8::new(size, fam)?, &name)
        }
        _ => return Err(MaskSearchError::NoExport(size)),
    };
    Ok((name, text))
}

/// Self-contained Verilog of one variant for 4×4 or 8×8 masks (seed diagonal family):
/// `(module name, text)`. The module is [`module_name`]; sub-modules are `name$...`.
pub fn mask_search_verilog(
    variant: Variant,
    size: MaskSize,
) -> Result<(String, String), MaskSearchError> {
    let name = module_name(variant, size);
    let fam = SearchFamily::DIAGONAL;
    let text = match (variant, size.bits()) {
        (Variant::Iterative, 16) => {
            crate::verilog::export(MaskSearchIter::<16>::new(size, fam)?, &name)
        }
        (Variant::Iterative, 64) => {
            crate::verilog::export(MaskSearchIter::<64>::new(size, fam)?, &name)
        }
        (Variant::Pipelined, 16) => {
            crate::verilog::export(MaskSearchPipe::<16>::new(size, fam)?, &name)
        }
        (Variant::Pipelined, 64) => {
            crate::verilog::export(MaskSearchPipe::<64>::new(size, fam)?, &name)
        }
        _ => return Err(MaskSearchError::NoExport(size)),
    };
    Ok((name, text))
}

/// Writes both variants for 4×4 and 8×8 into `dir`, the cores
/// (`mask_search_{iter,pipe}_{4x4,8x8}.v`) and their AXI4-Stream units
/// (`mask_search_{iter,pipe}_stream_{4x4,8x8}.v`), each file self-contained; returns the
/// paths.
pub fn write_mask_search_verilog(dir: &Path) -> Result<Vec<PathBuf>, MaskSearchError> {
    let io = |e: std::io::Error| MaskSearchError::Io(e.to_string());
    std::fs::create_dir_all(dir).map_err(io)?;
    let mut out = Vec::new();
    for (name, text) in mask_search_files()? {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(io)?;
        out.push(p);
    }
    Ok(out)
}

/// The files [`write_mask_search_verilog`] writes, as `(file name, text)`: both variants
/// at 4×4 and 8×8, core and stream unit.
pub fn mask_search_files() -> Result<Vec<(String, String)>, MaskSearchError> {
    let mut out = Vec::new();
    for size in [MaskSize::S4X4, MaskSize::S8X8] {
        for v in Variant::ALL {
            let (name, text) = mask_search_verilog(v, size)?;
            out.push((format!("{name}.v"), text));
            let (name, text) = mask_search_stream_verilog(v, size)?;
            out.push((format!("{name}.v"), text));
        }
    }
    Ok(out)
}

/// The Yosys check beside each block: `block`'s Verilog through rust-hdl's
/// `yosys_validate` (`hierarchy -check; proc`: no latch, nothing undriven or implicit).
/// Without `yosys` the check is skipped, except under `CI=true` where it fails.
#[cfg(test)]
pub(crate) fn yosys_check<B: Block>(prefix: &str, mut block: B) {
    let have = std::process::Command::new("yosys")
        .arg("-V")
        .output()
        .is_ok_and(|o| o.status.success());
    if !have {
        let ci = std::env::var("CI").is_ok_and(|v| v == "true");
        assert!(!ci, "yosys not installed (required under CI=true)");
        println!("SKIPPED: yosys not installed");
        return;
    }
    block.connect_all();
    let v = generate_verilog(&block);
    if let Err(e) = yosys_validate(prefix, &v) {
        panic!("{prefix}: yosys_validate failed: {e:?}");
    }
}

/// One clock of a block in the direct `simulate` loop: rising edge, then falling edge.
#[cfg(test)]
macro_rules! cycle {
    ($u:expr) => {{
        $u.clock.next = Clock { clk: true };
        assert!(simulate(&mut $u, 200));
        $u.clock.next = Clock { clk: false };
        assert!(simulate(&mut $u, 200));
    }};
}
#[cfg(test)]
pub(crate) use cycle;

/// The seed's worked example (seed 000, 4×4, Tables 1 and 2): AND result 0842H has ends
/// (−3, +1) and (+1, −3) in 1/8 px; this is its ROM word.
#[cfg(test)]
pub(crate) const SEED_WORD: u64 = 0xD | 1 << 4 | 1 << 8 | 0xD << 12 | 1 << 16;
/// The example's plane `z = 1000 + 3·dx − 5·dy` (Q.12) ...
#[cfg(test)]
pub(crate) const SEED_PLANE: [i64; 3] = [1000 << 12, 3 << 12, -5 << 12];
/// ... and its depths at the two ends: 1000 − 9 − 5 and 1000 + 3 + 15.
#[cfg(test)]
pub(crate) const SEED_DEPTHS: [i64; 2] = [986 << 12, 1018 << 12];

/// Plane field `v` as the 48-bit port value.
#[cfg(test)]
pub(crate) fn plane_bits(v: i64) -> Bits<PB> {
    (v as u64 & ((1 << PB) - 1)).to_bits()
}

/// Depth port value `v` as a signed number.
#[cfg(test)]
pub(crate) fn depth_of(v: Bits<Z_BITS>) -> i64 {
    ((v.to_u64() << (64 - Z_BITS)) as i64) >> (64 - Z_BITS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked() {
        assert!(matches!(
            MaskSearchIter::<16>::new(MaskSize::S8X8, SearchFamily::DIAGONAL),
            Err(MaskSearchError::Width { .. })
        ));
        assert!(matches!(
            MaskSearchPipe::<64>::new(MaskSize::S8X8, SearchFamily { p: 3, q: 3 }),
            Err(MaskSearchError::TooManyLines { .. })
        ));
        let p = MaskSearchPipe::<64>::new(MaskSize::S8X8, SearchFamily::DIAGONAL).unwrap();
        assert_eq!(p.latency(), 15 + 12);
        assert!(mask_search_verilog(Variant::Pipelined, MaskSize::new(4, 2).unwrap()).is_err());
    }
}
