//! The RustHDL core against its cycle-level golden model, every register and output port
//! every clock, on whole (small) frames with random gaps and back-pressure; the pixels
//! the RTL streams out must be the golden renderer's image, pixel for pixel.

use pixelproc_rtl::core_top::PixelprocCore;
use pixelproc_sim::core_model::{CoreModel, CoreStream, Stalls};
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::load_builtin;
use pixelproc_sim::shadow::{shadow_lights, FactorTable};
use pixelproc_sim::stream::SceneStream;
use pixelproc_testbench::core_tb::{compare_core, SMALL_IN_ABITS};
use rust_hdl::prelude::*;

fn run(scene: &str, w: u32, h: u32, n: usize, shadows: bool, gap: u32, stall: u32) {
    let mut ls = load_builtin(scene).unwrap();
    ls.scene.width = w;
    ls.scene.height = h;
    let ov = Overrides {
        no_shadows: !shadows,
        ..Default::default()
    };
    let fx = Effects::resolve(&ls, &ov).unwrap();
    assert_eq!(!fx.shadow_lights.is_empty(), shadows, "{scene}");
    let golden = pixelproc_sim::pipeline::render(&ls, &fx).unwrap();
    let frame = golden.frame.unwrap();
    let s = SceneStream::of_scene(&ls, &fx.shadow_lights, fx.shadow_form, fx.shading).unwrap();
    let table = shadows.then(|| {
        FactorTable::for_mode(
            &ls,
            &shadow_lights(&ls, &fx.shadow_lights).unwrap(),
            fx.shading,
        )
    });
    let cs = CoreStream::of_scene(&s, n, table.as_ref()).unwrap();
    let mut uut = PixelprocCore::<3, 4>::new(n, shadows, true).unwrap();
    uut.connect_all();
    let mut model = CoreModel::new(n, shadows, true, SMALL_IN_ABITS).unwrap();
    let mut st = Stalls::new(7, gap, stall);
    let r = compare_core(
        &mut uut,
        &mut model,
        &cs.beats,
        cs.pixels(),
        &mut st,
        2_000_000,
    )
    .unwrap();
    if let Some(m) = &r.mismatch {
        panic!("{scene} N {n}: after cycle {}: {}", m.cycle, m.what);
    }
    assert_eq!(r.pixels.len(), cs.pixels());
    for (k, (p, _)) in r.pixels.iter().enumerate() {
        let (x, y) = cs.position(k);
        let i = (y * w + x) as usize;
        let g = &golden.image.data[3 * i..3 * i + 3];
        assert_eq!(
            pixelproc_formats::unpack_rgb(p.rgb),
            [g[0], g[1], g[2]],
            "{scene} ({x}, {y})"
        );
        assert_eq!(
            p.state(),
            frame.px[i].without_shade_channel(),
            "{scene} ({x}, {y})"
        );
    }
    assert!(
        r.cycles.hazard_stall > 0 || n < 8,
        "the readout hazard was exercised"
    );
    println!(
        "{scene} {w}x{h} N {n}: {} cycles, {} beats, input stalls {}, hazard stalls {}, output stalls {} ({:.1} s)",
        r.cycles.cycles, r.cycles.beats, r.cycles.in_stall, r.cycles.hazard_stall, r.cycles.out_stall, r.seconds
    );
}

#[test]
fn default_scene_with_shadows_and_stalls() {
    run("default", 36, 10, 8, true, 30, 40);
}

#[test]
fn no_shadows_width_not_a_multiple_of_n() {
    run("default", 23, 6, 5, false, 10, 60);
}
