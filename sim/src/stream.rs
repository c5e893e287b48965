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
use crate::raster::divisor::FloorDivisor;
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
    /// Two span words in successive clocks: the same as `span(a)` then `span(b)` (the
    /// array applies a polygon's span and its shade-channel copy in one pass).
    fn span_pair(&mut self, a: &SpanWord, b: &SpanWord) {
        self.span(a);
        self.span(b);
    }
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
    #[inline]
    fn span_pair(&mut self, a: &SpanWord, b: &SpanWord) {
        self.step_span_pair(a, b);
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

/// Feeds one tile as [`feed_tile`] does, with the row's other commands already chosen
/// by a [`TileRouter`]: `ClearLine{bg}`, the OP span words `ops`, then `cmds[k]` for each
/// `k` of `list`.
pub fn feed_routed<'a>(
    sink: &mut impl CommandSink,
    bg: u32,
    ops: impl IntoIterator<Item = &'a SpanWord>,
    cmds: &[Command],
    list: &[u32],
) {
    feed_routed_with::<false>(sink, bg, ops, cmds, list)
}

/// [`feed_routed`] for a frame with shade channels: an OP word followed by a shade-channel
/// 1 word goes to the sink as a pair ([`CommandSink::span_pair`]: a polygon's span and its
/// copy's, which the array applies in one pass). The same clocks as [`feed_routed`].
pub fn feed_routed_pairs<'a>(
    sink: &mut impl CommandSink,
    bg: u32,
    ops: impl IntoIterator<Item = &'a SpanWord>,
    cmds: &[Command],
    list: &[u32],
) {
    feed_routed_with::<true>(sink, bg, ops, cmds, list)
}

#[inline(always)]
fn feed_routed_with<'a, const PAIRS: bool>(
    sink: &mut impl CommandSink,
    bg: u32,
    ops: impl IntoIterator<Item = &'a SpanWord>,
    cmds: &[Command],
    list: &[u32],
) {
    sink.command(&Command::ClearLine { bg });
    let mut ops = ops.into_iter().peekable();
    while let Some(w) = ops.next() {
        match PAIRS {
            true => match ops.next_if(|n| n.attr == Attr::Op && n.chan == 1) {
                Some(n) => sink.span_pair(w, n),
                None => sink.span(w),
            },
            false => sink.span(w),
        }
    }
    for &k in list {
        sink.command(&cmds[k as usize]);
    }
}

/// [`feed_tile`]'s choice of commands for every tile of a row at once: one pass over the
/// row's commands instead of one per tile. `lists[t]` receives, in order, the indices
/// into `cmds` of the commands `feed_tile` passes to tile `t` (columns `t·n .. t·n + n`);
/// a command goes to the tiles it touches, an IF span or a control to all, an EV span to
/// its own tiles and those a span of its volume touched (all after an IF), a `Check` to
/// its own tiles. The scratch state is kept between rows (no allocation per row).
#[derive(Debug, Default)]
pub struct TileRouter {
    vol: VolumeTiles,
}

/// A row's tiles of `n` processors: which of them a column range touches, with the
/// column's tile found by one multiplication ([`FloorDivisor`]) rather than a division
/// (a row with thousands of shadow spans asks several times per span).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowTiles {
    div: FloorDivisor,
    tiles: usize,
}

impl RowTiles {
    /// `tiles` tiles of `n > 0` processors (`n < 2^63`).
    pub(crate) fn new(n: usize, tiles: usize) -> RowTiles {
        RowTiles {
            div: FloorDivisor::new(n as i128).expect("tile width is positive"),
            tiles,
        }
    }

    /// The tiles that columns `xl..=xr` touch, `[a, b]`, if any ([`feed_tile`]'s
    /// `touches`).
    #[inline]
    pub(crate) fn span(&self, xl: u16, xr: u16) -> Option<(usize, usize)> {
        let tile = |x: u16| self.div.floor(x as i64) as usize;
        (xl <= xr)
            .then(|| (tile(xl), tile(xr)))
            .filter(|&(a, _)| a < self.tiles)
            .map(|(a, b)| (a, b.min(self.tiles - 1)))
    }
}

/// Which tiles the current volume's spans touched since the last EV or `Check`: the tiles
/// an EV span goes to besides its own ([`TileRouter`], and [`crate::pixel_array::RowFlags`]
/// which applies the same choice to a whole row).
#[derive(Debug, Default)]
pub(crate) struct VolumeTiles {
    /// Per tile: touched by a span since the last EV or `Check`.
    touched: Vec<bool>,
    /// The tiles whose `touched` is set (to clear them without a sweep).
    marked: Vec<usize>,
    /// An IF span since the last EV or `Check`: every tile counts as touched.
    all: bool,
}

impl VolumeTiles {
    /// A row of `tiles` tiles, none touched.
    pub(crate) fn start(&mut self, tiles: usize) {
        self.touched.clear();
        self.touched.resize(tiles, false);
        self.marked.clear();
        self.all = false;
    }

    /// A span touched tiles `a..=b`.
    #[inline]
    pub(crate) fn touch(&mut self, a: usize, b: usize) {
        for t in a..=b {
            if !self.touched[t] {
                self.touched[t] = true;
                self.marked.push(t);
            }
        }
    }

    /// An IF span: every tile counts as touched.
    pub(crate) fn touch_all(&mut self) {
        self.all = true;
    }

    /// Whether an IF span came since the last EV or `Check`.
    pub(crate) fn all(&self) -> bool {
        self.all
    }

    /// The touched tiles, in the order they were first touched.
    pub(crate) fn marked(&self) -> &[usize] {
        &self.marked
    }

    /// Ends a volume: no tile touched.
    pub(crate) fn reset(&mut self) {
        for &t in &self.marked {
            self.touched[t] = false;
        }
        self.marked.clear();
        self.all = false;
    }
}

impl TileRouter {
    /// Fills `lists` (one per tile, cleared first) for the commands `cmds` on tiles of `n`
    /// processors.
    pub fn route(&mut self, cmds: &[Command], n: u32, lists: &mut [Vec<u32>]) {
        let tiles = lists.len();
        for l in lists.iter_mut() {
            l.clear();
        }
        self.vol.start(tiles);
        let row_tiles = RowTiles::new(n as usize, tiles);
        let range = |xl: u16, xr: u16| row_tiles.span(xl, xr);
        for (i, c) in cmds.iter().enumerate() {
            let i = i as u32;
            match c {
                Command::Span(w) => match w.attr {
                    Attr::Op | Attr::Sp => {
                        if let Some((a, b)) = range(w.xl, w.xr) {
                            for list in &mut lists[a..=b] {
                                list.push(i);
                            }
                            self.vol.touch(a, b);
                        }
                    }
                    Attr::If => {
                        self.vol.touch_all();
                        lists.iter_mut().for_each(|l| l.push(i));
                    }
                    Attr::Ev => {
                        if self.vol.all() {
                            lists.iter_mut().for_each(|l| l.push(i));
                        } else {
                            let own = range(w.xl, w.xr);
                            for &t in self.vol.marked() {
                                if own.is_none_or(|(a, b)| t < a || t > b) {
                                    lists[t].push(i);
                                }
                            }
                            if let Some((a, b)) = own {
                                for l in &mut lists[a..=b] {
                                    l.push(i);
                                }
                            }
                        }
                        self.vol.reset();
                    }
                },
                Command::Check { xl, xr } => {
                    if let Some((a, b)) = range(*xl, *xr) {
                        for l in &mut lists[a..=b] {
                            l.push(i);
                        }
                    }
                    self.vol.reset();
                }
                _ => lists.iter_mut().for_each(|l| l.push(i)),
            }
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
            // Every light's commands on each row, one light's after the other's.
            let sc = shadow::shadow_commands_of(&shadow::occluders(ls), ls, &pj, &lights, form)?;
            stream.shadow = sc.rows;
            stream.shadow_stats = sc.stats;
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
        render_frame(&self.spans, self.bg, array_width, &self.shadow)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{Effects, Overrides};
    use crate::scene::load_builtin;

    /// The tiles a column range touches, by multiplication, are those of dividing each end
    /// column by the tile width: every range of columns `0..300` (empty ones included) on
    /// tile widths 1 to 70 and on rows shorter and longer than the columns.
    #[test]
    fn row_tiles_are_those_of_dividing_by_the_tile_width() {
        for n in 1..=70usize {
            for tiles in [1, 3, 300usize.div_ceil(n), 400] {
                let rt = RowTiles::new(n, tiles);
                for xl in 0..300u16 {
                    for xr in 0..300u16 {
                        let (a, b) = (xl as usize / n, xr as usize / n);
                        let want = (xl <= xr && a < tiles).then(|| (a, b.min(tiles - 1)));
                        assert_eq!(rt.span(xl, xr), want, "n {n} tiles {tiles} {xl}..={xr}");
                    }
                }
            }
        }
    }

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

    /// The router picks, for every tile, exactly the commands `feed_tile` passes to it, in
    /// the same order: random rows of spans (every attribute, empty and out-of-screen
    /// ranges), checks and controls, on several array widths.
    #[test]
    fn the_router_sends_each_tile_what_feed_tile_sends() {
        let mut rng = crate::rng::XorShift64Star(0x005e_ed0f_7113);
        let mut router = TileRouter::default();
        for case in 0..400 {
            let n = [1u32, 3, 8, 16, 64][case % 5];
            let width = 1 + (rng.next_u64() % 300) as u32;
            let tiles = width.div_ceil(n) as usize;
            let x =
                |r: &mut crate::rng::XorShift64Star| (r.next_u64() % (width as u64 + 40)) as u16;
            let cmds: Vec<Command> = (0..rng.next_u64() % 60)
                .map(|_| match rng.next_u64() % 10 {
                    0..=5 => Command::Span(SpanWord {
                        attr: [Attr::Op, Attr::Sp, Attr::Sp, Attr::Ev, Attr::Ev, Attr::If]
                            [(rng.next_u64() % 6) as usize],
                        xl: x(&mut rng),
                        xr: x(&mut rng),
                        ..Default::default()
                    }),
                    6 => Command::Check {
                        xl: x(&mut rng),
                        xr: x(&mut rng),
                    },
                    7 => Command::ClearFlags,
                    8 => Command::LatchShadow { bit: 2 },
                    _ => Command::AccumulateShadow,
                })
                .collect();
            let mut lists = vec![Vec::new(); tiles];
            router.route(&cmds, n, &mut lists);
            for (t, list) in lists.iter().enumerate() {
                let base = t as u32 * n;
                let (mut want, mut got) = (Vec::new(), Vec::new());
                feed_tile(&mut want, 0, [], &cmds, base, n);
                feed_routed(&mut got, 0, [], &cmds, list);
                assert_eq!(got, want, "case {case}, n {n}, tile {t}");
            }
        }
    }

    /// [`RowFlags::run`] on a whole row gives the state of feeding each tile its polygon
    /// spans and then the shadow commands the router picks for it ([`feed_routed`], the
    /// way rows were rendered before): random rows of polygon spans, then volumes of SP,
    /// EV and IF spans (half of them in the plane of a polygon span, so depth ties occur,
    /// some with depths and slopes at their formats' limits; ranges empty, cut by tiles
    /// and off the screen), `Check`s and every control, on
    /// screens that are not a multiple of the tile width; half the rows start with the
    /// flags an earlier light's volumes left.
    #[test]
    fn row_wide_flags_equal_the_routed_tiles() {
        use crate::pixel_array::{is_flag_command, RowFlags};
        let mut rng = crate::rng::XorShift64Star(0x000f_1a95_eed5);
        let (mut router, mut flags) = (TileRouter::default(), RowFlags::default());
        let mut shadowed = 0;
        for case in 0..600 {
            let mut r = |m: u64| rng.next_u64() % m;
            let n = [1usize, 3, 8, 16, 64][case % 5];
            let width = 1 + r(300) as usize;
            let tiles = width.div_ceil(n);
            let x = |r: &mut dyn FnMut(u64) -> u64| r(width as u64 + 40) as u16;
            let plane = |r: &mut dyn FnMut(u64) -> u64| {
                ((r(1 << 20) + 16) << 12, r(1 << 16) as i64 - (1 << 15))
            };
            let ops: Vec<SpanWord> = (0..r(12))
                .map(|_| {
                    let (zl, dz) = plane(&mut r);
                    let xl = x(&mut r);
                    SpanWord {
                        xl,
                        xr: xl + r(80) as u16,
                        zl,
                        dz,
                        ..Default::default()
                    }
                })
                .collect();
            let gen = |r: &mut dyn FnMut(u64) -> u64, len: u64| -> Vec<Command> {
                (0..len)
                    .map(|_| match r(12) {
                        0..=6 => {
                            let attr =
                                [Attr::Sp, Attr::Sp, Attr::Ev, Attr::Ev, Attr::If][r(5) as usize];
                            let (zl, dz) = match (ops.is_empty(), r(2)) {
                                (false, 0) => {
                                    let o = ops[r(ops.len() as u64) as usize];
                                    (o.zl, o.dz)
                                }
                                // Depths to the top of `ZL`'s 36 bits, slopes to `dZ`'s
                                // 38-bit limits: `Z` goes negative and past 32 bits.
                                _ if r(3) == 0 => (r(1 << 36), r(1 << 38) as i64 - (1 << 37)),
                                _ => plane(r),
                            };
                            let xl = x(r);
                            Command::Span(SpanWord {
                                attr,
                                xl,
                                xr: (xl + r(120) as u16).saturating_sub(r(2) as u16 * 30),
                                zl,
                                dz,
                                ..Default::default()
                            })
                        }
                        7 => Command::Check { xl: x(r), xr: x(r) },
                        8 => Command::ClearFlags,
                        9 => Command::LatchShadow { bit: r(8) as u8 },
                        10 => Command::AccumulateShadow,
                        _ => Command::Nop,
                    })
                    .collect()
            };
            // An earlier light's commands, ending its last volume, leave flags set where
            // the row's own commands may reach no span: the row is run from that state.
            let len = r(2) * r(30);
            let mut pre = gen(&mut r, len);
            pre.push(Command::Span(SpanWord {
                attr: Attr::Ev,
                xl: 1,
                xr: 0,
                ..Default::default()
            }));
            let len = r(60);
            let cmds = gen(&mut r, len);
            assert!(cmds.iter().all(is_flag_command));
            let all: Vec<Command> = pre.iter().chain(&cmds).copied().collect();
            let (mut lists, mut pre_lists) = (vec![Vec::new(); tiles], vec![Vec::new(); tiles]);
            router.route(&all, n as u32, &mut lists);
            router.route(&pre, n as u32, &mut pre_lists);
            let (mut want, mut got) = (Vec::new(), Vec::new());
            for t in 0..tiles {
                let base = (t * n) as u32;
                let k = (width - t * n).min(n);
                let mut arr = PixelArray::new(n, base);
                feed_routed(&mut arr, 7, ops.iter(), &all, &lists[t]);
                want.extend_from_slice(&arr.state()[..k]);
                feed_routed(&mut arr, 7, ops.iter(), &pre, &pre_lists[t]);
                got.extend_from_slice(&arr.state()[..k]);
            }
            flags.run(&mut got, &cmds, n);
            assert_eq!(got, want, "case {case}: n {n}, width {width}");
            shadowed += want.iter().filter(|p| p.fsf || p.mask != 0).count();
        }
        assert!(shadowed > 10_000, "{shadowed}");
    }
}
