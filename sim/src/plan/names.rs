//! The one spelling of every name a user types for an effect: anti-aliasing methods,
//! multi-scanning filters (seed 002 §2.2), A-buffer depth selections (seed 000), sample
//! patterns (seed 003), post-process normal and second-difference sources (seed 004),
//! shadow forms (seed 001 §5) and debug images. Each enum lists its names once, in
//! [`names!`]; `FromStr`, `Display`, the command line's possible values and the error
//! for an unknown name all come from that list.

use std::fmt;
use std::str::FromStr;
use thiserror::Error;

use crate::aa::postfx::SecondDiffSource;
use crate::aa::{AaMethod, Filter, Pattern};
use crate::mask_search::DepthSelect;
use crate::shadow::{Shading, ShadowForm};

/// An enum whose values a user selects by name.
pub trait Named: Sized + Copy + PartialEq + 'static {
    /// What the name selects, for messages, e.g. `filter`.
    const WHAT: &'static str;
    /// Every value, in the order messages list them.
    const ALL: &'static [Self];
    /// The value's name.
    fn name(self) -> &'static str;
    /// Every name, in the order of [`Named::ALL`].
    fn names() -> impl Iterator<Item = &'static str> {
        Self::ALL.iter().map(|v| v.name())
    }
}

/// A name that is not one of the known ones.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("unknown {what} '{value}' (known: {known})")]
pub struct NameError {
    /// What the name selects.
    pub what: &'static str,
    /// The name given.
    pub value: String,
    /// The known names, comma-separated.
    pub known: String,
}

/// Parses a name of `T`.
pub fn parse_name<T: Named>(s: &str) -> Result<T, NameError> {
    T::ALL
        .iter()
        .copied()
        .find(|v| v.name() == s)
        .ok_or_else(|| NameError {
            what: T::WHAT,
            value: s.to_string(),
            known: T::names().collect::<Vec<_>>().join(", "),
        })
}

/// Implements [`Named`], `FromStr` and `Display` for an enum from its list of names.
macro_rules! names {
    ($t:ty, $what:literal, [$($v:path => $n:literal),+ $(,)?]) => {
        impl Named for $t {
            const WHAT: &'static str = $what;
            const ALL: &'static [Self] = &[$($v),+];
            fn name(self) -> &'static str {
                match self {
                    $($v => $n,)+
                }
            }
        }
        names!(@traits $t);
    };
    (@traits $t:ty) => {
        impl FromStr for $t {
            type Err = NameError;
            fn from_str(s: &str) -> Result<Self, NameError> {
                parse_name(s)
            }
        }
        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(Named::name(*self))
            }
        }
    };
}

/// An anti-aliasing method without its parameters: what `--aa` and the scene's
/// `effects.aa.method` name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AaKind {
    /// No anti-aliasing: the pixel-processor array.
    None,
    /// The A-buffer with the depth search unit (seed 000).
    Abuffer,
    /// Multi-scanning (seed 002).
    Multiscan,
    /// Corner-shared sampling (seed 003).
    Corner,
    /// Post-process anti-aliasing (seed 004).
    PostFx,
    /// k×k supersampling.
    Ssaa,
}

names!(AaKind, "anti-aliasing method", [
    AaKind::None => "none",
    AaKind::Abuffer => "abuffer",
    AaKind::Multiscan => "multiscan",
    AaKind::Corner => "corner",
    AaKind::PostFx => "postfx",
    AaKind::Ssaa => "ssaa",
]);

impl AaKind {
    /// The kind of a configured method.
    pub fn of(m: &AaMethod) -> AaKind {
        match m {
            AaMethod::None => AaKind::None,
            AaMethod::Abuffer(_) => AaKind::Abuffer,
            AaMethod::Multiscan(_) => AaKind::Multiscan,
            AaMethod::Corner(_) => AaKind::Corner,
            AaMethod::PostFx(_) => AaKind::PostFx,
            AaMethod::Ssaa { .. } => AaKind::Ssaa,
        }
    }
}

/// Where the post-process takes normal edges from (seed 004), if at all.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PostFxNormals {
    /// No edges from normals.
    #[default]
    Off,
    /// Normals reconstructed from the z-buffer.
    Recon,
    /// Normals stored per pixel while drawing.
    Stored,
}

names!(PostFxNormals, "normal source", [
    PostFxNormals::Off => "off",
    PostFxNormals::Recon => "recon",
    PostFxNormals::Stored => "stored",
]);

names!(Filter, "filter", [
    Filter::Box => "box",
    Filter::Gauss => "gauss",
    Filter::Cone => "cone",
]);

names!(Pattern, "pattern", [
    Pattern::Corner => "corner",
    Pattern::D3d4x => "d3d4x",
    Pattern::Grid2x2 => "grid2x2",
]);

names!(SecondDiffSource, "second-difference source", [
    SecondDiffSource::FinalZ => "final",
    SecondDiffSource::DuringDraw => "draw",
]);

names!(ShadowForm, "shadow form", [
    ShadowForm::Ev => "ev",
    ShadowForm::Check => "check",
]);

names!(Shading, "shading", [
    Shading::Exact => "exact",
    Shading::Table => "table",
]);

names!(super::Aov, "AOV", [
    super::Aov::Depth => "depth",
    super::Aov::Shadow => "shadow",
    super::Aov::Coverage => "coverage",
]);

/// The depth selections keep their names beside their definition.
impl Named for DepthSelect {
    const WHAT: &'static str = "depth selection";
    const ALL: &'static [Self] = &DepthSelect::ALL;
    fn name(self) -> &'static str {
        DepthSelect::name(self)
    }
}
names!(@traits DepthSelect);

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<T: Named + FromStr<Err = NameError> + fmt::Display + fmt::Debug>() {
        for &v in T::ALL {
            assert_eq!(v.to_string().parse::<T>(), Ok(v));
        }
        let e = "nope".parse::<T>().unwrap_err();
        assert_eq!(e.value, "nope");
        assert!(e
            .to_string()
            .starts_with(&format!("unknown {} 'nope'", T::WHAT)));
    }

    #[test]
    fn every_name_parses_back() {
        round_trip::<AaKind>();
        round_trip::<PostFxNormals>();
        round_trip::<Filter>();
        round_trip::<Pattern>();
        round_trip::<SecondDiffSource>();
        round_trip::<ShadowForm>();
        round_trip::<super::super::Aov>();
        round_trip::<DepthSelect>();
    }
}
