//! The settings of the sweep: every anti-aliasing method of [`pixelproc_sim::aa`] with the
//! parameter values `docs/accuracy.md` reports, each with the family and setting labels the
//! CSV, the report and the chart use.

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::aa::{AaMethod, CornerParams, Filter, MultiscanParams, Pattern, PostFxParams};
use pixelproc_sim::abuffer::AbufferParams;
use pixelproc_sim::mask_search::DepthSelect;

/// One setting of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    /// Method family (`none`, `multiscan`, `abuffer`, `corner`, `d3d4x`, `grid2x2`,
    /// `postfx`, `ssaa`).
    pub method: String,
    /// The setting within the family, e.g. `n=3 box`.
    pub setting: String,
    /// The method with its parameters (for the A-buffer, `interpenetrating` is taken from
    /// each scene).
    pub aa: AaMethod,
}

/// Labels a method: its family and its setting within the family.
fn setting(aa: AaMethod) -> Setting {
    let (method, setting) = match &aa {
        AaMethod::None => ("none".to_string(), "1 sample".to_string()),
        AaMethod::Multiscan(p) => (
            "multiscan".into(),
            format!(
                "n={} {}",
                p.subscanlines,
                format!("{:?}", p.filter).to_lowercase()
            ),
        ),
        AaMethod::Abuffer(p) => ("abuffer".into(), format!("{} {}", p.size, p.depth.name())),
        AaMethod::Corner(p) => match p.pattern {
            Pattern::Corner => (
                "corner".into(),
                if p.centre {
                    "2 spp (+centre)".into()
                } else {
                    "1 spp".into()
                },
            ),
            Pattern::D3d4x => ("d3d4x".into(), "4 spp".into()),
            Pattern::Grid2x2 => ("grid2x2".into(), "4 spp".into()),
        },
        AaMethod::PostFx(p) => (
            "postfx".into(),
            if *p == PostFxParams::default() {
                "default".into()
            } else {
                p.label()
            },
        ),
        AaMethod::Ssaa { k } => ("ssaa".into(), format!("k={k} ({}x{})", k, k)),
    };
    let setting = if setting.is_empty() {
        "default".into()
    } else {
        setting
    };
    Setting {
        method,
        setting,
        aa,
    }
}

/// The settings of the sweep. Full: none; multiscan n ∈ {1,2,3,4,6,8,12} × {box, gauss};
/// A-buffer 4×4 and 8×8 × {center, search, slope, exhaustive}; corner sampling with 1 and
/// 2 samples per pixel; D3D 4× and ordered 2×2; post-process; supersampling k ∈ {2,3,4,8}.
/// Quick: a subset for tests (none, multiscan n ∈ {1,4,12} box, A-buffer 4×4 search,
/// corner 1 spp, post-process, ssaa k ∈ {2,8}).
pub fn sweep_settings(quick: bool) -> Vec<Setting> {
    let mut m = vec![AaMethod::None];
    let ns: &[u32] = if quick {
        &[1, 4, 12]
    } else {
        &[1, 2, 3, 4, 6, 8, 12]
    };
    let filters: &[Filter] = if quick {
        &[Filter::Box]
    } else {
        &[Filter::Box, Filter::Gauss]
    };
    for &f in filters {
        for &n in ns {
            m.push(AaMethod::Multiscan(MultiscanParams::new(n, f)));
        }
    }
    let sizes: &[MaskSize] = if quick {
        &[MaskSize::S4X4]
    } else {
        &[MaskSize::S4X4, MaskSize::S8X8]
    };
    let depths: &[DepthSelect] = if quick {
        &[DepthSelect::Search]
    } else {
        &DepthSelect::ALL
    };
    for &size in sizes {
        for &depth in depths {
            m.push(AaMethod::Abuffer(AbufferParams {
                size,
                depth,
                interpenetrating: false,
                compare_variants: false,
            }));
        }
    }
    m.push(AaMethod::Corner(CornerParams::new(Pattern::Corner, false)));
    if !quick {
        m.push(AaMethod::Corner(CornerParams::new(Pattern::Corner, true)));
        m.push(AaMethod::Corner(CornerParams::new(Pattern::D3d4x, false)));
        m.push(AaMethod::Corner(CornerParams::new(Pattern::Grid2x2, false)));
    }
    m.push(AaMethod::PostFx(PostFxParams::default()));
    // k = 3 as well: the multi-scanning paper compares against 3×3 supersampling.
    let ks: &[u32] = if quick { &[2, 8] } else { &[2, 3, 4, 8] };
    for &k in ks {
        m.push(AaMethod::Ssaa { k });
    }
    m.into_iter().map(setting).collect()
}
