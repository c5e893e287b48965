//! The core's command stream, driver side: beats, the binned frame stream with its
//! shading table, the unbinned comparison, and the pixel beats that come back.

use super::*;

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
    if t.channels() > 1 {
        return Err(CoreError::TooManyChannels(t.channels()));
    }
    if t.mask_bits() > SHADE_MASK_BITS as u32 {
        return Err(CoreError::TooManyLights(t.mask_bits()));
    }
    if t.counts() > 1 << SHADE_COUNT_BITS {
        return Err(CoreError::TooManySamples(t.counts() - 1));
    }
    Ok(t.entries()
        .map(|(nclass, mask, cnt, f, g)| {
            Beat::with_fields(
                KIND_TABLE,
                &[
                    (TABLE_ADDR, shade_addr(nclass, mask, cnt) as u64),
                    (TABLE_FACTOR, f as u64),
                    (TABLE_DROP, g as u64),
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
            sh: 0,
            won: false,
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
