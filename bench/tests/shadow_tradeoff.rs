//! The shadow trade-off: on a 3-D scene with real shadow volumes, the renderer's shadowed
//! fraction agrees with the sweep's independent ray cast away from boundaries, and its
//! boundary error falls as supersampling's k and multi-scanning's n rise.

use pixelproc_bench::shadow_sweep::{
    ray_cast_fraction, run_shadow_sweep, shadow_csv, shadow_scenes, shadow_settings,
};
use pixelproc_sim::aa::AaMethod;
use pixelproc_sim::pipeline::render;
use pixelproc_sim::plan::{Aov, Effects, Overrides};

#[test]
fn quick_shadow_sweep_errors_fall_with_each_parameter() {
    let scenes = shadow_scenes(true);
    let rows = run_shadow_sweep(&scenes, &shadow_settings(true), 1, false).unwrap();
    let err = |label: &str| {
        rows.iter()
            .find(|r| r.label == label)
            .unwrap_or_else(|| panic!("no row {label}"))
            .boundary_mae
    };
    for r in &rows {
        eprintln!(
            "{}: rmse {:.2}, boundary {:.4}",
            r.label, r.rmse, r.boundary_mae
        );
        assert!(r.ms > 0.0 && r.rmse.is_finite());
    }
    assert!(err("ssaa 4x4") < err("ssaa 2x2"));
    assert!(err("ssaa 2x2") < err("none"));
    assert!(err("multiscan n=4 box") < err("multiscan n=1 box"));
    assert!(err("postfx zth=64 zjump=4096 creases") < err("none"));
    let csv = shadow_csv(&rows);
    assert_eq!(csv.lines().count(), 1 + rows.len() * scenes.len());
}

/// Cross-check of two independent computations: away from shadow boundaries the ray
/// cast's fraction is 0 or 1 and the array's flags (no anti-aliasing) agree exactly.
#[test]
fn ray_cast_and_array_agree_away_from_boundaries() {
    for s in shadow_scenes(false) {
        let sc = &s.scene;
        let rc = ray_cast_fraction(sc);
        let ov = Overrides {
            aovs: vec![Aov::Shadow],
            ..Default::default()
        };
        let mut fx = Effects::resolve(sc, &ov).unwrap();
        fx.aa = AaMethod::None;
        let out = render(sc, &fx).unwrap();
        let f = &out.aovs[0].1.data;
        let (w, h) = (sc.scene.width as usize, sc.scene.height as usize);
        let (mut compared, mut shadowed) = (0, 0);
        for j in 1..h - 1 {
            for i in 1..w - 1 {
                let k = j * w + i;
                let same =
                    (0..3).all(|dy| (0..3).all(|dx| rc[(j + dy - 1) * w + i + dx - 1] == rc[k]));
                if !same {
                    continue;
                }
                // Area light: a uniform penumbra level is compared too (count / k).
                assert_eq!(
                    f[k],
                    (rc[k] * 255.0).round() as u8,
                    "{}: pixel ({i}, {j})",
                    s.name
                );
                compared += 1;
                shadowed += (rc[k] > 0.0) as usize;
            }
        }
        // The poles' shadows are thinner than the 3×3 neighbourhood: boundary pixels only.
        let min_shadowed = if s.name.starts_with("poles") { 0 } else { 50 };
        assert!(
            compared > 3000 && shadowed >= min_shadowed,
            "{}: {compared} compared, {shadowed} shadowed",
            s.name
        );
    }
}
