//! Prints one digest per (scene, setting) of everything a render produces except its
//! timings: the image, every AOV, the array's final per-pixel state and every counter.
//!
//! Used to show that a speed change computes the same thing: run it on the tree before
//! and after and compare the two outputs line by line (`diff`). The scenes are the
//! `--all-methods` benchmark's first four (`target_scenes`, 1920×1080; its hard scenes,
//! added later, are left out so that digests stay comparable across rounds) plus the
//! embedded default scene; the settings
//! cover every method with default and non-default parameters, with and without shadows.
//!
//! ```sh
//! cargo run --release -p pixelproc-bench --example output_digest > after.txt
//! cargo run --release -p pixelproc-bench --example output_digest -- postfx  # only settings whose name contains "postfx"
//! ```

use std::collections::hash_map::DefaultHasher;
use std::fmt::Write as _;
use std::hash::Hasher;

use pixelproc_bench::methods::target_scenes;
use pixelproc_sim::mask_search::DepthSelect;
use pixelproc_sim::pipeline::AaReport;
use pixelproc_sim::plan::{
    AaSpec, AbufferSpec, Aov, CornerSpec, Effects, MultiscanSpec, Overrides, PostFxSpec, SsaaSpec,
};
use pixelproc_sim::scene;

/// A `fmt::Write` that feeds a hasher, so `{:?}` of a large output is never held whole.
struct HashWriter(DefaultHasher);

impl std::fmt::Write for HashWriter {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.write(s.as_bytes());
        Ok(())
    }
}

fn settings() -> Vec<(String, Overrides)> {
    use pixelproc_formats::abuffer::MaskSize;
    use pixelproc_sim::aa::postfx::SecondDiffSource;
    use pixelproc_sim::aa::Filter;
    use pixelproc_sim::aa::Pattern;
    use pixelproc_sim::plan::PostFxNormals;
    let mut v: Vec<(String, AaSpec)> = vec![("none".into(), AaSpec::None)];
    for (mask, depth) in [
        (MaskSize::S4X4, DepthSelect::Search),
        (MaskSize::S8X8, DepthSelect::Search),
        (MaskSize::S4X4, DepthSelect::Center),
        (MaskSize::S4X4, DepthSelect::Slope),
        (MaskSize::S4X4, DepthSelect::Exhaustive),
    ] {
        v.push((
            format!("abuffer {mask:?} {depth:?}"),
            AaSpec::Abuffer(AbufferSpec {
                mask,
                depth,
                compare_depth: false,
            }),
        ));
    }
    for (n, filter) in [
        (1, Filter::Box),
        (4, Filter::Box),
        (16, Filter::Box),
        (3, Filter::Gauss),
        (5, Filter::Cone),
    ] {
        v.push((
            format!("multiscan {n} {filter:?}"),
            AaSpec::Multiscan(MultiscanSpec {
                subscanlines: n,
                filter,
            }),
        ));
    }
    for (samples, pattern) in [
        (1, Pattern::Corner),
        (2, Pattern::Corner),
        (1, Pattern::D3d4x),
        (1, Pattern::Grid2x2),
    ] {
        v.push((
            format!("corner {samples} {pattern:?}"),
            AaSpec::Corner(CornerSpec { samples, pattern }),
        ));
    }
    for k in [2, 3] {
        v.push((format!("ssaa {k}"), AaSpec::Ssaa(SsaaSpec { ssaa: k })));
    }
    for (w, normals, d2) in [
        (5, PostFxNormals::Off, SecondDiffSource::FinalZ),
        (3, PostFxNormals::Recon, SecondDiffSource::DuringDraw),
        (5, PostFxNormals::Stored, SecondDiffSource::FinalZ),
    ] {
        v.push((
            format!("postfx {w} {normals:?} {d2:?}"),
            AaSpec::PostFx(PostFxSpec {
                postfx_window: w,
                postfx_normals: normals,
                postfx_d2: d2,
            }),
        ));
    }
    let mut out = Vec::new();
    for (name, aa) in v {
        for shadows in [false, true] {
            out.push((
                format!("{name} shadows={shadows}"),
                Overrides {
                    aa: Some(aa.clone()),
                    no_shadows: !shadows,
                    aovs: vec![Aov::Depth, Aov::Shadow, Aov::Coverage],
                    ..Default::default()
                },
            ));
        }
    }
    out
}

fn main() -> anyhow::Result<()> {
    let filter = std::env::args().nth(1).unwrap_or_default();
    let mut scenes = target_scenes()?;
    scenes.push(scene::load_builtin("default")?);
    for ls in &scenes {
        for (name, ov) in settings() {
            if !name.contains(&filter) {
                continue;
            }
            let fx = Effects::resolve(ls, &ov)?;
            let mut o = pixelproc_sim::pipeline::render(ls, &fx)?;
            o.timings.clear();
            // Wall times are not outputs.
            if let Some(AaReport::Other(s)) = &mut o.aa {
                s.seconds = 0.0;
            }
            let mut h = HashWriter(DefaultHasher::new());
            write!(h, "{o:?}")?;
            println!("{:<10} {:<44} {:016x}", ls.name, name, h.0.finish());
        }
    }
    Ok(())
}
