//! A render runs exactly the stages its plan lists, in that order: nothing a scene does
//! not call for (no shadow stage without shadows, no array without a reason for it), and
//! nothing the plan leaves out.

use pixelproc_sim::pipeline::render;
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
