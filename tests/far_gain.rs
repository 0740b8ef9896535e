//! The far levels' light gain (issue 27, point 1; `render::far_gain`): its WGSL arithmetic
//! against the CPU twin, and on the prairie the measurement settling: the cards and the far
//! ground just beyond the blades' reach are lit with the gain so far, so one measurement
//! brings them to the blades' light model and the next ones stay. Were the gain not applied
//! to the far levels, each frame would measure the same correction and the gain would keep
//! moving by a quarter of it per frame.
//!
//! Measured on lavapipe at 240 x 136: the prairie's gain after 4 frames (0.89, 0.91, 0.89),
//! after 10 within 1 % of it; the GPU arithmetic within 1e-5 (relative) of the twin.

mod common;

use glam::Vec3;
use sward::render::far_gain::{self, GainPixel};

/// `n` pixels whose radiance is `scale` times the model's, with fog (the linear
/// congruential generator of Numerical Recipes).
fn pixels(n: usize, seed: u32, scale: f32) -> Vec<GainPixel> {
    let mut s = seed;
    let mut next = || {
        s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (s >> 8) as f32 / 16_777_216.0
    };
    (0..n)
        .map(|_| {
            let model = Vec3::new(next(), next(), next()) + Vec3::splat(0.05);
            let sky = Vec3::new(0.4, 0.5, 0.7) * next();
            let f = 0.4 * next();
            GainPixel {
                actual: (model * scale) * (1.0 - f) + sky * f,
                sky,
                f,
                model,
            }
        })
        .collect()
}

fn twin(pixels: &[GainPixel], previous: (Vec3, bool), blend: f32) -> (Vec3, Vec3, (Vec3, bool)) {
    let (mut shown, mut model) = (Vec3::ZERO, Vec3::ZERO);
    for p in pixels {
        let (s, m) = far_gain::gain_terms(p.actual, p.sky, p.f, p.model);
        shown += s;
        model += m;
    }
    let next = far_gain::next_gain(shown, model, pixels.len() as f32, previous, blend);
    (shown, model, next)
}

fn close(a: Vec3, b: Vec3, what: &str) {
    let d = (a - b).abs().max_element() / b.abs().max_element().max(1e-3);
    assert!(d < 1e-5, "{what}: gpu {a} cpu {b}");
}

#[test]
fn the_gpu_far_gain_arithmetic_matches_its_twin() {
    let gpu = common::gpu();
    let cases: [(&str, Vec<GainPixel>, (Vec3, bool)); 5] = [
        ("first measurement", pixels(200, 1, 1.3), (Vec3::ONE, false)),
        (
            "blended into a measured gain",
            pixels(300, 2, 0.8),
            (Vec3::new(0.9, 1.1, 0.7), true),
        ),
        (
            "too few pixels keep the gain",
            pixels(10, 3, 1.0),
            (Vec3::splat(0.6), true),
        ),
        ("clamped", pixels(200, 4, 0.01), (Vec3::ONE, false)),
        ("nothing to measure", Vec::new(), (Vec3::ZERO, false)),
    ];
    for (what, px, previous) in cases {
        let (shown, model, next, lit) =
            far_gain::probe(&gpu, &px, previous, far_gain::BLEND).expect("probe");
        let (ts, tm, tnext) = twin(&px, previous, far_gain::BLEND);
        close(shown, ts, what);
        close(model, tm, what);
        assert_eq!(next.1, tnext.1, "{what}: measured");
        close(next.0, tnext.0, what);
        // The far levels light with the gain once measured, with 1 before.
        let expected = if tnext.1 { tnext.0 } else { Vec3::ONE };
        close(lit, expected, what);
        eprintln!("{what}: gain {} ({})", next.0, next.1);
    }
    // The rules the cases rely on: pixels shown at `scale` times the model are brought back
    // by 1 / scale at once; too few keep the gain; the range holds.
    let (_, _, first) = twin(&pixels(200, 1, 1.3), (Vec3::ONE, false), far_gain::BLEND);
    assert!(
        (first.0 - Vec3::splat(1.0 / 1.3)).abs().max_element() < 1e-4,
        "{first:?}"
    );
    let (_, _, kept) = twin(
        &pixels(10, 3, 1.0),
        (Vec3::splat(0.6), true),
        far_gain::BLEND,
    );
    assert_eq!(kept, (Vec3::splat(0.6), true));
    let (_, _, clamped) = twin(&pixels(200, 4, 0.01), (Vec3::ONE, false), far_gain::BLEND);
    assert_eq!(clamped.0, Vec3::splat(far_gain::GAIN_RANGE.1));
}

#[test]
fn the_prairies_far_gain_settles() {
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
    let mut gains = Vec::new();
    for frame in 1..=10 {
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
        if frame == 4 || frame == 10 {
            gains.push(r.far_gain(&gpu).expect("read").expect("measured"));
        }
    }
    let (early, late) = (gains[0], gains[1]);
    eprintln!("far gain after 4 frames {early}, after 10 {late}");
    let drift = ((late - early) / early).abs().max_element();
    assert!(drift < 0.02, "the gain drifts: {early} -> {late}");
    let (lo, hi) = far_gain::GAIN_RANGE;
    assert!(
        late.min_element() > lo && late.max_element() < hi,
        "the gain ran to its clamp: {late}"
    );
}
