//! A decal (pattern, `host: Some`) over its own host face on a slanted plane: the decal
//! covers the far half of a pixel, so its nearest covered subpixel is deeper than the
//! host's. The seed-002 order "pattern in front of face" must still hold for every depth
//! variant and grid: the decal's colour shows on exactly the subpixels it covers.

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::abuffer::{render_abuffer, AbufferParams};
use pixelproc_sim::mask_search::DepthSelect;
use pixelproc_sim::reference::reference_image;
use pixelproc_sim::setup::{HostPlane, SnappedTri};

const HOST: u32 = 200;
const DECAL: u32 = 40;

fn tri(v: [[f64; 2]; 3], z: [u32; 3], grey: u32, tag: u16) -> SnappedTri {
    SnappedTri {
        v: v.map(|p| [(p[0] * 256.0) as i32, (p[1] * 256.0) as i32]),
        z,
        c: [[(grey << 12) + 2048; 3]; 3],
        tag,
        ..Default::default()
    }
}

/// A 4×3 screen: a host face (two triangles) far beyond the screen whose depth rises
/// steeply with x, and a decal rectangle on it covering x ∈ [1.5, 4], so the pixels of
/// column 1 are half decal (their right half), half host.
fn scene(decal_tag: u16) -> Vec<SnappedTri> {
    // Depth z = 1000000 + 20000·x (pixels), exact at the corners.
    let z = |x: f64| (1_000_000.0 + 20_000.0 * x) as u32;
    let (a, b) = ([-8.0, -8.0], [16.0, 16.0]);
    let h0 = tri([a, [b[0], a[1]], b], [z(a[0]), z(b[0]), z(b[0])], HOST, 1);
    let h1 = tri([a, b, [a[0], b[1]]], [z(a[0]), z(b[0]), z(a[0])], HOST, 1);
    let host = HostPlane { v: h0.v, z: h0.z };
    let rect = |v: [[f64; 2]; 3]| {
        let mut d = tri(v, [0; 3], DECAL, decal_tag);
        d.z = d.v.map(|p| z(p[0] as f64 / 256.0));
        d.host = Some(host);
        d
    };
    vec![
        h0,
        h1,
        rect([[1.5, 0.0], [4.0, 0.0], [4.0, 3.0]]),
        rect([[1.5, 0.0], [4.0, 3.0], [1.5, 3.0]]),
    ]
}

#[test]
fn decal_wins_over_its_host_where_it_covers_for_every_variant() {
    // By hand: column 1 is half host, half decal; columns 2 and 3 are decal; column 0 host.
    let half = (HOST + DECAL) as f64 / 2.0;
    let want = [HOST as f64, half, DECAL as f64, DECAL as f64];
    for tag in [1u16, 2] {
        let tris = scene(tag);
        let r = reference_image(&tris, 4, 3, [0, 0, 0]);
        for j in 0..3 {
            for (i, w) in want.iter().enumerate() {
                assert!(
                    (r.rgb[j * 4 + i][0] - w).abs() < 1e-9,
                    "reference ({i},{j})"
                );
            }
        }
        for size in [MaskSize::S4X4, MaskSize::S8X8] {
            for depth in DepthSelect::ALL {
                let p = AbufferParams {
                    size,
                    depth,
                    interpenetrating: false,
                    compare_variants: false,
                };
                let f = render_abuffer(&tris, 4, 3, [0, 0, 0], &p).unwrap();
                // Within one level: the A-buffer rounds the Q8.12 colour (with its +½
                // offset) half up once more. A lost decal would be off by 80.
                for j in 0..3 {
                    for (i, w) in want.iter().enumerate() {
                        let got = f.rgb[3 * (j * 4 + i)] as f64;
                        assert!(
                            (got - w).abs() <= 1.0,
                            "tag {tag} {size} {depth:?} pixel ({i},{j}): {got} vs {w}"
                        );
                    }
                }
            }
        }
    }
}
