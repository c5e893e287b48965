//! The Verilator build cache: one build per hash of the Verilog, the harness, the flags,
//! the Verilator version and the C++ compiler, completed atomically and pruned to the
//! most recently used entries.

use super::*;

/// How a Verilator model was obtained by [`verilator_build_cached`].
#[derive(Clone, Debug, PartialEq)]
pub struct BuildInfo {
    /// Wall-clock seconds spent: the build, or only the look-up when cached.
    pub seconds: f64,
    /// True if the model came from the build cache.
    pub cached: bool,
    /// The cache entry: the sources, `build.log` and the executable.
    pub dir: PathBuf,
}

impl std::fmt::Display for BuildInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.cached {
            write!(f, "build cached")
        } else {
            write!(f, "build {:.1} s", self.seconds)
        }
    }
}

/// The flags of every Verilator build, before a caller's extra flags. Why each:
/// - `-O3`: Verilator's own optimisations (they shrink the C++ it writes);
/// - `--x-assign fast --x-initial fast`: no code for X randomisation (every register
///   of the exported blocks has a power-on value, so the results are the same);
/// - `--output-split-cfuncs 500`: no giant C++ functions; the compiler's optimiser is
///   superlinear in function size, so this alone saves about a third of the compile;
/// - `--output-split 60000`: a few large C++ files instead of many small ones (each
///   file re-reads the Verilator headers, about 1.3 s), still enough for `-j 2`;
/// - `OPT_FAST=-O1 OPT_GLOBAL=-O1`: the model and Verilator's runtime at `-O1`
///   (the default is `-Os`; `-O0` compiles faster but runs about five times slower);
/// - `-Wno-fatal -Wno-lint -Wno-style`: lint is a separate gate (`tests/verilog_gates.rs`).
///
/// No `--trace` (tracing code roughly doubles the C++): Verilator then skips the
/// testbenches' `$dumpvars` (Icarus writes the VCD); pass `--trace` in the extra flags
/// when a Verilator VCD is wanted.
pub const VERILATOR_FLAGS: &[&str] = &[
    "-O3",
    "--x-assign",
    "fast",
    "--x-initial",
    "fast",
    "--output-split",
    "60000",
    "--output-split-cfuncs",
    "500",
    "-MAKEFLAGS",
    "OPT_FAST=-O1 OPT_GLOBAL=-O1",
    "-Wno-fatal",
    "-Wno-lint",
    "-Wno-style",
];

/// Version of the cache entry layout; part of every key.
const VCACHE_FORMAT: &str = "pixelproc-vcache 1";

/// The marker written last into a complete cache entry.
const VCACHE_MARKER: &str = "complete";

/// Cache entries kept (the most recently used); older ones are removed after a build.
const VCACHE_KEEP: usize = 24;

/// Where [`verilator_build_cached`] keeps its builds: `$PIXELPROC_VCACHE` if set,
/// otherwise `pixelproc-vcache` in the workspace's `target` folder (`$CARGO_TARGET_DIR`
/// if set), or in the system's temporary folder if there is no such folder.
pub fn verilator_cache_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("PIXELPROC_VCACHE").filter(|d| !d.is_empty()) {
        return PathBuf::from(d);
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
    if target.is_dir() {
        target.join("pixelproc-vcache")
    } else {
        std::env::temp_dir().join("pixelproc-vcache")
    }
}

/// 128-bit FNV-1a of length-prefixed parts (stable across runs and Rust versions).
fn fnv128(parts: &[&[u8]]) -> u128 {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013b;
    let mut h = OFFSET;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h ^= b as u128;
            h = h.wrapping_mul(PRIME);
        }
    };
    for p in parts {
        eat(&(p.len() as u64).to_le_bytes());
        eat(p);
    }
    h
}

/// A plain file name: no folder part, not empty, not `.` or `..`.
fn plain_file_name(name: &str) -> bool {
    !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\', '\0'])
        && Path::new(name)
            .file_name()
            .map(|n| n == name)
            .unwrap_or(false)
}

/// A Verilog identifier usable as a top module and executable name.
fn plain_identifier(name: &str) -> bool {
    let mut c = name.chars();
    c.next()
        .map(|f| f.is_ascii_alphabetic() || f == '_')
        .unwrap_or(false)
        && c.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Builds a Verilator model, or reuses the one built before from the same input.
///
/// - `top`: the top module (a plain identifier, no `$`);
/// - `verilog_files`: `(file name, text)` of every Verilog file, in the order given to
///   Verilator (plain file names, no folders);
/// - `harness_cpp`: the C++ `main` driving the model (`#include "V{top}.h"`), built with
///   `--cc --exe --build`; empty for a self-running Verilog testbench (`--binary`:
///   Verilator's own `main`, `--timing`, so `initial` blocks with delays run);
/// - `extra_flags`: further Verilator flags after [`VERILATOR_FLAGS`] (e.g. `--trace`,
///   `-GWIDTH=8`).
///
/// Returns the executable (run it in the folder holding its input files; it does not
/// depend on where it was built) and what the build cost. The build goes into the cache
/// ([`verilator_cache_dir`]) under a hash of the inputs, the flags, the `verilator
/// --version` and `$CXX`; a later call with the same key reuses it (`BuildInfo::cached`).
/// An entry is built in a private folder, gets its completion marker last, and is then
/// renamed into place, so an interrupted or failed build is never reused and concurrent
/// builders of one key do not disturb each other. Builds use all cores (`-j`), show a
/// spinner on stderr after a few seconds when stderr is a terminal, and the least
/// recently used entries beyond 24 are removed. Delete the folder to clear the cache.
pub fn verilator_build_cached(
    top: &str,
    verilog_files: &[(String, String)],
    harness_cpp: &str,
    extra_flags: &[&str],
) -> Result<(PathBuf, BuildInfo), TbError> {
    verilator_build_cached_in(
        &verilator_cache_dir(),
        top,
        verilog_files,
        harness_cpp,
        extra_flags,
    )
}

/// [`verilator_build_cached`] with the cache in `cache` instead of
/// [`verilator_cache_dir`].
pub fn verilator_build_cached_in(
    cache: &Path,
    top: &str,
    verilog_files: &[(String, String)],
    harness_cpp: &str,
    extra_flags: &[&str],
) -> Result<(PathBuf, BuildInfo), TbError> {
    let t0 = std::time::Instant::now();
    if !plain_identifier(top) {
        return Err(TbError::Sim(format!(
            "verilator build: `{top}` is not a plain module name"
        )));
    }
    if verilog_files.is_empty() {
        return Err(TbError::Sim("verilator build: no Verilog files".into()));
    }
    let mut seen = std::collections::HashSet::new();
    for (name, _) in verilog_files {
        if !plain_file_name(name) || name == "harness.cpp" || !seen.insert(name.as_str()) {
            return Err(TbError::Sim(format!(
                "verilator build: `{name}` is not a plain, distinct file name"
            )));
        }
    }
    let version = Proc::new("verilator")
        .arg("--version")
        .output()
        .map_err(|e| TbError::Sim(format!("verilator does not run: {e}")))?;
    let mode: Vec<&str> = if harness_cpp.is_empty() {
        vec!["--binary"]
    } else {
        vec!["--cc", "--exe", "--build", "harness.cpp"]
    };
    let flags: Vec<&str> = mode
        .iter()
        .chain(VERILATOR_FLAGS)
        .chain(extra_flags)
        .copied()
        .collect();
    let cxx = std::env::var("CXX").unwrap_or_default();
    let mut parts: Vec<&[u8]> = vec![
        VCACHE_FORMAT.as_bytes(),
        &version.stdout,
        cxx.as_bytes(),
        top.as_bytes(),
        harness_cpp.as_bytes(),
    ];
    for f in &flags {
        parts.push(f.as_bytes());
    }
    for (name, text) in verilog_files {
        parts.push(name.as_bytes());
        parts.push(text.as_bytes());
    }
    let key = format!("{:032x}", fnv128(&parts));
    let entry = cache.join(&key);
    let exe_name = format!("V{top}");
    let exe = entry.join(&exe_name);
    if entry.join(VCACHE_MARKER).is_file() && exe.is_file() {
        touch(&entry.join(VCACHE_MARKER));
        return Ok((
            exe,
            BuildInfo {
                seconds: t0.elapsed().as_secs_f64(),
                cached: true,
                dir: entry,
            },
        ));
    }
    std::fs::create_dir_all(cache)?;
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    let part = cache.join(format!("{key}.part-{}-{nanos}", std::process::id()));
    let result = build_entry(&part, top, verilog_files, harness_cpp, &flags);
    if let Err(e) = result {
        std::fs::remove_dir_all(&part).ok();
        return Err(e);
    }
    let seconds = t0.elapsed().as_secs_f64();
    std::fs::write(
        part.join(VCACHE_MARKER),
        format!(
            "built in {seconds:.1} s with: verilator {}\n",
            flags.join(" ")
        ),
    )?;
    if std::fs::rename(&part, &entry).is_err() {
        // Another builder finished first (its entry is complete), or a leftover without
        // a marker is in the way: use theirs, or replace the leftover.
        if !entry.join(VCACHE_MARKER).is_file() {
            std::fs::remove_dir_all(&entry).ok();
            std::fs::rename(&part, &entry)?;
        } else {
            std::fs::remove_dir_all(&part).ok();
        }
    }
    prune_cache(cache, &key);
    Ok((
        exe,
        BuildInfo {
            seconds,
            cached: false,
            dir: entry,
        },
    ))
}

/// Writes the sources into `dir` and builds the model there; leaves the executable
/// `V{top}`, the sources and `build.log`, and removes Verilator's intermediate files.
fn build_entry(
    dir: &Path,
    top: &str,
    verilog_files: &[(String, String)],
    harness_cpp: &str,
    flags: &[&str],
) -> Result<(), TbError> {
    std::fs::create_dir_all(dir)?;
    for (name, text) in verilog_files {
        std::fs::write(dir.join(name), text)?;
    }
    if !harness_cpp.is_empty() {
        std::fs::write(dir.join("harness.cpp"), harness_cpp)?;
    }
    let jobs = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .to_string();
    let log = std::fs::File::create(dir.join("build.log"))?;
    let mut cmd = Proc::new("verilator");
    cmd.current_dir(dir)
        .args(flags)
        .args(["-j", &jobs, "--top-module", top, "-Mdir", "obj_dir"])
        .args(verilog_files.iter().map(|(n, _)| n))
        .stdout(log.try_clone()?)
        .stderr(log);
    let status = wait_with_spinner(&mut cmd, &format!("verilator: building {top}"))?;
    let exe = dir.join("obj_dir").join(format!("V{top}"));
    if !status.success() || !exe.is_file() {
        let text = std::fs::read_to_string(dir.join("build.log")).unwrap_or_default();
        let tail: Vec<&str> = text.lines().rev().take(40).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(TbError::Sim(format!(
            "verilator build of {top} failed ({status}):\n{}",
            tail.join("\n")
        )));
    }
    std::fs::rename(&exe, dir.join(format!("V{top}")))?;
    std::fs::remove_dir_all(dir.join("obj_dir"))?;
    Ok(())
}

/// Runs `cmd` to completion; after three seconds, and only if stderr is a terminal,
/// shows a spinner with `what` and the elapsed time.
fn wait_with_spinner(cmd: &mut Proc, what: &str) -> Result<std::process::ExitStatus, TbError> {
    use std::io::IsTerminal;
    let mut child = cmd.spawn()?;
    let t0 = std::time::Instant::now();
    let tty = std::io::stderr().is_terminal();
    let mut bar: Option<indicatif::ProgressBar> = None;
    loop {
        if let Some(status) = child.try_wait()? {
            if let Some(b) = bar {
                b.finish_and_clear();
            }
            return Ok(status);
        }
        if tty && bar.is_none() && t0.elapsed() > std::time::Duration::from_secs(3) {
            let b = indicatif::ProgressBar::new_spinner();
            if let Ok(style) =
                indicatif::ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
            {
                b.set_style(style);
            }
            b.set_message(what.to_string());
            b.enable_steady_tick(std::time::Duration::from_millis(120));
            bar = Some(b);
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// Sets a file's modification time to now (the cache's use stamp); best effort.
fn touch(path: &Path) {
    if let Ok(f) = std::fs::File::options().append(true).open(path) {
        f.set_modified(std::time::SystemTime::now()).ok();
    }
}

/// Removes the least recently used complete entries beyond [`VCACHE_KEEP`] (never
/// `keep`), and private build folders left by interrupted builds over a day ago.
fn prune_cache(cache: &Path, keep: &str) {
    let Ok(rd) = std::fs::read_dir(cache) else {
        return;
    };
    let now = std::time::SystemTime::now();
    let age = |p: &Path| {
        std::fs::metadata(p)
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| now.duration_since(t).ok())
            .unwrap_or_default()
    };
    let mut entries = Vec::new();
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let p = e.path();
        if name.contains(".part-") {
            if age(&p) > std::time::Duration::from_secs(86_400) {
                std::fs::remove_dir_all(&p).ok();
            }
        } else if name != keep && p.join(VCACHE_MARKER).is_file() {
            entries.push((age(&p.join(VCACHE_MARKER)), p));
        }
    }
    entries.sort_by_key(|e| e.0);
    for (_, p) in entries.into_iter().skip(VCACHE_KEEP.saturating_sub(1)) {
        std::fs::remove_dir_all(p).ok();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_key_hash_is_stable_and_length_prefixed() {
        // Fixed value: a change of the hash would silently orphan every cache entry.
        assert_eq!(
            fnv128(&[b"ab", b"c"]),
            fnv128(&[b"ab".as_slice(), b"c".as_slice()])
        );
        assert_ne!(fnv128(&[b"ab", b"c"]), fnv128(&[b"a", b"bc"]));
        assert_eq!(fnv128(&[]), 0x6c62272e07bb014262b821756295c58d);
        assert_eq!(fnv128(&[b"pixelproc"]), 0xd76fb4b6bc91ddf0dc1ed838fbb0f50c);
    }

    #[test]
    fn cached_build_rejects_bad_names_before_running_anything() {
        let cache = tempfile::tempdir().unwrap();
        let v = |n: &str| vec![(n.to_string(), "module m; endmodule\n".to_string())];
        for (top, files) in [
            ("m", v("../m.v")),
            ("m", v("sub/m.v")),
            ("m", v("")),
            ("m", v("harness.cpp")),
            ("m", vec![]),
            ("a$b", v("m.v")),
            ("", v("m.v")),
            ("m", [v("m.v"), v("m.v")].concat()),
        ] {
            let r = verilator_build_cached_in(cache.path(), top, &files, "", &[]);
            assert!(matches!(r, Err(TbError::Sim(_))), "{top} {files:?}");
        }
        assert_eq!(std::fs::read_dir(cache.path()).unwrap().count(), 0);
    }

    /// A self-running Verilog testbench printing `sum=N`.
    fn counter_tb(limit: u32) -> Vec<(String, String)> {
        vec![
            (
                "cnt.v".to_string(),
                "module cnt(input clk, output reg [7:0] q);\n  initial q = 0;\n  always @(posedge clk) q <= q + 8'd1;\nendmodule\n".to_string(),
            ),
            (
                "tb_cnt.v".to_string(),
                format!("module tb_cnt;\n  reg clk = 0;\n  wire [7:0] q;\n  cnt u(.clk(clk), .q(q));\n  always #5 clk = ~clk;\n  initial begin\n    repeat ({limit}) @(posedge clk);\n    #1 $display(\"sum=%0d\", q);\n    $finish;\n  end\nendmodule\n"),
            ),
        ]
    }

    fn run_exe(exe: &Path) -> String {
        let o = Proc::new(exe).output().unwrap();
        String::from_utf8_lossy(&o.stdout).into_owned()
    }

    #[test]
    fn verilator_builds_are_cached_and_incomplete_entries_rebuilt() {
        if !tool_available("verilator") {
            skip_or_fail("verilator").unwrap();
            return;
        }
        let cache = tempfile::tempdir().unwrap();
        let c = cache.path();
        let (exe, b1) = verilator_build_cached_in(c, "tb_cnt", &counter_tb(7), "", &[]).unwrap();
        assert!(!b1.cached && b1.seconds > 0.0);
        assert!(run_exe(&exe).contains("sum=7"), "{}", run_exe(&exe));
        assert!(b1.dir.join(VCACHE_MARKER).is_file() && !b1.dir.join("obj_dir").exists());
        let (exe2, b2) = verilator_build_cached_in(c, "tb_cnt", &counter_tb(7), "", &[]).unwrap();
        assert!(b2.cached && exe2 == exe && b2.to_string() == "build cached");
        // Another input, another entry.
        let (exe3, b3) = verilator_build_cached_in(c, "tb_cnt", &counter_tb(9), "", &[]).unwrap();
        assert!(!b3.cached && exe3 != exe && run_exe(&exe3).contains("sum=9"));
        // An entry without its completion marker is never reused.
        std::fs::remove_file(b1.dir.join(VCACHE_MARKER)).unwrap();
        let (exe4, b4) = verilator_build_cached_in(c, "tb_cnt", &counter_tb(7), "", &[]).unwrap();
        assert!(!b4.cached && exe4 == exe && run_exe(&exe4).contains("sum=7"));
        // A failing build leaves nothing behind and reports Verilator's error.
        let mut bad = counter_tb(7);
        bad[0].1 = bad[0].1.replace("endmodule", "endmodul");
        let e = verilator_build_cached_in(c, "tb_cnt", &bad, "", &[]).unwrap_err();
        assert!(
            e.to_string().contains("verilator build of tb_cnt failed"),
            "{e}"
        );
        let names: Vec<String> = std::fs::read_dir(c)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        assert!(names.iter().all(|n| !n.contains(".part-")));
    }

    #[test]
    fn verilator_build_with_a_cpp_harness() {
        if !tool_available("verilator") {
            skip_or_fail("verilator").unwrap();
            return;
        }
        let cache = tempfile::tempdir().unwrap();
        let files = vec![(
            "add.v".to_string(),
            "module add(input [7:0] a, input [7:0] b, output [8:0] y);\n  assign y = {1'b0, a} + {1'b0, b};\nendmodule\n".to_string(),
        )];
        let main = "#include \"Vadd.h\"\n#include <cstdio>\nint main() {\n  Vadd m;\n  m.a = 200; m.b = 100; m.eval();\n  std::printf(\"y=%d\\n\", (int)m.y);\n  m.final();\n  return 0;\n}\n";
        let (exe, b) = verilator_build_cached_in(cache.path(), "add", &files, main, &[]).unwrap();
        assert!(!b.cached);
        assert_eq!(run_exe(&exe).trim(), "y=300");
        let (_, b) = verilator_build_cached_in(cache.path(), "add", &files, main, &[]).unwrap();
        assert!(b.cached);
        // The harness is part of the key.
        let other = main.replace("200", "201");
        let (exe, b) = verilator_build_cached_in(cache.path(), "add", &files, &other, &[]).unwrap();
        assert!(!b.cached && run_exe(&exe).trim() == "y=301");
    }
}
