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

use glam::{Vec2, Vec3};
use sward::render::far_gain::{self, GainPixel, RingSums};

/// The frames of the prairie compared: once the gusts have built up from the still start
/// (the blades' ratio to the model, measured on the blades alone, rises from 1.1 at frame
/// 4 to 1.3-1.4 by frame 30 as they bend, and the gain follows). Measured with the grid of
/// 128 × 64 samples: gain (green) 0.83 at frame 20, still rising, then 0.89, 0.90, 0.89
/// and 0.90 at frames 30, 40, 60 and 80. (With 64 × 32 samples the near ring's ratio
/// wandered by ±12 % from frame to frame, 1.48 at frame 20 and 1.31 at 40, and frame 20
/// happened to read as settled.) Since the coarsest level has two segments (the near ring's
/// blades are drawn at it at 240 × 136), its blades follow their bend as the finest do and
/// brighten on until the gusts have built up: gain (green) 0.96, 1.02 and 1.00 at frames 30,
/// 60 and 90, and 6-7 % of drift between 30 and 60 (1.9-2.8 % between 60 and 90).
const SETTLE_FRAMES: (u32, u32) = (60, 90);
/// How far the gain may move between them: each frame measures other pixels of each grid
/// cell, and the wind moves the blades the near ring measures (measured 0.2 % in green,
/// 2.7 % in blue).
const SETTLED: f32 = 0.06;
/// The same for the contrast gain, which follows how much the gusts make the blades vary
/// (measured 9 %; from frame 20 to 60 it wanders between 2.99 and 3.36).
const CONTRAST_SETTLED: f32 = 0.15;

/// The linear congruential generator of Numerical Recipes, in [0, 1).
fn lcg(seed: u32) -> impl FnMut() -> f32 {
    let mut s = seed;
    move || {
        s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (s >> 8) as f32 / 16_777_216.0
    }
}

/// The luminance sums of a block of `far_gain::CONTRAST_BLOCK`² texels (`GainPixel::block`)
/// around a pixel of radiance `actual`, its texels varying by `spread` about it.
fn block(actual: Vec3, spread: f32, next: &mut impl FnMut() -> f32) -> Vec2 {
    let l = actual.dot(far_gain::LUMA);
    (0..far_gain::CONTRAST_BLOCK * far_gain::CONTRAST_BLOCK).fold(Vec2::ZERO, |sum, _| {
        let t = l * (1.0 + spread * (2.0 * next() - 1.0));
        sum + Vec2::new(t, t * t)
    })
}

/// `n` far pixels whose radiance is `scale` times the model's, varying by `spread` about
/// it (and within their blocks), with fog; then `near` pixels of blades `ratio` times the
/// model's, varying by `near_spread`.
fn pixels(n: usize, seed: u32, scale: f32, spread: f32, near: (usize, f32, f32)) -> Vec<GainPixel> {
    let mut next = lcg(seed);
    let mut pixel = |k: f32, s: f32, near: bool| {
        let model = Vec3::new(next(), next(), next()) + Vec3::splat(0.05);
        let sky = Vec3::new(0.4, 0.5, 0.7) * next();
        let f = 0.4 * next();
        let wobble = 1.0 + s * (2.0 * next() - 1.0);
        let actual = (model * k * wobble) * (1.0 - f) + sky * f;
        GainPixel {
            actual,
            sky,
            f,
            model,
            near,
            standing: true,
            block: block(actual, s, &mut next),
        }
    };
    let mut out: Vec<GainPixel> = (0..n).map(|_| pixel(scale, spread, false)).collect();
    out.extend((0..near.0).map(|_| pixel(near.1, near.2, true)));
    out
}

/// `n` far pixels of one model radiance, without fog, varying by `far` about it (and
/// within their blocks), and as many near pixels varying by `near`.
fn steady_pixels(n: usize, seed: u32, far: f32, near: f32) -> Vec<GainPixel> {
    let mut next = lcg(seed);
    let model = Vec3::new(0.3, 0.5, 0.2);
    (0..2 * n)
        .map(|i| {
            let spread = if i < n { far } else { near };
            let actual = model * (1.0 + spread * (2.0 * next() - 1.0));
            GainPixel {
                actual,
                sky: Vec3::ZERO,
                f: 0.0,
                model,
                near: i >= n,
                standing: true,
                block: block(actual, spread, &mut next),
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

/// The same pixels with one near pixel in four on the soil between the blades, showing
/// `soil` times the model (dark soil, or ground lit with the gain), and every far pixel
/// flagged as on the ground (the far ring measures cards and ground alike).
fn soil_between(mut pixels: Vec<GainPixel>, soil: f32) -> Vec<GainPixel> {
    for (i, p) in pixels.iter_mut().enumerate() {
        if !p.near {
            p.standing = i % 2 == 0;
        } else if i % 4 == 1 {
            p.standing = false;
            p.actual = p.model * soil * (1.0 - p.f) + p.sky * p.f;
        }
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
            near.add(terms, p.contrast(), p.standing);
        } else {
            far.add(terms, p.contrast(), true);
        }
    }
    let next = far_gain::next_gain(&far, &near, previous, blend);
    let n = if previous.1 > 0.5 { previous.1 } else { 0.0 };
    let k = far_gain::next_contrast(&far, &near, contrast, n, blend);
    (far, near, next, k)
}

/// The twin's next running mean of the blades' ratio, from `ratio` before, over the
/// measurements the gain averaged before (`previous.1`).
fn twin_mean(pixels: &[GainPixel], previous: (Vec3, f32), ratio: Vec3, blend: f32) -> Vec3 {
    let (_, near, _, _) = twin(pixels, previous, 0.0, blend);
    let n = if previous.1 > 0.5 { previous.1 } else { 0.0 };
    far_gain::next_blades_mean(&near, ratio, n, blend)
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
    assert_eq!(a.pixels, b.pixels, "{what}: pixels");
    close(Vec3::splat(a.contrast), Vec3::splat(b.contrast), what);
}

#[test]
fn the_gpu_far_gain_arithmetic_matches_its_twin() {
    let gpu = common::gpu();
    let mut poisoned = pixels(200, 10, 1.3, 0.1, (120, 1.2, 0.4));
    poisoned[7].actual = Vec3::new(f32::NAN, 0.2, 0.2);
    poisoned[150].actual = Vec3::splat(f32::INFINITY);
    // Their blocks hold them too.
    poisoned[7].block = Vec2::splat(f32::NAN);
    poisoned[150].block = Vec2::splat(f32::INFINITY);
    let cases: [Case; 10] = [
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
        (
            "blades with soil between them",
            soil_between(pixels(200, 9, 1.3, 0.1, (120, 1.2, 0.4)), 0.3),
            (Vec3::new(0.9, 1.0, 0.8), 4.0),
            2.5,
        ),
    ];
    for (what, px, previous, contrast) in cases {
        // The blades' running mean before: none before the first measurement.
        let ratio = if previous.1 > 0.5 {
            Vec3::new(1.15, 1.0, 0.85)
        } else {
            Vec3::ZERO
        };
        let (far, near, next, lit, (k, k_lit), mean) =
            far_gain::probe(&gpu, &px, previous, contrast, ratio, far_gain::BLEND).expect("probe");
        let (tf, tn, tnext, tk) = twin(&px, previous, contrast, far_gain::BLEND);
        close(mean, twin_mean(&px, previous, ratio, far_gain::BLEND), what);
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
    // The ratio the panel shows is averaged over the frames as the gain averages its aims:
    // the first measurement taken as it is, the second moves it half way, the fifth a
    // quarter.
    let mean = |previous: Vec3, n: f32| far_gain::next_blades_mean(&near, previous, n, b);
    for (previous, n, expected) in [
        (Vec3::ZERO, 0.0, 1.2),
        (Vec3::ONE, 1.0, 1.1),
        (Vec3::ONE, 4.0, 1.05),
    ] {
        let m = mean(previous, n);
        assert!(
            (m - Vec3::splat(expected)).abs().max_element() < 1e-4,
            "from {previous} after {n}: {m}"
        );
    }
    // The soil between the near blades (dark, or lit with the gain as the far ground is)
    // is not measured: the ratio and the contrast are the blades' alone.
    let with_soil = twin(
        &pixels(200, 5, 1.3, 0.0, (120, 1.2, 0.2)),
        (Vec3::ONE, 0.0),
        0.0,
        b,
    );
    for soil in [0.05, 3.0] {
        let (_, near, aimed, _) = twin(
            &soil_between(pixels(200, 5, 1.3, 0.0, (120, 1.2, 0.0)), soil),
            (Vec3::ONE, 0.0),
            0.0,
            b,
        );
        assert_eq!((near.count, near.pixels), (90.0, 120.0), "soil {soil}");
        assert!(
            (far_gain::blades_ratio(&near) - Vec3::splat(1.2))
                .abs()
                .max_element()
                < 1e-4,
            "soil {soil}: {near:?}"
        );
        assert!(
            (aimed.0 - Vec3::splat(1.2 / 1.3)).abs().max_element() < 1e-4,
            "soil {soil}: {aimed:?}"
        );
        let (_, _, _, k) = twin(
            &soil_between(pixels(200, 5, 1.3, 0.0, (120, 1.2, 0.2)), soil),
            (Vec3::ONE, 0.0),
            0.0,
            b,
        );
        // The contrast is that of the standing pixels: within the spread of a sample of
        // 90 against 120 of the same blades (measured 3 %), not the soil's (many times).
        assert!(
            (k / with_soil.3 - 1.0).abs() < 0.1,
            "soil {soil}: {k} against {}",
            with_soil.3
        );
    }
    // A near ring where few pixels stand on blades (bare ground) is not taken for blades.
    let (_, near, bare, _) = twin(
        &on_the_ground(pixels(200, 5, 1.3, 0.0, (120, 1.2, 0.0))),
        (Vec3::ONE, 0.0),
        0.0,
        b,
    );
    assert_eq!(far_gain::blades_ratio(&near), Vec3::ONE);
    // ... nor does it move the blades' running mean towards 1.
    assert_eq!(
        far_gain::next_blades_mean(&near, Vec3::splat(0.9), 3.0, b),
        Vec3::splat(0.9)
    );
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
    // Cards that vary half as much as the blades between neighbouring pixels: the
    // contrast gain doubles (the first measurement taken as it is).
    let px = steady_pixels(4000, 9, 0.2, 0.4);
    let (far, near, _, k) = twin(&px, (Vec3::ONE, 0.0), 0.0, b);
    let want = near.local_contrast() / far.local_contrast();
    assert!((want - 2.0).abs() < 0.15, "variation ratio {want}");
    assert!((k - want).abs() < 1e-5, "contrast gain {k} against {want}");
    // A frame with an infinite pixel measures nothing; a NaN pixel reads as black.
    let clean = pixels(200, 10, 1.3, 0.1, (120, 1.2, 0.4));
    let mut px = clean.clone();
    px[7].actual = Vec3::splat(f32::INFINITY);
    px[7].block = Vec2::splat(f32::INFINITY);
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
    let scene = common::prairie_scene(&[]);
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
    assert_eq!(
        r.far_calibration(&gpu).expect("read"),
        far_gain::FarCalibration::default()
    );
    let mut seen = Vec::new();
    for frame in 1..=SETTLE_FRAMES.1 {
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
        if frame == SETTLE_FRAMES.0 || frame == SETTLE_FRAMES.1 {
            let gain = r.far_gain(&gpu).expect("read").expect("measured");
            let c = r.far_calibration(&gpu).expect("read");
            let (ratio, contrast) = (c.ratio, c.contrast);
            seen.push((gain, ratio, contrast));
        }
    }
    let ((g0, r0, k0), (g1, r1, k1)) = (seen[0], seen[1]);
    let (a, b) = SETTLE_FRAMES;
    eprintln!("after {a} frames: gain {g0}, blades {r0}, contrast {k0}");
    eprintln!("after {b} frames: gain {g1}, blades {r1}, contrast {k1}");
    let drift = ((g1 - g0) / g0).abs().max_element();
    assert!(drift < SETTLED, "the gain drifts: {g0} -> {g1}");
    let drift = ((k1 - k0) / k0).abs();
    assert!(
        drift < CONTRAST_SETTLED,
        "the contrast gain drifts: {k0} -> {k1}"
    );
    let (lo, hi) = far_gain::GAIN_RANGE;
    assert!(
        g1.min_element() > lo && g1.max_element() < hi,
        "the gain ran to its clamp: {g1}"
    );
    let (lo, hi) = far_gain::CONTRAST_RANGE;
    assert!(
        k1 > lo && k1 < hi,
        "the contrast gain ran to its clamp: {k1}"
    );
    // The blades were measured (a ratio that is not the default).
    assert!(r1 != Vec3::ONE, "no blades measured");
    // The gusts' bend shown is the cull's count of this frame (its two words, which the far
    // levels' shading waves read), and the prairie's gusts bend its blades.
    let bend = r.far_calibration(&gpu).expect("read").bend;
    let counted = r.stats(&gpu).expect("stats").counters;
    assert!(
        counted.wave_blades > 0,
        "no blades counted at the reach's edge"
    );
    let expected =
        counted.wave_sum as f32 / (sward::sim::layout::WAVE_QUANTA * counted.wave_blades as f32);
    assert_eq!(bend, expected, "the bend shown is not the cull's count");
    assert!(
        bend > 0.1 && bend <= 1.0,
        "the prairie's gusts bend its blades: {bend}"
    );
}

/// The cards' contrast curve: the GPU's against its twin, and what it promises — the line
/// about the card's mean (which keeps the mean) down to its floor, never black under it,
/// no kink where they meet, and rising everywhere.
#[test]
fn the_cards_contrast_never_goes_below_black() {
    let gpu = common::gpu();
    let mut points = Vec::new();
    for &k in &[0.5f32, 1.0, 2.5, 4.0] {
        for &m in &[0.02f32, 0.3, 1.7] {
            for i in 0..=40 {
                points.push((m * i as f32 / 16.0, m, k));
            }
        }
    }
    points.push((0.5, 0.0, 4.0));
    points.push((-1.0, 0.3, 4.0));
    let gpu_values = far_gain::contrast_probe(&gpu, &points).expect("probe");
    for (&(l, m, k), &g) in points.iter().zip(&gpu_values) {
        let t = far_gain::contrast_luma(l, m, k);
        assert!(
            (g - t).abs() <= 1e-5 * t.abs().max(m).max(1e-3),
            "({l}, {m}, {k}): gpu {g} cpu {t}"
        );
        assert!(
            t.is_finite() && (t > 0.0 || m == 0.0),
            "({l}, {m}, {k}): {t}"
        );
        let line = m + k * (l - m);
        if line >= far_gain::CONTRAST_FLOOR * m {
            assert_eq!(t, line, "the line above the floor");
        }
    }
    for &k in &[0.5f32, 2.5, 4.0] {
        let m = 0.3;
        // Where the line meets the floor: the same slope on both sides.
        let joint = m - (1.0 - far_gain::CONTRAST_FLOOR) * m / k;
        let h = 1e-4 * m;
        let slope = |a: f32, b: f32| {
            (far_gain::contrast_luma(b, m, k) - far_gain::contrast_luma(a, m, k)) / (b - a)
        };
        assert!(
            (slope(joint - h, joint) / k - 1.0).abs() < 0.02,
            "kink at gain {k}"
        );
        assert!(
            (slope(joint, joint + h) / k - 1.0).abs() < 0.02,
            "kink at gain {k}"
        );
        let mut last = 0.0;
        for i in 0..=100 {
            let v = far_gain::contrast_luma(m * i as f32 / 50.0, m, k);
            assert!(v > last, "rising at gain {k}");
            last = v;
        }
    }
}
