//! Bad input never yields a silent wrong picture: degenerate cameras and transforms,
//! inputs that are not regular files, all-or-nothing outputs, strict scenes, messages that
//! name the right flag or field, and stale outputs. Each case runs the real binary.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn pixelproc(dir: &Path, args: &[&str]) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_pixelproc"))
        .args(args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run pixelproc");
    let t0 = Instant::now();
    let out = child.wait_with_output().expect("wait");
    assert!(
        t0.elapsed() < Duration::from_secs(60),
        "{args:?} took {:?}",
        t0.elapsed()
    );
    out
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Files in `dir` a failed run could have left: PNGs and temporaries.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png") || n.starts_with(".pixelproc-"))
        .collect()
}

/// A failing run: exit 1, one `error:` line containing every needle, no panic, nothing
/// left behind.
fn expect_error(dir: &Path, args: &[&str], needles: &[&str]) -> String {
    let o = pixelproc(dir, args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: expected one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: '{n}' not in: {err}");
    }
    assert!(err.len() < 300, "{args:?}: overlong message: {err}");
    assert!(
        leftovers(dir).is_empty(),
        "{args:?} left {:?}",
        leftovers(dir)
    );
    err
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

const BOX: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";

/// A 3-D scene with `camera` and one mesh entry `mesh` (JSON object text).
fn scene3d(camera: &str, mesh: &str) -> String {
    format!(
        r#"{{"width":32,"height":24,"camera":{camera},"lights":[{{"position":[3,5,4]}}],"meshes":[{mesh}]}}"#
    )
}

const CAM: &str = r#"{"eye":[2,2,5],"target":[0.5,0.5,0.5],"up":[0,1,0],"fov_y_deg":45}"#;
const MESH: &str = r#"{"obj":"box.obj","color":[0.8,0.2,0.2]}"#;

#[test]
fn degenerate_cameras_and_transforms_name_the_field() {
    let d = tempfile::tempdir().unwrap();
    write(d.path(), "box.obj", BOX);
    let cases = [
        (
            r#"{"eye":[1,1,1],"target":[1,1,1],"up":[0,1,0],"fov_y_deg":45}"#,
            MESH.to_string(),
            "camera.target equals camera.eye",
        ),
        (
            r#"{"eye":[2,2,5],"target":[0,0,0],"up":[0,0,0],"fov_y_deg":45}"#,
            MESH.to_string(),
            "camera.up",
        ),
        (
            r#"{"eye":[0,5,0],"target":[0,0,0],"up":[0,-2,0],"fov_y_deg":45}"#,
            MESH.to_string(),
            "parallel to the view direction",
        ),
        (
            CAM,
            r#"{"obj":"box.obj","color":[1,1,1],"scale":[1e300,1,1]}"#.to_string(),
            "meshes[0].scale",
        ),
        (
            CAM,
            r#"{"obj":"box.obj","color":[1,1,1],"translate":[0,1e308,0]}"#.to_string(),
            "meshes[0].translate",
        ),
        (
            CAM,
            r#"{"obj":"box.obj","color":[1,1,1],"scale":[5e8,5e8,5e8],"translate":[8e8,0,0]}"#
                .to_string(),
            "vertex",
        ),
    ];
    for (k, (cam, mesh, needle)) in cases.iter().enumerate() {
        let name = format!("s{k}.json");
        write(d.path(), &name, &scene3d(cam, mesh));
        expect_error(d.path(), &["render", &name, "-o", "o.png"], &[needle]);
    }
}

#[cfg(unix)]
#[test]
fn meshes_must_be_regular_files_of_bounded_size() {
    let d = tempfile::tempdir().unwrap();
    let fifo = d.path().join("fifo.obj");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    write(
        d.path(),
        "f.json",
        &scene3d(CAM, r#"{"obj":"fifo.obj","color":[1,1,1]}"#),
    );
    expect_error(
        d.path(),
        &["render", "f.json", "-o", "o.png"],
        &["FIFO", "not a regular file"],
    );
    write(
        d.path(),
        "z.json",
        &scene3d(CAM, r#"{"obj":"/dev/zero","color":[1,1,1]}"#),
    );
    expect_error(
        d.path(),
        &["render", "z.json", "-o", "o.png"],
        &["/dev/zero", "device"],
    );
    // Over the size limit (1 MiB here), refused before reading.
    write(d.path(), "big.obj", &"# padding line\n".repeat(80_000));
    write(
        d.path(),
        "b.json",
        &scene3d(CAM, r#"{"obj":"big.obj","color":[1,1,1]}"#),
    );
    expect_error(
        d.path(),
        &["render", "b.json", "-o", "o.png", "--max-input-mb", "1"],
        &["big.obj", "--max-input-mb"],
    );
    // The scene file itself follows the same rules.
    expect_error(
        d.path(),
        &["render", "/dev/null", "-o", "o.png"],
        &["not a regular file"],
    );
}

#[test]
fn sandbox_keeps_meshes_inside_the_scene_folder() {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir(d.path().join("s")).unwrap();
    write(d.path(), "box.obj", BOX);
    write(
        &d.path().join("s"),
        "up.json",
        &scene3d(CAM, r#"{"obj":"../box.obj","color":[1,1,1]}"#),
    );
    expect_error(
        d.path(),
        &["render", "s/up.json", "-o", "o.png", "--sandbox"],
        &["outside the scene folder"],
    );
    // Without --sandbox the documented default reads it.
    let o = pixelproc(d.path(), &["render", "s/up.json", "-o", "o.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn outputs_are_all_or_nothing() {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir(d.path().join("dir.png")).unwrap();
    let o = pixelproc(d.path(), &["render", "@default", "-o", "dir.png"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
    // A render whose AOV target is a directory replaces nothing, leaves nothing.
    let o = pixelproc(d.path(), &["render", "@default", "-o", "a.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(d.path().join("a.png")).unwrap();
    std::fs::write(d.path().join("a.png"), b"old").unwrap();
    std::fs::create_dir(d.path().join("a.shadow.png")).unwrap();
    let o = pixelproc(
        d.path(),
        &["render", "@default", "-o", "a.png", "--aov", "depth,shadow"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(std::fs::read(d.path().join("a.png")).unwrap(), b"old");
    assert!(!d.path().join("a.depth.png").exists());
    let temps: Vec<_> = leftovers(d.path())
        .into_iter()
        .filter(|n| n.starts_with(".pixelproc"))
        .collect();
    assert!(temps.is_empty(), "{temps:?}");
    // A successful rerun writes the usual mode.
    std::fs::remove_dir(d.path().join("a.shadow.png")).unwrap();
    std::fs::remove_file(d.path().join("a.png")).unwrap();
    let o = pixelproc(d.path(), &["render", "@default", "-o", "a.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(d.path().join("a.png")).unwrap(), before);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(d.path().join("a.png"))
            .unwrap()
            .permissions()
            .mode();
        assert_ne!(
            mode & 0o044,
            0,
            "written PNG is not readable by others: {mode:o}"
        );
    }
}

#[test]
fn verilog_reruns_remove_stale_exported_files() {
    let d = tempfile::tempdir().unwrap();
    let run = |w: &str| {
        let o = pixelproc(
            d.path(),
            &[
                "verilog",
                "@default",
                "-o",
                "v",
                "--array-width",
                w,
                "--no-shadows",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    run("4");
    assert!(d.path().join("v/pixel_processor_array_n4.v").exists());
    std::fs::write(d.path().join("v/notes.v"), "// mine").unwrap();
    let out = run("2");
    assert!(out.contains("removed stale"), "{out}");
    assert!(!d.path().join("v/pixel_processor_array_n4.v").exists());
    assert!(d.path().join("v/pixel_processor_array_n2.v").exists());
    assert!(
        d.path().join("v/notes.v").exists(),
        "a file it does not own was removed"
    );
}

#[test]
fn strict_scenes_and_obj_statements() {
    let d = tempfile::tempdir().unwrap();
    write(
        d.path(),
        "t.json",
        r#"{"width":8,"height":8,"triangels":[]}"#,
    );
    let o = pixelproc(d.path(), &["render", "t.json", "-o", "t.png"]);
    assert!(o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("warning: scene t.json: unknown key `triangels` (did you mean `triangles`?)"),
        "{err}"
    );
    std::fs::remove_file(d.path().join("t.png")).unwrap();
    expect_error(
        d.path(),
        &["render", "t.json", "-o", "t.png", "--strict"],
        &["triangels", "--strict"],
    );
    write(d.path(), "a.json", "[64, 48]");
    expect_error(
        d.path(),
        &["render", "a.json", "-o", "a.png"],
        &["JSON object", "array"],
    );
    write(
        d.path(),
        "box.obj",
        &format!("{BOX}frobnicate 1\nbevel 2\n"),
    );
    write(d.path(), "m.json", &scene3d(CAM, MESH));
    let o = pixelproc(d.path(), &["render", "m.json", "-o", "m.png"]);
    assert!(o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("2 statement(s) not understood") && err.contains("`frobnicate 1`"),
        "{err}"
    );
}

#[test]
fn messages_name_the_right_thing() {
    let d = tempfile::tempdir().unwrap();
    write(
        d.path(),
        "v4.json",
        r#"{"width":8,"height":8,"triangles":[{"v":[[0,0,0,1],[5,0,0],[0,5,0]],"color":[1,0,0]}]}"#,
    );
    let e = expect_error(
        d.path(),
        &["render", "v4.json", "-o", "o.png"],
        &["triangles[0].v[0]"],
    );
    assert!(!e.contains("trailing characters"), "{e}");
    write(
        d.path(),
        "huge.json",
        r#"{"width":8,"height":8,"triangles":[{"v":[[1e190,0,0],[5,0,0],[0,5,0]],"color":[1,0,0]}]}"#,
    );
    let e = expect_error(
        d.path(),
        &["render", "huge.json", "-o", "o.png"],
        &["1e190"],
    );
    assert!(!e.contains("0000000000"), "{e}");
    write(
        d.path(),
        "box.obj",
        "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
    );
    write(d.path(), "nan.json", &scene3d(CAM, MESH));
    expect_error(
        d.path(),
        &["render", "nan.json", "-o", "o.png"],
        &["meshes[0]", "line 2", "vertex 2"],
    );
    let e = expect_error(
        d.path(),
        &["render", "missing.json", "-o", "o.png"],
        &["missing.json"],
    );
    assert_eq!(e.matches("No such file").count(), 1, "{e}");
    expect_error(
        d.path(),
        &["testbench", "@default", "--rows", "a..b"],
        &["--rows a..b"],
    );
    let o = pixelproc(
        d.path(),
        &["testbench", "@default", "--aa", "abuffer", "--mask", "3x5"],
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1));
    assert!(!out.contains("bit-exact"), "ran before refusing: {out}");
    assert!(stderr(&o).contains("--mask 3x5"), "{}", stderr(&o));
    // A byte-order mark is skipped.
    std::fs::write(
        d.path().join("bom.json"),
        b"\xEF\xBB\xBF{\"width\":4,\"height\":4,\"triangles\":[]}",
    )
    .unwrap();
    let o = pixelproc(d.path(), &["render", "bom.json", "-o", "bom.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[cfg(unix)]
#[test]
fn non_utf8_file_names_are_accepted() {
    use std::os::unix::ffi::OsStrExt;
    let d = tempfile::tempdir().unwrap();
    let name = std::ffi::OsStr::from_bytes(b"sc\xE9ne.json");
    std::fs::write(
        d.path().join(name),
        r#"{"width":4,"height":4,"triangles":[]}"#,
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_pixelproc"))
        .arg("render")
        .arg(name)
        .args(["-o", "x.png"])
        .current_dir(d.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn usage_errors_exit_2_and_other_errors_exit_1() {
    let d = tempfile::tempdir().unwrap();
    let o = pixelproc(d.path(), &["render", "--no-such-flag"]);
    assert_eq!(o.status.code(), Some(2));
    let o = pixelproc(d.path(), &["render", "nothing.json"]);
    assert_eq!(o.status.code(), Some(1));
}

/// `tradeoff`'s hardware configuration: a bad `--array-width` or `--clock-mhz` (zero,
/// negative, not a number, absurd) is a usage error: exit 2, one `error:` line naming the
/// flag and the value as typed, no panic, before any sweep runs or any file is written.
#[test]
fn tradeoff_rejects_bad_hardware_configurations() {
    let d = tempfile::tempdir().unwrap();
    let run = |flag: &str, v: &str| {
        let args = ["tradeoff", "--quick", "--runs", "1", "-o", "t", flag, v];
        let o = pixelproc(d.path(), &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: expected one line: {err}");
        assert!(err.starts_with(&format!("error: {flag} {v}: ")), "{err}");
        assert!(!d.path().join("t").exists(), "{flag} {v} wrote output");
    };
    for v in ["0", "-3", "eight", "4097", "1e3", "99999999999999999999"] {
        run("--array-width", v);
    }
    for v in ["0", "-81", "fast", "nan", "inf", "1e9"] {
        run("--clock-mhz", v);
    }
}

/// `--runs` of `bench` and `tradeoff`: zero or more than 10000 is a usage error (exit 2, one
/// `error:` line naming the flag and the value) before anything renders or is written; a
/// count of a hundred billion once ran until the machine ran out of memory (`bench` kept
/// every run's image) or aborted in an allocation (`tradeoff`).
#[test]
fn runs_outside_the_bound_are_usage_errors() {
    let d = tempfile::tempdir().unwrap();
    let cases: [&[&str]; 4] = [
        &["bench", "@default", "--runs"],
        &["bench", "--all-methods", "--runs"],
        &["tradeoff", "--quick", "-o", "t", "--runs"],
        &["bench", "@boxes", "--runs"],
    ];
    for c in cases {
        for v in ["0", "10001", "99999999999"] {
            let mut args = c.to_vec();
            args.push(v);
            let o = pixelproc(d.path(), &args);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
            assert!(!err.contains("panicked"), "{args:?}: {err}");
            assert_eq!(err.lines().count(), 1, "{args:?}: expected one line: {err}");
            assert_eq!(
                err.trim(),
                format!("error: --runs {v} is outside 1..=10000")
            );
            assert!(o.stdout.is_empty(), "{args:?} printed before failing");
            assert!(!d.path().join("t").exists(), "{args:?} wrote output");
        }
    }
}

/// `bench` keeps only each run's stage times, so its memory does not grow with `--runs`:
/// 200 runs of `@default` peak within 64 MiB of 1 run. Each run's output (image and
/// buffers) is about 3 MiB, so keeping every run's output, as `bench` once did, adds
/// about 600 MiB. The peak is the child's own maximum resident set, read by a Python
/// parent (`getrusage` of its one child).
#[test]
fn bench_memory_does_not_grow_with_runs() {
    let d = tempfile::tempdir().unwrap();
    let peak_kib = |runs: &str| -> u64 {
        let script = "import resource, subprocess, sys\n\
                      r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL)\n\
                      assert r.returncode == 0, r\n\
                      print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)";
        let o = Command::new("python3")
            .args(["-c", script, env!("CARGO_BIN_EXE_pixelproc")])
            .args(["bench", "@default", "--runs", runs])
            .current_dir(d.path())
            .output()
            .expect("python3");
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).trim().parse().unwrap()
    };
    let (one, many) = (peak_kib("1"), peak_kib("200"));
    assert!(
        many < one + 64 * 1024,
        "peak {one} KiB with 1 run, {many} KiB with 200"
    );
}
