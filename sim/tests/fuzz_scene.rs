//! Fuzzing the scene loader and the setup stages with mutated scenes (a long proptest run).
//!
//! Each case takes a committed seed (`tests/fuzz_corpus/`: scene JSON and OBJ meshes),
//! applies random byte- and token-level mutations to the scene and to one mesh, and runs
//! what a user's file goes through before any pixel is drawn: strict JSON parsing,
//! validation, OBJ loading, the front end (transform, clip, light, snap), span setup and
//! the shadow volumes. A case passes when it returns `Ok` or a one-line `Err`; it fails on
//! a panic, on a message with a line break, on more than [`MEM_BUDGET`] bytes allocated at
//! once, or on taking longer than [`CASE_SECONDS`].
//!
//! CI runs `PROPTEST_CASES` cases (default 400 here) from a fixed seed; a long run with
//! another seed: `PROPTEST_CASES=1000000 FUZZ_SEED=run2 cargo test --release -p
//! pixelproc-sim --test fuzz_scene -- --nocapture` (it prints the count of cases that got
//! through setup). A failing case is printed, shrunk, with its mutations.

use pixelproc_sim::frontend::{self, Projector};
use pixelproc_sim::render::SpanSource;
use pixelproc_sim::scene::{self, MeshSource};
use pixelproc_sim::shadow::{self, ShadowForm};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use std::alloc::{GlobalAlloc, Layout, System};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Largest allowed live allocation during one case.
const MEM_BUDGET: usize = 1 << 30;
/// Longest allowed case.
const CASE_SECONDS: f64 = 20.0;

struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
        PEAK.fetch_max(now, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

const SCENES: &[(&str, &str)] = &[
    ("scene3d.json", include_str!("fuzz_corpus/scene3d.json")),
    ("screen.json", include_str!("fuzz_corpus/screen.json")),
    ("area.json", include_str!("fuzz_corpus/area.json")),
];

const MESHES: &[(&str, &str)] = &[
    ("box.obj", include_str!("fuzz_corpus/box.obj")),
    ("ground.obj", include_str!("fuzz_corpus/ground.obj")),
    ("lblock.obj", include_str!("fuzz_corpus/lblock.obj")),
    ("wall.obj", include_str!("fuzz_corpus/wall.obj")),
];

/// Tokens worth splicing in: extremes, wrong types, structure.
const TOKENS: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "4096",
    "4097",
    "65535",
    "4294967296",
    "NaN",
    "null",
    "true",
    "\"\"",
    "[]",
    "{}",
    "[0,0,0]",
    "[0,0,0,0]",
    "[1e300,0,0]",
    ",",
    ":",
    "\"",
    "\"obj\"",
    "\"width\"",
    "\"camera\"",
    "\"up\"",
    "\"eye\"",
    "\"target\"",
    "\"scale\"",
    "\"on_mesh\"",
    "\"pattern_on\"",
    "\"samples\"",
    "\"radius\"",
    "\"aa\"",
    "\"ssaa\"",
    "\"abuffer\"",
    "\"multiscan\"",
    "\"subscanlines\"",
    "\"../x.obj\"",
    "\u{FEFF}",
    "v 0 0 0\n",
    "v 1e38 1e38 1e38\n",
    "v nan 0 0\n",
    "f 1 2 3\n",
    "f 1 1 1\n",
    "f -1 -2 -3\n",
    "f 99999 1 2\n",
    "vn 0 0 0\n",
    "o x\n",
    "f 1/1/1 2/2/2 3/3/3\n",
    "\n",
    " ",
];

#[derive(Clone, Debug)]
enum Mutation {
    Flip {
        at: usize,
        bit: u8,
    },
    Delete {
        at: usize,
        len: usize,
    },
    Insert {
        at: usize,
        token: usize,
    },
    Duplicate {
        at: usize,
        len: usize,
        to: usize,
    },
    /// Replaces the n-th number literal with a token: keeps the JSON valid more often, so
    /// cases reach validation and setup instead of stopping at the syntax check.
    ReplaceNumber {
        nth: usize,
        token: usize,
    },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(at, bit)| Mutation::Flip { at, bit }),
        (any::<usize>(), 1usize..16).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(at, token)| Mutation::Insert { at, token }),
        (any::<usize>(), 1usize..64, any::<usize>())
            .prop_map(|(at, len, to)| Mutation::Duplicate { at, len, to }),
        (any::<usize>(), 0..TOKENS.len())
            .prop_map(|(nth, token)| Mutation::ReplaceNumber { nth, token }),
        (any::<usize>(), 0..TOKENS.len())
            .prop_map(|(nth, token)| Mutation::ReplaceNumber { nth, token }),
    ]
}

fn apply(mut b: Vec<u8>, ms: &[Mutation]) -> Vec<u8> {
    for m in ms {
        let n = b.len().max(1);
        match *m {
            Mutation::Flip { at, bit } => {
                if !b.is_empty() {
                    b[at % n] ^= 1 << bit;
                }
            }
            Mutation::Delete { at, len } => {
                let a = at % n;
                let e = (a + len).min(b.len());
                if a < e {
                    b.drain(a..e);
                }
            }
            Mutation::Insert { at, token } => {
                let a = at % (b.len() + 1);
                b.splice(a..a, TOKENS[token].bytes());
            }
            Mutation::Duplicate { at, len, to } => {
                let a = at % n;
                let e = (a + len).min(b.len());
                let piece: Vec<u8> = b.get(a..e).unwrap_or(&[]).to_vec();
                let t = to % (b.len() + 1);
                b.splice(t..t, piece);
            }
            Mutation::ReplaceNumber { nth, token } => {
                let nums = number_spans(&b);
                if !nums.is_empty() {
                    let (a, e) = nums[nth % nums.len()];
                    b.splice(a..e, TOKENS[token].bytes());
                }
            }
        }
    }
    b
}

/// Byte ranges of number literals (`-`, digits, `.`, `e`, `+`).
fn number_spans(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            let a = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b".eE+-".contains(&b[i])) {
                i += 1;
            }
            out.push((a, i));
        } else {
            i += 1;
        }
    }
    out
}

/// An error and its causes on one line, as the CLI prints them.
fn chain(e: impl std::error::Error) -> String {
    let mut s = e.to_string();
    let mut src = e.source();
    while let Some(c) = src {
        s.push_str(": ");
        s.push_str(&c.to_string());
        src = c.source();
    }
    s
}

/// Everything before drawing; an `Err` is a clean refusal.
fn load_and_set_up(scene: &[u8], meshes: BTreeMap<String, String>) -> Result<(), String> {
    let text =
        pixelproc_sim::input::decode_text(scene.to_vec(), "fuzz.json".as_ref()).map_err(chain)?;
    let (s, _) = scene::parse_with_warnings(&text, "fuzz").map_err(chain)?;
    let ls = scene::load_with(s, &MeshSource::Embedded(meshes), "fuzz").map_err(chain)?;
    let p = frontend::project(&ls).map_err(chain)?;
    SpanSource::new(&p.tris, ls.scene.width, ls.scene.height).map_err(chain)?;
    if ls.is_3d() {
        let lights = shadow::shadow_lights(&ls, &(0..ls.scene.lights.len()).collect::<Vec<_>>())
            .map_err(chain)?;
        let pj = Projector::new(&ls);
        shadow::shadow_commands(&ls, &pj, &lights, ShadowForm::Ev).map_err(chain)?;
    }
    Ok(())
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(400)
}

/// One fuzz case: the strategy's value.
type Case = (usize, Vec<Mutation>, usize, Vec<Mutation>);

fn case() -> impl Strategy<Value = Case> {
    (
        0..SCENES.len(),
        prop::collection::vec(mutation(), 0..6),
        0..MESHES.len(),
        prop::collection::vec(mutation(), 0..4),
    )
}

/// Runs one case; `Ok(true)` when the scene got through setup, `Ok(false)` when refused.
fn run_case(c: &Case) -> Result<bool, TestCaseError> {
    let (seed, scene_muts, mesh, mesh_muts) = c;
    let scene = apply(SCENES[*seed].1.as_bytes().to_vec(), scene_muts);
    let mut meshes: BTreeMap<String, String> = MESHES
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let m = apply(MESHES[*mesh].1.as_bytes().to_vec(), mesh_muts);
    meshes.insert(
        MESHES[*mesh].0.to_string(),
        String::from_utf8_lossy(&m).into_owned(),
    );
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let t0 = Instant::now();
    let res = std::panic::catch_unwind(|| load_and_set_up(&scene, meshes));
    let secs = t0.elapsed().as_secs_f64();
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
    prop_assert!(
        res.is_ok(),
        "panic on input {:?}",
        String::from_utf8_lossy(&scene)
    );
    if let Ok(Err(msg)) = &res {
        prop_assert!(!msg.contains('\n'), "multi-line message: {msg}");
        prop_assert!(!msg.is_empty());
    }
    prop_assert!(peak <= MEM_BUDGET, "{peak} bytes allocated");
    prop_assert!(secs <= CASE_SECONDS, "{secs} s");
    Ok(matches!(res, Ok(Ok(()))))
}

#[test]
fn mutated_scenes_load_or_fail_cleanly() {
    let config = ProptestConfig {
        cases: cases(),
        max_shrink_iters: 200,
        ..ProptestConfig::default()
    };
    let mut runner = proptest::test_runner::TestRunner::new_with_rng(
        config,
        proptest::test_runner::TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &seed_bytes(),
        ),
    );
    let accepted = std::sync::atomic::AtomicU64::new(0);
    let total = std::sync::atomic::AtomicU64::new(0);
    let t0 = Instant::now();
    let res = runner.run(&case(), |c| {
        total.fetch_add(1, Ordering::Relaxed);
        if run_case(&c)? {
            accepted.fetch_add(1, Ordering::Relaxed);
        }
        Ok(())
    });
    println!(
        "fuzz: {} cases in {:.1} s, {} reached setup and were accepted, the rest refused with one line; seed {}",
        total.load(Ordering::Relaxed),
        t0.elapsed().as_secs_f64(),
        accepted.load(Ordering::Relaxed),
        seed_text()
    );
    if let Err(e) = res {
        panic!("{e}");
    }
}

/// The run's seed: `FUZZ_SEED` (any text) or a fixed default, so CI runs are repeatable.
fn seed_text() -> String {
    std::env::var("FUZZ_SEED").unwrap_or_else(|_| "pixelproc".into())
}

fn seed_bytes() -> [u8; 32] {
    let mut out = [0u8; 32];
    for (i, b) in seed_text().bytes().enumerate() {
        out[i % 32] ^= b.wrapping_add(i as u8);
    }
    out
}

#[test]
fn every_seed_loads_unmutated() {
    for (name, text) in SCENES {
        let meshes = MESHES
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        load_and_set_up(text.as_bytes(), meshes).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}
