//! The command stream of a scene: what the pixel-processor array is fed, per row and per
//! tile (seed 001, Matsumoto: sections 1 and 3 for the OP span words of each scanline,
//! sections 4–6 for the shadow commands that follow them).
//!
//! Per scanline `j` the array sees `ClearLine`, the OP span words of row `j` in scene
//! order ([`SpanSource::row_spans`]), then, for each shadowing light in order, that
//! light's shadow commands ([`crate::shadow::shadow_commands`]: per light sample
//! `ClearFlags`, the volumes' SP/EV/IF spans or `Check`s, then `LatchShadow` or
//! `AccumulateShadow`). A line wider than the array is processed in tiles; each tile gets
//! its own `ClearLine` and the same commands, of which [`feed_tile`] skips those that
//! cannot change the tile (same final state).
//!
//! [`SceneStream`] is that stream for a whole scene; the renderer
//! ([`crate::render::render_frame`]) feeds its tiles through [`feed_tile`], and the
//! testbenches take their stimulus from [`SceneStream::rows`].

use crate::frontend::{self, FrontError, Projector};
use crate::pixel_array::{Command, PixelArray};
use crate::render::{render_frame, Frame, SpanSource};
use crate::scene::LoadedScene;
use crate::setup::SetupError;
use crate::shadow::{self, Shading, ShadowError, ShadowForm, ShadowStats};
use pixelproc_formats::{pack_rgb, Attr, SpanWord};
use thiserror::Error;

/// Why a scene's command stream cannot be built.
#[derive(Debug, Error)]
pub enum StreamError {
    /// Front-end failure.
    #[error(transparent)]
    Front(#[from] FrontError),
    /// Span setup failure.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// Shadow failure.
    #[error(transparent)]
    Shadow(#[from] ShadowError),
}

/// The scene's background as RGB8: each channel clamped to 0..1, times 255, rounded.
pub fn background_rgb8(ls: &LoadedScene) -> [u8; 3] {
    ls.scene
        .background
        .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// Where the array's commands go, one call per clock: the pixel-processor array itself,
/// or a recorder.
pub trait CommandSink {
    /// A span word (the same clock as `Command::Span(*w)`).
    fn span(&mut self, w: &SpanWord);
    /// Any other command.
    fn command(&mut self, c: &Command);
}

impl CommandSink for PixelArray {
    #[inline]
    fn span(&mut self, w: &SpanWord) {
        self.step_span(w);
    }
    #[inline]
    fn command(&mut self, c: &Command) {
        self.step(c);
    }
}

impl CommandSink for Vec<Command> {
    fn span(&mut self, w: &SpanWord) {
        self.push(Command::Span(*w));
    }
    fn command(&mut self, c: &Command) {
        self.push(*c);
    }
}

/// Feeds one tile (processors for columns `base .. base + n`) of one row: `ClearLine{bg}`,
/// the row's OP span words `ops` that touch the tile (the caller's choice: an OP span
/// outside a tile is a no-op there), then the row's other commands `cmds`, skipping those
/// that cannot change the tile, with the same final state as feeding all of them:
/// - an SP span that does not touch the tile toggles nothing there;
/// - an EV span ORs DSF into FSF; where no span of its volume touched the tile (and no IF),
///   DSF is what it was after the previous volume's end, when FSF already absorbed it, so
///   the OR changes nothing: it is skipped too (its own range test still applies if it
///   touches the tile);
/// - IF spans and controls always go through; a `Check` only where its range touches.
pub fn feed_tile<'a>(
    sink: &mut impl CommandSink,
    bg: u32,
    ops: impl IntoIterator<Item = &'a SpanWord>,
    cmds: &[Command],
    base: u32,
    n: u32,
) {
    sink.command(&Command::ClearLine { bg });
    for w in ops {
        sink.span(w);
    }
    let touches = |xl: u16, xr: u16| (xl as u32) < base + n && (xr as u32) >= base && xl <= xr;
    let mut touched = false;
    for c in cmds {
        match c {
            Command::Span(w) => match w.attr {
                Attr::Op | Attr::Sp => {
                    if touches(w.xl, w.xr) {
                        touched = true;
                        sink.command(c);
                    }
                }
                Attr::If => {
                    touched = true;
                    sink.command(c);
                }
                Attr::Ev => {
                    if touched || touches(w.xl, w.xr) {
                        sink.command(c);
                    }
                    touched = false;
                }
            },
            Command::Check { xl, xr } => {
                if touches(*xl, *xr) {
                    sink.command(c);
                }
                touched = false;
            }
            _ => sink.command(c),
        }
    }
}

/// The per-row and per-tile command stream of a scene (see the module header).
pub struct SceneStream {
    /// Background, RGB8.
    pub bg: [u8; 3],
    /// The OP span words per row.
    pub spans: SpanSource,
    /// Per row, the shadow commands after the OP spans (empty without shadows).
    pub shadow: Vec<Vec<Command>>,
    /// Shadow statistics, summed over the lights.
    pub shadow_stats: ShadowStats,
}

impl SceneStream {
    /// The stream of a loaded scene: front end, span setup, then the shadow commands of
    /// the lights `shadow_lights` (indices into the scene's lights, in this order) in
    /// shadow form `form`.
    pub fn of_scene(
        ls: &LoadedScene,
        shadow_lights: &[usize],
        form: ShadowForm,
        shading: Shading,
    ) -> Result<SceneStream, StreamError> {
        let (w, h) = (ls.scene.width, ls.scene.height);
        let channels = match shading {
            Shading::Exact => shadow_lights,
            Shading::Table => &[],
        };
        let projected = frontend::project_shaded(ls, channels)?;
        let spans = SpanSource::new(&projected.array_tris(), w, h)?;
        let mut stream = SceneStream {
            bg: background_rgb8(ls),
            spans,
            shadow: vec![Vec::new(); h as usize],
            shadow_stats: ShadowStats::default(),
        };
        if !shadow_lights.is_empty() {
            let lights = shadow::shadow_lights(ls, shadow_lights)?;
            let pj = Projector::new(ls);
            for l in &lights {
                let sc = shadow::shadow_commands(ls, &pj, std::slice::from_ref(l), form)?;
                for (dst, add) in stream.shadow.iter_mut().zip(sc.rows) {
                    dst.extend(add);
                }
                stream.shadow_stats.volumes += sc.stats.volumes;
                stream.shadow_stats.span_words += sc.stats.span_words;
                stream.shadow_stats.eye_inside += sc.stats.eye_inside;
                stream.shadow_stats.near_caps += sc.stats.near_caps;
            }
        }
        Ok(stream)
    }

    /// Screen width.
    pub fn width(&self) -> u32 {
        self.spans.width()
    }

    /// Screen height.
    pub fn height(&self) -> u32 {
        self.spans.height()
    }

    /// Background, RGB888 packed (the `ClearLine` operand).
    pub fn bg_packed(&self) -> u32 {
        pack_rgb(self.bg)
    }

    /// The commands of row `j` after its `ClearLine`: OP span words, then shadow commands.
    pub fn row(&self, j: u32) -> Vec<Command> {
        let ops = self.spans.row_spans(j).iter().copied().map(Command::Span);
        ops.chain(self.shadow[j as usize].iter().copied()).collect()
    }

    /// [`SceneStream::row`] for every row, top to bottom.
    pub fn rows(&self) -> Vec<Vec<Command>> {
        (0..self.height()).map(|j| self.row(j)).collect()
    }

    /// The commands the renderer feeds the tile of row `j` starting at column `base` on an
    /// array of `n` processors, `ClearLine` first ([`feed_tile`]).
    pub fn tile(&self, j: u32, base: u32, n: u32) -> Vec<Command> {
        let ops = self.spans.row_spans(j).iter().filter(|w| {
            let (a, b) = (w.xl as u32 / n, w.xr as u32 / n);
            a <= base / n && base / n <= b
        });
        let mut out = Vec::new();
        feed_tile(
            &mut out,
            self.bg_packed(),
            ops,
            &self.shadow[j as usize],
            base,
            n,
        );
        out
    }

    /// Renders the stream on an array of `array_width` processors
    /// ([`crate::render::render_frame`]).
    pub fn render(&self, array_width: usize) -> Frame {
        render_frame(&self.spans, self.bg, array_width, |j, cmds| {
            cmds.extend_from_slice(&self.shadow[j as usize])
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{Effects, Overrides};
    use crate::scene::load_builtin;

    /// Feeding every tile of every row its [`SceneStream::tile`] commands gives the
    /// rendered frame, and so does feeding every tile the whole row.
    #[test]
    fn the_stream_drives_the_array_to_the_rendered_frame() {
        let mut ls = load_builtin("default").unwrap();
        ls.scene.width = 48;
        ls.scene.height = 20;
        let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
        assert!(!fx.shadow_lights.is_empty());
        let s = SceneStream::of_scene(&ls, &fx.shadow_lights, fx.shadow_form, fx.shading).unwrap();
        let n = 16u32;
        let frame = s.render(n as usize);
        let mut arr = PixelArray::new(n as usize, 0);
        for j in 0..s.height() {
            let row = s.row(j);
            for base in (0..s.width()).step_by(n as usize) {
                for whole in [false, true] {
                    arr.set_base(base);
                    if whole {
                        arr.run_line(s.bg_packed(), &row);
                    } else {
                        for c in s.tile(j, base, n) {
                            arr.step(&c);
                        }
                    }
                    let k = ((s.width() - base) as usize).min(n as usize);
                    let at = (j * s.width() + base) as usize;
                    assert_eq!(
                        arr.state()[..k],
                        frame.px[at..at + k],
                        "row {j} tile {base}"
                    );
                }
            }
        }
        assert!(
            frame.px.iter().any(|p| p.mask != 0),
            "some pixel is shadowed"
        );
    }
}
