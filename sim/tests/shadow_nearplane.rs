//! Shadow flags where the camera's near plane cuts a shadow volume, and where the eye is
//! inside one or several volumes, against an independent floating-point ray caster written
//! here: a ray from the eye through each pixel centre to the first surface beyond the near
//! plane (what the renderer can see), then a shadow ray from that point to the light.
//! Every pixel whose 3×3 neighbourhood agrees (same visible triangle, same ray-cast shadow
//! bit) must carry the same shadow bit in the model, in both the EV and the check-span
//! form.

use pixelproc_sim::frontend::Projector;
use pixelproc_sim::pipeline::render;
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::{self, LoadedScene, MeshSource};
use pixelproc_sim::shadow::{shadow_commands, shadow_lights, ShadowForm};
use std::collections::BTreeMap;

mod ray_common;
use ray_common::*;

/// World triangles with whether their mesh casts shadows.
fn world(ls: &LoadedScene) -> Vec<([V3; 3], bool)> {
    let mut tris = Vec::new();
    for (m, mr) in ls.meshes.iter().zip(&ls.scene.meshes) {
        for t in &m.triangles {
            tris.push((t.map(|i| m.positions[i as usize]), mr.casts_shadows));
        }
    }
    tris
}

/// Per pixel: the visible triangle (first hit beyond the near plane) and whether the light
/// is blocked from it.
fn ray_cast(ls: &LoadedScene, light: V3) -> Vec<Option<(usize, bool)>> {
    let tris = world(ls);
    let s = &ls.scene;
    let cam = s.camera.as_ref().unwrap();
    let near = cam.near.unwrap_or(0.1);
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
            // The renderer clips at the near plane: hits nearer than it are not seen.
            let t_near = near / dot(d, fwd);
            let first = tris
                .iter()
                .enumerate()
                .filter_map(|(k, t)| {
                    hit(cam.eye, d, &t.0)
                        .filter(|&u| u > t_near)
                        .map(|u| (u, k))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            out.push(first.map(|(u, k)| {
                // The shadow of a surface point is that of the space just in front of it,
                // on the viewer's side (an open sheet seen from below is dark).
                let p = add(cam.eye, mul(d, u - 1e-5));
                let to = sub(light, p);
                let dist = dot(to, to).sqrt();
                let dl = mul(to, 1.0 / dist);
                let blocked = tris
                    .iter()
                    .any(|t2| t2.1 && hit(p, dl, &t2.0).is_some_and(|u| u > 0.0 && u < dist));
                (k, blocked)
            }));
        }
    }
    out
}

const BOX: &str = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\nv -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
const GROUND: &str = "v -12 0 -12\nv 12 0 -12\nv 12 0 12\nv -12 0 12\nf 1 4 3 2\n";
/// An open caster: one quad (two triangles), so one volume per triangle.
const SHEET: &str = "v -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0.5 0 0.5\nv -0.5 0 0.5\nf 1 2 3 4\n";

fn load(json: &str) -> LoadedScene {
    let files: BTreeMap<String, String> = [
        ("box.obj".to_string(), BOX.to_string()),
        ("ground.obj".to_string(), GROUND.to_string()),
        ("sheet.obj".to_string(), SHEET.to_string()),
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

/// Result of one comparison.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
struct Tally {
    /// Volumes with a near cap.
    caps: usize,
    compared: usize,
    shadowed: usize,
    mismatches: usize,
}

/// The model's per-pixel shadow bit (light 0) for a scene in one shadow form.
fn model_bits(ls: &LoadedScene, form: ShadowForm) -> Vec<bool> {
    let ov = Overrides {
        shadow_form: Some(form),
        ..Default::default()
    };
    let fx = Effects::resolve(ls, &ov).unwrap();
    let frame = render(ls, &fx)
        .unwrap()
        .frame
        .expect("shadows run the array");
    frame.px.iter().map(|p| p.mask & 1 == 1).collect()
}

/// Pixels whose 3×3 neighbourhood has the same ray-cast key (visible triangle, shadow bit).
fn stable(ls: &LoadedScene, rc: &[Option<(usize, bool)>]) -> Vec<bool> {
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let mut out = vec![false; w * h];
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let k = j * w + i;
            out[k] = rc[k].is_some()
                && (0..3).all(|dy| (0..3).all(|dx| rc[(j + dy - 1) * w + i + dx - 1] == rc[k]));
        }
    }
    out
}

/// Volumes drawn with a near cap (the near plane cuts them).
fn near_caps(ls: &LoadedScene) -> usize {
    let pj = Projector::new(ls);
    let lights = shadow_lights(ls, &[0]).unwrap();
    let sc = shadow_commands(ls, &pj, &lights, ShadowForm::Ev).unwrap();
    sc.stats.near_caps
}

/// Compares the model with the ray cast away from boundaries, in both forms.
fn tally(json: &str) -> Tally {
    let ls = load(json);
    let caps = near_caps(&ls);
    let light = ls.scene.lights[0].position;
    let rc = ray_cast(&ls, light);
    let st = stable(&ls, &rc);
    let mut res = Vec::new();
    for form in [ShadowForm::Ev, ShadowForm::Check] {
        let bits = model_bits(&ls, form);
        let mut t = Tally {
            caps,
            ..Default::default()
        };
        for k in 0..bits.len() {
            if !st[k] {
                continue;
            }
            let b = rc[k].unwrap().1;
            t.compared += 1;
            t.shadowed += b as usize;
            t.mismatches += (bits[k] != b) as usize;
        }
        res.push(t);
    }
    assert_eq!(res[0], res[1], "EV and check forms differ");
    res[0]
}

/// A 160×120 scene: the ground mesh, then `casters` (JSON mesh objects, comma-separated).
fn scene(camera: impl std::fmt::Display, light: V3, casters: &str) -> String {
    format!(
        r#"{{"width":160,"height":120,"background":[0.2,0.2,0.2],"camera":{camera},"lights":[{{"position":{light:?}}}],"meshes":[{{"obj":"ground.obj","color":[0.7,0.7,0.7]}},{casters}]}}"#
    )
}

fn camera(eye: V3, target: V3, near: f64) -> String {
    format!(r#"{{"eye":{eye:?},"target":{target:?},"up":[0,1,0],"fov_y_deg":60,"near":{near}}}"#)
}

/// A long roof beam along z: x ∈ [−1, 1], y ∈ [1.8, 2.2], z ∈ [−15, 15]. With the light at
/// (0, 10, 0) its volume's right side is the plane 7.8·x + y = 10 (x ≈ 1.205 at y = 0.6).
const BEAM: &str =
    r#"{"obj":"box.obj","color":[0.5,0.5,0.9],"translate":[0,2,0],"scale":[2,0.4,30]}"#;
/// A second beam, higher and to the right: x ∈ [0.1, 2.1], y ∈ [3.3, 3.7]. Its volume's
/// left side is x = 0.1·(10 − y)/6.3 (x ≈ 0.149 at y = 0.6).
const BEAM2: &str =
    r#"{"obj":"box.obj","color":[0.9,0.5,0.5],"translate":[1.1,3.5,0],"scale":[2,0.4,30]}"#;
const TOP: V3 = [0.0, 10.0, 0.0];

/// Asserts no mismatch, enough lit and shadowed pixels compared, and whether the near plane
/// cuts a volume (`cut`) as the scene intends.
fn check(name: &str, json: &str, cut: bool, min_compared: usize, min_each: usize) -> Tally {
    let t = tally(json);
    eprintln!("{name}: {t:?}");
    assert_eq!(t.mismatches, 0, "{name}: {t:?}");
    assert_eq!(t.caps > 0, cut, "{name}: near caps {}", t.caps);
    assert!(
        t.compared >= min_compared && t.shadowed >= min_each && t.compared - t.shadowed >= min_each,
        "{name}: too few pixels compared: {t:?}"
    );
    t
}

#[test]
fn eye_just_outside_a_side_looking_along_it() {
    // 0.035 outside the beam volume's right side; the near plane (0.3) cuts the side.
    let j = scene(camera([1.24, 0.6, 8.0], [1.24, 0.3, -4.0], 0.3), TOP, BEAM);
    check("outside side", &j, true, 10000, 2000);
}

#[test]
fn eye_just_inside_a_side_looking_along_it() {
    let j = scene(camera([1.17, 0.6, 8.0], [1.17, 0.3, -4.0], 0.3), TOP, BEAM);
    check("inside side", &j, true, 10000, 2000);
}

#[test]
fn eye_inside_one_volume_far_from_its_sides() {
    // The near plane cuts nothing: the IF path.
    let j = scene(camera([0.3, 0.6, 3.0], [3.0, 0.3, -2.0], 0.1), TOP, BEAM);
    check("inside one", &j, false, 10000, 2000);
}

#[test]
fn eye_inside_two_volumes_near_the_first_ones_side() {
    let j = scene(
        camera([1.17, 0.6, 8.0], [1.4, 0.3, -4.0], 0.3),
        TOP,
        &format!("{BEAM},{BEAM2}"),
    );
    check("inside two, near side of the first", &j, true, 10000, 500);
}

#[test]
fn eye_inside_two_volumes_near_the_second_ones_side() {
    let j = scene(
        camera([0.17, 0.6, 8.0], [-0.2, 0.3, -4.0], 0.3),
        TOP,
        &format!("{BEAM},{BEAM2}"),
    );
    check("inside two, near side of the second", &j, true, 10000, 500);
}

#[test]
fn near_plane_cuts_the_caster() {
    // The near plane passes through the beam itself (its light-facing top and its right
    // side): part of the view is inside the caster.
    let j = scene(camera([1.1, 2.3, 8.0], [0.5, 0.0, 3.0], 0.3), TOP, BEAM);
    check("near cuts caster", &j, true, 8000, 1000);
}

#[test]
fn near_plane_cuts_open_casters_volumes() {
    // An open sheet (one volume per triangle), eye beside its volume's side.
    let sheet = r#"{"obj":"sheet.obj","color":[0.3,0.8,0.3],"translate":[0,2,0],"scale":[2,1,30]}"#;
    let j = scene(camera([1.24, 0.6, 8.0], [1.0, 0.3, -4.0], 0.3), TOP, sheet);
    check("open sheet", &j, true, 10000, 2000);
}

#[test]
fn camera_sweep_around_a_caster() {
    // 20 eyes around a box's volume, some inside, some outside, near its sides, looking
    // inwards or along the side.
    let caster =
        r#"{"obj":"box.obj","color":[0.5,0.5,0.9],"translate":[0,2,0],"scale":[1.6,0.4,1.6]}"#;
    let light = [0.3, 9.0, 0.2];
    let mut total = Tally::default();
    let mut failed = Vec::new();
    for k in 0..20 {
        let th = k as f64 * std::f64::consts::TAU / 20.0;
        let r = 0.85 + 0.1 * (k % 3) as f64;
        let eye = [r * th.cos(), 0.7, r * th.sin()];
        let phi = th + std::f64::consts::PI + (k % 4) as f64 * 30f64.to_radians();
        let target = [eye[0] + 3.0 * phi.cos(), 0.2, eye[2] + 3.0 * phi.sin()];
        let j = scene(camera(eye, target, 0.3), light, caster);
        let t = tally(&j);
        eprintln!("sweep {k}: {t:?}");
        if t.mismatches > 0 {
            failed.push((k, t.mismatches));
        }
        total.caps += (t.caps > 0) as usize;
        total.compared += t.compared;
        total.shadowed += t.shadowed;
        total.mismatches += t.mismatches;
    }
    eprintln!("sweep total: {total:?}");
    assert!(failed.is_empty(), "positions with mismatches: {failed:?}");
    // `caps` counts here the positions where the near plane cuts the volume.
    assert!(
        total.compared > 200_000 && total.shadowed > 20_000 && total.caps >= 5,
        "{total:?}"
    );
}

#[test]
fn far_geometry_that_casts_no_visible_shadow_changes_no_shadow_pixel() {
    // The same scene with a box far behind the camera (it enlarges the ray box but shadows
    // nothing in view). The far plane is fixed so depths do not change either.
    let cam = r#"{"eye":[1.24,0.6,8.0],"target":[1.24,0.3,-4.0],"up":[0,1,0],"fov_y_deg":60,"near":0.3,"far":80}"#;
    let far_box = r#"{"obj":"box.obj","color":[1,1,1],"translate":[0,0.5,40]}"#;
    let a = scene(cam, TOP, BEAM);
    let b = scene(cam, TOP, &format!("{BEAM},{far_box}"));
    let ta = check("without far box", &a, true, 10000, 2000);
    let tb = check("with far box", &b, true, 10000, 2000);
    assert_eq!(ta, tb);
    for form in [ShadowForm::Ev, ShadowForm::Check] {
        let (la, lb) = (load(&a), load(&b));
        let (ba, bb) = (model_bits(&la, form), model_bits(&lb, form));
        let differ = ba.iter().zip(&bb).filter(|(x, y)| x != y).count();
        assert_eq!(differ, 0, "{form:?}: {differ} shadow pixels differ");
    }
}

#[test]
fn wide_sweep_heights_directions_near_distances_lights() {
    // 120 more cameras near the box's volume: heights 0.3..1.8, any direction, near 0.1, 0.3
    // or 0.6, the light moved sideways; most of them cut the volume.
    let caster =
        r#"{"obj":"box.obj","color":[0.5,0.5,0.9],"translate":[0,2,0],"scale":[1.6,0.4,1.6]}"#;
    let mut bad = Vec::new();
    let (mut caps, mut compared) = (0, 0);
    for k in 0..120 {
        let th = k as f64 * 0.7331;
        let r = 0.7 + 0.05 * (k % 9) as f64;
        let h = 0.3 + 0.25 * (k % 7) as f64;
        let eye = [r * th.cos(), h, r * th.sin()];
        let phi = th + 2.1 * k as f64;
        let target = [
            eye[0] + 3.0 * phi.cos(),
            -0.5 + 0.3 * (k % 5) as f64,
            eye[2] + 3.0 * phi.sin(),
        ];
        let near = [0.1, 0.3, 0.6][k % 3];
        let light = [0.3 * (k % 4) as f64, 9.0, 0.2];
        let j = scene(camera(eye, target, near), light, caster);
        let t = tally(&j);
        caps += (t.caps > 0) as usize;
        compared += t.compared;
        if t.mismatches > 0 {
            bad.push((k, t));
        }
    }
    eprintln!("wide sweep: {caps} of 120 cut, {compared} pixels compared");
    assert!(bad.is_empty(), "positions with mismatches: {bad:?}");
    assert!(
        caps >= 60 && compared > 1_000_000,
        "{caps} cut, {compared} compared"
    );
}
