//! Every anti-aliasing method judged against the exact reference on generated scenes:
//! errors must fall as the method's parameters rise.

mod aa_common;
use aa_common::*;
use pixelproc_sim::aa::multiscan::GAUSS_SIGMA;
use pixelproc_sim::aa::{
    edge_shade_levels, render_aa, AaMethod, CornerParams, Filter, MultiscanParams, Pattern,
    PostFxParams,
};
use pixelproc_sim::reference::{filtered_reference_image, reference_image, RefFilter, RefImage};
use pixelproc_sim::setup::SnappedTri;

const W: u32 = 64;
const H: u32 = 48;
const BG: [u8; 3] = [20, 40, 60];

fn scenes() -> Vec<(Vec<SnappedTri>, RefImage)> {
    (11..14u64)
        .map(|s| {
            let t = random_scene(s, 24, W as f64, H as f64);
            let r = reference_image(&t, W, H, BG);
            (t, r)
        })
        .collect()
}

fn rmse(t: &[SnappedTri], r: &RefImage, m: AaMethod) -> f64 {
    r.rmse(&render_aa(t, W, H, BG, &m).unwrap().rgb)
}

fn rmse_edges(t: &[SnappedTri], r: &RefImage, m: AaMethod) -> f64 {
    let e = r.edge_mask();
    r.rmse_masked(&render_aa(t, W, H, BG, &m).unwrap().rgb, |k| e[k])
}

/// Full-image RMSE of multiscan with each subscanline count of `ns` and filter `f`.
fn multiscan_errors(t: &[SnappedTri], r: &RefImage, ns: &[u32], f: Filter) -> Vec<f64> {
    ns.iter()
        .map(|&n| rmse(t, r, AaMethod::Multiscan(MultiscanParams::new(n, f))))
        .collect()
}

#[test]
fn multiscan_box_error_falls_from_1_to_8_subscanlines() {
    for (k, (t, r)) in scenes().iter().enumerate() {
        let e = multiscan_errors(t, r, &[1, 2, 4, 8], Filter::Box);
        assert!(e.windows(2).all(|w| w[1] < w[0]), "scene {k}: {e:?}");
        assert!(e[3] < 1.0, "scene {k}: n=8 RMSE {}", e[3]);
    }
}

#[test]
fn multiscan_gauss_and_cone_errors_fall_from_1_to_8_subscanlines_against_their_filter() {
    for (k, (t, _)) in scenes().iter().enumerate() {
        for (f, rf) in [
            (Filter::Gauss, RefFilter::Gauss { sigma: GAUSS_SIGMA }),
            (Filter::Cone, RefFilter::Cone),
        ] {
            let r = filtered_reference_image(t, W, H, BG, rf).image;
            let e = multiscan_errors(t, &r, &[1, 2, 4, 8], f);
            assert!(e.windows(2).all(|w| w[1] < w[0]), "scene {k} {f:?}: {e:?}");
            assert!(e[3] < 1.0, "scene {k} {f:?}: n=8 RMSE {}", e[3]);
        }
    }
}

#[test]
fn ssaa_error_falls_from_2_to_8() {
    for (k, (t, r)) in scenes().iter().enumerate() {
        let e: Vec<f64> = [1, 2, 4, 8]
            .iter()
            .map(|&s| rmse(t, r, AaMethod::Ssaa { k: s }))
            .collect();
        assert!(e.windows(2).all(|w| w[1] < w[0]), "scene {k}: {e:?}");
    }
}

#[test]
fn corner_patterns_and_postfx_beat_no_aa_on_edges() {
    for (k, (t, r)) in scenes().iter().enumerate() {
        let none = rmse_edges(t, r, AaMethod::None);
        for m in [
            AaMethod::Corner(CornerParams::new(Pattern::Corner, false)),
            AaMethod::Corner(CornerParams::new(Pattern::Corner, true)),
            AaMethod::Corner(CornerParams::new(Pattern::D3d4x, false)),
            AaMethod::Corner(CornerParams::new(Pattern::Grid2x2, false)),
            AaMethod::PostFx(PostFxParams::default()),
        ] {
            let e = rmse_edges(t, r, m.clone());
            assert!(e < none, "scene {k}: {} {e} vs none {none}", m.label());
        }
        // The centre sample helps the corner pattern.
        let c1 = rmse_edges(
            t,
            r,
            AaMethod::Corner(CornerParams::new(Pattern::Corner, false)),
        );
        let c2 = rmse_edges(
            t,
            r,
            AaMethod::Corner(CornerParams::new(Pattern::Corner, true)),
        );
        assert!(c2 < c1, "scene {k}: {c2} vs {c1}");
    }
}

#[test]
fn visible_surface_errors_fall_with_subscanlines_and_samples() {
    for (k, (t, r)) in scenes().iter().enumerate() {
        let wrong = |m: AaMethod| {
            let f = render_aa(t, W, H, BG, &m).unwrap();
            f.visible
                .unwrap()
                .iter()
                .zip(&r.dominant)
                .filter(|(a, b)| a != b)
                .count()
        };
        let (a, b) = (
            wrong(AaMethod::Multiscan(MultiscanParams::new(2, Filter::Box))),
            wrong(AaMethod::Multiscan(MultiscanParams::new(12, Filter::Box))),
        );
        assert!(b < a || b == 0, "scene {k}: multiscan {a} → {b}");
        let (a, b) = (
            wrong(AaMethod::Ssaa { k: 2 }),
            wrong(AaMethod::Ssaa { k: 8 }),
        );
        assert!(b < a, "scene {k}: ssaa {a} → {b}");
    }
}

#[test]
fn a_uniform_screen_stays_exactly_its_colour() {
    let c = [(123u32 << 12) + 2048, (45 << 12) + 2048, (210 << 12) + 2048];
    let q = |x: f64| q8(x);
    let tri = |v: [[f64; 2]; 3]| SnappedTri {
        v: v.map(|p| [q(p[0]), q(p[1])]),
        z: [1000, 2000, 3000],
        c: [c; 3],
        ..Default::default()
    };
    let t = [
        tri([[-3.0, -3.0], [70.0, -3.0], [70.0, 60.0]]),
        tri([[-3.0, -3.0], [70.0, 60.0], [-3.0, 60.0]]),
    ];
    for m in [
        AaMethod::None,
        AaMethod::Multiscan(MultiscanParams::new(3, Filter::Box)),
        AaMethod::Multiscan(MultiscanParams::new(5, Filter::Gauss)),
        AaMethod::Multiscan(MultiscanParams::new(4, Filter::Cone)),
        AaMethod::Corner(CornerParams::new(Pattern::Corner, true)),
        AaMethod::Corner(CornerParams::new(Pattern::D3d4x, false)),
        AaMethod::PostFx(PostFxParams::default()),
        AaMethod::Ssaa { k: 3 },
    ] {
        let f = render_aa(&t, W, H, BG, &m).unwrap();
        assert!(
            f.rgb.chunks(3).all(|p| p == [123, 45, 210]),
            "{}",
            m.label()
        );
    }
}

#[test]
fn multiscan_splits_interpenetrating_quads_at_their_intersection() {
    // A: z = 1000 + 100x (red), B: z = 1850 − 100x (blue): equal at x = 4.25.
    let white = |rgb: [u32; 3]| rgb.map(|c| (c << 12) + 2048);
    let quad = |z0: u32, z1: u32, rgb: [u32; 3]| {
        let t = |v: [[f64; 2]; 3], z: [u32; 3]| SnappedTri {
            v: v.map(|p| [q8(p[0]), q8(p[1])]),
            z,
            c: [white(rgb); 3],
            ..Default::default()
        };
        [
            t([[0.0, 0.0], [8.0, 0.0], [8.0, 8.0]], [z0, z1, z1]),
            t([[0.0, 0.0], [8.0, 8.0], [0.0, 8.0]], [z0, z1, z0]),
        ]
    };
    let mut tris = quad(1000, 1800, [255, 0, 0]).to_vec();
    tris.extend(quad(1850, 1050, [0, 0, 255]));
    let f = render_aa(
        &tris,
        8,
        8,
        [0, 255, 0],
        &AaMethod::Multiscan(MultiscanParams::new(4, Filter::Box)),
    )
    .unwrap();
    for j in 0..8 {
        for i in 0..8 {
            let red = (4.25 - i as f64).clamp(0.0, 1.0) * 255.0;
            let p = &f.rgb[3 * (j * 8 + i)..3 * (j * 8 + i) + 3];
            assert!((p[0] as f64 - red).abs() <= 1.0, "({i},{j}) {p:?}");
            assert!(
                (p[2] as f64 - (255.0 - red)).abs() <= 1.0,
                "({i},{j}) {p:?}"
            );
            assert_eq!(p[1], 0, "({i},{j})");
        }
    }
}

#[test]
fn corner_resolve_reads_one_sample_per_pixel_with_the_row_buffer() {
    let (t, _) = &scenes()[0];
    for (centre, extra) in [(false, 0u64), (true, 1)] {
        let f = render_aa(
            t,
            W,
            H,
            BG,
            &AaMethod::Corner(CornerParams::new(Pattern::Corner, centre)),
        )
        .unwrap();
        // Each of the (W+1)(H+1) corner samples is read exactly once, plus the centres.
        let want = (W as u64 + 1) * (H as u64 + 1) + extra * (W * H) as u64;
        assert_eq!(f.stats.sample_reads, want);
        let d3d = render_aa(
            t,
            W,
            H,
            BG,
            &AaMethod::Corner(CornerParams::new(Pattern::D3d4x, centre)),
        )
        .unwrap();
        assert_eq!(d3d.stats.sample_reads, (4 + extra) * (W * H) as u64);
    }
}

#[test]
fn corner_pattern_gives_five_levels_on_near_horizontal_and_vertical_edges() {
    // Seed 003: four distinct x and y offsets give 0, ¼, ½, ¾, 1; the 2×2 grid only 3.
    for v in [false, true] {
        let c = edge_shade_levels(
            &AaMethod::Corner(CornerParams::new(Pattern::Corner, false)),
            v,
        )
        .unwrap();
        let g = edge_shade_levels(
            &AaMethod::Corner(CornerParams::new(Pattern::Grid2x2, false)),
            v,
        )
        .unwrap();
        let n = edge_shade_levels(&AaMethod::None, v).unwrap();
        assert_eq!((c, g, n), (5, 3, 2), "vertical = {v}");
    }
}

#[test]
fn bad_parameters_are_errors_not_panics() {
    let t = random_scene(1, 3, 16.0, 16.0);
    for m in [
        AaMethod::Multiscan(MultiscanParams::new(0, Filter::Box)),
        AaMethod::Multiscan(MultiscanParams::new(17, Filter::Gauss)),
        AaMethod::Ssaa { k: 0 },
        AaMethod::Ssaa { k: 65 },
    ] {
        assert!(render_aa(&t, 16, 16, BG, &m).is_err(), "{}", m.label());
    }
    assert!(render_aa(&t, 0, 16, BG, &AaMethod::None).is_err());
}
