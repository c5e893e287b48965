//! Whole frames through the exported Verilog of the core in Verilator, every pixel (and,
//! in the debug configuration, depth, flags, light mask, counter and normal class)
//! compared with the golden renderer's image, under random input gaps and output
//! back-pressure; the Verilog run's cycle counts must equal the cycle-level model's.
//! Scenes: the embedded scene at reduced size with shadows, a screen-space scene with
//! Gouraud colours and decals, a 3-D scene with an area light.

use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::{load_builtin, load_file, LoadedScene};
use pixelproc_testbench::frame::{plan_frame, run_frame_check, FrameSim, FrameSpec};
use std::path::Path;

fn check(ls: &LoadedScene, n: usize, seed: u64, expect_shadows: bool) {
    let fx = Effects::resolve(ls, &Overrides::default()).unwrap();
    assert_eq!(!fx.shadow_lights.is_empty(), expect_shadows, "{}", ls.name);
    let work = tempfile::tempdir().unwrap();
    let spec = FrameSpec {
        array_width: n,
        debug: true,
        seed,
        gap_pct: 25,
        stall_pct: 30,
        work: work.path().to_path_buf(),
        cache: Path::new(env!("CARGO_TARGET_TMPDIR")).join("verilator-cache"),
        corrupt_golden: None,
    };
    let r = run_frame_check(ls, &fx, &spec, FrameSim::Verilator, &mut |m| {
        eprintln!("{m}")
    })
    .unwrap();
    println!(
        "{} {}x{} N {n}: identical {}, {} pixels, {} cycles (model {}), build {:.1} s, run {:.2} s",
        ls.name,
        r.width,
        r.height,
        r.identical,
        r.pixels,
        r.cycles.cycles,
        r.model_cycles.cycles,
        r.build_seconds,
        r.run_seconds
    );
    assert!(r.mismatch.is_none(), "{}: {:?}", ls.name, r.mismatch);
    assert!(
        r.identical,
        "{}: cycles {:?} vs model {:?}",
        ls.name, r.cycles, r.model_cycles
    );
    assert!(
        r.cycles.out_stall > 0 && r.cycles.in_stall > 0,
        "stalls were exercised"
    );
}

#[test]
fn embedded_scene_reduced_with_shadows() {
    let mut ls = load_builtin("default").unwrap();
    ls.scene.width = 160;
    ls.scene.height = 90;
    check(&ls, 16, 3, true);
}

#[test]
fn screen_space_gouraud_and_decals() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("screen.json");
    std::fs::write(
        &p,
        r#"{"width": 100, "height": 40, "background": [0.1, 0.1, 0.2], "depth_range": [0, 100],
 "triangles": [
  {"v": [[2, 2, 10], [90, 5, 10], [8, 38, 10]], "color": [0.8, 0.2, 0.2]},
  {"v": [[10, 3, 5], [98, 20, 50], [20, 39, 90]], "color": [1, 1, 1], "colors": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]},
  {"v": [[4, 4, 10], [40, 6, 10], [6, 30, 10]], "color": [0.9, 0.9, 0.1], "pattern_on": 0},
  {"v": [[50, 10, 30], [70, 12, 30], [55, 35, 30]], "color": [0.2, 0.9, 0.3], "colors": [[0.2, 0.9, 0.3], [0.9, 0.1, 0.9], [0.1, 0.1, 0.9]]},
  {"v": [[52, 14, 30], [62, 15, 30], [55, 28, 30]], "color": [1, 1, 1], "pattern_on": 3}
 ]}"#,
    )
    .unwrap();
    let ls = load_file(&p).unwrap();
    check(&ls, 16, 11, false);
}

#[test]
fn area_light() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim/tests/fuzz_corpus/area.json");
    let ls = load_file(&p).unwrap();
    check(&ls, 16, 5, true);
}

/// A scene the core cannot take is refused before any simulation, naming the limit.
#[test]
fn scenes_beyond_the_core_are_refused_up_front() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim/tests/fuzz_corpus/area.json");
    let mut ls = load_file(&p).unwrap();
    ls.scene.lights[0].samples = Some(32);
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    let e = plan_frame(&ls, &fx, 16).err().expect("refused").to_string();
    assert!(e.contains("32 samples") && e.contains("15"), "{e}");
    let mut ls = load_builtin("default").unwrap();
    let l = ls.scene.lights[0].clone();
    for k in 0..3 {
        let mut m = l.clone();
        m.position[0] += 3.0 * (k + 1) as f64;
        ls.scene.lights.push(m);
    }
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    assert_eq!(fx.shadow_lights.len(), 4);
    // Exact shading (the default) needs one shade register per shadowing light.
    let e = plan_frame(&ls, &fx, 16).err().expect("refused").to_string();
    assert!(
        e.contains("4 shadowing lights") && e.contains("--shading table"),
        "{e}"
    );
    // The seed's table takes three point lights' mask bits.
    let ov = Overrides {
        shading: Some(pixelproc_sim::shadow::Shading::Table),
        ..Default::default()
    };
    let fx = Effects::resolve(&ls, &ov).unwrap();
    let e = plan_frame(&ls, &fx, 16).err().expect("refused").to_string();
    assert!(
        e.contains("4 shadowing point lights") && e.contains("at most 3"),
        "{e}"
    );
}

/// The mismatch report: a golden value flipped on purpose must be found at its pixel, with
/// its tile and clock, and a VCD of the clocks around it must be written.
#[test]
fn a_difference_is_reported_with_its_pixel_clock_and_trace() {
    let mut ls = load_builtin("default").unwrap();
    ls.scene.width = 40;
    ls.scene.height = 6;
    let ov = Overrides {
        no_shadows: true,
        ..Default::default()
    };
    let fx = Effects::resolve(&ls, &ov).unwrap();
    let work = tempfile::tempdir().unwrap();
    let spec = FrameSpec {
        array_width: 8,
        debug: false,
        seed: 9,
        gap_pct: 10,
        stall_pct: 10,
        work: work.path().to_path_buf(),
        cache: Path::new(env!("CARGO_TARGET_TMPDIR")).join("verilator-cache"),
        corrupt_golden: Some(3 * 40 + 21),
    };
    let r = run_frame_check(&ls, &fx, &spec, FrameSim::Verilator, &mut |m| {
        eprintln!("{m}")
    })
    .unwrap();
    assert!(!r.identical);
    let m = r.mismatch.expect("the flipped pixel is reported");
    assert_eq!((m.x, m.y, m.tile_base), (21, 3, 16));
    assert_eq!(m.golden.rgb ^ (1 << 16), m.rtl.unwrap().rgb);
    let c = m.clock.expect("the pixel came out");
    assert!(c > 0 && c < r.cycles.cycles);
    let vcd = std::fs::read_to_string(m.vcd.expect("a VCD")).unwrap();
    assert!(vcd.contains("$enddefinitions") && vcd.contains("m_axis_tdata"));
    assert!(
        vcd.contains(&format!("#{}", 2 * c)),
        "the VCD covers the pixel's clock"
    );
}
