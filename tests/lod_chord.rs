//! The coarse levels' v along the blade (issue 27, point 1; `render::lod_chord`,
//! `lod_chord.wgsl`): the coarsest level draws each blade as one or two straight segments,
//! and each fragment's v is mapped back to the curve's, so that a blade shades alike at
//! every level. The WGSL against its CPU twins, the mapping's invariants, and the
//! prairie's blades drawn at the coarsest level against the same blades at the finest.
//!
//! Measured on lavapipe: the GPU values within 1e-6 of the twin's; the prairie without
//! wind at 240 × 136 after 8 frames, every blade at the coarsest level against every blade
//! at the finest: rows 64-127 within 2.9 levels (2.1 with one mapped segment, 8.0-11.3
//! levels brighter at af5b692, before the mapping); with wind after 24 frames within 4.2
//! (6.7 with one segment). The bottom rows, blades a few metres away, differ by their shape
//! (a stick against a curve, −5.5 levels): the levels never draw those so coarsely.

mod common;

use sward::compare::compare_bands;
use sward::render::lod_chord::{self, chord_v, code_one, code_two, lod_v, shape};

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
    for (p, &[v, a, one, two]) in points.iter().zip(&got) {
        if p.iter().any(|x| x.is_nan()) {
            continue;
        }
        assert!(
            (v - chord_v(p[0], p[1])).abs() <= 1e-6,
            "chord_v {p:?}: {v}"
        );
        assert!((a - shape(p[2])).abs() <= 1e-6, "shape {p:?}: {a}");
        let want = lod_v(p[0], code_one(p[1]), p[3]);
        assert!(
            (one - want).abs() <= 1e-6,
            "lod_v {p:?}: {one} against {want}"
        );
        let want = lod_v(p[0], code_two(p[1], p[2]), p[3]);
        assert!(
            (two - want).abs() <= 1e-6,
            "two halves {p:?}: {two} against {want}"
        );
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
        assert_eq!(
            lod_v(v, code_one(0.5), 0.3),
            v,
            "a straight blade keeps its v"
        );
        assert_eq!(
            lod_v(v, code_one(0.9), 1.0),
            v,
            "nothing drawn: nothing to map"
        );
        assert_eq!(lod_v(v, code_two(0.9, 0.1), 1.0), v);
    }
    // Two halves: each half of the drawn blade maps onto its half of v, as one segment of
    // its own shape does (the codes keep each shape to 1 / 2047).
    let (root, a0, a1) = (0.2, 0.85, 0.3);
    let code = code_two(a0, a1);
    for i in 0..=100 {
        let s = i as f32 / 100.0;
        let v = lod_v(root + (1.0 - root) * s, code, root);
        let (half, a) = if s >= 0.5 { (1.0, a1) } else { (0.0, a0) };
        let want = root + (1.0 - root) * 0.5 * (half + chord_v(2.0 * s - half, a));
        assert!((v - want).abs() < 2e-3, "s {s}: {v} against {want}");
        if s == 0.5 {
            assert!(
                (v - (root + 0.5 * (1.0 - root))).abs() < 1e-6,
                "the rows stay"
            );
        }
    }
    // An upright blade's middle projects high on its chord (a near 1): half the chord's
    // length is well under half of v.
    assert!(chord_v(0.5, 0.9) < 0.35);
    assert_eq!(shape(0.5), 0.5);
    assert_eq!(shape(0.0), 0.0);
    assert_eq!(shape(2.0), 1.0);
}

/// The prairie's blades all drawn at the coarsest level against all at the finest
/// (`culling.lod=false`), `frames` frames with `sets`: the worst band of rows 64-127 (blades
/// in both, far enough to be drawn coarsely by the levels), in levels.
fn coarsest_against_finest(sets: &[&str], frames: usize) -> f64 {
    let size = (240, 136);
    let with = |extra: &[&str]| {
        let all: Vec<&str> = sets
            .iter()
            .chain(&["render.billboard_distance=0"])
            .chain(extra)
            .copied()
            .collect();
        common::prairie_frame(&all, size, frames)
    };
    let finest = with(&["culling.lod=false"]);
    let coarsest = with(&["culling.lod_near_px=4000", "culling.lod_far_px=3000"]);
    let diffs = compare_bands(&coarsest, &finest, 64..128).expect("same size");
    for d in &diffs {
        println!(
            "band {:3}: {:+.2} levels, contrast {:+.0} %",
            d.top,
            d.luminance,
            100.0 * d.contrast
        );
    }
    diffs.iter().map(|d| d.luminance.abs()).fold(0.0, f64::max)
}

/// Without wind the blades stand nearly straight: the coarsest level (two segments, each
/// mapped onto its half of the curve) reads as the finest. Measured 2.9 levels (rows
/// 104-119, the nearest blades, whose curve two straight halves follow less closely than
/// one mapped chord did: 2.1).
#[test]
fn the_coarsest_level_shades_as_the_finest() {
    let still = ["wind.source=Analytic", "wind.directional.strength=0.0"];
    let worst = coarsest_against_finest(&still, 8);
    assert!(
        worst <= 3.2,
        "the coarsest level {worst:.2} levels off the finest"
    );
}

/// With the prairie's wind after 24 frames the blades are bent (their mean shading wave
/// about 0.7): one straight segment cut the corner of each curve and read up to 6.7 levels
/// brighter than the finest mesh (rows 64-79); two segments, 4.2 (measured).
#[test]
fn the_coarsest_level_shades_as_the_finest_in_the_wind() {
    let worst = coarsest_against_finest(&[], 24);
    assert!(
        worst <= 4.7,
        "the coarsest level {worst:.2} levels off the finest in the wind"
    );
}
