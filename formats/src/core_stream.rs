//! The stream formats of the pixelproc core (`pixelproc_rtl::core_top::PixelprocCore`): what
//! a host or DMA sends on the command stream, what the core sends back on the pixel
//! stream, and the address of the shadow-shading table. `docs/core.md` prints these
//! tables bit by bit; a test checks the document against them.
//!
//! **Command stream** (AXI4-Stream slave `s_axis`): one beat carries
//! `tdata[255:0]` and a beat kind in `tuser[3:0]` ([`KIND_BITS`]). The kinds below 8 are
//! the array's own opcodes (seed 001, Matsumoto: sections 3–6) and go to the array
//! unchanged: `tdata` is the packed span word for SPAN and CHECK, and `tdata[2:0]` the
//! light bit for LATCH_SHADOW. The core's own kinds frame the tiles:
//! - [`KIND_TILE`] starts a tile-line (one scanline of one tile): `tdata` holds
//!   [`TILE_FIELDS`] (background, first column, last processor index, start of frame).
//!   The array receives it as CLEAR_LINE, which moves the previous tile-line into the
//!   readout registers; the core then streams that tile-line out.
//! - [`KIND_END`] ends a frame: the last tile-line is streamed out, nothing new starts.
//! - [`KIND_TABLE`] writes one entry of the shading table ([`TABLE_FIELDS`]).
//!
//! The stream has no `tlast`: the TILE and END beats frame the tile-lines (a DMA that
//! needs packets may set `tlast` on the beat before each TILE or END; the core does not
//! look at it).
//!
//! **Pixel stream** (AXI4-Stream master `m_axis`): one beat per pixel, `tdata[23:0]` the
//! final RGB888 ([`crate::pack_rgb`] layout), `tlast` on the last pixel of a tile-line,
//! `tuser` the [`OUT_USER_FIELDS`] (start of frame; in the debug configuration the
//! pixel's depth, shadow flags, counter, light mask and normal class).
//!
//! **Shading table** (seed 001 §6: "correct the intensity and store it"): addressed by
//! `{NCLASS, MASK[2:0], COUNT[3:0]}` ([`SHADE_ADDR_FIELDS`]), each entry a Q0.8 factor
//! `F` (9 bits, 256 = 1); a covered pixel's channels become `min((c·F + 128) >> 8, 255)`,
//! a background pixel (`ZB = Z_FAR`) passes unchanged.

use crate::fields::{table_end, Field};
use crate::opcodes::*;

/// Width of a command beat's data (one span word).
pub const BEAT_DATA_BITS: usize = 256;
/// Width of a command beat's kind (`s_axis_tuser`).
pub const KIND_BITS: usize = 4;

/// Beat kind: no operation (the array sees a bubble).
pub const KIND_NOP: u64 = OP_NOP;
/// Beat kind: a span word for the array.
pub const KIND_SPAN: u64 = OP_SPAN;
/// Beat kind: `DSF := 0; FSF := 0`.
pub const KIND_CLEAR_FLAGS: u64 = OP_CLEAR_FLAGS;
/// Beat kind: `COUNT := min(COUNT + FSF, 255)`.
pub const KIND_ACCUMULATE: u64 = OP_ACCUMULATE;
/// Beat kind: latch FSF into light-mask bit `tdata[2:0]`.
pub const KIND_LATCH_SHADOW: u64 = OP_LATCH_SHADOW;
/// Beat kind: the software form's check span (range in the span word's `XL`, `XR`).
pub const KIND_CHECK: u64 = OP_CHECK;
/// Beat kind: start a tile-line ([`TILE_FIELDS`]).
pub const KIND_TILE: u64 = 8;
/// Beat kind: end of frame (stream out the last tile-line).
pub const KIND_END: u64 = 9;
/// Beat kind: write one shading-table entry ([`TABLE_FIELDS`]).
pub const KIND_TABLE: u64 = 10;

/// True for the kinds the core accepts; any other kind (CLEAR_LINE and RESET included,
/// which only the core itself issues) sets the sticky `proto_err` output and is dropped.
pub fn kind_is_valid(kind: u64) -> bool {
    matches!(
        kind,
        KIND_NOP
            | KIND_SPAN
            | KIND_CLEAR_FLAGS
            | KIND_ACCUMULATE
            | KIND_LATCH_SHADOW
            | KIND_CHECK
            | KIND_TILE
            | KIND_END
            | KIND_TABLE
    )
}

/// TILE field: background colour, RGB888.
pub const TILE_BG: Field = Field::first("BG", 24);
/// TILE field: the tile's first screen column (a multiple of the array width).
pub const TILE_BASE: Field = TILE_BG.then("BASE", 12);
/// TILE field: index of the tile's last processor on screen (`min(N, width − BASE) − 1`):
/// the core streams out processors `0 ..= LAST`.
pub const TILE_LAST: Field = TILE_BASE.then("LAST", 12);
/// TILE field: this tile-line is the first of a frame (copied to the first pixel's
/// `tuser` start-of-frame bit).
pub const TILE_SOF: Field = TILE_LAST.then("SOF", 1);
/// The TILE beat's `tdata`, LSB first (the bits above are zero).
pub const TILE_FIELDS: &[Field] = &[TILE_BG, TILE_BASE, TILE_LAST, TILE_SOF];

/// LATCH_SHADOW field: the light's bit in the mask.
pub const LATCH_BIT: Field = Field::first("BIT", 3);

/// TABLE field: entry address ([`SHADE_ADDR_FIELDS`]).
pub const TABLE_ADDR: Field = Field::first("ADDR", SHADE_ADDR_BITS);
/// TABLE field: the factor, Q0.8 (256 = 1).
pub const TABLE_FACTOR: Field = TABLE_ADDR.then("FACTOR", FACTOR_BITS);
/// TABLE field: the drop weight, Q0.8 (256 = all of shade channel 1's difference).
pub const TABLE_DROP: Field = TABLE_FACTOR.then("DROP", FACTOR_BITS);
/// The TABLE beat's `tdata`, LSB first.
pub const TABLE_FIELDS: &[Field] = &[TABLE_ADDR, TABLE_FACTOR, TABLE_DROP];

/// Width of a shading factor (Q0.8, 0 ..= 256).
pub const FACTOR_BITS: usize = 9;
/// Light-mask bits the shading table is indexed by: scenes with more shadowing point
/// lights do not fit the core.
pub const SHADE_MASK_BITS: usize = 3;
/// Counter bits the shading table is indexed by: an area light with more samples than
/// `2^SHADE_COUNT_BITS − 1` does not fit the core.
pub const SHADE_COUNT_BITS: usize = 4;
/// Shading address field: the counter's low bits.
pub const SHADE_COUNT: Field = Field::first("COUNT", SHADE_COUNT_BITS);
/// Shading address field: the light mask's low bits.
pub const SHADE_MASK: Field = SHADE_COUNT.then("MASK", SHADE_MASK_BITS);
/// Shading address field: the normal class.
pub const SHADE_NCLASS: Field = SHADE_MASK.then("NCLASS", crate::NCLASS_BITS as usize);
/// The shading-table address, LSB first.
pub const SHADE_ADDR_FIELDS: &[Field] = &[SHADE_COUNT, SHADE_MASK, SHADE_NCLASS];
/// Width of a shading-table address.
pub const SHADE_ADDR_BITS: usize = table_end(SHADE_ADDR_FIELDS);

/// Shading-table address of a pixel's normal class, light mask and counter.
pub fn shade_addr(nclass: u8, mask: u8, count: u8) -> u32 {
    let mut w = 0u128;
    SHADE_COUNT.put_u128(&mut w, count as u64);
    SHADE_MASK.put_u128(&mut w, mask as u64);
    SHADE_NCLASS.put_u128(&mut w, nclass as u64);
    w as u32
}

/// Register stages of the core's shading step, from the readout word to the shaded pixel:
/// the readout word as it arrives, the table read (every bank), each bank's entry
/// registered at its block RAM with `max(0, c − s)`, each bank's entry again in a fabric
/// register, the addressed bank's entry within each group of 8 banks, the
/// addressed group's entry (the multipliers' operands), the two products, the products
/// again beside the rounding, and the clamp and subtraction (`rtl::shade_unit`, the golden
/// `core_model`).
pub const SHADE_STAGES: usize = 9;

/// Edges a TABLE write spends in the shading step's write registers before its bank
/// takes it: a TABLE beat issued at edge `E` is in the table at edge `E + 1`, and a
/// table read at edge `E + 2` or later sees it (a read at the edge of the write gets
/// the old entry). `docs/core.md`, "Timing".
pub const TABLE_WRITE_DELAY: usize = 1;

/// A pixel's channels after shading, per channel `c` of `rgb` and `s` of `sh` (shade
/// register 1), with the table entry's factor `f` and drop weight `g` (both Q0.8):
///
/// `out = max(0, min((c·f + 128) >> 8, 255) − ((max(0, c − s)·g + 128) >> 8))`.
///
/// The seed's table mode (§6) has `g = 0`: `out = min((c·f + 128) >> 8, 255)`. Exact
/// shading has `f = 256`, and `g` the shadowed share of light 0 (256 for a point light
/// that shadows the pixel, `round(256·count/k)` for an area light of `k` samples): a fully
/// shadowed pixel gets exactly `s`, the intensity without the light.
pub fn shade_rgb(rgb: u32, sh: u32, f: u32, g: u32) -> u32 {
    let (c, s) = (crate::unpack_rgb(rgb), crate::unpack_rgb(sh));
    let ch = |k: usize| {
        let lit = ((c[k] as u32 * f + 128) >> 8).min(255);
        let d = (c[k] as u32).saturating_sub(s[k] as u32);
        lit.saturating_sub((d * g + 128) >> 8) as u8
    };
    crate::pack_rgb([ch(0), ch(1), ch(2)])
}

/// Output `tuser` field: start of frame (first pixel of a TILE with `SOF`).
pub const OUT_SOF: Field = Field::first("SOF", 1);
/// Output `tuser` field (debug): depth `ZB`.
pub const OUT_ZB: Field = OUT_SOF.then("ZB", crate::Z_BITS as usize);
/// Output `tuser` field (debug): DSF.
pub const OUT_DSF: Field = OUT_ZB.then("DSF", 1);
/// Output `tuser` field (debug): FSF.
pub const OUT_FSF: Field = OUT_DSF.then("FSF", 1);
/// Output `tuser` field (debug): shadow counter.
pub const OUT_COUNT: Field = OUT_FSF.then("COUNT", crate::regs::COUNT_BITS);
/// Output `tuser` field (debug): light mask.
pub const OUT_MASK: Field = OUT_COUNT.then("MASK", crate::regs::MASK_BITS);
/// Output `tuser` field (debug): normal class.
pub const OUT_NCLASS: Field = OUT_MASK.then("NCLASS", crate::NCLASS_BITS as usize);
/// The pixel stream's `tuser`, LSB first (the debug fields read 0 outside the debug
/// configuration).
pub const OUT_USER_FIELDS: &[Field] = &[
    OUT_SOF, OUT_ZB, OUT_DSF, OUT_FSF, OUT_COUNT, OUT_MASK, OUT_NCLASS,
];
/// Width of the pixel stream's `tuser`.
pub const OUT_USER_BITS: usize = table_end(OUT_USER_FIELDS);

/// The core's control registers, as the RTL probe reads them and the cycle-level golden
/// model (`pixelproc_sim::core_model`) holds them, compared after every rising edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoreRegs {
    /// Input FIFO: write pointer, read pointer, head-valid.
    pub in_fifo: (u32, u32, bool),
    /// Output FIFO: write pointer, read pointer, head-valid.
    pub out_fifo: (u32, u32, bool),
    /// Base column of the tile being drawn.
    pub base: u32,
    /// A tile-line is in the array (`valid`, its `LAST`, its `SOF`).
    pub pending: (bool, u32, bool),
    /// The readout job (`valid`, wait counter, `LAST`, `SOF`, next address).
    pub job: (bool, u32, u32, bool, u32),
    /// The readout pipeline's three stages, each `valid | last << 1 | sof << 2`.
    pub track: [u8; 3],
    /// Pixels read and not yet in the output FIFO.
    pub inflight: u32,
    /// Sticky protocol error.
    pub err: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_fit_their_words() {
        const {
            assert!(TILE_SOF.end() <= BEAT_DATA_BITS);
            assert!(TABLE_FACTOR.end() <= BEAT_DATA_BITS);
            assert!(SHADE_ADDR_BITS == TABLE_ADDR.width);
            assert!(OUT_USER_BITS == 51);
        }
        assert!(!kind_is_valid(OP_CLEAR_LINE) && !kind_is_valid(OP_RESET));
        assert!(kind_is_valid(KIND_TABLE) && !kind_is_valid(11));
    }

    #[test]
    fn tables_match_docs() {
        use crate::fields::{parse_doc_table, table_rows};
        let doc = include_str!("../../docs/core.md");
        for (heading, fields) in [
            ("### TILE beat", TILE_FIELDS),
            ("### TABLE beat", TABLE_FIELDS),
            ("### Shading-table address", SHADE_ADDR_FIELDS),
            ("### Pixel `tuser`", OUT_USER_FIELDS),
        ] {
            assert_eq!(
                parse_doc_table(doc, heading),
                table_rows(fields),
                "{heading}"
            );
        }
    }

    #[test]
    fn shading_rounds_and_saturates() {
        assert_eq!(shade_rgb(0x80FF01, 0, 256, 0), 0x80FF01);
        // 0x80·128 = 16384 → (16384 + 128) >> 8 = 64; 0xFF·128 → 128 (127.5 rounds up).
        assert_eq!(shade_rgb(0x80FF01, 0, 128, 0), 0x408001);
        assert_eq!(shade_rgb(0x000000, 0, 300, 0), 0);
        assert_eq!(shade_rgb(0xFF0000, 0, 300, 0), 0xFF0000);
        // Exact mode: a full drop gives the shade register; half a drop the midpoint
        // (0x80 − ((0x80 − 0x20)·128 + 128) >> 8 = 0x80 − 48 = 0x50); a shade register
        // above the lit value drops nothing.
        assert_eq!(shade_rgb(0x80FF01, 0x204002, 256, 256), 0x204001);
        assert_eq!(shade_rgb(0x800000, 0x200000, 256, 128), 0x500000);
        assert_eq!(shade_rgb(0x100000, 0x200000, 256, 256), 0x100000);
        assert_eq!(shade_addr(0xAB, 0b101, 9), 0xAB << 7 | 0b101 << 4 | 9);
    }
}
