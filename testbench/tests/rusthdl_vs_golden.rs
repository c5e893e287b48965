//! Clock-by-clock comparison of the RustHDL array with the golden model (small arrays,
//! few hundred cycles, so it stays fast in debug builds).

use pixelproc_sim::pixel_array::Command;
use pixelproc_testbench::compare::{compare_commands, compare_stream};
use pixelproc_testbench::stimulus::{
    corner_cases, random_command, random_triangles, LineStream, Rng,
};

fn assert_exact(c: &pixelproc_testbench::compare::Comparison) {
    if let Some(m) = &c.mismatch {
        panic!("{m}");
    }
    assert!(c.cycles > 0 && c.comparisons > 0);
}

#[test]
fn corner_cases_with_shadows_n8() {
    let cmds: Vec<(u32, Command)> = corner_cases(8).into_iter().map(|c| (0, c)).collect();
    let c = compare_commands(&cmds, 8, true, None).unwrap();
    assert_exact(&c);
}

#[test]
fn random_commands_across_tiles_n8() {
    let mut rng = Rng::new(7);
    let cmds: Vec<(u32, Command)> = (0..300)
        .map(|_| (rng.range(0, 40) as u32, random_command(&mut rng, 48)))
        .collect();
    let c = compare_commands(&cmds, 8, true, None).unwrap();
    assert_exact(&c);
}

#[test]
fn random_triangles_tiled_without_shadows_n8() {
    let mut rng = Rng::new(11);
    let tris = random_triangles(&mut rng, 6, 20, 4);
    let s = LineStream::from_triangles(&tris, 20, 4, [10, 20, 30]).unwrap();
    assert!(s.span_words() > 4, "stimulus must contain spans");
    let c = compare_stream(&s, 8, false, None).unwrap();
    assert_exact(&c);
}

#[test]
fn a_shadow_stream_on_a_shadowless_array_is_reported_with_a_trace() {
    // The comparison must be able to fail: without parity logic the flags stay 0.
    let cmds: Vec<(u32, Command)> = corner_cases(8).into_iter().map(|c| (0, c)).collect();
    let dir = std::env::temp_dir().join(format!("pixelproc-tb-{}", std::process::id()));
    let c =
        pixelproc_testbench::compare::compare_commands_checked(&cmds, 8, false, false, Some(&dir))
            .unwrap();
    let m = c
        .mismatch
        .expect("flags differ, so a mismatch must be reported");
    // The difference lies in the shadow registers only (flags, WON, SH).
    assert_ne!(m.expected, m.got);
    assert_eq!(
        m.expected.without_shadow_regs(),
        m.got.without_shadow_regs()
    );
    let vcd = m.vcd.expect("a VCD is written");
    let text = std::fs::read_to_string(&vcd).unwrap();
    assert!(text.contains("$var") && text.contains("cmd_op"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn quick_check_is_bit_exact() {
    let s = pixelproc_testbench::quick_check().unwrap();
    assert!(s.outcome.bit_exact(), "{}", s.outcome);
    assert!(s.span_words > 0 && s.cycles > 0);
}

// ---- Real scenes: the golden pipeline's span-word streams.

use pixelproc_sim::pixel_array::{PixelArray, ProcState};
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::{load_builtin, load_with, parse, LoadedScene, MeshSource};
use pixelproc_testbench::scene_stream;

/// The default scene (3-D, one shadowing light) at `w × h` (same camera and aspect).
fn default_scene(w: u32, h: u32) -> (LoadedScene, Effects) {
    let mut ls = load_builtin("default").unwrap();
    ls.scene.width = w;
    ls.scene.height = h;
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    (ls, fx)
}

/// Per-pixel golden state of a stream fed to an `n`-wide array tile by tile, every
/// command to every tile (the testbench's feeding).
fn golden_frame(rows: &[Vec<Command>], bg: u32, width: u32, n: usize) -> Vec<ProcState> {
    let mut px = Vec::new();
    let mut a = PixelArray::new(n, 0);
    for r in rows {
        let mut base = 0;
        while base < width {
            a.set_base(base);
            a.run_line(bg, r);
            let k = ((width - base) as usize).min(n);
            px.extend_from_slice(&a.state()[..k]);
            base += n as u32;
        }
    }
    px
}

#[test]
fn default_scene_stream_is_the_pipelines() {
    // The stream must reproduce what `pipeline::render` computes (it feeds each tile only
    // the commands touching it, with a 64-wide array): depth, normal class, light mask.
    let (ls, fx) = default_scene(64, 36);
    assert!(
        !fx.shadow_lights.is_empty(),
        "the default scene has shadows"
    );
    let (rows, bg) = scene_stream(&ls, &fx).unwrap();
    let out = pixelproc_sim::pipeline::render(&ls, &fx).unwrap();
    let frame = out.frame.unwrap();
    let ours = golden_frame(&rows, bg, 64, 16);
    assert_eq!(ours.len(), frame.px.len());
    for (i, (a, b)) in ours.iter().zip(&frame.px).enumerate() {
        assert_eq!(
            (a.zb, a.nclass, a.mask, a.count),
            (b.zb, b.nclass, b.mask, b.count),
            "pixel {i}"
        );
    }
    let shadowed = ours.iter().filter(|s| s.mask != 0).count();
    let lit = ours
        .iter()
        .filter(|s| s.mask == 0 && s.zb != 0xff_ffff)
        .count();
    assert!(shadowed > 20 && lit > 200, "shadowed {shadowed}, lit {lit}");
}

#[test]
fn default_scene_all_rows_reduced_resolution_n16() {
    // Every scanline of the 3-D default scene with its shadow commands, at 64 × 36
    // (four tiles per row on a 16-processor array), every register compared every clock.
    let (ls, fx) = default_scene(64, 36);
    let (rows, bg) = scene_stream(&ls, &fx).unwrap();
    let cmds = rows.iter().flatten();
    let latch = cmds
        .clone()
        .filter(|c| matches!(c, Command::LatchShadow { .. }))
        .count();
    let shadow_spans = cmds
        .clone()
        .filter(|c| matches!(c, Command::Span(w) if w.attr != pixelproc_formats::Attr::Op))
        .count();
    assert!(
        latch == 36 && shadow_spans > 36,
        "latch {latch}, shadow spans {shadow_spans}"
    );
    let s = LineStream {
        width: 64,
        bg,
        lines: rows,
    };
    let c = compare_stream(&s, 16, true, None).unwrap();
    assert_exact(&c);
    assert!(c.span_words > 1000, "span words {}", c.span_words);
}

#[test]
fn default_scene_full_resolution_rows_n64() {
    // The three busiest scanlines of the 640 × 360 default scene, ten tiles each on a
    // 64-processor array.
    let (ls, fx) = default_scene(640, 360);
    let (rows, bg) = scene_stream(&ls, &fx).unwrap();
    // The three busiest rows.
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by_key(|&j| std::cmp::Reverse(rows[j].len()));
    let pick: Vec<Vec<Command>> = order[..3].iter().map(|&j| rows[j].clone()).collect();
    assert!(pick.iter().all(|r| r.len() > 10));
    let s = LineStream {
        width: 640,
        bg,
        lines: pick,
    };
    let c = compare_stream(&s, 64, true, None).unwrap();
    assert_exact(&c);
}

#[test]
fn screen_space_scene_with_decal_and_gouraud_n16() {
    let json = r#"{
      "width": 40, "height": 12, "background": [0.1, 0.2, 0.3],
      "triangles": [
        {"v": [[-3, -2, 0.5], [30, 1, 0.2], [6, 14, 0.9]], "color": [0.9, 0.2, 0.1]},
        {"v": [[10, 0, 0.1], [43, 5, 0.8], [22, 13, 0.4]], "color": [0, 0, 0], "colors": [[1,0,0],[0,1,0],[0,0,1]]},
        {"v": [[12, 3, 0], [20, 3, 0], [16, 9, 0]], "color": [1, 1, 1], "pattern_on": 1},
        {"v": [[0, 6, 0.3], [40, 6, 0.3], [0, 12, 0.3]], "color": [0.5, 0.5, 0.5]}
      ]
    }"#;
    let scene = parse(json, "screen").unwrap();
    let ls = load_with(scene, &MeshSource::Embedded(Default::default()), "screen").unwrap();
    assert!(!ls.is_3d());
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    assert!(fx.shadow_lights.is_empty());
    let (rows, bg) = scene_stream(&ls, &fx).unwrap();
    let decals = rows
        .iter()
        .flatten()
        .filter(|c| matches!(c, Command::Span(w) if w.decal))
        .count();
    assert!(decals > 0, "the pattern gives decal spans");
    let s = LineStream {
        width: 40,
        bg,
        lines: rows,
    };
    for shadows in [false, true] {
        let c = compare_stream(&s, 16, shadows, None).unwrap();
        assert_exact(&c);
    }
}
