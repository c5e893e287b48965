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

/// TABLE beats in the middle of readouts: after every TILE and END beat, 24 TABLE beats
/// rewrite the entries the frame's covered pixels use, round robin, each with a value
/// never written before. They issue one per clock while the previous tile-line is swept
/// out, so pixels read the table at the clocks right before and after writes to their
/// own entry: a write that landed one edge earlier or later than the model's
/// `TABLE_WRITE_DELAY` (or in the wrong bank, or with another group's address or data)
/// changes a pixel. RTL against the model only (the rewritten table is not the golden
/// renderer's), with and without stalls.
#[test]
fn table_writes_during_readout_land_when_the_model_says() {
    use pixelproc_formats::core_stream::{
        shade_addr, KIND_END, KIND_TABLE, KIND_TILE, SHADE_ADDR_BITS, TABLE_ADDR, TABLE_DROP,
        TABLE_FACTOR,
    };
    use pixelproc_formats::Z_FAR;
    use pixelproc_sim::core_model::Beat;
    let (w, h, n) = (36, 10, 8);
    let mut ls = load_builtin("default").unwrap();
    ls.scene.width = w;
    ls.scene.height = h;
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    let golden = pixelproc_sim::pipeline::render(&ls, &fx).unwrap();
    let frame = golden.frame.unwrap();
    let s = SceneStream::of_scene(&ls, &fx.shadow_lights, fx.shadow_form, fx.shading).unwrap();
    let table = FactorTable::for_mode(
        &ls,
        &shadow_lights(&ls, &fx.shadow_lights).unwrap(),
        fx.shading,
    );
    let cs = CoreStream::of_scene(&s, n, Some(&table)).unwrap();
    let mut used: Vec<u64> = frame
        .px
        .iter()
        .filter(|p| p.zb != Z_FAR)
        .map(|p| (shade_addr(p.nclass, p.mask, p.count) & ((1 << SHADE_ADDR_BITS) - 1)) as u64)
        .collect();
    used.sort_unstable();
    used.dedup();
    // Entries in more than one bank group (address bits 14:13), so the group copies of the
    // write registers are all exercised.
    let groups: std::collections::BTreeSet<u64> = used.iter().map(|a| a >> 13).collect();
    assert!(used.len() >= 2 && groups.len() >= 2, "{used:?}");
    let mut beats = Vec::new();
    let mut k = 0u64;
    for b in &cs.beats {
        beats.push(*b);
        if b.kind as u64 == KIND_TILE || b.kind as u64 == KIND_END {
            for _ in 0..24 {
                k += 1;
                beats.push(Beat::with_fields(
                    KIND_TABLE,
                    &[
                        (TABLE_ADDR, used[k as usize % used.len()]),
                        (TABLE_FACTOR, (37 * k + 11) % 512),
                        (TABLE_DROP, (101 * k + 3) % 512),
                    ],
                ));
            }
        }
    }
    for (seed, gap, stall) in [(1, 0, 0), (5, 25, 30)] {
        let mut uut = PixelprocCore::<3, 4>::new(n, true, true).unwrap();
        uut.connect_all();
        let mut model = CoreModel::new(n, true, true, SMALL_IN_ABITS).unwrap();
        let mut st = Stalls::new(seed, gap, stall);
        let r = compare_core(
            &mut uut,
            &mut model,
            &beats,
            cs.pixels(),
            &mut st,
            2_000_000,
        )
        .unwrap();
        if let Some(m) = &r.mismatch {
            panic!(
                "gap {gap} stall {stall}: after cycle {}: {}",
                m.cycle, m.what
            );
        }
        assert_eq!(r.pixels.len(), cs.pixels());
    }
}
