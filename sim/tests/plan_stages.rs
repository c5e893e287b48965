//! A render runs exactly the stages its plan lists, in that order: nothing a scene does
//! not call for (no shadow stage without shadows, no array without a reason for it), and
//! nothing the plan leaves out.

use pixelproc_sim::pipeline::{render, AaReport};
use pixelproc_sim::plan::{plan, AaKind, AaSpec, Aov, Effects, Overrides, Stage};
use pixelproc_sim::scene::load_builtin;

#[test]
fn a_render_runs_exactly_the_planned_stages() {
    let ls = load_builtin("default").unwrap();
    let aa = |k: AaKind| Some(AaSpec::default_for(k));
    let cases = [
        Overrides::default(),
        Overrides {
            no_shadows: true,
            ..Default::default()
        },
        Overrides {
            aa: aa(AaKind::Ssaa),
            ..Default::default()
        },
        Overrides {
            aa: aa(AaKind::Abuffer),
            no_shadows: true,
            aovs: vec![Aov::Coverage],
            ..Default::default()
        },
        Overrides {
            aa: aa(AaKind::PostFx),
            aovs: vec![Aov::Depth, Aov::Shadow],
            ..Default::default()
        },
    ];
    let mut with_shadows = 0;
    for ov in cases {
        let fx = Effects::resolve(&ls, &ov).unwrap();
        let ran: Vec<Stage> = render(&ls, &fx)
            .unwrap()
            .timings
            .iter()
            .map(|t| t.0.clone())
            .collect();
        assert_eq!(ran, plan(&fx), "{ov:?}");
        let casters = ran.iter().filter(|s| **s == Stage::ShadowCasters).count();
        assert_eq!(casters, usize::from(!fx.shadow_lights.is_empty()), "{ov:?}");
        with_shadows += casters;
    }
    assert!(with_shadows >= 3, "the default scene casts shadows");
}

/// A method's counters are divided by the frame's pixels, whichever path the pipeline
/// takes (the post-process of a shadowed baseline runs outside the common entry point):
/// per pixel, with and without shadows.
#[test]
fn every_methods_counters_count_the_frames_pixels() {
    let ls = load_builtin("default").unwrap();
    let pixels = ls.scene.width as u64 * ls.scene.height as u64;
    for kind in [
        AaKind::Multiscan,
        AaKind::Corner,
        AaKind::PostFx,
        AaKind::Ssaa,
    ] {
        for no_shadows in [false, true] {
            let ov = Overrides {
                aa: Some(AaSpec::default_for(kind)),
                no_shadows,
                ..Default::default()
            };
            let fx = Effects::resolve(&ls, &ov).unwrap();
            let Some(AaReport::Other(st)) = render(&ls, &fx).unwrap().aa else {
                panic!("{kind:?}: no counters");
            };
            assert_eq!(st.pixels, pixels, "{kind:?}, no_shadows {no_shadows}");
            assert!(st.reads_per_pixel() < 100.0, "{kind:?}: {st:?}");
        }
    }
    // The common entry point, every method (the baseline and the A-buffer too).
    let tris = pixelproc_sim::frontend::project(&ls).unwrap().tris;
    let (w, h) = (ls.scene.width, ls.scene.height);
    for kind in [
        AaKind::None,
        AaKind::Abuffer,
        AaKind::Multiscan,
        AaKind::Corner,
        AaKind::PostFx,
        AaKind::Ssaa,
    ] {
        let ov = Overrides {
            aa: Some(AaSpec::default_for(kind)),
            ..Default::default()
        };
        let fx = Effects::resolve(&ls, &ov).unwrap();
        let f = pixelproc_sim::aa::render_aa(&tris, w, h, [0; 3], &fx.aa).unwrap();
        assert_eq!(f.stats.pixels, pixels, "{kind:?} through render_aa");
    }
}
