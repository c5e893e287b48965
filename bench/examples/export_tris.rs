//! Writes the snapped triangles of the `--all-methods` benchmark scenes (what the golden
//! model renders, after the front end) as flat binary files, so that a CPU rasterizer a
//! user would pick instead (Mesa's llvmpipe, `bench/cpu_renderer/llvmpipe.py`) renders the
//! very same triangles side by side with `pixelproc bench --all-methods`.
//!
//! ```sh
//! cargo run --release -p pixelproc-bench --example export_tris -- OUTDIR
//! ```
//!
//! `OUTDIR/<scene>.tris`, little-endian: `u32 width, u32 height, u32 count`, then per
//! triangle three vertices of seven `f32`: x and y in pixels, depth in `0..1` (the 24-bit
//! depth over `2^24 − 1`), r, g, b in `0..1` (the Q8.12 intensity over `255·2^12`), and a
//! padding zero.

use std::io::Write;

use anyhow::{Context, Result};
use pixelproc_bench::methods::bench_scenes;
use pixelproc_sim::frontend::project;

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let out = std::env::args()
        .nth(1)
        .context("usage: export_tris OUTDIR (writes OUTDIR/<scene>.tris)")?;
    std::fs::create_dir_all(&out).with_context(|| format!("creating {out}"))?;
    for ls in bench_scenes()? {
        let p = project(&ls)?;
        let (w, h) = (ls.scene.width, ls.scene.height);
        let mut buf = Vec::with_capacity(12 + p.tris.len() * 84);
        for v in [w, h, p.tris.len() as u32] {
            buf.extend_from_slice(&v.to_le_bytes());
        }
        let zmax = pixelproc_formats::Z_FAR as f32;
        for t in &p.tris {
            for k in 0..3 {
                let c = t.c[k].map(|q| q as f32 / (255.0 * 4096.0));
                let vals = [
                    t.v[k][0] as f32 / 256.0,
                    t.v[k][1] as f32 / 256.0,
                    t.z[k] as f32 / zmax,
                    c[0],
                    c[1],
                    c[2],
                    0.0,
                ];
                for f in vals {
                    buf.extend_from_slice(&f.to_le_bytes());
                }
            }
        }
        let name = ls.name.trim_start_matches('@');
        let path = std::path::Path::new(&out).join(format!("{name}.tris"));
        std::fs::File::create(&path)
            .and_then(|mut f| f.write_all(&buf))
            .with_context(|| format!("writing {}", path.display()))?;
        println!("{}: {w}x{h}, {} triangles", path.display(), p.tris.len());
    }
    Ok(())
}
