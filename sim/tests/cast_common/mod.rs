//! A glam ray caster's scene side for the shadow tests: the test scenes' meshes, the
//! world triangles of a loaded scene, the camera as a pinhole written independently of the
//! front end, and a two-sided ray–triangle test.
// Each test binary that declares `mod cast_common` compiles its own copy and uses a
// different subset of these items; the rest would warn as dead code in that binary.
#![allow(dead_code)]

use glam::DVec3;
use pixelproc_sim::scene::{self, LoadedScene, MeshSource};
use std::collections::BTreeMap;

pub const BOX: &str = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\nv -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
/// A ground square of two triangles (y = 0, normal +y), wholly in view: no clipping, so
/// the renderer interpolates over the same triangles as this test.
pub const GROUND: &str = "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nf 1 4 3\nf 1 3 2\n";
/// One far triangle.
pub const FAR: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

pub fn load(json: &str) -> LoadedScene {
    let files: BTreeMap<String, String> =
        [("box.obj", BOX), ("ground.obj", GROUND), ("far.obj", FAR)]
            .into_iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
    scene::load_with(
        scene::parse(json, "t").unwrap(),
        &MeshSource::Embedded(files),
        "t",
    )
    .unwrap()
}

/// Two-sided ray–triangle distance.
pub fn hit(o: DVec3, d: DVec3, t: &[DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = o - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then(|| e2.dot(q) / det)
}

pub struct Tri {
    pub p: [DVec3; 3],
    pub ground: bool,
    pub casts: bool,
}

pub fn world(ls: &LoadedScene) -> Vec<Tri> {
    let mut out = Vec::new();
    for (m, mr) in ls.meshes.iter().zip(&ls.scene.meshes) {
        for t in &m.triangles {
            out.push(Tri {
                p: t.map(|i| DVec3::from(m.positions[i as usize])),
                ground: mr.obj == "ground.obj",
                casts: mr.casts_shadows,
            });
        }
    }
    out
}

/// The camera of the scene as this test builds it: ray through a pixel centre, and the
/// screen position of a world point (the same pinhole model, written independently).
pub struct Cam {
    pub eye: DVec3,
    pub fwd: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub th: f64,
    pub aspect: f64,
    pub w: f64,
    pub h: f64,
}

impl Cam {
    /// The camera of a 3-D scene.
    pub fn new(ls: &LoadedScene) -> Cam {
        let c = ls.scene.camera.as_ref().unwrap();
        let eye = DVec3::from(c.eye);
        let fwd = (DVec3::from(c.target) - eye).normalize();
        let right = fwd.cross(DVec3::from(c.up)).normalize();
        Cam {
            eye,
            fwd,
            right,
            up: right.cross(fwd),
            th: (c.fov_y_deg.to_radians() / 2.0).tan(),
            aspect: ls.scene.width as f64 / ls.scene.height as f64,
            w: ls.scene.width as f64,
            h: ls.scene.height as f64,
        }
    }
    /// The ray through pixel `(i, j)`'s centre.
    pub fn ray(&self, i: usize, j: usize) -> DVec3 {
        self.ray_at(i as f64 + 0.5, j as f64 + 0.5)
    }
    /// The ray through screen point `(x, y)` (pixels, y down).
    pub fn ray_at(&self, sx: f64, sy: f64) -> DVec3 {
        let x = (sx / self.w * 2.0 - 1.0) * self.th * self.aspect;
        let y = (1.0 - sy / self.h * 2.0) * self.th;
        (self.fwd + self.right * x + self.up * y).normalize()
    }
    /// Screen position (pixels, y down) of a world point.
    pub fn screen(&self, p: DVec3) -> (f64, f64) {
        let v = p - self.eye;
        let z = v.dot(self.fwd);
        let x = v.dot(self.right) / (z * self.th * self.aspect);
        let y = v.dot(self.up) / (z * self.th);
        ((x + 1.0) * 0.5 * self.w, (1.0 - y) * 0.5 * self.h)
    }
}
