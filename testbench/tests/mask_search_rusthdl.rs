//! The RustHDL mask search unit against the golden `SearchUnit`, every clock: exhaustive
//! 4×4 (every mask × 4 corners) in both variants, random 8×8, the default scene's
//! multi-fragment pixels, and a deliberate mismatch that must be reported.
//!
//! The exhaustive runs are meant for release builds (`cargo test --release`, as CI runs);
//! a debug build checks every 13th job of the same set and says so.

use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use pixelproc_rtl::mask_search::Variant;
use pixelproc_testbench::mask_search_tb::{
    check_rusthdl_against, exhaustive_jobs, random_jobs, scene_jobs, SearchJob,
};

fn run(variant: Variant, size: MaskSize, jobs: &[SearchJob]) {
    let dir = std::env::temp_dir().join(format!(
        "pixelproc-msu-test-{}-{size}-{}",
        variant.name(),
        std::process::id()
    ));
    let s = check_rusthdl_against(variant, size, jobs, SearchFamily::DIAGONAL, Some(&dir)).unwrap();
    assert!(s.bit_exact, "{:?} {size}: {}", variant, s.detail);
    assert!(s.cycles as usize >= jobs.len());
    println!(
        "{} {size}: {} jobs, {} cycles, {:.1} s",
        variant.name(),
        s.jobs,
        s.cycles,
        s.seconds
    );
    std::fs::remove_dir_all(&dir).ok();
}

fn exhaustive() -> Vec<SearchJob> {
    let all = exhaustive_jobs();
    assert_eq!(all.len(), 4 * 65_536);
    if cfg!(debug_assertions) {
        println!("debug build: every 13th job of the exhaustive set (release runs all)");
        all.into_iter().step_by(13).collect()
    } else {
        all
    }
}

#[test]
fn exhaustive_4x4_iterative() {
    run(Variant::Iterative, MaskSize::S4X4, &exhaustive());
}

#[test]
fn exhaustive_4x4_pipelined() {
    run(Variant::Pipelined, MaskSize::S4X4, &exhaustive());
}

#[test]
fn random_8x8_both_variants() {
    let jobs = random_jobs(MaskSize::S8X8, 3000, 11);
    // The stimulus reaches deep lines and empty masks, not only first-line hits.
    assert!(jobs.iter().any(|j| j.mask == 0));
    assert!(jobs.iter().any(|j| j.mask.count_ones() == 1));
    for v in Variant::ALL {
        run(v, MaskSize::S8X8, &jobs);
    }
}

#[test]
fn default_scene_edge_pixels() {
    let jobs = scene_jobs("default", MaskSize::S4X4).unwrap();
    assert!(jobs.len() > 1000, "{} jobs", jobs.len());
    // Edge pixels: many partial masks (the rest are fully covered fragments under or over
    // another triangle's edge).
    let partial = jobs.iter().filter(|j| j.mask != 0xFFFF).count();
    println!("{} searches, {partial} with partial masks", jobs.len());
    assert!(partial > 1000, "{partial} of {}", jobs.len());
    // The whole stream runs by hand (`mask_search_check`); here every search of a partial
    // mask (the edge pixels proper) and the first 2,000 others, in stream order.
    let mut others = 0;
    let sel: Vec<SearchJob> = jobs
        .into_iter()
        .filter(|j| {
            let keep = j.mask != 0xFFFF || others < 2000;
            others += (j.mask == 0xFFFF) as usize;
            keep
        })
        .collect();
    for v in Variant::ALL {
        run(v, MaskSize::S4X4, &sel);
    }
}

#[test]
fn mismatch_is_reported_with_trace() {
    // The golden model with the column family disagrees with the diagonal RTL: the first
    // differing clock must be reported with inputs, both outputs and a VCD.
    let jobs = random_jobs(MaskSize::S4X4, 200, 5);
    let dir = std::env::temp_dir().join(format!("pixelproc-msu-mm-{}", std::process::id()));
    for v in Variant::ALL {
        let s = check_rusthdl_against(
            v,
            MaskSize::S4X4,
            &jobs,
            SearchFamily { p: 1, q: 0 },
            Some(&dir),
        )
        .unwrap();
        assert!(!s.bit_exact, "{v:?}");
        assert!(
            s.detail.contains("golden") && s.detail.contains("rtl"),
            "{}",
            s.detail
        );
        let vcd = s.vcd.expect("a trace");
        let text = std::fs::read_to_string(&vcd).unwrap();
        assert!(text.contains("$enddefinitions") && text.contains("in_mask"));
        assert!(s.cycles < 400, "stops at the first mismatch: {}", s.cycles);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The A-buffer cost model (`pixelproc_sim::hwcost::abuffer`) counts the clocks the RTL
/// takes: for searches back to back, the clocks from the one whose edge accepts the first
/// search to the one whose edge shows the last result equal the model's `search_cycles`.
/// The schedule is the one the RustHDL unit matches clock for clock (checked here first):
/// per clock, the inputs sampled at its edge and the outputs shown after it.
#[test]
fn the_cost_model_counts_the_units_clocks() {
    use pixelproc_sim::hwcost::abuffer::{lines, search_cycles, SearchKind};
    use pixelproc_sim::mask_search::{SearchTables, SearchUnit};
    use pixelproc_testbench::mask_search_tb::schedule;
    for size in [MaskSize::S4X4, MaskSize::S8X8] {
        // Fewer jobs than the pipelined schedule's bubble period (97): back to back.
        let jobs = random_jobs(size, 60, 5);
        let tables = SearchTables::new(size, SearchFamily::DIAGONAL);
        let mut unit = SearchUnit::new(&tables);
        let steps: Vec<u32> = jobs
            .iter()
            .map(|j| unit.run(j.mask, j.corner).steps)
            .collect();
        for (v, kind) in [
            (Variant::Iterative, SearchKind::Iterative),
            (Variant::Pipelined, SearchKind::Pipelined),
        ] {
            run(v, size, &jobs);
            let s = schedule(v, size, &jobs);
            let first = s.inputs.iter().position(|i| i.valid).unwrap();
            let last = s.expect.iter().rposition(|o| o.result.valid).unwrap();
            let results = s.expect.iter().filter(|o| o.result.valid).count();
            assert_eq!(results, jobs.len());
            let model = search_cycles(kind, steps.iter().copied(), lines(size));
            assert_eq!((last - first + 1) as u64, model, "{v:?} {size}");
        }
    }
}
