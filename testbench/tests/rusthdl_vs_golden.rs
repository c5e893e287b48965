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
    assert!(m.expected.dsf != m.got.dsf || m.expected.fsf != m.got.fsf);
    let vcd = m.vcd.expect("a VCD is written");
    let text = std::fs::read_to_string(&vcd).unwrap();
    assert!(text.contains("$var") && text.contains("cmd_op"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn quick_check_is_bit_exact() {
    let s = pixelproc_testbench::quick_check().unwrap();
    assert!(s.bit_exact, "{}", s.detail);
    assert!(s.span_words > 0 && s.cycles > 0);
}
