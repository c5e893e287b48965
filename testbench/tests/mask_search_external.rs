//! The exported mask search Verilog in Verilator and Icarus Verilog against golden vector
//! files: Verilator on the exhaustive 4×4 set, Icarus on the first 6,000 partial-mask
//! searches of the default scene's fragment stream (Icarus runs about 1,000 clocks/s on this unit, so the
//! exhaustive set takes several minutes there; `mask_search_check` runs it by hand); both
//! must also report a deliberate mismatch. A missing tool prints
//! `SKIPPED: ...` (and fails under `CI=true`).

use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use pixelproc_rtl::mask_search::Variant;
use pixelproc_testbench::mask_search_tb::{
    check_external, check_external_against, exhaustive_jobs, random_jobs, scene_jobs, SearchJob,
};
use pixelproc_testbench::SimKind;

fn dir(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("pixelproc-msu-ext-{tag}-{}", std::process::id()))
}

fn check(v: Variant, sim: SimKind, jobs: &[SearchJob], tag: &str) {
    let d = dir(tag);
    let s = check_external(v, MaskSize::S4X4, jobs, sim, &d).unwrap();
    if s.skipped() {
        println!("{}", s.detail);
        return;
    }
    assert!(s.bit_exact, "{v:?} {sim:?}:\n{}", s.detail);
    assert!(s.cycles as usize > jobs.len());
    println!(
        "{} {sim:?}: {} cycles, build {:.1} s, run {:.2} s",
        v.name(),
        s.cycles,
        s.build_seconds,
        s.seconds
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn verilator_exhaustive_4x4_both_variants() {
    let jobs = exhaustive_jobs();
    for v in Variant::ALL {
        check(v, SimKind::Verilator, &jobs, &format!("vl-{}", v.name()));
    }
}

#[test]
fn icarus_default_scene_both_variants() {
    // The edge pixels proper: the first 6,000 searches of partial masks.
    let jobs: Vec<SearchJob> = scene_jobs("default", MaskSize::S4X4)
        .unwrap()
        .into_iter()
        .filter(|j| j.mask != 0xFFFF)
        .take(6000)
        .collect();
    assert_eq!(jobs.len(), 6000);
    for v in Variant::ALL {
        check(v, SimKind::Icarus, &jobs, &format!("iv-{}", v.name()));
    }
}

#[test]
fn external_mismatch_is_reported() {
    let jobs = random_jobs(MaskSize::S4X4, 300, 9);
    for sim in [SimKind::Icarus, SimKind::Verilator] {
        for v in Variant::ALL {
            let d = dir(&format!("mm-{sim:?}-{}", v.name()));
            let s = check_external_against(
                v,
                MaskSize::S4X4,
                &jobs,
                sim,
                &d,
                SearchFamily { p: 1, q: 0 },
            )
            .unwrap();
            if s.skipped() {
                println!("{}", s.detail);
                continue;
            }
            assert!(!s.bit_exact, "{v:?} {sim:?}");
            assert!(s.detail.contains("MISMATCH cycle="), "{}", s.detail);
            std::fs::remove_dir_all(&d).ok();
        }
    }
}
