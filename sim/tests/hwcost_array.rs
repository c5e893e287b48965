//! The array's closed-form cycle model (`hwcost::array`) against the core's cycle-level
//! model (`core_model::CoreModel`, the count the Verilog run reports) on whole frames:
//! several scenes and sizes, with and without shadows, array widths that do and do not
//! divide the width.

use pixelproc_sim::core_model::{run_frame, CoreModel, CoreStream, Stalls, DEFAULT_IN_ABITS};
use pixelproc_sim::hwcost::array::{core_cycles, no_aa_cost, stream_tile_lines};
use pixelproc_sim::hwcost::{Frame, HwConfig};
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::{load_builtin, LoadedScene};
use pixelproc_sim::shadow::{shadow_lights, FactorTable};
use pixelproc_sim::stream::SceneStream;

/// The cycle model's count for `s` on `n` processors: no stalls (a beat offered every
/// clock, the sink always ready).
fn cycle_model(s: &SceneStream, n: usize, table: Option<&FactorTable>) -> (u64, CoreStream) {
    let cs = CoreStream::of_scene(s, n, table).unwrap();
    let mut m = CoreModel::new(n, table.is_some(), false, DEFAULT_IN_ABITS).unwrap();
    let run = run_frame(
        &mut m,
        &cs.beats,
        cs.pixels(),
        &mut Stalls::new(1, 0, 0),
        1 << 34,
    )
    .unwrap();
    assert!(!run.err && !run.overflow);
    (run.cycles.cycles, cs)
}

fn scene(name: &str, w: u32, h: u32) -> LoadedScene {
    let mut ls = load_builtin(name).unwrap();
    ls.scene.width = w;
    ls.scene.height = h;
    ls
}

/// Scene streams with and without shadows, and the factor table of the shadowed one.
fn streams(ls: &LoadedScene) -> Vec<(SceneStream, Option<FactorTable>)> {
    let mut out = Vec::new();
    for no_shadows in [true, false] {
        let ov = Overrides {
            no_shadows,
            ..Default::default()
        };
        let fx = Effects::resolve(ls, &ov).unwrap();
        let s = SceneStream::of_scene(ls, &fx.shadow_lights, fx.shadow_form, fx.shading).unwrap();
        let table = (!fx.shadow_lights.is_empty()).then(|| {
            let lights = shadow_lights(ls, &fx.shadow_lights).unwrap();
            FactorTable::for_mode(ls, &lights, fx.shading)
        });
        out.push((s, table));
    }
    out
}

#[test]
fn closed_form_equals_the_cycle_model_on_whole_frames() {
    let mut checked = 0;
    let sizes = [
        ("default", 40, 12),
        ("default", 160, 90),
        ("default", 97, 31),
        ("boxes", 120, 68),
    ];
    for (name, w, h) in sizes {
        let ls = scene(name, w, h);
        for (s, table) in streams(&ls) {
            for n in [1usize, 7, 8, 16, 64] {
                let (want, cs) = cycle_model(&s, n, table.as_ref());
                let got = core_cycles(cs.table_beats as u64, stream_tile_lines(&s, n as u32));
                assert_eq!(
                    got,
                    want,
                    "{name} {w}x{h} N={n} shadows={}",
                    table.is_some()
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 40);
}

/// The method entry point on snapped triangles (no shadows) equals the cycle model on the
/// stream of the same triangles.
#[test]
fn no_aa_cost_equals_the_cycle_model() {
    for (w, h, n) in [(160u32, 90u32, 64u32), (200, 50, 8), (61, 23, 16)] {
        let ls = scene("default", w, h);
        let proj = pixelproc_sim::frontend::project(&ls).unwrap();
        let tris = proj.array_tris();
        let s = SceneStream {
            bg: [0, 0, 0],
            spans: pixelproc_sim::render::SpanSource::new(&tris, w, h).unwrap(),
            shadow: vec![Vec::new(); h as usize],
            shadow_stats: Default::default(),
        };
        let (want, _) = cycle_model(&s, n as usize, None);
        let cfg = HwConfig::new(n as u64, 81.04).unwrap();
        let frame = Frame {
            tris: &tris,
            width: w,
            height: h,
        };
        let got = no_aa_cost(&frame, &cfg).unwrap();
        assert_eq!(got.cycles, want, "{w}x{h} N={n}");
    }
}

/// A single pass of sample rows at the pixel centres, one sample per pixel, is the no-AA
/// frame; and a two-tile-line frame by hand through the public entry point.
#[test]
fn one_centre_pass_is_the_plain_frame() {
    use pixelproc_sim::hwcost::array::{sample_rows_cycles, SampleRows};
    let ls = scene("default", 130, 40);
    let proj = pixelproc_sim::frontend::project(&ls).unwrap();
    let tris = proj.array_tris();
    let frame = Frame {
        tris: &tris,
        width: 130,
        height: 40,
    };
    for n in [8u32, 64] {
        let cfg = HwConfig::new(n as u64, 81.04).unwrap();
        let plain = no_aa_cost(&frame, &cfg).unwrap().cycles;
        let pass = SampleRows {
            dy_q8: 128,
            rows: 0..40,
            num: 1,
            den: 1,
            width: 130,
        };
        let (c, samples) = sample_rows_cycles(&frame, n, &[pass]).unwrap();
        assert_eq!((c, samples), (plain, 130 * 40));
    }
}

/// The Verilog run of `docs/core.md` ("Cycle accounting": @default 640×360 with shadows,
/// no stalls, N = 64): 248,931 cycles, the Verilator run's count with the nine-stage
/// shading step (`pixelproc testbench @default --frame --sim verilator --array-width 64`;
/// 248,930 with eight stages, 248,929 with seven, 248,927 with five).
#[test]
fn closed_form_gives_the_verilog_figures_of_the_core_page() {
    let ls = load_builtin("default").unwrap();
    let (s, table) = streams(&ls).pop().unwrap();
    let table_beats = pixelproc_sim::core_model::table_beats(table.as_ref().unwrap())
        .unwrap()
        .len() as u64;
    assert_eq!(core_cycles(table_beats, stream_tile_lines(&s, 64)), 248_931);
}
