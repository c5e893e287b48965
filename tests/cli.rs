//! The command line as a user meets it: the default run, `render`, and bad input (one
//! clear line, non-zero exit, no panic trace, no output file).

use std::path::Path;
use std::process::{Command, Output};

fn pixelproc(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pixelproc"))
        .args(args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("run pixelproc")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs a command that must fail: exit code 1, a single `error:` line, no panic, and no
/// output file left behind.
fn expect_error(dir: &Path, args: &[&str], needle: &str) -> String {
    let o = pixelproc(dir, args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert_eq!(
        err.lines().count(),
        1,
        "{args:?}: expected one line, got: {err}"
    );
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains(needle), "{args:?}: '{needle}' not in: {err}");
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png") || n.starts_with(".pixelproc-"))
        .collect();
    assert!(leftovers.is_empty(), "{args:?} left files: {leftovers:?}");
    err
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

#[test]
fn no_arguments_renders_the_default_scene() {
    let d = tempfile::tempdir().unwrap();
    let o = pixelproc(d.path(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("pixel-processor array"), "{out}");
    let png = d.path().join("pixelproc-out/default.png");
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (640, 360));
    assert!(out.contains("bit-exact: yes"), "{out}");
    assert!(d
        .path()
        .join("pixelproc-out/verilog/pixelproc_top.v")
        .exists());
}

#[test]
fn testbench_reports_bit_exactness_for_a_scene() {
    let d = tempfile::tempdir().unwrap();
    write(
        d.path(),
        "tb.json",
        r#"{"width":40,"height":6,"background":[0.1,0.2,0.3],"triangles":[{"v":[[0,0,0.2],[40,2,0.9],[3,6,0.5]],"color":[1,0.5,0]},{"v":[[10,-1,0.1],[30,7,0.8],[5,5,0.3]],"color":[0,0.5,1],"colors":[[0,0,1],[1,0,0],[0,1,0]]}]}"#,
    );
    let o = pixelproc(
        d.path(),
        &[
            "testbench",
            "tb.json",
            "--array-width",
            "16",
            "--rows",
            "1..4",
            "--work",
            "w",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("bit-exact: yes") && out.contains("4 scanlines"),
        "{out}"
    );
    expect_error(
        d.path(),
        &["testbench", "tb.json", "--rows", "5..9"],
        "--rows 5..9",
    );
}

#[test]
fn render_writes_the_named_file_and_aovs() {
    let d = tempfile::tempdir().unwrap();
    write(
        d.path(),
        "s.json",
        r#"{"width":8,"height":8,"background":[0,0,0],"triangles":[{"v":[[0,0,0],[8,0,0],[0,8,0]],"color":[1,0,0]}]}"#,
    );
    let o = pixelproc(
        d.path(),
        &["render", "s.json", "-o", "out/x.png", "--aov", "depth"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(d.path().join("out/x.png")).unwrap().to_rgb8();
    assert_eq!(img.get_pixel(1, 1).0, [255, 0, 0]);
    assert_eq!(img.get_pixel(7, 7).0, [0, 0, 0]);
    assert!(d.path().join("out/x.depth.png").exists());
}

#[test]
fn help_exists_for_every_subcommand() {
    let d = tempfile::tempdir().unwrap();
    for args in [
        vec!["--help"],
        vec!["render", "--help"],
        vec!["bench", "--help"],
        vec!["verilog", "--help"],
        vec!["testbench", "--help"],
        vec!["tradeoff", "--help"],
    ] {
        let o = pixelproc(d.path(), &args);
        assert!(o.status.success());
        assert!(String::from_utf8_lossy(&o.stdout).contains("Usage"));
    }
}

#[test]
fn bad_inputs_give_one_clear_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    expect_error(
        p,
        &["render", "missing.json", "-o", "a.png"],
        "cannot read scene missing.json",
    );
    write(
        p,
        "bad.json",
        "{\n  \"width\": 8,\n  \"height\": 8,\n  \"triangles\": [ }\n",
    );
    expect_error(p, &["render", "bad.json", "-o", "a.png"], "line 4 column");
    write(
        p,
        "obj.json",
        r#"{"width":8,"height":8,"camera":{"eye":[0,0,5],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":40},"meshes":[{"obj":"nope.obj","color":[1,1,1]}]}"#,
    );
    expect_error(p, &["render", "obj.json", "-o", "a.png"], "nope.obj");
    write(p, "nanobj.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    write(
        p,
        "nan.json",
        r#"{"width":8,"height":8,"camera":{"eye":[0,0,5],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":40},"meshes":[{"obj":"nanobj.obj","color":[1,1,1]}]}"#,
    );
    expect_error(p, &["render", "nan.json", "-o", "a.png"], "not finite");
    write(
        p,
        "inf.json",
        r#"{"width":8,"height":8,"triangles":[{"v":[[0,0,0],[1e999,0,0],[0,8,0]],"color":[1,0,0]}]}"#,
    );
    expect_error(p, &["render", "inf.json", "-o", "a.png"], "inf.json");
    write(
        p,
        "far.json",
        r#"{"width":8,"height":8,"triangles":[{"v":[[0,0,0],[1e6,0,0],[0,8,0]],"color":[1,0,0]}]}"#,
    );
    expect_error(
        p,
        &["render", "far.json", "-o", "a.png"],
        "outside the fixed-point range",
    );
    write(p, "big.json", r#"{"width":5000,"height":8,"triangles":[]}"#);
    expect_error(
        p,
        &["render", "big.json", "-o", "a.png"],
        "resolution 5000x8",
    );
    write(
        p,
        "col.json",
        r#"{"width":8,"height":8,"triangles":[{"v":[[0,0,0],[8,0,0],[0,8,0]],"color":[2,0,0]}]}"#,
    );
    expect_error(p, &["render", "col.json", "-o", "a.png"], "not within 0..1");
    expect_error(
        p,
        &["render", "@nosuch", "-o", "a.png"],
        "unknown built-in scene",
    );
    expect_error(
        p,
        &["render", "@default", "-o", "a.jpg"],
        "must end in .png",
    );
    expect_error(
        p,
        &["render", "@default", "-o", "a.png", "--aov", "nope"],
        "unknown AOV",
    );
}

#[test]
fn degenerate_triangles_are_not_an_error() {
    let d = tempfile::tempdir().unwrap();
    write(
        d.path(),
        "deg.json",
        r#"{"width":8,"height":8,"triangles":[{"v":[[1,1,0],[4,4,0],[7,7,0]],"color":[1,0,0]},{"v":[[2,2,0],[2,2,0],[2,2,0]],"color":[1,0,0]}]}"#,
    );
    let o = pixelproc(d.path(), &["render", "deg.json", "-o", "d.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(d.path().join("d.png")).unwrap().to_rgb8();
    assert!(img.pixels().all(|p| p.0 == [0, 0, 0]));
}

#[test]
fn anti_aliasing_flags_and_scene_field() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // Every method renders the default scene.
    for args in [
        vec!["--aa", "abuffer", "--mask", "8x8", "--depth", "exhaustive"],
        vec![
            "--aa",
            "multiscan",
            "--subscanlines",
            "2",
            "--filter",
            "gauss",
        ],
        vec!["--aa", "corner", "--samples", "2"],
        vec!["--aa", "postfx", "--postfx-normals", "stored"],
        vec!["--aa", "ssaa", "--ssaa", "2"],
    ] {
        let mut a = vec!["render", "@default", "-o", "aa.png"];
        a.extend(&args);
        let o = pixelproc(p, &a);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert!(
            String::from_utf8_lossy(&o.stdout).contains("anti-aliasing"),
            "{args:?}"
        );
    }
    std::fs::remove_file(p.join("aa.png")).unwrap();
    expect_error(
        p,
        &[
            "render", "@default", "-o", "a.png", "--aa", "corner", "--mask", "4x4",
        ],
        "--mask applies to --aa abuffer",
    );
    expect_error(
        p,
        &["render", "@default", "-o", "a.png", "--subscanlines", "4"],
        "need --aa",
    );
    expect_error(
        p,
        &[
            "render",
            "@default",
            "-o",
            "a.png",
            "--aa",
            "multiscan",
            "--subscanlines",
            "17",
        ],
        "outside 1..=16",
    );
    // The scene's effects.aa object, with the same parameter names as the flags.
    write(
        p,
        "ms.json",
        r#"{"width":16,"height":16,"triangles":[{"v":[[0,0,0],[16,3,0],[0,16,0]],"color":[1,1,1]}],"effects":{"aa":{"method":"multiscan","subscanlines":4}}}"#,
    );
    let o = pixelproc(p, &["render", "ms.json", "-o", "ms.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("multiscan n=4"));
    std::fs::remove_file(p.join("ms.png")).unwrap();
    write(
        p,
        "bad_aa.json",
        r#"{"width":16,"height":16,"triangles":[],"effects":{"aa":{"method":"multiscan","subscanline":4}}}"#,
    );
    expect_error(
        p,
        &["render", "bad_aa.json", "-o", "b.png"],
        "unknown field",
    );
}

#[test]
fn parameter_errors_name_the_flag_or_the_scene_key() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let render = |extra: &[&'static str]| {
        let mut a = vec!["render", "@default", "-o", "a.png"];
        a.extend(extra);
        a
    };
    let err = expect_error(
        p,
        &render(&["--aa", "abuffer", "--mask", "abc"]),
        "--mask abc: expected NxM",
    );
    assert!(!err.contains("0x0"), "{err}");
    for (extra, want) in [
        (
            "multiscan --subscanlines 99",
            "--subscanlines 99 is outside 1..=16",
        ),
        ("ssaa --ssaa 0", "--ssaa 0 is outside 1..=64"),
        (
            "postfx --postfx-window 4",
            "--postfx-window 4: expected 5 or 3",
        ),
        (
            "abuffer --mask 9x9",
            "--mask 9x9: mask size 9x9 is not supported",
        ),
        (
            "multiscan --filter blur",
            "--filter: unknown filter 'blur' (known: box, gauss, cone)",
        ),
        (
            "corner --filter box",
            "--filter applies to --aa multiscan, not --aa corner",
        ),
        ("abuffer --depth deep", "unknown depth selection 'deep'"),
    ] {
        // `extra` is the method after `--aa`, then its flags.
        let args: Vec<&'static str> = ["--aa"].into_iter().chain(extra.split(' ')).collect();
        expect_error(p, &render(&args), want);
    }
    let scene = |name: &str, aa: &str| {
        write(
            p,
            name,
            &format!(r#"{{"width":16,"height":16,"triangles":[],"effects":{{"aa":{aa}}}}}"#),
        );
    };
    scene("range.json", r#"{"method":"multiscan","subscanlines":99}"#);
    expect_error(
        p,
        &["render", "range.json", "-o", "a.png"],
        "effects.aa.subscanlines 99 is outside 1..=16",
    );
    scene("mask.json", r#"{"method":"abuffer","mask":"abc"}"#);
    let err = expect_error(
        p,
        &["render", "mask.json", "-o", "a.png"],
        "effects.aa.mask abc: expected NxM",
    );
    assert!(!err.contains("0x0"), "{err}");
    scene("filter.json", r#"{"method":"multiscan","filter":"blur"}"#);
    expect_error(
        p,
        &["render", "filter.json", "-o", "a.png"],
        "unknown filter 'blur'",
    );
    scene("other.json", r#"{"method":"corner","subscanlines":4}"#);
    expect_error(
        p,
        &["render", "other.json", "-o", "a.png"],
        "unknown field `subscanlines`",
    );
    scene("name.json", r#""blur""#);
    expect_error(
        p,
        &["render", "name.json", "-o", "a.png"],
        "unknown anti-aliasing method 'blur'",
    );
    // A bare method name is still accepted.
    scene("bare.json", r#""corner""#);
    let o = pixelproc(p, &["render", "bare.json", "-o", "bare.png"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("anti-aliasing: corner"));
}

#[test]
fn verilog_top_holds_only_what_the_scene_needs() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    write(
        p,
        "flat.json",
        r#"{"width":16,"height":16,"triangles":[{"v":[[0,0,0],[16,3,0],[0,16,0]],"color":[1,1,1]}]}"#,
    );
    let o = pixelproc(
        p,
        &["verilog", "flat.json", "-o", "flat", "--array-width", "8"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let top = std::fs::read_to_string(p.join("flat/pixelproc_top.v")).unwrap();
    assert!(top.contains("module pixelproc_top"));
    assert!(
        !top.contains("parity"),
        "a scene without shadows must not get the span-parity logic"
    );
    let o = pixelproc(
        p,
        &[
            "verilog",
            "@default",
            "-o",
            "shadowed",
            "--array-width",
            "8",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let top = std::fs::read_to_string(p.join("shadowed/pixelproc_top.v")).unwrap();
    assert!(
        top.contains("parity"),
        "the default scene's light casts shadows"
    );
}

/// `bench --all-methods SCENE` times every case on the user's scene (one table, every
/// row named after it) and counts the same work as `render` of that case; effect flags,
/// which the cases set themselves, are usage errors naming the flag, not silently ignored.
#[test]
fn bench_all_methods_on_a_given_scene() {
    let d = tempfile::tempdir().unwrap();
    let o = pixelproc(
        d.path(),
        &["bench", "--all-methods", "@default", "--runs", "1"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let rows: Vec<Vec<&str>> = out
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| scene"))
        .map(|l| l.trim_matches('|').split('|').map(str::trim).collect())
        .collect();
    let cases: Vec<&str> = rows.iter().map(|r| r[2]).collect();
    assert_eq!(
        cases,
        [
            "plain",
            "shadows",
            "abuffer",
            "multiscan",
            "corner",
            "ssaa",
            "postfx"
        ],
        "{out}"
    );
    assert!(rows.iter().all(|r| r[0] == "@default"), "{out}");
    assert_eq!(rows[0][4], "1.00", "{out}");
    // The A-buffer row's fragments are those `render` reports for the same case.
    let r = pixelproc(
        d.path(),
        &[
            "render",
            "@default",
            "--aa",
            "abuffer",
            "--no-shadows",
            "-o",
            "a.png",
        ],
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let log = String::from_utf8_lossy(&r.stdout);
    let frags = log
        .lines()
        .find_map(|l| l.strip_prefix("a-buffer: "))
        .and_then(|l| l.split(' ').next())
        .unwrap_or_else(|| panic!("no a-buffer line: {log}"));
    assert_eq!(rows[2][5], format!("{frags} fragment"), "{out}");
    for flag in [
        &["--aa", "ssaa"][..],
        &["--no-shadows"],
        &["--array-width", "8"],
        &["--shading", "table"],
    ] {
        let mut args = vec!["bench", "--all-methods", "@default", "--runs", "1"];
        args.extend_from_slice(flag);
        let o = pixelproc(d.path(), &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.starts_with(&format!(
                "error: {} cannot be used with --all-methods",
                flag[0]
            )),
            "{err}"
        );
        assert!(o.stdout.is_empty(), "{args:?} printed before failing");
    }
}
