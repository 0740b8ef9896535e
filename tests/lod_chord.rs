//! The coarse levels' v along the blade (issue 27, point 1; `render::lod_chord`,
//! `lod_chord.wgsl`): the coarsest level draws each blade as its chord, and each fragment's
//! v is mapped back to the curve's, so that a blade shades alike at every level. The WGSL
//! against its CPU twins, the mapping's invariants, and the prairie's blades drawn at the
//! coarsest level against the same blades at the finest.
//!
//! Measured on lavapipe: the GPU values within 1e-6 of the twin's; the prairie without
//! wind at 240 × 136 after 8 frames, every blade at the coarsest level against every blade
//! at the finest: rows 64-127 within 2.1 levels (8.0-11.3 levels brighter at af5b692,
//! before the mapping). The bottom rows, blades a few metres away, differ by their shape
//! (a stick against a curve, −5.5 levels): the levels never draw those so coarsely.

mod common;

use sward::compare::compare_bands;
use sward::render::lod_chord::{self, chord_v, lod_v, shape};

#[test]
fn the_gpu_chord_matches_its_twin() {
    let gpu = common::gpu();
    let mut points = Vec::new();
    for i in 0..=20 {
        for j in 0..=10 {
            let s = i as f32 / 20.0;
            let a = j as f32 / 10.0;
            points.push([s, a, 0.1 * j as f32 - 0.2, 0.05 * (i % 7) as f32]);
        }
    }
    points.push([f32::NAN, 0.5, 0.5, 0.0]);
    points.push([2.0, -1.0, 3.0, 1.0]);
    let got = lod_chord::probe(&gpu, &points).expect("probe");
    for (p, &(v, a, l)) in points.iter().zip(&got) {
        if p.iter().any(|x| x.is_nan()) {
            continue;
        }
        assert!(
            (v - chord_v(p[0], p[1])).abs() <= 1e-6,
            "chord_v {p:?}: {v}"
        );
        assert!((a - shape(p[2])).abs() <= 1e-6, "shape {p:?}: {a}");
        let want = lod_v(p[0], p[1], p[3]);
        assert!((l - want).abs() <= 1e-6, "lod_v {p:?}: {l} against {want}");
    }
}

/// The curve's v found for a chord fraction s is the one whose point projects at s (the
/// quadratic's projection `2 v (1 − v) a + v²`), it rises with s from the root to the tip,
/// and a straight blade (a = 0.5) keeps its v.
#[test]
fn the_chord_maps_back_onto_the_curve() {
    for j in 0..=20 {
        let a = j as f32 / 20.0;
        let mut last = -1.0;
        for i in 0..=200 {
            let s = i as f32 / 200.0;
            let v = chord_v(s, a);
            assert!((0.0..=1.0).contains(&v));
            let projected = 2.0 * v * (1.0 - v) * a + v * v;
            assert!(
                (projected - s).abs() < 1e-4,
                "a {a} s {s}: v {v} projects at {projected}"
            );
            assert!(v >= last - 1e-6, "a {a}: v falls at s {s}");
            last = v;
        }
        assert_eq!(chord_v(0.0, a), 0.0);
        assert!((chord_v(1.0, a) - 1.0).abs() < 1e-6);
    }
    for i in 0..=10 {
        let v = i as f32 / 10.0;
        assert_eq!(lod_v(v, 0.5, 0.3), v, "a straight blade keeps its v");
        assert_eq!(lod_v(v, 0.9, 1.0), v, "nothing drawn: nothing to map");
    }
    // An upright blade's middle projects high on its chord (a near 1): half the chord's
    // length is well under half of v.
    assert!(chord_v(0.5, 0.9) < 0.35);
    assert_eq!(shape(0.5), 0.5);
    assert_eq!(shape(0.0), 0.0);
    assert_eq!(shape(2.0), 1.0);
}

/// The prairie without wind, every blade drawn at the coarsest level (one segment) against
/// every blade at the finest (`culling.lod=false`): the blades' bands read alike.
#[test]
fn the_coarsest_level_shades_as_the_finest() {
    let still = [
        "wind.source=Analytic",
        "wind.directional.strength=0.0",
        "render.billboard_distance=0",
    ];
    let size = (240, 136);
    let with = |extra: &[&str]| {
        let sets: Vec<&str> = still.iter().chain(extra).copied().collect();
        common::prairie_frame(&sets, size, 8)
    };
    let finest = with(&["culling.lod=false"]);
    let coarsest = with(&["culling.lod_near_px=4000", "culling.lod_far_px=3000"]);
    // Rows 64-127: blades in both, far enough to be drawn coarsely by the levels.
    let diffs = compare_bands(&coarsest, &finest, 64..128).expect("same size");
    for d in &diffs {
        println!(
            "band {:3}: {:+.2} levels, contrast {:+.0} %",
            d.top,
            d.luminance,
            100.0 * d.contrast
        );
    }
    let worst = diffs.iter().map(|d| d.luminance.abs()).fold(0.0, f64::max);
    assert!(
        worst <= 2.5,
        "the coarsest level {worst:.2} levels off the finest"
    );
}
