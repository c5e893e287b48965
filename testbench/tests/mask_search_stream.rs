//! The AXI4-Stream search units on the whole search stream of an A-buffer render of the
//! built-in default scene (walls with coplanar decals, boxes, an L-block; every search the
//! render runs, in order), with random input gaps and output back-pressure, every result
//! compared with the golden model: Verilator at 4×4 (the scene as declared: min searches)
//! and 8×8 (interpenetrating surfaces declared: min and max searches) for both variants;
//! Icarus and RustHDL on the first searches of the stream. A flipped bit in one expected result must
//! be reported at its index. A missing simulator fails the test (install command in the
//! error). The traffic seed is printed; `MASK_SEARCH_STREAM_SEED` replaces the default.

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_rtl::mask_search::Variant;
use pixelproc_testbench::mask_search_tb::stream::{rerun_verilator, Word};
use pixelproc_testbench::mask_search_tb::{
    run_stream_words, scene_requests, stream_words, StreamSummary, StreamWords,
};
use pixelproc_testbench::SimKind;
use std::path::PathBuf;

fn seed() -> u64 {
    std::env::var("MASK_SEARCH_STREAM_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0001)
}

fn dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("pixelproc-msu-stream-{tag}-{}", std::process::id()))
}

/// The default scene's search stream; `interpenetrating` declares interpenetrating
/// surfaces (the render then also runs the max search of every fragment).
fn scene_words(size: MaskSize, interpenetrating: bool) -> StreamWords {
    let mut ls = pixelproc_sim::scene::load_builtin("default").unwrap();
    ls.scene.effects.interpenetrating = interpenetrating;
    let reqs = scene_requests(&ls, size).unwrap();
    assert!(reqs.len() > 10_000, "{} searches", reqs.len());
    stream_words(&reqs, size)
}

fn prefix(w: &StreamWords, n: usize) -> StreamWords {
    StreamWords {
        input: w.input[..n].to_vec(),
        expect: w.expect[..n].to_vec(),
    }
}

fn check(s: &StreamSummary) {
    println!("{s}");
    assert!(s.identical, "{s}");
    assert_eq!(s.results, s.searches);
    assert!(s.cycles as usize > s.searches);
}

/// A wrong expected result (one bit flipped) must be reported at its index.
fn flip_is_caught(
    mut words: StreamWords,
    k: usize,
    bit: usize,
    run: impl Fn(&StreamWords) -> StreamSummary,
) {
    words.expect[k].flip(bit);
    let s = run(&words);
    println!("flipped bit {bit} of result {k}: {}", s.detail);
    assert!(!s.identical);
    assert_eq!(s.results, k, "{}", s.detail);
    assert!(s.detail.contains(&format!("result {k} ")), "{}", s.detail);
}

#[test]
fn verilator_whole_scene_stream_4x4_and_8x8_both_variants() {
    let seed = seed();
    let t0 = std::time::Instant::now();
    let sizes = [MaskSize::S4X4, MaskSize::S8X8];
    // 4×4 as the scene declares it (min searches), 8×8 with interpenetrating surfaces
    // declared (min and max searches, both start corners of every fragment).
    let words = [scene_words(sizes[0], false), scene_words(sizes[1], true)];
    let runs: Vec<(usize, Variant)> = (0..2).flat_map(|k| Variant::ALL.map(|v| (k, v))).collect();
    // Two runs at a time: the Verilator builds dominate and take one core each.
    let next = std::sync::atomic::AtomicUsize::new(0);
    std::thread::scope(|sc| {
        for _ in 0..2 {
            sc.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                let Some(&(k, v)) = runs.get(i) else { break };
                let (size, w) = (sizes[k], &words[k]);
                let d = dir(&format!("vl-{}-{}", v.name(), size.n()));
                let s = run_stream_words(w, size, v, SimKind::Verilator, seed, &d).unwrap();
                check(&s);
                if v == Variant::Pipelined && size == MaskSize::S4X4 {
                    // The same model, a wrong expectation: the compare must catch it.
                    flip_is_caught(w.clone(), w.expect.len() / 2, 7, |w| {
                        rerun_verilator(w, size, v, seed, &d).unwrap()
                    });
                }
                std::fs::remove_dir_all(&d).ok();
            });
        }
    });
    println!("4 stream runs in {:.1} s", t0.elapsed().as_secs_f64());
}

#[test]
fn icarus_and_rusthdl_on_the_start_of_the_stream() {
    let seed = seed();
    for (size, n) in [(MaskSize::S4X4, 400), (MaskSize::S8X8, 200)] {
        let words = prefix(&scene_words(size, true), n);
        for v in Variant::ALL {
            let d = dir(&format!("iv-{}-{}", v.name(), size.n()));
            check(&run_stream_words(&words, size, v, SimKind::Icarus, seed, &d).unwrap());
            std::fs::remove_dir_all(&d).ok();
            check(&run_stream_words(&words, size, v, SimKind::RustHdl, seed, &d).unwrap());
        }
        // A flipped bit in RustHDL too (in the and field, the top bits of the word).
        flip_is_caught(words.clone(), n / 3, 240, |w| {
            run_stream_words(
                w,
                size,
                Variant::Iterative,
                SimKind::RustHdl,
                seed,
                &d_unused(),
            )
            .unwrap()
        });
    }
}

fn d_unused() -> PathBuf {
    dir("unused")
}

#[test]
fn words_decode_as_written() {
    let w = Word::parse_hex("1f");
    assert_eq!(w.get(0, 5), 0x1f);
}
