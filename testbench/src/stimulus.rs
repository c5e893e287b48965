//! Stimulus for the array testbenches: scanline command streams from screen-space
//! triangles (through the golden span setup), random command vectors and corner cases,
//! and their flattening into one command per clock.

use crate::TbError;
use pixelproc_formats::{pack_rgb, Attr, SpanWord, SUBPIXEL_ONE, Z_GEOM_MAX, Z_GEOM_MIN};
use pixelproc_sim::pixel_array::Command;
use pixelproc_sim::plan::Effects;
use pixelproc_sim::render::SpanSource;
use pixelproc_sim::scene::LoadedScene;
use pixelproc_sim::setup::SnappedTri;
use pixelproc_sim::stream::SceneStream;

/// The golden pipeline's per-scanline command stream of a scene, as the array sees it
/// ([`pixelproc_sim::stream::SceneStream`]): for row `j`, the OP span words of the row,
/// then, for each shadowing light of `effects` in order, that light's shadow commands.
/// Returns the rows (no `ClearLine`; [`LineStream::flatten`] adds one per tile) and the
/// background, RGB888 packed.
pub fn scene_stream(
    ls: &LoadedScene,
    effects: &Effects,
) -> Result<(Vec<Vec<Command>>, u32), TbError> {
    let s = SceneStream::of_scene(
        ls,
        &effects.shadow_lights,
        effects.shadow_form,
        effects.shading,
    )
    .map_err(pixelproc_sim::pipeline::RenderError::from)?;
    Ok((s.rows(), s.bg_packed()))
}

/// The command stream of a frame: per scanline, the commands after its `ClearLine`
/// (span words in scene order, then any shadow commands), plus the background.
#[derive(Clone, Debug)]
pub struct LineStream {
    /// Screen width in pixels (lines wider than the array are processed in tiles).
    pub width: u32,
    /// Background colour, RGB888 packed.
    pub bg: u32,
    /// Per scanline, its commands (no `ClearLine`: the testbench adds one per tile).
    pub lines: Vec<Vec<Command>>,
}

impl LineStream {
    /// The OP span words of every row of `tris` on a `width × height` screen.
    pub fn from_triangles(
        tris: &[SnappedTri],
        width: u32,
        height: u32,
        bg: [u8; 3],
    ) -> Result<LineStream, pixelproc_sim::setup::SetupError> {
        let src = SpanSource::new(tris, width, height)?;
        let lines = (0..height)
            .map(|j| {
                src.row_spans(j)
                    .iter()
                    .copied()
                    .map(Command::Span)
                    .collect()
            })
            .collect();
        Ok(LineStream {
            width,
            bg: pack_rgb(bg),
            lines,
        })
    }

    /// Number of span words in the stream (each is fed once per tile).
    pub fn span_words(&self) -> usize {
        self.lines
            .iter()
            .flatten()
            .filter(|c| matches!(c, Command::Span(_)))
            .count()
    }

    /// One command per clock for an array of `n` processors: for each line and tile,
    /// `ClearLine{bg}` then the line's commands, each paired with the tile base; a final
    /// `ClearLine` moves the last line into the readout registers.
    pub fn flatten(&self, n: usize) -> Vec<(u32, Command)> {
        let mut out = Vec::new();
        for line in &self.lines {
            let mut base = 0u32;
            while base < self.width.max(1) {
                out.push((base, Command::ClearLine { bg: self.bg }));
                out.extend(line.iter().map(|c| (base, *c)));
                base += n as u32;
            }
        }
        out.push((0, Command::ClearLine { bg: self.bg }));
        out
    }
}

/// A small deterministic generator (SplitMix64) for reproducible random vectors.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `lo ..= hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % ((hi - lo + 1) as u64)) as i64
    }
}

/// `count` random well-shaped triangles (doubled area at least a quarter of the longest
/// edge squared, so colour and depth slopes fit the span word) with vertices within a
/// margin around a `w × h` screen.
pub fn random_triangles(rng: &mut Rng, count: usize, w: u32, h: u32) -> Vec<SnappedTri> {
    (0..count)
        .map(|k| loop {
            let mut t = SnappedTri {
                tag: k as u16,
                ..Default::default()
            };
            for i in 0..3 {
                t.v[i] = [
                    rng.range(
                        -8 * SUBPIXEL_ONE as i64,
                        (w as i64 + 8) * SUBPIXEL_ONE as i64,
                    ) as i32,
                    rng.range(
                        -8 * SUBPIXEL_ONE as i64,
                        (h as i64 + 8) * SUBPIXEL_ONE as i64,
                    ) as i32,
                ];
                t.z[i] = rng.range(Z_GEOM_MIN as i64, Z_GEOM_MAX as i64) as u32;
                for c in 0..3 {
                    // 0..=255: the span setup scales vertex colours by 2^12 itself
                    // (see the final report of this change), so these give Q8.12 spans.
                    t.c[i][c] = rng.range(0, 255) as u32;
                }
            }
            let d = |a: usize, b: usize| {
                let dx = (t.v[a][0] - t.v[b][0]) as i64;
                let dy = (t.v[a][1] - t.v[b][1]) as i64;
                (dx, dy)
            };
            let (e1, e2) = (d(1, 0), d(2, 0));
            let area2 = (e1.0 * e2.1 - e1.1 * e2.0).abs();
            let longest = [d(1, 0), d(2, 0), d(2, 1)]
                .iter()
                .map(|e| e.0 * e.0 + e.1 * e.1)
                .max()
                .unwrap_or(0);
            let min_len = (2 * SUBPIXEL_ONE as i64).pow(2);
            if longest >= min_len && 4 * area2 >= longest {
                break t;
            }
        })
        .collect()
}

/// A random span word with every field drawn over its whole range (any attribute,
/// decal or not), including empty spans (`XR < XL`) and ends beyond the tile.
pub fn random_word(rng: &mut Rng, max_x: u16) -> SpanWord {
    let xl = rng.range(0, max_x as i64) as u16;
    let xr = rng.range(xl as i64 - 2, max_x as i64).max(0) as u16;
    let mut w = SpanWord {
        chan: 0,
        attr: Attr::from_code(rng.next_u64() as u8),
        xl,
        xr,
        zl: rng.next_u64() & ((1 << 36) - 1),
        dz: pixelproc_formats::sign_extend(rng.next_u64(), 38),
        il: [0; 3],
        di: [0; 3],
        tag: rng.next_u64() as u16,
        nclass: rng.next_u64() as u8,
        decal: rng.next_u64() & 1 == 1,
    };
    // Mix in small slopes, as real spans have, so depth tests both pass and fail.
    if rng.next_u64() & 1 == 0 {
        w.zl = rng.range(0, (1 << 36) - 1) as u64;
        w.dz = rng.range(-(1 << 16), 1 << 16);
    }
    for c in 0..3 {
        w.il[c] = (rng.next_u64() & ((1 << 20) - 1)) as u32;
        w.di[c] = if rng.next_u64() & 1 == 0 {
            pixelproc_formats::sign_extend(rng.next_u64(), 21) as i32
        } else {
            rng.range(-(1 << 12), 1 << 12) as i32
        };
    }
    w
}

/// A random command: mostly spans, with every other command mixed in (LATCH_SHADOW
/// with every bit index, CHECK over random and empty ranges).
pub fn random_command(rng: &mut Rng, max_x: u16) -> Command {
    match rng.range(0, 17) {
        0 => Command::ClearLine {
            bg: (rng.next_u64() & 0xff_ffff) as u32,
        },
        1 => Command::ClearFlags,
        2 => Command::AccumulateShadow,
        3 => Command::Nop,
        4 => Command::LatchShadow {
            bit: rng.range(0, 7) as u8,
        },
        5 => {
            let xl = rng.range(0, max_x as i64) as u16;
            let xr = rng.range(xl as i64 - 2, max_x as i64).max(0) as u16;
            Command::Check { xl, xr }
        }
        _ => Command::Span(random_word(rng, max_x)),
    }
}

/// Corner cases: spans at the tile edges, one pixel wide, empty, decal ties, depth and
/// intensity at the limits of their formats, IF/EV with empty ranges, counter saturation.
pub fn corner_cases(n: u16) -> Vec<Command> {
    let op = |xl: u16, xr: u16, zl: u64, dz: i64, il: u32, di: i32, decal: bool| {
        Command::Span(SpanWord {
            attr: Attr::Op,
            xl,
            xr,
            zl,
            dz,
            il: [il, il, il],
            di: [di, -di - 1, 0],
            decal,
            nclass: (xl as u8) ^ 0xa5,
            ..Default::default()
        })
    };
    let sh = |attr: Attr, xl: u16, xr: u16, zl: u64, dz: i64| {
        Command::Span(SpanWord {
            attr,
            xl,
            xr,
            zl,
            dz,
            ..Default::default()
        })
    };
    let sh_decal = |attr: Attr, xl: u16, xr: u16, zl: u64| {
        Command::Span(SpanWord {
            attr,
            xl,
            xr,
            zl,
            decal: true,
            ..Default::default()
        })
    };
    let last = n - 1;
    let mut v = vec![
        Command::ClearLine { bg: 0x123456 },
        op(0, last, 1000 << 12, 0, 0, 0, false),
        op(0, 0, 999 << 12, 0, 255 << 12, 0, false),
        op(last, last, 999 << 12, 0, 255 << 12, 0, false),
        op(3, 2, 1 << 12, 0, 0, 0, false),          // empty span
        op(2, 4, 1000 << 12, 0, 7 << 12, 0, false), // tie, not decal: loses
        op(2, 4, 1000 << 12, 0, 9 << 12, 0, true),  // tie, decal: wins
        op(0, 4095, (1 << 36) - 1, -(1 << 37), 0, (1 << 20) - 1, false), // extremes
        op(1, 4095, 0, (1 << 37) - 1, (1 << 20) - 1, -(1 << 20), false),
        op(0, last, 5 << 12, -(6 << 12), 100 << 12, 200 << 12, false), // negative z wraps
        op(0, last, 0x10_0000_0000 - 1, 4096, 0, -(1 << 12), false),   // z crosses 2^24
        Command::ClearFlags,
        sh(Attr::Sp, 1, 5, 10 << 12, 0),
        sh(Attr::Ev, 3, 2, 0, 0), // empty EV still ORs DSF into FSF
        Command::AccumulateShadow,
        sh(Attr::If, 4, 3, 0, 0),
        sh(Attr::Ev, 0, last, (1 << 36) - 1, 0),
        Command::LatchShadow { bit: 0 },
        Command::LatchShadow { bit: 7 },
        Command::ClearFlags,
        sh(Attr::Sp, 2, 6, 0, 0),
        Command::Check { xl: 3, xr: 4 },
        Command::Check { xl: 6, xr: 5 }, // empty check range
        Command::LatchShadow { bit: 3 },
        sh(Attr::Sp, 0, last, 0, 0),
        Command::Check { xl: 0, xr: 4095 },
        Command::LatchShadow { bit: 5 },
        op(1, 2, 1, 0, 0, 0, false), // nclass replaced where nearer
    ];
    for _ in 0..260 {
        v.push(Command::AccumulateShadow); // saturates at 255
    }
    v.push(Command::ClearFlags);
    v.push(Command::AccumulateShadow);
    v.push(Command::ClearLine { bg: 0xabcdef });
    // Directly after CLEAR_LINE (ZB = Z_FAR at the coming edge): a decal at Z = Z_FAR
    // passes (`Z <= ZB`), a plain span at Z_FAR does not.
    let zfar = (pixelproc_formats::Z_FAR as u64) << 12;
    v.push(op(0, 2, zfar, 0, 77 << 12, 0, true));
    v.push(op(3, 5, zfar, 0, 66 << 12, 0, false));
    // Back to back at one depth: a span that writes, then a decal at its depth (passes
    // against the depth being written), then a plain span at it (does not).
    v.push(op(4, 7, 2000 << 12, 0, 11 << 12, 0, false));
    v.push(op(4, 7, 2000 << 12, 0, 22 << 12, 0, true));
    v.push(op(4, 7, 2000 << 12, 0, 33 << 12, 0, false));
    // Directly behind a span that writes, a plain span at its depth and one behind it
    // (both fail against the depth being written; against the ZB held before the write
    // they would pass), then a decal at the depth (passes).
    v.push(op(0, last, 1500 << 12, 0, 44 << 12, 0, false));
    v.push(op(0, last, 1500 << 12, 0, 55 << 12, 0, false));
    v.push(op(0, last, 1600 << 12, 0, 66 << 12, 0, false));
    v.push(op(0, last, 1500 << 12, 0, 88 << 12, 0, true));
    // Shadow spans flagged decal still test `Z < ZB` strictly (the decal's `Z <= ZB` is
    // for OP spans): at ZB's depth no toggle, held and directly behind a write.
    v.push(Command::ClearFlags);
    v.push(sh_decal(Attr::Sp, 0, last, 1500 << 12));
    v.push(op(0, last, 1400 << 12, 0, 99 << 12, 0, false));
    v.push(sh_decal(Attr::Sp, 0, last, 1400 << 12));
    v.push(sh_decal(Attr::Ev, 0, last, 1400 << 12));
    v.push(Command::LatchShadow { bit: 1 });
    v.push(Command::ClearLine { bg: 0x010203 });
    // Directly after CLEAR_LINE, a plain span at Z_FAR over the whole tile: it fails
    // (`Z_FAR < Z_FAR` is false) at every processor; a shadow span at Z_FAR likewise.
    v.push(op(0, last, zfar, 0, 12 << 12, 0, false));
    v.push(Command::ClearLine { bg: 0x040506 });
    v.push(sh_decal(Attr::If, 0, last, zfar));
    v.push(sh_decal(Attr::Ev, 0, last, 0));
    v.push(Command::LatchShadow { bit: 2 });
    v.push(Command::ClearLine { bg: 0x070809 });
    v
}
