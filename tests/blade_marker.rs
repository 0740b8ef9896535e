//! The deferred grass marks the share of each pixel its blades cover in the scene target's
//! alpha (`deferred::BLADE_ALPHA`: 1 + (BLADE_ALPHA − 1) × share, every other lit pass
//! leaving 1), and the far gain's measurement tells the near ring's blades from the cards
//! by it (`far_gain::near_ring_marked`, issue 27, point 1). The marker is held against the
//! frame's own count of the pixels its grass covers (the coverage measurement, an
//! occlusion count of the samples where the grass's depth is the finished depth), with one
//! sample and with 4x MSAA; the forward path, which does not mark, leaves no alpha above 1.

mod common;

use sward::render::deferred::BLADE_ALPHA;
use sward::render::far_gain::{near_ring, near_ring_marked, NEAR_RING, NEAR_RING_MARKED};
use sward::render::work::WorkSummary;
use sward::scene::Scene;
use sward::session::Session;

const SIZE: (u32, u32) = (160, 90);

/// The scene target's alpha per pixel after 2 frames of the default field with `samples`
/// samples, deferred or forward, the pixels the frame's grass covers (its coverage count
/// over the samples) and whether the grass took the deferred path.
fn scene_alpha(samples: u32, deferred: bool) -> (Vec<f32>, u64, bool) {
    let gpu = common::gpu();
    let mut scene = Scene::default();
    scene.render.msaa = samples;
    scene.render.taa = false;
    let session = Session::new(scene, None, Some(&gpu)).expect("field");
    let (mut r, _) = common::draw_frames(&gpu, &session, SIZE, 2, true, |r| {
        r.deferred_grass(deferred)
    });
    let work = r.read_work(&gpu).expect("read").expect("a counted frame");
    let covered = WorkSummary::of(&work, r.samples()).grass_pixels;
    let texels = r.read_scene(&gpu).expect("a frame drawn").expect("read");
    (
        texels.iter().map(|t| t[3]).collect(),
        covered,
        r.grass_deferred(),
    )
}

/// The blades' share of a pixel its alpha tells.
fn share(alpha: f32) -> f32 {
    ((alpha - 1.0) / (BLADE_ALPHA - 1.0)).clamp(0.0, 1.0)
}

#[test]
fn one_sample_deferred_grass_marks_the_pixels_it_lights() {
    let (alpha, covered, took) = scene_alpha(1, true);
    assert!(took, "one sample, filled, specialised: the deferred path");
    let marked = alpha.iter().filter(|&&a| a == BLADE_ALPHA).count() as u64;
    let other = alpha
        .iter()
        .filter(|&&a| a != BLADE_ALPHA && a > 1.0)
        .count();
    println!("marked {marked} pixels, the grass covers {covered}");
    assert!(covered > u64::from(SIZE.0 * SIZE.1) / 4, "grass on screen");
    assert_eq!(other, 0, "a pixel is the grass's or not");
    assert_eq!(
        marked, covered,
        "every pixel the grass covers, and no other"
    );
}

#[test]
fn multisampled_deferred_grass_marks_its_share_of_each_pixel() {
    let (alpha, covered, took) = scene_alpha(4, true);
    assert!(took, "4x MSAA takes the deferred path");
    // Each grass sample adds BLADE_ALPHA, every other 1 (no arrows, no cards here): a
    // quarter of the way per sample.
    for &a in &alpha {
        assert!(
            [1.0, 1.5, 2.0, 2.5, 3.0].contains(&a),
            "alpha {a}: not 1 + (BLADE_ALPHA - 1) k / 4"
        );
    }
    let shares: f64 = alpha.iter().map(|&a| f64::from(share(a))).sum();
    println!("shares sum to {shares:.1} pixels, the grass covers {covered}");
    assert!(covered > u64::from(SIZE.0 * SIZE.1) / 4, "grass on screen");
    assert!(
        (shares - covered as f64).abs() <= 1.0,
        "the marked shares ({shares:.1}) are the covered samples ({covered} pixels)"
    );
}

#[test]
fn forward_grass_leaves_no_marker() {
    let (alpha, covered, took) = scene_alpha(1, false);
    assert!(!took);
    assert!(covered > 0, "grass on screen");
    let above = alpha.iter().filter(|&&a| a > 1.0).count();
    assert_eq!(above, 0, "the forward path marks nothing");
}

/// Where the frame marks its blades the near ring reaches past where the cards begin to
/// fade in (the marker tells them apart); unmarked it ends there. Looking down, both go
/// over to the same ring.
#[test]
fn the_marked_near_ring_reaches_into_the_cards_fade_in() {
    let reach = 28.0;
    let fade_in = sward::render::billboard::fade_in(reach);
    let marked = near_ring_marked(reach, 1.7);
    let unmarked = near_ring(reach, 1.7);
    assert_eq!(
        marked,
        (NEAR_RING_MARKED.0 * reach, NEAR_RING_MARKED.1 * reach)
    );
    assert!(
        unmarked.1 <= fade_in.0 + 1e-4,
        "{unmarked:?} against {fade_in:?}"
    );
    assert!(marked.1 > fade_in.0 && marked.0 > unmarked.0, "{marked:?}");
    assert!(NEAR_RING_MARKED.1 > NEAR_RING.1);
    let (a, b) = (near_ring_marked(reach, 19.0), near_ring(reach, 19.0));
    assert!(
        (a.0 - b.0).abs() < 1e-4 && (a.1 - b.1).abs() < 1e-4,
        "{a:?} {b:?}"
    );
    assert_eq!(near_ring_marked(0.0, 5.0), (0.0, 0.0));
    assert_eq!(
        near_ring_marked(reach, f32::NAN),
        near_ring_marked(reach, 0.0)
    );
}
