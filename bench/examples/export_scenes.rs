//! Writes the `--all-methods` benchmark's generated scenes (`large`, `grid-1k`, `grid-10k`,
//! `forest`, `spheres`, `closeup`, `shards`, `tori`; the city is the built-in `@boxes`) as
//! scene files: `OUTDIR/<name>/scene.json` and the OBJ files it names, so
//! that they can be rendered with `pixelproc render`, benchmarked one case at a time with
//! `pixelproc bench`, or given to a build that predates them.
//!
//! ```sh
//! cargo run --release -p pixelproc-bench --example export_scenes -- OUTDIR
//! pixelproc bench --all-methods OUTDIR/forest/scene.json --runs 5
//! ```

use anyhow::{Context, Result};
use pixelproc_bench::methods::{hard_scene_files, target_scene_files};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let out = std::env::args()
        .nth(1)
        .context("usage: export_scenes OUTDIR")?;
    for (name, (json, files)) in target_scene_files().into_iter().chain(hard_scene_files()) {
        let dir = std::path::Path::new(&out).join(name);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        for (file, text) in files.iter().chain([(&"scene.json".to_string(), &json)]) {
            let p = dir.join(file);
            std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))?;
        }
        println!("wrote {}", dir.join("scene.json").display());
    }
    Ok(())
}
