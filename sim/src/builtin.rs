//! Procedural built-in scenes (for benchmarks): generated, not stored.

use std::collections::BTreeMap;
use std::fmt::Write;

use crate::rng::Lcg64;

/// Boxes per mesh in the `boxes` scene.
const BOXES_PER_MESH: usize = 104;
/// Meshes in the `boxes` scene (one colour each).
const MESHES: usize = 8;

/// A 1920×1080 3-D scene: a ground plane and 832 boxes (9,986 triangles), one light.
/// Returns the scene JSON and its generated OBJ files.
pub fn boxes_scene() -> (String, BTreeMap<String, String>) {
    let mut files = BTreeMap::new();
    files.insert(
        "ground.obj".to_string(),
        "v -40 0 -40\nv 40 0 -40\nv 40 0 40\nv -40 0 40\nf 1 4 3 2\n".to_string(),
    );
    // The shared 64-bit LCG: deterministic placement. This scene takes the top 31 bits
    // of each state (not `Lcg64::unit`'s 53), which keeps the generated scene unchanged.
    let mut lcg = Lcg64(0x2545_F491_4F6C_DD1D);
    let mut rnd = move || ((lcg.step() >> 33) as f64) / ((1u64 << 31) as f64);
    let mut meshes = vec![
        r#"{"obj": "ground.obj", "color": [0.55, 0.6, 0.5], "casts_shadows": false}"#.to_string(),
    ];
    for m in 0..MESHES {
        let mut obj = String::new();
        for b in 0..BOXES_PER_MESH {
            let (cx, cz) = (rnd() * 36.0 - 18.0, rnd() * 30.0 - 24.0);
            let (sx, sy, sz) = (0.3 + rnd() * 0.9, 0.3 + rnd() * 2.5, 0.3 + rnd() * 0.9);
            let a = rnd() * std::f64::consts::PI;
            let (s, c) = a.sin_cos();
            for (x, y, z) in [
                (-1.0, 0.0, -1.0),
                (1.0, 0.0, -1.0),
                (1.0, 2.0, -1.0),
                (-1.0, 2.0, -1.0),
                (-1.0, 0.0, 1.0),
                (1.0, 0.0, 1.0),
                (1.0, 2.0, 1.0),
                (-1.0, 2.0, 1.0),
            ] {
                let (px, py, pz) = (x * sx * 0.5, y * sy * 0.5, z * sz * 0.5);
                let _ = writeln!(
                    obj,
                    "v {} {} {}",
                    cx + c * px + s * pz,
                    py,
                    cz - s * px + c * pz
                );
            }
            let o = b * 8;
            for f in [
                [1, 4, 3, 2],
                [5, 6, 7, 8],
                [1, 2, 6, 5],
                [4, 8, 7, 3],
                [1, 5, 8, 4],
                [2, 3, 7, 6],
            ] {
                let _ = writeln!(obj, "f {} {} {} {}", o + f[0], o + f[1], o + f[2], o + f[3]);
            }
        }
        let name = format!("boxes{m}.obj");
        files.insert(name.clone(), obj);
        let hue = m as f64 / MESHES as f64;
        meshes.push(format!(
            r#"{{"obj": "{name}", "color": [{:.3}, {:.3}, {:.3}]}}"#,
            0.35 + 0.5 * (hue * std::f64::consts::TAU).sin().abs(),
            0.35 + 0.5 * (hue * 4.0 + 1.0).sin().abs(),
            0.35 + 0.5 * (hue * 3.0 + 2.0).cos().abs()
        ));
    }
    let json = format!(
        r#"{{"width": 1920, "height": 1080, "background": [0.5, 0.65, 0.85],
  "camera": {{"eye": [0, 14, 22], "target": [0, 0, -6], "up": [0, 1, 0], "fov_y_deg": 50}},
  "lights": [{{"position": [12, 30, 14]}}],
  "meshes": [{}]}}"#,
        meshes.join(",\n")
    );
    (json, files)
}
