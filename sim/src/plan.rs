//! Effects planning: the one place that turns what a scene asks for into the stages to
//! run ("simulate only the effects a scene calls for").
//!
//! A scene declares its effects (`effects` in the JSON, per-light `shadows`, `patterns`);
//! command-line options override them ([`Overrides`]). [`Effects::resolve`] merges the
//! two, and [`plan`] lists the [`Stage`]s. Nothing outside the plan is computed: a stage
//! that is not listed does not run, and each method registers its stages here.

mod names;
mod spec;

use crate::scene::LoadedScene;
use std::fmt;
use thiserror::Error;

pub use crate::aa::AaMethod;
pub use names::{parse_name, AaKind, NameError, Named, PostFxNormals};
pub use spec::{
    parse_mask, parse_param, AaSpec, AbufferSpec, CornerSpec, Key, MultiscanSpec, Origin,
    PostFxSpec, SsaaSpec,
};

/// A debug image written beside the main image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Aov {
    /// Depth buffer, near bright.
    Depth,
    /// Shadow flag or penumbra fraction.
    Shadow,
    /// Coverage (A-buffer: fragment count or coverage per pixel).
    Coverage,
}

/// A planning error: an effect that does not exist or a parameter out of range. Each
/// names the scene key or flag the value came from.
#[derive(Debug, Error)]
pub enum PlanError {
    /// A number outside its range.
    #[error("{key} {value} is outside {lo}..={hi}")]
    Range {
        /// Where it was written.
        key: Key,
        /// The value.
        value: u32,
        /// Smallest accepted.
        lo: u32,
        /// Largest accepted.
        hi: u32,
    },
    /// A number that is not one of a few accepted values.
    #[error("{key} {value}: expected {expected}")]
    Choice {
        /// Where it was written.
        key: Key,
        /// The value.
        value: u32,
        /// The accepted values, in words.
        expected: &'static str,
    },
    /// An unknown name for a parameter.
    #[error("{key}")]
    Param {
        /// Where it was written.
        key: Key,
        /// The unknown name.
        source: NameError,
    },
    /// An unknown name (of a method or debug image).
    #[error(transparent)]
    Name(#[from] NameError),
    /// A subpixel grid not written `NxM`.
    #[error("{key} {value}: expected NxM, e.g. 4x4 or 8x8")]
    MaskSyntax {
        /// Where it was written.
        key: Key,
        /// The value.
        value: String,
    },
    /// A subpixel grid the A-buffer does not support.
    #[error("{key} {value}")]
    Mask {
        /// Where it was written.
        key: Key,
        /// The value.
        value: String,
        /// Why it is not supported.
        source: pixelproc_formats::abuffer::MaskSizeError,
    },
    /// An array width out of range.
    #[error("array width {0} is outside 1..=4096")]
    ArrayWidth(usize),
}

/// An error and its causes on one line, `outer: cause: ...`.
pub(crate) fn one_line(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        s += &format!(": {c}");
        cause = c.source();
    }
    s
}

/// Command-line overrides of the scene's effects.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// `--aa METHOD` with its parameter flags.
    pub aa: Option<AaSpec>,
    /// `--no-shadows`.
    pub no_shadows: bool,
    /// `--shadow-form check`: the software form of seed 001 §5.
    pub shadow_form: Option<crate::shadow::ShadowForm>,
    /// `--aov` requests.
    pub aovs: Vec<Aov>,
    /// `--array-width N`.
    pub array_width: Option<usize>,
    /// `--shading exact|table`.
    pub shading: Option<crate::shadow::Shading>,
}

/// Default number of processors in the array (one tile).
pub const DEFAULT_ARRAY_WIDTH: usize = 64;

/// The effects one render will simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct Effects {
    /// Anti-aliasing method.
    pub aa: AaMethod,
    /// Indices of the lights whose shadows are simulated.
    pub shadow_lights: Vec<usize>,
    /// The scene has patterns (decals).
    pub patterns: bool,
    /// Surfaces may interpenetrate.
    pub interpenetrating: bool,
    /// Debug images to write.
    pub aovs: Vec<Aov>,
    /// Processors in the array.
    pub array_width: usize,
    /// How a shadow volume's end is marked (EV in hardware, a check span in software).
    pub shadow_form: crate::shadow::ShadowForm,
    /// How shadowed pixels are shaded (exact by default, or the seed's table).
    pub shading: crate::shadow::Shading,
}

impl Effects {
    /// Merges the scene's declared effects with command-line overrides.
    pub fn resolve(ls: &LoadedScene, ov: &Overrides) -> Result<Effects, PlanError> {
        let s = &ls.scene;
        let (spec, origin) = match (&ov.aa, &s.effects.aa) {
            (Some(a), _) => (a, Origin::CommandLine),
            (None, Some(a)) => (a, Origin::Scene),
            (None, None) => (&AaSpec::None, Origin::CommandLine),
        };
        let aa = spec.method(s.effects.interpenetrating, origin)?;
        let shadows_on = !ov.no_shadows && s.effects.shadows.unwrap_or(true) && ls.is_3d();
        let shadow_lights = if shadows_on {
            s.lights
                .iter()
                .enumerate()
                .filter(|(_, l)| l.shadows)
                .map(|(k, _)| k)
                .collect()
        } else {
            Vec::new()
        };
        let patterns = !s.patterns.is_empty() || s.triangles.iter().any(|t| t.pattern_on.is_some());
        let array_width = ov.array_width.unwrap_or(DEFAULT_ARRAY_WIDTH);
        if !(1..=4096).contains(&array_width) {
            return Err(PlanError::ArrayWidth(array_width));
        }
        let mut aovs = ov.aovs.clone();
        aovs.sort();
        aovs.dedup();
        Ok(Effects {
            aa,
            shadow_lights,
            patterns,
            interpenetrating: s.effects.interpenetrating,
            aovs,
            array_width,
            shadow_form: ov.shadow_form.unwrap_or_default(),
            shading: ov.shading.unwrap_or_default(),
        })
    }

    /// The scene lights whose exact-shading channels the spans carry, in channel order:
    /// the shadowing lights under [`crate::shadow::Shading::Exact`], else none.
    pub fn shade_channels(&self) -> &[usize] {
        match self.shading {
            crate::shadow::Shading::Exact => &self.shadow_lights,
            crate::shadow::Shading::Table => &[],
        }
    }
}

/// One stage of a render, in execution order.
#[derive(Clone, Debug, PartialEq)]
pub enum Stage {
    /// Front end: camera, lighting, clipping, projection, snapping.
    FrontEnd,
    /// Span setup: triangles to span words, binned by scanline.
    SpanSetup,
    /// The scene's shadow casters: each shadow-casting mesh welded, split into connected
    /// components, tested for closed and convex (seed 001's silhouette volumes need
    /// both). Found once per frame, alongside the front end and span setup; its time is
    /// the wall time it adds after those two.
    ShadowCasters,
    /// Shadow volumes of one light (all its samples), set up for the array: extruded,
    /// clipped, snapped, their triangles set up (seed 001). Their shadow span words are
    /// made a band of rows at a time as the array draws the rows, in its stage, and never
    /// stored.
    ShadowVolumes {
        /// Index of the light in the scene.
        light: usize,
    },
    /// The pixel-processor array expands OP spans (Z test, intensity), then any shadow
    /// spans (DSF/FSF parity, counters); with shadows, each row's intensities are
    /// corrected from its shadow flags as it is read out (seed 001 §2, §6 table; the
    /// core's shade unit).
    PixelArray,
    /// An anti-aliasing method renders the image (its own stages inside; the A-buffer's
    /// masks, search unit, packing and resolve; multi-scanning's sub-scanline passes; ...).
    Antialias(AaKind),
    /// Multiplies the anti-aliased image by the shadow factor of each pixel centre.
    ShadowApply,
    /// Writes a debug image.
    Aov(Aov),
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stage::FrontEnd => write!(f, "front end (project, clip, snap)"),
            Stage::SpanSetup => write!(f, "span setup"),
            Stage::ShadowCasters => write!(f, "shadow casters (beyond setup)"),
            Stage::ShadowVolumes { light } => write!(f, "shadow volumes, light {light}"),
            Stage::PixelArray => write!(f, "pixel-processor array"),
            Stage::Antialias(m) => write!(f, "anti-aliasing: {m}"),
            Stage::ShadowApply => write!(f, "shadows at the method's samples"),
            Stage::Aov(a) => write!(f, "aov {a}"),
        }
    }
}

/// The pixel-processor array's part of a render.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayPlan {
    /// Lights whose shadow volumes run through the array (and then shade the frame).
    pub shadow_lights: Vec<usize>,
    /// Debug images made from the array's per-pixel state, in output order.
    pub aovs: Vec<Aov>,
}

/// The shape of a render: which parts run, each handing its output to the next. The
/// pixel-processor array renders the image when there is no other anti-aliasing method;
/// with one, the array runs only when shadows or a debug image need its per-pixel state.
#[derive(Clone, Debug, PartialEq)]
pub enum Plan {
    /// The array renders the image.
    Array(ArrayPlan),
    /// An anti-aliasing method renders the image.
    Antialias {
        /// The method.
        method: AaKind,
        /// The array, for the shadow factor and debug images.
        array: Option<ArrayPlan>,
        /// A coverage image from the method itself (the A-buffer's).
        coverage: bool,
    },
}

impl Plan {
    /// The plan for the given effects.
    pub fn new(e: &Effects) -> Plan {
        let method = AaKind::of(&e.aa);
        let own_coverage = method == AaKind::Abuffer && e.aovs.contains(&Aov::Coverage);
        let array = ArrayPlan {
            shadow_lights: e.shadow_lights.clone(),
            aovs: e
                .aovs
                .iter()
                .copied()
                .filter(|&a| !(own_coverage && a == Aov::Coverage))
                .collect(),
        };
        if method == AaKind::None {
            return Plan::Array(array);
        }
        let needed = !array.shadow_lights.is_empty() || !array.aovs.is_empty();
        Plan::Antialias {
            method,
            array: needed.then_some(array),
            coverage: own_coverage,
        }
    }

    /// The array's part, when it runs.
    pub fn array(&self) -> Option<&ArrayPlan> {
        match self {
            Plan::Array(a) => Some(a),
            Plan::Antialias { array, .. } => array.as_ref(),
        }
    }

    /// The stages, in execution order.
    pub fn stages(&self) -> Vec<Stage> {
        let mut st = vec![Stage::FrontEnd];
        let shadows = self.array().is_some_and(|a| !a.shadow_lights.is_empty());
        if let Some(a) = self.array() {
            st.push(Stage::SpanSetup);
            if shadows {
                st.push(Stage::ShadowCasters);
            }
            for &l in &a.shadow_lights {
                st.push(Stage::ShadowVolumes { light: l });
            }
            st.push(Stage::PixelArray);
        }
        if let Plan::Antialias { method, .. } = self {
            st.push(Stage::Antialias(*method));
            // Post-processing takes the shaded baseline and its shadow edges itself.
            if shadows && *method != AaKind::PostFx {
                st.push(Stage::ShadowApply);
            }
        }
        st.extend(
            self.array()
                .into_iter()
                .flat_map(|a| &a.aovs)
                .map(|&a| Stage::Aov(a)),
        );
        if let Plan::Antialias { coverage: true, .. } = self {
            st.push(Stage::Aov(Aov::Coverage));
        }
        st
    }
}

/// The stages that render a scene with the given effects ([`Plan::stages`]).
pub fn plan(e: &Effects) -> Vec<Stage> {
    Plan::new(e).stages()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_scene_runs_only_the_array() {
        let e = Effects {
            aa: AaMethod::None,
            shadow_lights: vec![],
            patterns: false,
            interpenetrating: false,
            aovs: vec![],
            array_width: 64,
            shadow_form: Default::default(),
            shading: Default::default(),
        };
        assert_eq!(
            plan(&e),
            vec![Stage::FrontEnd, Stage::SpanSetup, Stage::PixelArray]
        );
        let with = Effects {
            shadow_lights: vec![0, 2],
            ..e
        };
        assert_eq!(
            plan(&with),
            vec![
                Stage::FrontEnd,
                Stage::SpanSetup,
                Stage::ShadowCasters,
                Stage::ShadowVolumes { light: 0 },
                Stage::ShadowVolumes { light: 2 },
                Stage::PixelArray
            ]
        );
    }

    #[test]
    fn coverage_comes_from_the_abuffer_or_the_array() {
        let with = |kind: AaKind| Effects {
            aa: AaSpec::default_for(kind)
                .method(false, Origin::CommandLine)
                .unwrap(),
            shadow_lights: vec![],
            patterns: false,
            interpenetrating: false,
            aovs: vec![Aov::Coverage],
            array_width: 64,
            shadow_form: Default::default(),
            shading: Default::default(),
        };
        assert_eq!(
            plan(&with(AaKind::Abuffer)),
            vec![
                Stage::FrontEnd,
                Stage::Antialias(AaKind::Abuffer),
                Stage::Aov(Aov::Coverage)
            ]
        );
        assert_eq!(
            plan(&with(AaKind::Multiscan)),
            vec![
                Stage::FrontEnd,
                Stage::SpanSetup,
                Stage::PixelArray,
                Stage::Antialias(AaKind::Multiscan),
                Stage::Aov(Aov::Coverage)
            ]
        );
    }
}
