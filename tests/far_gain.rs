//! The far levels' calibration on the blades (issue 27, point 1; `render::far_gain`): its
//! WGSL arithmetic against the CPU twin, the rules it follows, and on the prairie the
//! measurement settling. The cards and the far ground just beyond the blades' reach are
//! lit with the gain so far, so a measurement brings them to the blades' ratio to the light
//! model at once and the next ones stay; the cards' texels are shown about their mean with
//! the contrast gain so far, which brings their variation to the blades'.
//!
//! Measured on lavapipe at 240 x 136: the prairie's gain after 4 frames and after 10 within
//! 2.2 % of each other, the contrast gain (2.46, then 2.67) within 8.4 %; the GPU arithmetic
//! within 1e-5 (relative) of the twin.

mod common;

use glam::Vec3;
use sward::render::far_gain::{self, GainPixel, RingSums};

/// How far the gain may move from frame 4 to frame 10 of the prairie: each frame measures
/// other pixels of each grid cell, and the wind moves the blades the near ring measures
/// (measured 2.2 %).
const SETTLED: f32 = 0.06;
/// The same for the contrast gain, which follows how much the gusts make the blades vary
/// (measured 8.4 %; from frame 4 to 60 it wanders between 2.46 and 2.79 without a trend).
const CONTRAST_SETTLED: f32 = 0.15;

/// The linear congruential generator of Numerical Recipes, in [0, 1).
fn lcg(seed: u32) -> impl FnMut() -> f32 {
    let mut s = seed;
    move || {
        s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (s >> 8) as f32 / 16_777_216.0
    }
}

/// `n` far pixels whose radiance is `scale` times the model's, varying by `spread` about
/// it, with fog; then `near` pixels of blades `ratio` times the model's, varying by
/// `near_spread`.
fn pixels(n: usize, seed: u32, scale: f32, spread: f32, near: (usize, f32, f32)) -> Vec<GainPixel> {
    let mut next = lcg(seed);
    let mut pixel = |k: f32, s: f32, near: bool| {
        let model = Vec3::new(next(), next(), next()) + Vec3::splat(0.05);
        let sky = Vec3::new(0.4, 0.5, 0.7) * next();
        let f = 0.4 * next();
        let wobble = 1.0 + s * (2.0 * next() - 1.0);
        GainPixel {
            actual: (model * k * wobble) * (1.0 - f) + sky * f,
            sky,
            f,
            model,
            near,
            standing: true,
        }
    };
    let mut out: Vec<GainPixel> = (0..n).map(|_| pixel(scale, spread, false)).collect();
    out.extend((0..near.0).map(|_| pixel(near.1, near.2, true)));
    out
}

/// `n` far pixels of one model radiance, without fog, varying by `far` about it, and as
/// many near pixels varying by `near`.
fn steady_pixels(n: usize, seed: u32, far: f32, near: f32) -> Vec<GainPixel> {
    let mut next = lcg(seed);
    let model = Vec3::new(0.3, 0.5, 0.2);
    (0..2 * n)
        .map(|i| {
            let spread = if i < n { far } else { near };
            GainPixel {
                actual: model * (1.0 + spread * (2.0 * next() - 1.0)),
                sky: Vec3::ZERO,
                f: 0.0,
                model,
                near: i >= n,
                standing: true,
            }
        })
        .collect()
}

/// The same pixels with the near ones on the ground between blades (not standing on one),
/// but for one in four.
fn on_the_ground(mut pixels: Vec<GainPixel>) -> Vec<GainPixel> {
    for (i, p) in pixels.iter_mut().enumerate() {
        p.standing = !p.near || i % 4 == 0;
    }
    pixels
}

/// The twin's sums, next gain and next contrast gain.
fn twin(
    pixels: &[GainPixel],
    previous: (Vec3, f32),
    contrast: f32,
    blend: f32,
) -> (RingSums, RingSums, (Vec3, f32), f32) {
    let (mut far, mut near) = (RingSums::default(), RingSums::default());
    for p in pixels {
        let terms = far_gain::gain_terms(p.actual, p.sky, p.f, p.model);
        if p.near {
            near.add(terms, p.standing);
        } else {
            far.add(terms, p.standing);
        }
    }
    let next = far_gain::next_gain(&far, &near, previous, blend);
    let n = if previous.1 > 0.5 { previous.1 } else { 0.0 };
    let k = far_gain::next_contrast(&far, &near, contrast, n, blend);
    (far, near, next, k)
}

/// A probe case: its name, pixels, previous gain and measurements, previous contrast gain.
type Case = (&'static str, Vec<GainPixel>, (Vec3, f32), f32);

/// `a` within 1e-5 of `b` relative to its largest component; sums a NaN or an infinity
/// entered match where both are the same non-finite value.
fn close(a: Vec3, b: Vec3, what: &str) {
    let scale = b.abs().max_element().max(1e-3);
    for (x, y) in a.to_array().into_iter().zip(b.to_array()) {
        let same = (x.is_nan() && y.is_nan()) || x == y || (x - y).abs() / scale < 1e-5;
        assert!(same, "{what}: gpu {a} cpu {b}");
    }
}

fn close_sums(a: &RingSums, b: &RingSums, what: &str) {
    close(a.shown, b.shown, what);
    close(a.model, b.model, what);
    assert_eq!(a.count, b.count, "{what}: count");
    assert_eq!(a.standing, b.standing, "{what}: standing");
    close(
        Vec3::new(a.luma, a.luma2, 0.0),
        Vec3::new(b.luma, b.luma2, 0.0),
        what,
    );
}

#[test]
fn the_gpu_far_gain_arithmetic_matches_its_twin() {
    let gpu = common::gpu();
    let mut poisoned = pixels(200, 10, 1.3, 0.1, (120, 1.2, 0.4));
    poisoned[7].actual = Vec3::new(f32::NAN, 0.2, 0.2);
    poisoned[150].actual = Vec3::splat(f32::INFINITY);
    let cases: [Case; 9] = [
        (
            "first measurement, no blades in view",
            pixels(200, 1, 1.3, 0.2, (0, 1.0, 0.0)),
            (Vec3::ONE, 0.0),
            0.0,
        ),
        (
            "first measurement against the blades",
            pixels(200, 5, 1.3, 0.1, (120, 1.2, 0.4)),
            (Vec3::ONE, 0.0),
            0.0,
        ),
        (
            "into a running mean",
            pixels(300, 2, 0.8, 0.3, (80, 0.9, 0.3)),
            (Vec3::new(0.9, 1.1, 0.7), 2.0),
            1.4,
        ),
        (
            "blended once the mean is full",
            pixels(300, 6, 0.8, 0.3, (80, 0.9, 0.3)),
            (Vec3::new(0.9, 1.1, 0.7), 4.0),
            2.0,
        ),
        (
            "too few pixels keep both gains",
            pixels(10, 3, 1.0, 0.2, (5, 1.0, 0.2)),
            (Vec3::splat(0.6), 3.0),
            1.7,
        ),
        (
            "clamped",
            pixels(200, 4, 0.01, 0.0, (50, 1.0, 0.9)),
            (Vec3::ONE, 0.0),
            0.0,
        ),
        ("nothing to measure", Vec::new(), (Vec3::ZERO, 0.0), 0.0),
        (
            "a frame with a NaN and an infinity keeps both gains",
            poisoned,
            (Vec3::splat(0.8), 3.0),
            1.5,
        ),
        (
            "a near ring of bare ground",
            on_the_ground(pixels(200, 8, 1.3, 0.1, (120, 1.2, 0.4))),
            (Vec3::ONE, 0.0),
            0.0,
        ),
    ];
    for (what, px, previous, contrast) in cases {
        let (far, near, next, lit, (k, k_lit)) =
            far_gain::probe(&gpu, &px, previous, contrast, far_gain::BLEND).expect("probe");
        let (tf, tn, tnext, tk) = twin(&px, previous, contrast, far_gain::BLEND);
        close_sums(&far, &tf, what);
        close_sums(&near, &tn, what);
        assert_eq!(next.1, tnext.1, "{what}: measurements");
        close(next.0, tnext.0, what);
        // The far levels light with the gain once measured, with 1 before.
        let expected = if tnext.1 > 0.5 { tnext.0 } else { Vec3::ONE };
        close(lit, expected, what);
        close(Vec3::splat(k), Vec3::splat(tk), what);
        close(
            Vec3::splat(k_lit),
            Vec3::splat(if tk > 0.0 { tk } else { 1.0 }),
            what,
        );
        eprintln!("{what}: gain {} ({}), contrast {k}", next.0, next.1);
    }
}

/// The rules the measurement follows, on the twin.
#[test]
fn the_far_gain_brings_the_far_levels_to_the_blades() {
    let b = far_gain::BLEND;
    // No blades measured: the far pixels shown at `scale` times the model come back by
    // 1 / scale at once.
    let (_, _, first, _) = twin(
        &pixels(200, 1, 1.3, 0.0, (0, 1.0, 0.0)),
        (Vec3::ONE, 0.0),
        0.0,
        b,
    );
    assert!(
        (first.0 - Vec3::splat(1.0 / 1.3)).abs().max_element() < 1e-4,
        "{first:?}"
    );
    assert_eq!(first.1, 1.0);
    // Blades 1.2 times the model: the far levels aim at 1.2 times it.
    let (_, near, aimed, _) = twin(
        &pixels(200, 5, 1.3, 0.0, (120, 1.2, 0.0)),
        (Vec3::ONE, 0.0),
        0.0,
        b,
    );
    assert!(
        (far_gain::blades_ratio(&near) - Vec3::splat(1.2))
            .abs()
            .max_element()
            < 1e-4
    );
    assert!(
        (aimed.0 - Vec3::splat(1.2 / 1.3)).abs().max_element() < 1e-4,
        "{aimed:?}"
    );
    // A near ring where few pixels stand on blades (bare ground) is not taken for blades.
    let (_, near, bare, _) = twin(
        &on_the_ground(pixels(200, 5, 1.3, 0.0, (120, 1.2, 0.0))),
        (Vec3::ONE, 0.0),
        0.0,
        b,
    );
    assert_eq!(far_gain::blades_ratio(&near), Vec3::ONE);
    assert!(
        (bare.0 - Vec3::splat(1.0 / 1.3)).abs().max_element() < 1e-4,
        "{bare:?}"
    );
    // A running mean: the second measurement moves the gain half way, the fifth a quarter.
    let px = pixels(200, 7, 0.5, 0.0, (0, 1.0, 0.0));
    let (_, _, second, _) = twin(&px, (Vec3::ONE, 1.0), 0.0, b);
    assert!(
        (second.0 - Vec3::splat(1.5)).abs().max_element() < 1e-4,
        "{second:?}"
    );
    let (_, _, fifth, _) = twin(&px, (Vec3::ONE, 4.0), 0.0, b);
    assert!(
        (fifth.0 - Vec3::splat(1.25)).abs().max_element() < 1e-4,
        "{fifth:?}"
    );
    assert_eq!(fifth.1, 4.0, "the mean stops growing at 1 / blend");
    // Too few pixels keep the gain; the range holds.
    let (_, _, kept, _) = twin(
        &pixels(10, 3, 1.0, 0.0, (0, 1.0, 0.0)),
        (Vec3::splat(0.6), 2.0),
        0.0,
        b,
    );
    assert_eq!(kept, (Vec3::splat(0.6), 2.0));
    let (_, _, clamped, _) = twin(
        &pixels(200, 4, 0.01, 0.0, (0, 1.0, 0.0)),
        (Vec3::ONE, 0.0),
        0.0,
        b,
    );
    assert_eq!(clamped.0, Vec3::splat(far_gain::GAIN_RANGE.1));
    // Cards that vary half as much as the blades about their mean: the contrast gain
    // doubles (the first measurement taken as it is).
    let px = steady_pixels(4000, 9, 0.2, 0.4);
    let (far, near, _, k) = twin(&px, (Vec3::ONE, 0.0), 0.0, b);
    let want = near.variation() / far.variation();
    assert!((want - 2.0).abs() < 0.15, "variation ratio {want}");
    assert!((k - want).abs() < 1e-5, "contrast gain {k} against {want}");
    // A frame with an infinite pixel measures nothing; a NaN pixel reads as black.
    let clean = pixels(200, 10, 1.3, 0.1, (120, 1.2, 0.4));
    let mut px = clean.clone();
    px[7].actual = Vec3::splat(f32::INFINITY);
    let (_, _, kept_inf, k_inf) = twin(&px, (Vec3::splat(0.8), 3.0), 1.5, b);
    assert_eq!((kept_inf, k_inf), ((Vec3::splat(0.8), 3.0), 1.5));
    let (mut nan, mut black) = (clean.clone(), clean);
    nan[7].actual = Vec3::splat(f32::NAN);
    black[7].actual = Vec3::ZERO;
    black[7].f = 0.0;
    nan[7].f = 0.0;
    let (_, _, g_nan, _) = twin(&nan, (Vec3::splat(0.8), 3.0), 1.5, b);
    let (_, _, g_black, _) = twin(&black, (Vec3::splat(0.8), 3.0), 1.5, b);
    assert!(
        g_nan.0.is_finite() && g_nan == g_black,
        "{g_nan:?} against {g_black:?}"
    );
    // No blades in view: the contrast gain is kept.
    let (_, _, _, kept) = twin(
        &pixels(200, 9, 1.0, 0.2, (0, 1.0, 0.0)),
        (Vec3::ONE, 2.0),
        1.7,
        b,
    );
    assert_eq!(kept, 1.7);
}

#[test]
fn the_prairies_far_calibration_settles() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/prairie.ron");
    let scene = sward::scene::load_scene(&path).expect("prairie");
    let gpu = common::gpu();
    let session = sward::session::Session::new(scene, None, Some(&gpu)).expect("field");
    let mut r = common::world(&gpu, &session);
    let camera = sward::render::camera::CameraView::from_scene(&session.scene.camera);
    let target = sward::render::target::Target::new(&gpu, 240, 136).expect("target");
    assert_eq!(
        r.far_gain(&gpu).expect("read"),
        None,
        "measured before any frame"
    );
    assert_eq!(r.far_calibration(&gpu).expect("read"), (Vec3::ONE, 1.0));
    let mut seen = Vec::new();
    for frame in 1..=10 {
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
        if frame == 4 || frame == 10 {
            let gain = r.far_gain(&gpu).expect("read").expect("measured");
            let (ratio, contrast) = r.far_calibration(&gpu).expect("read");
            seen.push((gain, ratio, contrast));
        }
    }
    let ((g4, r4, k4), (g10, r10, k10)) = (seen[0], seen[1]);
    eprintln!("after 4 frames: gain {g4}, blades {r4}, contrast {k4}");
    eprintln!("after 10 frames: gain {g10}, blades {r10}, contrast {k10}");
    let drift = ((g10 - g4) / g4).abs().max_element();
    assert!(drift < SETTLED, "the gain drifts: {g4} -> {g10}");
    let drift = ((k10 - k4) / k4).abs();
    assert!(
        drift < CONTRAST_SETTLED,
        "the contrast gain drifts: {k4} -> {k10}"
    );
    let (lo, hi) = far_gain::GAIN_RANGE;
    assert!(
        g10.min_element() > lo && g10.max_element() < hi,
        "the gain ran to its clamp: {g10}"
    );
    let (lo, hi) = far_gain::CONTRAST_RANGE;
    assert!(
        k10 > lo && k10 < hi,
        "the contrast gain ran to its clamp: {k10}"
    );
    // The blades were measured (a ratio that is not the default).
    assert!(r10 != Vec3::ONE, "no blades measured");
}
