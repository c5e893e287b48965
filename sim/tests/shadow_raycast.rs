//! Shadow flags of the span-parity model against an independent floating-point ray caster
//! written here (its own camera rays, its own ray–triangle test), on every pixel farther
//! than one pixel from a shadow or object boundary.

use pixelproc_sim::pipeline::render;
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::{self, LoadedScene, MeshSource};
use pixelproc_sim::shadow::ShadowForm;
use std::collections::BTreeMap;

mod ray_common;
use ray_common::*;

struct World {
    /// Triangles with (mesh index, casts shadows).
    tris: Vec<([V3; 3], usize, bool)>,
}

fn world(ls: &LoadedScene) -> World {
    let mut tris = Vec::new();
    for (mi, (m, mr)) in ls.meshes.iter().zip(&ls.scene.meshes).enumerate() {
        for t in &m.triangles {
            tris.push((t.map(|i| m.positions[i as usize]), mi, mr.casts_shadows));
        }
    }
    World { tris }
}

/// Per pixel: the visible triangle's index and, per light, whether it is shadowed.
fn ray_cast(ls: &LoadedScene, w: &World, lights: &[V3]) -> Vec<Option<(usize, Vec<bool>)>> {
    let s = &ls.scene;
    let cam = s.camera.as_ref().unwrap();
    let fwd = norm(sub(cam.target, cam.eye));
    let right = norm(cross(fwd, cam.up));
    let up = cross(right, fwd);
    let th = (cam.fov_y_deg.to_radians() / 2.0).tan();
    let aspect = s.width as f64 / s.height as f64;
    let mut out = Vec::new();
    for j in 0..s.height {
        for i in 0..s.width {
            let x = ((i as f64 + 0.5) / s.width as f64 * 2.0 - 1.0) * th * aspect;
            let y = (1.0 - (j as f64 + 0.5) / s.height as f64 * 2.0) * th;
            let d = norm(add(fwd, add(mul(right, x), mul(up, y))));
            let near = w
                .tris
                .iter()
                .enumerate()
                .filter_map(|(k, t)| hit(cam.eye, d, &t.0).filter(|&t| t > 1e-6).map(|t| (t, k)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            out.push(near.map(|(t, k)| {
                let p = add(cam.eye, mul(d, t));
                let shadowed = lights
                    .iter()
                    .map(|l| {
                        let to = sub(*l, p);
                        let dist = dot(to, to).sqrt();
                        let dl = mul(to, 1.0 / dist);
                        w.tris.iter().enumerate().any(|(k2, t2)| {
                            k2 != k
                                && t2.2
                                && hit(p, dl, &t2.0).is_some_and(|u| u > 1e-7 && u < dist - 1e-7)
                        })
                    })
                    .collect();
                (k, shadowed)
            }));
        }
    }
    out
}

const BOX: &str = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\nv -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
const GROUND: &str = "v -12 0 -12\nv 12 0 -12\nv 12 0 12\nv -12 0 12\nf 1 4 3 2\n";
/// A U-shaped (non-convex) block: three boxes' worth, one closed mesh.
fn u_block() -> String {
    // Profile in x-y (counter-clockwise), extruded along z.
    let prof = [
        (0.0, 0.0),
        (3.0, 0.0),
        (3.0, 2.0),
        (2.2, 2.0),
        (2.2, 0.7),
        (0.8, 0.7),
        (0.8, 2.0),
        (0.0, 2.0),
    ];
    let n = prof.len();
    let mut s = String::new();
    for z in [-0.5, 0.5] {
        for (x, y) in prof {
            s += &format!("v {x} {y} {z}\n");
        }
    }
    // Caps as convex pieces: bottom bar and two uprights.
    for (a, b, c, d) in [(0, 1, 4, 5), (0, 5, 6, 7), (1, 2, 3, 4)] {
        s += &format!(
            "f {} {} {} {}\n",
            n + a + 1,
            n + b + 1,
            n + c + 1,
            n + d + 1
        );
        s += &format!("f {} {} {} {}\n", d + 1, c + 1, b + 1, a + 1);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        s += &format!("f {} {} {} {}\n", i + 1, j + 1, n + j + 1, n + i + 1);
    }
    s
}

fn load(json: &str) -> LoadedScene {
    let files: BTreeMap<String, String> = [
        ("box.obj".to_string(), BOX.to_string()),
        ("ground.obj".to_string(), GROUND.to_string()),
        ("u.obj".to_string(), u_block()),
    ]
    .into_iter()
    .collect();
    scene::load_with(
        scene::parse(json, "t").unwrap(),
        &MeshSource::Embedded(files),
        "t",
    )
    .unwrap()
}

/// Compares the model's per-light shadow bits with the ray cast on every pixel whose 3×3
/// neighbourhood agrees (same visible mesh, same ray-cast shadow bits). Returns
/// (compared, shadowed among them).
fn check(ls: &LoadedScene, form: ShadowForm) -> (usize, usize) {
    let ov = Overrides {
        shadow_form: Some(form),
        ..Default::default()
    };
    let fx = Effects::resolve(ls, &ov).unwrap();
    let out = render(ls, &fx).unwrap();
    let frame = out.frame.expect("shadows run the array");
    let wld = world(ls);
    let pos: Vec<V3> = ls.scene.lights.iter().map(|l| l.position).collect();
    let rc = ray_cast(ls, &wld, &pos);
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let key = |k: usize| rc[k].as_ref().map(|(t, s)| (wld.tris[*t].1, s.clone()));
    let (mut compared, mut shadowed) = (0, 0);
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let k = j * w + i;
            let Some((_, bits)) = &rc[k] else { continue };
            let here = key(k);
            let stable =
                (0..3).all(|dy| (0..3).all(|dx| key((j + dy - 1) * w + i + dx - 1) == here));
            if !stable {
                continue;
            }
            let st = &frame.px[k];
            for (l, &b) in bits.iter().enumerate() {
                let model = (st.mask >> l) & 1 == 1;
                assert_eq!(
                    model,
                    b,
                    "pixel ({i},{j}) light {l}: model {model}, ray cast {b}; ray hits mesh {:?}, model state {st:?}",
                    here.as_ref().map(|h| h.0)
                );
            }
            compared += 1;
            shadowed += bits.iter().any(|&b| b) as usize;
        }
    }
    (compared, shadowed)
}

/// A 160×120 scene: the ground mesh, then `casters` (JSON mesh objects, comma-separated).
fn scene(camera: &str, lights: &str, casters: &str) -> String {
    format!(
        r#"{{"width":160,"height":120,"background":[0.2,0.2,0.2],"camera":{camera},"lights":[{lights}],"meshes":[{GROUND_MESH},{casters}]}}"#
    )
}

const CAM: &str = r#"{"eye":[3,6,9],"target":[0,0.5,0],"up":[0,1,0],"fov_y_deg":45}"#;
const GROUND_MESH: &str = r#"{"obj":"ground.obj","color":[0.7,0.7,0.7]}"#;

fn both_forms(json: &str) -> (usize, usize) {
    both_forms_loaded(&load(json))
}

fn both_forms_loaded(ls: &LoadedScene) -> (usize, usize) {
    let a = check(ls, ShadowForm::Ev);
    let b = check(ls, ShadowForm::Check);
    assert_eq!(a, b);
    a
}

#[test]
fn box_over_plane() {
    let j = scene(
        CAM,
        r#"{"position":[2,8,3]}"#,
        r#"{"obj":"box.obj","color":[1,0,0],"translate":[0,1.5,0],"scale":[2,1,2]}"#,
    );
    let (n, s) = both_forms(&j);
    assert!(n > 10000 && s > 150, "compared {n}, shadowed {s}");
}

#[test]
fn non_convex_u_caster() {
    // Light low and to the side so the U's two uprights cast overlapping shadow lobes.
    let j = scene(
        CAM,
        r#"{"position":[-6,5,1]}"#,
        r#"{"obj":"u.obj","color":[0.9,0.8,0.2],"translate":[-1,0.4,0],"rotate_y_deg":60}"#,
    );
    let (n, s) = both_forms(&j);
    assert!(n > 10000 && s > 500, "compared {n}, shadowed {s}");
}

#[test]
fn two_lights() {
    let j = scene(
        CAM,
        r#"{"position":[4,7,2.6],"intensity":0.5},{"position":[-4,6,3],"intensity":0.5}"#,
        r#"{"obj":"box.obj","color":[1,0,0],"translate":[0,1,0]},{"obj":"box.obj","color":[0,0,1],"translate":[1.5,0.5,1.5]}"#,
    );
    let (n, s) = both_forms(&j);
    assert!(n > 10000 && s > 250, "compared {n}, shadowed {s}");
}

#[test]
fn camera_inside_a_shadow_volume() {
    // A large roof between the light and a camera looking down at the ground: the eye is in
    // the roof's shadow volume, so its spans carry IF.
    let cam = r#"{"eye":[0,2,1],"target":[0,0,-1],"up":[0,1,0],"fov_y_deg":60}"#;
    let j = scene(
        cam,
        r#"{"position":[0.5,12,1]}"#,
        r#"{"obj":"box.obj","color":[0.5,0.5,0.9],"translate":[0,5,0],"scale":[3,0.2,3]},{"obj":"box.obj","color":[1,0,0],"translate":[0.8,0.5,0.5]}"#,
    );
    let ls = load(&j);
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    let out = render(&ls, &fx).unwrap();
    assert!(
        out.shadow.eye_inside >= 1,
        "the eye should be inside the roof's volume"
    );
    let (n, s) = both_forms(&j);
    assert!(n > 10000 && s > 5000, "compared {n}, shadowed {s}");
}

#[test]
fn shadows_off_runs_no_shadow_stage_and_leaves_flags_clear() {
    let j = scene(
        CAM,
        r#"{"position":[2,8,3],"shadows":false}"#,
        r#"{"obj":"box.obj","color":[1,0,0],"translate":[0,1.5,0]}"#,
    );
    let ls = load(&j);
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    assert!(fx.shadow_lights.is_empty());
    let out = render(&ls, &fx).unwrap();
    assert!(out
        .timings
        .iter()
        .all(|(s, _)| !s.to_string().contains("shadow")));
    assert!(out.frame.unwrap().px.iter().all(|p| p.mask == 0 && !p.fsf));
}

#[test]
fn area_light_counter_counts_shadowing_samples() {
    // One area light of 8 samples: the per-pixel counter equals the number of samples the
    // ray cast finds blocked (sample positions are the scene's definition of the light).
    let j = scene(
        CAM,
        r#"{"position":[1,6,2],"radius":3.0,"samples":8}"#,
        r#"{"obj":"box.obj","color":[1,0,0],"translate":[0,2.2,0],"scale":[1.5,0.4,1.5]}"#,
    );
    let ls = load(&j);
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    let frame = render(&ls, &fx).unwrap().frame.unwrap();
    let samples: Vec<V3> = pixelproc_sim::shadow::light_samples(&ls.scene.lights[0])
        .iter()
        .map(|p| p.to_array())
        .collect();
    let wld = world(&ls);
    let rc = ray_cast(&ls, &wld, &samples);
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let key = |k: usize| {
        rc[k]
            .as_ref()
            .map(|(t, s)| (wld.tris[*t].1, s.iter().filter(|&&b| b).count()))
    };
    let (mut compared, mut penumbra) = (0, 0);
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let k = j * w + i;
            let Some((_, n)) = key(k) else { continue };
            if !(0..3).all(|dy| (0..3).all(|dx| key((j + dy - 1) * w + i + dx - 1) == key(k))) {
                continue;
            }
            assert_eq!(frame.px[k].count as usize, n, "pixel ({i},{j})");
            compared += 1;
            penumbra += (n > 0 && n < 8) as usize;
        }
    }
    assert!(
        compared > 10000 && penumbra > 100,
        "compared {compared}, penumbra {penumbra}"
    );
}

#[test]
fn tiling_and_shadow_form_do_not_change_a_bit() {
    // The array width (tiles skip commands that cannot change them) and the EV/check form
    // must leave every processor register identical.
    let j = scene(
        CAM,
        r#"{"position":[4,7,2.6],"intensity":0.5},{"position":[1,6,2],"radius":2.0,"samples":4}"#,
        r#"{"obj":"u.obj","color":[0.9,0.8,0.2],"translate":[-1,0.4,0]},{"obj":"box.obj","color":[0,0,1],"translate":[1.5,0.5,1.5]}"#,
    );
    let ls = load(&j);
    let run = |aw: usize, form: ShadowForm| {
        let ov = Overrides {
            array_width: Some(aw),
            shadow_form: Some(form),
            ..Default::default()
        };
        let out = render(&ls, &Effects::resolve(&ls, &ov).unwrap()).unwrap();
        (out.frame.unwrap().px, out.image.data)
    };
    let reference = run(160, ShadowForm::Ev);
    assert!(reference.0.iter().any(|p| p.mask != 0) && reference.0.iter().any(|p| p.count > 0));
    for aw in [1, 7, 64] {
        for form in [ShadowForm::Ev, ShadowForm::Check] {
            let r = run(aw, form);
            // DSF is a working register; compare what the array delivers: depth, colour,
            // the light mask and counter (built from FSF), and the normal class.
            let strip = |v: &Vec<pixelproc_sim::pixel_array::ProcState>| {
                v.iter()
                    .map(|p| (p.zb, p.rgb, p.mask, p.count, p.nclass))
                    .collect::<Vec<_>>()
            };
            assert_eq!(
                strip(&r.0),
                strip(&reference.0),
                "array width {aw}, form {form:?}"
            );
            assert_eq!(r.1, reference.1);
        }
    }
}

/// A heightfield of `n`×`n` quads (two triangles each) over ±`half`: one open mesh, so
/// every face casts its own volume, and faces meet at edges the volumes pass through.
fn terrain(n: usize, half: f64) -> String {
    let mut s = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let x = (i as f64 / n as f64 - 0.5) * 2.0 * half;
            let z = (j as f64 / n as f64 - 0.5) * 2.0 * half;
            let y = 0.6 * (x * 1.1).sin() * (z * 0.9).cos() + 0.3 * (x * 0.4 + z * 0.7).sin();
            s += &format!("v {x} {y} {z}\n");
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c) = (a + 1, a + n + 1);
            let d = c + 1;
            s += &format!("f {a} {c} {b}\nf {b} {c} {d}\n");
        }
    }
    s
}

/// A hilly terrain (one open mesh of 2,048 faces, each its own volume) shadowing itself,
/// under a high and a low light: every pixel whose neighbourhood agrees matches the ray
/// cast, in both shadow forms.
#[test]
fn terrain_shadows_itself() {
    for light in ["[8,5,2]", "[-6,2.5,-3]"] {
        let j = format!(
            r#"{{"width":400,"height":300,"background":[0.2,0.2,0.2],"camera":{{"eye":[0,3.5,7],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":50}},"lights":[{{"position":{light}}}],"meshes":[{{"obj":"terrain.obj","color":[0.5,0.6,0.4]}}]}}"#
        );
        let files = [("terrain.obj".to_string(), terrain(32, 5.0))];
        let ls = scene::load_with(
            scene::parse(&j, "t").unwrap(),
            &MeshSource::Embedded(files.into_iter().collect()),
            "t",
        )
        .unwrap();
        let (n, s) = both_forms_loaded(&ls);
        assert!(
            n > 60000 && s > 2000,
            "light {light}: compared {n}, shadowed {s}"
        );
    }
}
