//! The anti-aliasing request as typed configuration: one parameter struct per method
//! (seed 000 A-buffer, 002 multi-scanning, 003 corner sampling, 004 post-process, and
//! supersampling), read from the scene's `effects.aa` or built from the command line.
//!
//! A parameter is a field of its method's struct with its default in the struct's
//! `Default`; the scene's key and the command-line flag are the field's name. Values
//! that need a range check are checked in [`AaSpec::method`], which names the scene key
//! or the flag the value came from ([`Origin`]).

use std::fmt;

use serde::de::{DeserializeOwned, Error as _};
use serde::{Deserialize, Deserializer};

use super::names::{AaKind, Named, PostFxNormals};
use super::PlanError;
use crate::aa::postfx::{NormalSource, SecondDiffSource};
use crate::aa::{AaMethod, CornerParams, Filter, MultiscanParams, Pattern, PostFxParams};
use crate::abuffer::AbufferParams;
use crate::mask_search::DepthSelect;
use pixelproc_formats::abuffer::MaskSize;

/// Where a setting was written: errors name the scene key or the command-line flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// The scene file's `effects.aa`.
    Scene,
    /// A command-line flag.
    CommandLine,
}

/// A parameter as the user wrote it: `effects.aa.subscanlines` or `--subscanlines`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    /// Where the parameter was written.
    pub origin: Origin,
    /// The parameter's name (a spec field, e.g. `postfx_window`).
    pub field: &'static str,
}

impl Key {
    /// The command-line flag of a parameter.
    pub fn flag(field: &'static str) -> Key {
        Key {
            origin: Origin::CommandLine,
            field,
        }
    }
    /// The scene key of a parameter.
    pub fn scene(field: &'static str) -> Key {
        Key {
            origin: Origin::Scene,
            field,
        }
    }
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.origin {
            Origin::Scene => write!(f, "effects.aa.{}", self.field),
            Origin::CommandLine => write!(f, "--{}", self.field.replace('_', "-")),
        }
    }
}

/// Parses an A-buffer subpixel grid `NxM` written at `key`.
pub fn parse_mask(key: Key, s: &str) -> Result<MaskSize, PlanError> {
    let sides: Vec<&str> = s.trim().split(['x', 'X']).collect();
    let numeric = sides.len() == 2
        && sides
            .iter()
            .all(|v| !v.is_empty() && v.bytes().all(|b| b.is_ascii_digit()));
    if !numeric {
        return Err(PlanError::MaskSyntax {
            key,
            value: s.to_string(),
        });
    }
    MaskSize::parse(s).map_err(|source| PlanError::Mask {
        key,
        value: s.to_string(),
        source,
    })
}

/// Parses a name written at `key`.
pub fn parse_param<T: Named>(key: Key, s: &str) -> Result<T, PlanError> {
    super::names::parse_name(s).map_err(|source| PlanError::Param { key, source })
}

/// A-buffer parameters (seed 000).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AbufferSpec {
    /// Subpixel grid, e.g. `4x4` (default) or `8x8`.
    #[serde(deserialize_with = "scene_mask")]
    pub mask: MaskSize,
    /// Depth selection: `search` (default), `center`, `slope`, `exhaustive`.
    #[serde(deserialize_with = "scene_name")]
    pub depth: DepthSelect,
    /// Also run every depth-selection variant and count where it orders or resolves
    /// fragments differently from `exhaustive` (slower; for reports).
    pub compare_depth: bool,
}

impl Default for AbufferSpec {
    fn default() -> Self {
        AbufferSpec {
            mask: MaskSize::S4X4,
            depth: DepthSelect::Search,
            compare_depth: false,
        }
    }
}

/// Multi-scanning parameters (seed 002).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MultiscanSpec {
    /// Sub-scanlines per pixel row, 1..=16 (default 3).
    pub subscanlines: u32,
    /// Filter: `box` (default), `gauss`, `cone`.
    #[serde(deserialize_with = "scene_name")]
    pub filter: Filter,
}

impl Default for MultiscanSpec {
    fn default() -> Self {
        MultiscanSpec {
            subscanlines: 3,
            filter: Filter::Box,
        }
    }
}

/// Corner-sampling parameters (seed 003).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CornerSpec {
    /// Samples per pixel, 1 (default) or 2 (adds the centre sample).
    pub samples: u32,
    /// Sample pattern: `corner` (default), `d3d4x`, `grid2x2`.
    #[serde(deserialize_with = "scene_name")]
    pub pattern: Pattern,
}

impl Default for CornerSpec {
    fn default() -> Self {
        CornerSpec {
            samples: 1,
            pattern: Pattern::Corner,
        }
    }
}

/// Post-process parameters (seed 004).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PostFxSpec {
    /// Lines in the pattern window, 5 (default) or 3.
    pub postfx_window: u32,
    /// Normal edges: `off` (default), `recon` (from z) or `stored`.
    #[serde(deserialize_with = "scene_name")]
    pub postfx_normals: PostFxNormals,
    /// Second differences from the `final` z-buffer (default) or kept during `draw`ing.
    #[serde(deserialize_with = "scene_name")]
    pub postfx_d2: SecondDiffSource,
}

impl Default for PostFxSpec {
    fn default() -> Self {
        PostFxSpec {
            postfx_window: 5,
            postfx_normals: PostFxNormals::Off,
            postfx_d2: SecondDiffSource::FinalZ,
        }
    }
}

/// Supersampling parameters.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SsaaSpec {
    /// Factor k (k×k samples), 1..=64 (default 4).
    pub ssaa: u32,
}

impl Default for SsaaSpec {
    fn default() -> Self {
        SsaaSpec { ssaa: 4 }
    }
}

/// No parameters (the method `none`): any key is unknown.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NoParams {}

/// An anti-aliasing request: a method and its parameters. In a scene, `effects.aa` is a
/// method name (`"corner"`, all defaults) or an object `{"method": "multiscan",
/// "subscanlines": 4}` whose other keys are the method's parameters.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum AaSpec {
    /// No anti-aliasing.
    #[default]
    None,
    /// The A-buffer.
    Abuffer(AbufferSpec),
    /// Multi-scanning.
    Multiscan(MultiscanSpec),
    /// Corner sampling.
    Corner(CornerSpec),
    /// Post-process.
    PostFx(PostFxSpec),
    /// Supersampling.
    Ssaa(SsaaSpec),
}

impl AaSpec {
    /// A method with every parameter at its default.
    pub fn default_for(kind: AaKind) -> AaSpec {
        match kind {
            AaKind::None => AaSpec::None,
            AaKind::Abuffer => AaSpec::Abuffer(Default::default()),
            AaKind::Multiscan => AaSpec::Multiscan(Default::default()),
            AaKind::Corner => AaSpec::Corner(Default::default()),
            AaKind::PostFx => AaSpec::PostFx(Default::default()),
            AaKind::Ssaa => AaSpec::Ssaa(Default::default()),
        }
    }

    /// The method this spec asks for.
    pub fn kind(&self) -> AaKind {
        match self {
            AaSpec::None => AaKind::None,
            AaSpec::Abuffer(_) => AaKind::Abuffer,
            AaSpec::Multiscan(_) => AaKind::Multiscan,
            AaSpec::Corner(_) => AaKind::Corner,
            AaSpec::PostFx(_) => AaKind::PostFx,
            AaSpec::Ssaa(_) => AaKind::Ssaa,
        }
    }

    /// The method with its parameters, range-checked; an error names the parameter as
    /// written at `origin`. `interpenetrating` enables the A-buffer's max search.
    pub fn method(&self, interpenetrating: bool, origin: Origin) -> Result<AaMethod, PlanError> {
        let key = |field| Key { origin, field };
        Ok(match self {
            AaSpec::None => AaMethod::None,
            AaSpec::Abuffer(p) => AaMethod::Abuffer(AbufferParams {
                size: p.mask,
                depth: p.depth,
                interpenetrating,
                compare_variants: p.compare_depth,
            }),
            AaSpec::Multiscan(p) => {
                in_range(key("subscanlines"), p.subscanlines, 1, 16)?;
                AaMethod::Multiscan(MultiscanParams::new(p.subscanlines, p.filter))
            }
            AaSpec::Corner(p) => {
                let centre = match p.samples {
                    1 => false,
                    2 => true,
                    n => return Err(choice(key("samples"), n, "1 or 2")),
                };
                AaMethod::Corner(CornerParams::new(p.pattern, centre))
            }
            AaSpec::PostFx(p) => AaMethod::PostFx(p.params(key("postfx_window"))?),
            AaSpec::Ssaa(p) => {
                in_range(key("ssaa"), p.ssaa, 1, 64)?;
                AaMethod::Ssaa { k: p.ssaa }
            }
        })
    }
}

impl PostFxSpec {
    /// The post-process parameters; `window` names the window parameter for errors.
    fn params(&self, window: Key) -> Result<PostFxParams, PlanError> {
        let window = match self.postfx_window {
            5 => true,
            3 => false,
            n => return Err(choice(window, n, "5 or 3")),
        };
        let d = PostFxParams::default();
        let (normals, normal_source) = match self.postfx_normals {
            PostFxNormals::Off => (false, d.normal_source),
            PostFxNormals::Recon => (true, NormalSource::Reconstructed),
            PostFxNormals::Stored => (true, NormalSource::Stored),
        };
        Ok(PostFxParams {
            window,
            normals,
            normal_source,
            d2_source: self.postfx_d2,
            ..d
        })
    }
}

fn in_range(key: Key, value: u32, lo: u32, hi: u32) -> Result<(), PlanError> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(PlanError::Range { key, value, lo, hi })
    }
}

fn choice(key: Key, value: u32, expected: &'static str) -> PlanError {
    PlanError::Choice {
        key,
        value,
        expected,
    }
}

/// Reads a named scene parameter (the field is named in the error by its type's
/// [`Named::WHAT`]).
fn scene_name<'de, D: Deserializer<'de>, T: Named>(d: D) -> Result<T, D::Error> {
    let s = String::deserialize(d)?;
    super::names::parse_name(&s).map_err(D::Error::custom)
}

/// Reads the scene's `mask`.
fn scene_mask<'de, D: Deserializer<'de>>(d: D) -> Result<MaskSize, D::Error> {
    let s = String::deserialize(d)?;
    parse_mask(Key::scene("mask"), &s).map_err(|e| D::Error::custom(super::one_line(&e)))
}

/// One method's parameters from the rest of the `effects.aa` object.
fn params<T: DeserializeOwned, E: serde::de::Error>(rest: serde_json::Value) -> Result<T, E> {
    serde_json::from_value(rest).map_err(|e| E::custom(format!("effects.aa: {e}")))
}

impl<'de> Deserialize<'de> for AaSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let method = |v: &serde_json::Value| -> Result<AaKind, D::Error> {
            let s = v
                .as_str()
                .ok_or_else(|| D::Error::custom("effects.aa.method must be a method name"))?;
            s.parse()
                .map_err(|e| D::Error::custom(format!("effects.aa: {e}")))
        };
        let mut map = match serde_json::Value::deserialize(d)? {
            serde_json::Value::String(s) => {
                return Ok(AaSpec::default_for(method(&serde_json::Value::String(s))?))
            }
            serde_json::Value::Object(map) => map,
            _ => {
                return Err(D::Error::custom(
                    "effects.aa must be a method name or an object",
                ))
            }
        };
        let kind = method(
            &map.remove("method")
                .ok_or_else(|| D::Error::missing_field("method"))?,
        )?;
        let rest = serde_json::Value::Object(map);
        Ok(match kind {
            AaKind::None => params::<NoParams, _>(rest).map(|_| AaSpec::None)?,
            AaKind::Abuffer => AaSpec::Abuffer(params(rest)?),
            AaKind::Multiscan => AaSpec::Multiscan(params(rest)?),
            AaKind::Corner => AaSpec::Corner(params(rest)?),
            AaKind::PostFx => AaSpec::PostFx(params(rest)?),
            AaKind::Ssaa => AaSpec::Ssaa(params(rest)?),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(json: &str) -> Result<AaSpec, String> {
        serde_json::from_str(json).map_err(|e| e.to_string())
    }

    #[test]
    fn scene_forms() {
        assert_eq!(scene(r#""corner""#), Ok(AaSpec::Corner(Default::default())));
        assert_eq!(
            scene(r#"{"method": "multiscan", "subscanlines": 4, "filter": "cone"}"#),
            Ok(AaSpec::Multiscan(MultiscanSpec {
                subscanlines: 4,
                filter: Filter::Cone
            }))
        );
        assert!(scene(r#"{"method": "multiscan", "subscanline": 4}"#)
            .unwrap_err()
            .contains("unknown field"));
        assert!(scene(r#"{"method": "none", "ssaa": 4}"#)
            .unwrap_err()
            .contains("unknown field"));
        assert!(scene(r#""blur""#)
            .unwrap_err()
            .contains("unknown anti-aliasing method 'blur'"));
        assert!(scene(r#"{"method": "abuffer", "mask": "abc"}"#)
            .unwrap_err()
            .contains("effects.aa.mask abc: expected NxM"));
    }

    #[test]
    fn range_errors_name_where_the_value_was_written() {
        let s = AaSpec::Multiscan(MultiscanSpec {
            subscanlines: 99,
            ..Default::default()
        });
        let e = |o| s.method(false, o).unwrap_err().to_string();
        assert_eq!(
            e(Origin::Scene),
            "effects.aa.subscanlines 99 is outside 1..=16"
        );
        assert_eq!(
            e(Origin::CommandLine),
            "--subscanlines 99 is outside 1..=16"
        );
        let p = AaSpec::PostFx(PostFxSpec {
            postfx_window: 4,
            ..Default::default()
        });
        assert_eq!(
            p.method(false, Origin::CommandLine)
                .unwrap_err()
                .to_string(),
            "--postfx-window 4: expected 5 or 3"
        );
    }
}
