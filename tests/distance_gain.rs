//! The far field's distance gain (issue 27, point 1; `render::far_gain::distance_gain`):
//! its WGSL arithmetic against the CPU twin, the rules it follows (the ring lit with the
//! light gain alone, the field's multiplier beyond the ramp, nothing from an unmeasured,
//! non-finite or reachless frame), and the field brought to the ring's aim by repeated
//! measurements, also when part of its pixels do not answer the gain.
//!
//! Measured on lavapipe: the GPU values within 1e-6 (relative) of the twin.

mod common;

use sward::render::far_gain::{
    self, distance_gain, next_distance_gain, DISTANCE_GAIN_RANGE, FAR_BIN, FAR_RAMP, RING,
};

const REACH: f32 = 28.0;

#[test]
fn the_gpu_distance_gains_match_their_twin() {
    let gpu = common::gpu();
    let mut points = Vec::new();
    for i in 0..=80 {
        let d = REACH * i as f32 / 16.0;
        points.push((
            [d, REACH, 0.8, 0.0],
            [1.0, 1.2, 40.0, 1.1],
            [1.1, 2.0, 0.25],
        ));
        points.push((
            [d, REACH, 0.0, 0.0],
            [2.0, 1.0, 15.0, 0.9],
            [0.0, 0.0, 0.25],
        ));
        points.push((
            [d, REACH, 1.3, 0.0],
            [2.0, 1.0, 16.0, 0.9],
            [1.3, 1.0, 0.25],
        ));
    }
    let odd = [
        (
            [10.0, f32::INFINITY, 0.8, 0.0],
            [f32::NAN, 1.0, 40.0, 1.0],
            [1.2, 4.0, 0.25],
        ),
        (
            [10.0, 0.0, 0.8, 0.0],
            [1.0, 1.0, 40.0, 0.0],
            [1.2, 4.0, 0.25],
        ),
        (
            [f32::INFINITY, REACH, 0.8, 0.0],
            [1e-3, 10.0, 40.0, 1.0],
            [1.0, 4.0, 0.25],
        ),
        (
            [60.0, REACH, 0.8, 0.0],
            [10.0, 1e-3, 40.0, 1.0],
            [1.0, 4.0, 1.0],
        ),
        (
            [60.0, REACH, 0.8, 0.0],
            [1.0, 1.0, 40.0, f32::INFINITY],
            [1.0, 0.0, 1.0],
        ),
    ];
    points.extend_from_slice(&odd);
    let gpu_values = far_gain::distance_probe(&gpu, &points).expect("probe");
    for (p, &(g, next)) in points.iter().zip(&gpu_values) {
        let (a, s, q) = p;
        let tg = distance_gain(a[0], a[1], a[2]);
        let tn = next_distance_gain((s[0], s[1], s[2]), s[3], q[0], q[1], q[2]);
        assert!(
            (g - tg).abs() <= 1e-6 * tg.abs().max(1.0),
            "{p:?}: gain gpu {g} cpu {tg}"
        );
        assert!(
            (next - tn).abs() <= 1e-6 * tn.abs().max(1.0),
            "{p:?}: next gpu {next} cpu {tn}"
        );
    }
}

#[test]
fn the_ring_is_lit_with_the_light_gain_alone() {
    for f in [0.8, 1.3] {
        // Over the ring and up to the ramp the multiplier is 1 exactly: the ring's pixels
        // answer the light gain alone, which the field is measured against.
        for i in 0..=50 {
            let d = REACH * (FAR_RAMP.0 * i as f32 / 50.0);
            assert_eq!(distance_gain(d, REACH, f), 1.0, "at {d} m");
        }
        assert!(FAR_RAMP.0 >= RING.1, "the ramp starts past the ring");
        // The field is lit with its own multiplier all through its bin, and beyond.
        for i in 0..=40 {
            let d = REACH * (FAR_BIN.0 + (2.0 * FAR_BIN.1 - FAR_BIN.0) * i as f32 / 40.0);
            assert_eq!(distance_gain(d, REACH, f), f, "far field at {d} m");
        }
        // Between, it moves one way, without a step.
        let mut last = 1.0;
        for i in 0..=2000 {
            let d = REACH * 2.5 * i as f32 / 2000.0;
            let g = distance_gain(d, REACH, f);
            assert!((g - last).abs() < 0.01, "a step at {d} m: {last} -> {g}");
            assert!(
                (g - last) * (f - 1.0) >= 0.0,
                "one way at {d} m: {last} -> {g}"
            );
            last = g;
        }
    }
    // Unmeasured (0) is 1; no reach, or a non-finite one or distance, is 1.
    assert_eq!(distance_gain(100.0, REACH, 0.0), 1.0);
    for (d, r) in [
        (100.0, 0.0),
        (100.0, f32::INFINITY),
        (f32::NAN, REACH),
        (100.0, f32::NAN),
    ] {
        assert_eq!(distance_gain(d, r, 1.3), 1.0, "distance {d}, reach {r}");
    }
}

#[test]
fn the_far_field_is_brought_to_the_rings_aim() {
    let blend = far_gain::BLEND;
    // The ring needs 1.25 times what it shows; the field, lit with the multiplier m, shows
    // m times 0.9 of its model: it needs 1 / 0.9 of it, m = (1 / 0.9) / 1.25.
    let ring_need = 1.25;
    let (lo, hi) = DISTANCE_GAIN_RANGE;
    let aim: f32 = 1.0 / 0.9 / ring_need;
    assert!(aim > lo && aim < hi);
    let mut m = 0.0;
    for n in 0..40 {
        let shown = if m > 0.0 { m } else { 1.0 } * 0.9 * 100.0;
        m = next_distance_gain((shown, 100.0, 64.0), ring_need, m, n as f32, blend);
    }
    assert!((m - aim).abs() < 1e-3 * aim, "settled at {m}, aim {aim}");

    // Half the field's pixels do not answer the gain (the sky's haze, a mesh), reading as
    // the ring's aim asks: the other half alone moves with the multiplier, so each step
    // corrects part of the gap, and the field still comes to its aim, from above.
    let blades = 0.5 * 100.0 / ring_need;
    let cards = 0.5 * 0.9;
    let want = (100.0 / ring_need - blades) / (cards * 100.0);
    assert!(want > lo && want < hi);
    let mut m = 0.0;
    for n in 0..200 {
        let lit = if m > 0.0 { m } else { 1.0 };
        let shown = blades + lit * cards * 100.0;
        let next = next_distance_gain((shown, 100.0, 64.0), ring_need, m, n as f32, blend);
        assert!(next >= want - 1e-4, "beyond the aim: {next} < {want}");
        m = next;
    }
    assert!((m - want).abs() < 1e-3 * want, "settled at {m}, aim {want}");

    // Far off: held at the range's bounds.
    let dark = next_distance_gain((1.0, 100.0, 64.0), 1.0, 1.0, 0.0, 1.0);
    assert_eq!(dark, hi);
    let bright = next_distance_gain((100.0, 1.0, 64.0), 1.0, 1.0, 0.0, 1.0);
    assert_eq!(bright, lo);
}

/// The far field may be darkened, never brightened, past the ring (the range's top is 1):
/// the blades' own ratio to the light model falls with distance (the prairie unthinned,
/// after 64 frames, luminance: 1.22, 1.18, 1.16 at 10-14, 14-20 and 17.5-25 m with wind,
/// 0.85, 0.83, 0.78 without), so cards and ground that read darker against the model
/// than the ring are doing what the blades do. Brought up to the ring's (1.10 on the
/// prairie with wind, 1.07 without), the horizon's band read +9.5 levels against blades
/// to 50 m.
#[test]
fn the_far_field_is_never_lit_above_the_ring() {
    assert_eq!(DISTANCE_GAIN_RANGE.1, 1.0);
    // A field reading half of what the ring needs, however often measured, stays at 1.
    let mut m = 0.0;
    for n in 0..20 {
        let shown = if m > 0.0 { m } else { 1.0 } * 50.0;
        m = next_distance_gain((shown, 100.0, 64.0), 1.0, m, n as f32, far_gain::BLEND);
        assert!(m <= 1.0, "brightened to {m}");
    }
    assert_eq!(m, 1.0);
}

#[test]
fn the_far_field_without_a_measurement_keeps_its_gain() {
    let keep = 1.17;
    let cases = [
        ((50.0, 60.0, 10.0), 1.0, "too few pixels"),
        ((0.0, 60.0, 64.0), 1.0, "nothing shown"),
        ((50.0, 0.0, 64.0), 1.0, "no model"),
        ((50.0, 60.0, 64.0), 0.0, "the ring unmeasured"),
        ((f32::NAN, 60.0, 64.0), 1.0, "a NaN shown"),
        ((50.0, f32::INFINITY, 64.0), 1.0, "an infinite model"),
        ((50.0, 60.0, 64.0), f32::INFINITY, "an infinite ring"),
    ];
    for (sums, ring, what) in cases {
        assert_eq!(
            next_distance_gain(sums, ring, keep, 4.0, 0.25),
            keep,
            "{what}"
        );
    }
}
