//! Effects planning: the one place that turns what a scene asks for into the stages to
//! run ("simulate only the effects a scene calls for").
//!
//! A scene declares its effects (`effects` in the JSON, per-light `shadows`, `patterns`);
//! command-line options override them ([`Overrides`]). [`Effects::resolve`] merges the
//! two, and [`plan`] lists the [`Stage`]s. Nothing outside the plan is computed: a stage
//! that is not listed does not run, and each method registers its stages here.

use crate::scene::LoadedScene;
use std::fmt;
use thiserror::Error;

/// Anti-aliasing method (off unless the scene or the command line asks for it).
#[derive(Clone, Debug, PartialEq, Default)]
pub enum AaMethod {
    /// One sample per pixel centre: the pixel-processor array alone.
    #[default]
    None,
}

impl AaMethod {
    /// Names accepted by `--aa` and the scene's `effects.aa.method`.
    pub const NAMES: &'static [&'static str] = &["none"];

    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            AaMethod::None => "none",
        }
    }
}

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

impl Aov {
    /// Parses an AOV name.
    pub fn parse(s: &str) -> Result<Aov, PlanError> {
        match s {
            "depth" => Ok(Aov::Depth),
            "shadow" => Ok(Aov::Shadow),
            "coverage" => Ok(Aov::Coverage),
            _ => Err(PlanError(format!(
                "unknown AOV '{s}' (known: depth, shadow, coverage)"
            ))),
        }
    }
    /// Name, used in file names.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Depth => "depth",
            Aov::Shadow => "shadow",
            Aov::Coverage => "coverage",
        }
    }
}

/// A planning error (an effect that cannot be combined or does not exist).
#[derive(Debug, Error)]
#[error("{0}")]
pub struct PlanError(pub String);

/// Command-line overrides of the scene's effects.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// `--aa METHOD` (with its parameters).
    pub aa: Option<AaMethod>,
    /// `--no-shadows`.
    pub no_shadows: bool,
    /// `--shadow-form check`: the software form of seed 001 §5.
    pub shadow_form: Option<crate::shadow::ShadowForm>,
    /// `--aov` requests.
    pub aovs: Vec<Aov>,
    /// `--array-width N`.
    pub array_width: Option<usize>,
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
}

impl Effects {
    /// Merges the scene's declared effects with command-line overrides.
    pub fn resolve(ls: &LoadedScene, ov: &Overrides) -> Result<Effects, PlanError> {
        let s = &ls.scene;
        let aa = match (&ov.aa, &s.effects.aa) {
            (Some(a), _) => a.clone(),
            (None, Some(v)) => parse_scene_aa(v)?,
            (None, None) => AaMethod::None,
        };
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
            return Err(PlanError(format!(
                "array width {array_width} is outside 1..=4096"
            )));
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
        })
    }
}

/// Parses the scene's `effects.aa` value: a method name, or an object with `method`.
fn parse_scene_aa(v: &serde_json::Value) -> Result<AaMethod, PlanError> {
    let name = match v {
        serde_json::Value::String(s) => s.as_str(),
        serde_json::Value::Object(o) => o.get("method").and_then(|m| m.as_str()).unwrap_or(""),
        _ => "",
    };
    match name {
        "none" => Ok(AaMethod::None),
        _ => Err(PlanError(format!(
            "scene effects.aa: unknown method '{name}' (known: {})",
            AaMethod::NAMES.join(", ")
        ))),
    }
}

/// One stage of a render, in execution order.
#[derive(Clone, Debug, PartialEq)]
pub enum Stage {
    /// Front end: camera, lighting, clipping, projection, snapping.
    FrontEnd,
    /// Span setup: triangles to span words, binned by scanline.
    SpanSetup,
    /// Shadow volumes of one light (all its samples) to shadow span words (seed 001).
    ShadowVolumes {
        /// Index of the light in the scene.
        light: usize,
    },
    /// The pixel-processor array expands OP spans (Z test, intensity), then any shadow
    /// spans (DSF/FSF parity, counters).
    PixelArray,
    /// Intensity correction from the shadow flags (seed 001 §2, §6 table).
    ShadowShade,
    /// Writes a debug image.
    Aov(Aov),
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stage::FrontEnd => write!(f, "front end (project, clip, snap)"),
            Stage::SpanSetup => write!(f, "span setup"),
            Stage::ShadowVolumes { light } => write!(f, "shadow volumes, light {light}"),
            Stage::PixelArray => write!(f, "pixel-processor array"),
            Stage::ShadowShade => write!(f, "shadow shading"),
            Stage::Aov(a) => write!(f, "aov {}", a.name()),
        }
    }
}

/// The stages that render a scene with the given effects.
pub fn plan(e: &Effects) -> Vec<Stage> {
    let mut st = vec![Stage::FrontEnd, Stage::SpanSetup];
    for &l in &e.shadow_lights {
        st.push(Stage::ShadowVolumes { light: l });
    }
    st.push(Stage::PixelArray);
    if !e.shadow_lights.is_empty() {
        st.push(Stage::ShadowShade);
    }
    for a in &e.aovs {
        st.push(Stage::Aov(*a));
    }
    st
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
        };
        assert_eq!(plan(&e), vec![Stage::FrontEnd, Stage::SpanSetup, Stage::PixelArray]);
        let with = Effects { shadow_lights: vec![0, 2], ..e };
        assert_eq!(
            plan(&with),
            vec![
                Stage::FrontEnd,
                Stage::SpanSetup,
                Stage::ShadowVolumes { light: 0 },
                Stage::ShadowVolumes { light: 2 },
                Stage::PixelArray,
                Stage::ShadowShade
            ]
        );
    }
}
