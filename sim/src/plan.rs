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

use crate::aa::postfx::{NormalSource, SecondDiffSource};
pub use crate::aa::AaMethod;
use crate::aa::{CornerParams, Filter, MultiscanParams, Pattern, PostFxParams};
use crate::abuffer::AbufferParams;
use crate::mask_search::DepthSelect;
use pixelproc_formats::abuffer::MaskSize;
use serde::Deserialize;

/// Names accepted by `--aa` and the scene's `effects.aa.method`.
pub const AA_NAMES: &[&str] = &["none", "abuffer", "multiscan", "corner", "postfx", "ssaa"];

/// An anti-aliasing request with optional parameters: what `--aa` and its flags, or the
/// scene's `effects.aa` object, say. [`AaSpec::method`] turns it into an [`AaMethod`] with
/// defaults for everything unsaid, and rejects parameters that belong to another method.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AaSpec {
    /// Method name (one of [`AA_NAMES`]).
    pub method: String,
    /// A-buffer subpixel grid, e.g. `4x4` (default) or `8x8`.
    #[serde(default)]
    pub mask: Option<String>,
    /// A-buffer depth selection: `search` (default), `center`, `slope`, `exhaustive`.
    #[serde(default)]
    pub depth: Option<String>,
    /// Multi-scanning: sub-scanlines per pixel row, 1..=16 (default 3).
    #[serde(default)]
    pub subscanlines: Option<u32>,
    /// Multi-scanning filter: `box` (default), `gauss`, `cone`.
    #[serde(default)]
    pub filter: Option<String>,
    /// Corner sampling: samples per pixel, 1 (default) or 2 (adds the centre sample).
    #[serde(default)]
    pub samples: Option<u32>,
    /// Sample pattern: `corner` (default), `d3d4x`, `grid2x2`.
    #[serde(default)]
    pub pattern: Option<String>,
    /// Supersampling factor k (k×k samples), 1..=64 (default 4).
    #[serde(default)]
    pub ssaa: Option<u32>,
    /// Post-process: lines in the pattern window, 5 (default) or 3.
    #[serde(default)]
    pub postfx_window: Option<u32>,
    /// Post-process: normal edges `off` (default), `recon` (from z) or `stored`.
    #[serde(default)]
    pub postfx_normals: Option<String>,
    /// Post-process: second differences from the `final` z-buffer (default) or kept
    /// during `draw`ing.
    #[serde(default)]
    pub postfx_d2: Option<String>,
    /// A-buffer: also run every depth-selection variant and count where it orders or
    /// resolves fragments differently from `exhaustive` (slower; for reports).
    #[serde(default)]
    pub compare_depth: bool,
}

impl AaSpec {
    /// A bare method name.
    pub fn named(name: &str) -> AaSpec {
        AaSpec {
            method: name.to_string(),
            ..Default::default()
        }
    }

    /// The method with its parameters; `interpenetrating` enables the A-buffer's max search.
    pub fn method(&self, interpenetrating: bool) -> Result<AaMethod, PlanError> {
        let m = self.method.as_str();
        let only = |set: bool, flag: &str, owner: &str| -> Result<(), PlanError> {
            if set && m != owner {
                return Err(PlanError(format!(
                    "{flag} applies to --aa {owner}, not --aa {m}"
                )));
            }
            Ok(())
        };
        only(self.mask.is_some(), "--mask", "abuffer")?;
        only(self.depth.is_some(), "--depth", "abuffer")?;
        only(self.subscanlines.is_some(), "--subscanlines", "multiscan")?;
        only(self.filter.is_some(), "--filter", "multiscan")?;
        only(self.samples.is_some(), "--samples", "corner")?;
        only(self.pattern.is_some(), "--pattern", "corner")?;
        only(self.ssaa.is_some(), "--ssaa", "ssaa")?;
        only(self.postfx_window.is_some(), "--postfx-window", "postfx")?;
        only(self.postfx_normals.is_some(), "--postfx-normals", "postfx")?;
        only(self.postfx_d2.is_some(), "--postfx-d2", "postfx")?;
        only(self.compare_depth, "--compare-depth", "abuffer")?;
        Ok(match m {
            "none" => AaMethod::None,
            "abuffer" => {
                let size = match &self.mask {
                    Some(s) => {
                        MaskSize::parse(s).map_err(|e| PlanError(format!("--mask {s}: {e}")))?
                    }
                    None => MaskSize::S4X4,
                };
                let depth = match &self.depth {
                    Some(d) => DepthSelect::parse(d).ok_or_else(|| {
                        PlanError(format!(
                            "--depth {d}: expected center, search, slope or exhaustive"
                        ))
                    })?,
                    None => DepthSelect::Search,
                };
                AaMethod::Abuffer(AbufferParams {
                    size,
                    depth,
                    interpenetrating,
                    compare_variants: self.compare_depth,
                })
            }
            "multiscan" => {
                let n = self.subscanlines.unwrap_or(3);
                if !(1..=16).contains(&n) {
                    return Err(PlanError(format!("--subscanlines {n} is outside 1..=16")));
                }
                let filter = match self.filter.as_deref().unwrap_or("box") {
                    "box" => Filter::Box,
                    "gauss" => Filter::Gauss,
                    "cone" => Filter::Cone,
                    f => {
                        return Err(PlanError(format!(
                            "--filter {f}: expected box, gauss or cone"
                        )))
                    }
                };
                AaMethod::Multiscan(MultiscanParams::new(n, filter))
            }
            "corner" => {
                let pattern = match self.pattern.as_deref().unwrap_or("corner") {
                    "corner" => Pattern::Corner,
                    "d3d4x" => Pattern::D3d4x,
                    "grid2x2" => Pattern::Grid2x2,
                    p => {
                        return Err(PlanError(format!(
                            "--pattern {p}: expected corner, d3d4x or grid2x2"
                        )))
                    }
                };
                let centre = match self.samples.unwrap_or(1) {
                    1 => false,
                    2 => true,
                    n => return Err(PlanError(format!("--samples {n}: expected 1 or 2"))),
                };
                AaMethod::Corner(CornerParams::new(pattern, centre))
            }
            "postfx" => {
                let mut p = PostFxParams::default();
                match self.postfx_window.unwrap_or(5) {
                    5 => p.window = true,
                    3 => p.window = false,
                    n => return Err(PlanError(format!("--postfx-window {n}: expected 5 or 3"))),
                }
                match self.postfx_normals.as_deref().unwrap_or("off") {
                    "off" => p.normals = false,
                    "recon" => (p.normals, p.normal_source) = (true, NormalSource::Reconstructed),
                    "stored" => (p.normals, p.normal_source) = (true, NormalSource::Stored),
                    n => {
                        return Err(PlanError(format!(
                            "--postfx-normals {n}: expected off, recon or stored"
                        )))
                    }
                }
                p.d2_source = match self.postfx_d2.as_deref().unwrap_or("final") {
                    "final" => SecondDiffSource::FinalZ,
                    "draw" => SecondDiffSource::DuringDraw,
                    d => {
                        return Err(PlanError(format!(
                            "--postfx-d2 {d}: expected final or draw"
                        )))
                    }
                };
                AaMethod::PostFx(p)
            }
            "ssaa" => {
                let k = self.ssaa.unwrap_or(4);
                if !(1..=64).contains(&k) {
                    return Err(PlanError(format!("--ssaa {k} is outside 1..=64")));
                }
                AaMethod::Ssaa { k }
            }
            other => {
                return Err(PlanError(format!(
                    "unknown anti-aliasing method '{other}' (known: {})",
                    AA_NAMES.join(", ")
                )))
            }
        })
    }
}

/// Short name of a method, as `--aa` spells it.
pub fn aa_name(m: &AaMethod) -> &'static str {
    match m {
        AaMethod::None => "none",
        AaMethod::Abuffer(_) => "abuffer",
        AaMethod::Multiscan(_) => "multiscan",
        AaMethod::Corner(_) => "corner",
        AaMethod::PostFx(_) => "postfx",
        AaMethod::Ssaa { .. } => "ssaa",
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
        let spec = match (&ov.aa, &s.effects.aa) {
            (Some(a), _) => a.clone(),
            (None, Some(v)) => parse_scene_aa(v)?,
            (None, None) => AaSpec::named("none"),
        };
        let aa = spec.method(s.effects.interpenetrating)?;
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

/// Parses the scene's `effects.aa` value: a method name, or an object with `method` and
/// parameters named as the command-line flags.
fn parse_scene_aa(v: &serde_json::Value) -> Result<AaSpec, PlanError> {
    match v {
        serde_json::Value::String(s) => Ok(AaSpec::named(s)),
        serde_json::Value::Object(_) => serde_json::from_value(v.clone())
            .map_err(|e| PlanError(format!("scene effects.aa: {e}"))),
        _ => Err(PlanError(
            "scene effects.aa must be a method name or an object".into(),
        )),
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
    /// An anti-aliasing method renders the image (its own stages inside; the A-buffer's
    /// masks, search unit, packing and resolve; multi-scanning's sub-scanline passes; ...).
    Antialias(&'static str),
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
            Stage::ShadowVolumes { light } => write!(f, "shadow volumes, light {light}"),
            Stage::PixelArray => write!(f, "pixel-processor array"),
            Stage::ShadowShade => write!(f, "shadow shading"),
            Stage::Antialias(m) => write!(f, "anti-aliasing: {m}"),
            Stage::ShadowApply => write!(f, "shadow factor on AA image"),
            Stage::Aov(a) => write!(f, "aov {}", a.name()),
        }
    }
}

/// The stages that render a scene with the given effects. The pixel-processor array runs
/// when there is no other anti-aliasing method, or when shadows or a depth/shadow AOV need
/// its per-pixel state; an anti-aliasing method adds only its own stage.
pub fn plan(e: &Effects) -> Vec<Stage> {
    let shadows = !e.shadow_lights.is_empty();
    let aa = !matches!(e.aa, AaMethod::None);
    let array = !aa || shadows || e.aovs.iter().any(|a| matches!(a, Aov::Depth | Aov::Shadow));
    let mut st = vec![Stage::FrontEnd];
    if array {
        st.push(Stage::SpanSetup);
        for &l in &e.shadow_lights {
            st.push(Stage::ShadowVolumes { light: l });
        }
        st.push(Stage::PixelArray);
        if shadows {
            st.push(Stage::ShadowShade);
        }
    }
    if aa {
        st.push(Stage::Antialias(aa_name(&e.aa)));
        if shadows {
            st.push(Stage::ShadowApply);
        }
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
                Stage::ShadowVolumes { light: 0 },
                Stage::ShadowVolumes { light: 2 },
                Stage::PixelArray,
                Stage::ShadowShade
            ]
        );
    }
}
