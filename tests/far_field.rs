//! The levels that stand for the blades far away (issue 27, point 1): the prairie as it
//! ships (blades to 28 m, thinned by Eq. 20, then billboards, then the far ground) against
//! the same frame with blades out to 50 m and no thinning, compared in bands of 8 rows
//! (`compare::compare_bands`: mean luminance and 8 × 8 block contrast).
//!
//! The target is 5 levels and 30 % in every band. What holds today, and is held
//! here so that it cannot slide back (measured at 240 × 136 and 480 × 270):
//! - the far ground at the horizon, where both frames show it, within 5 levels: the
//!   billboards and the far ground are lit alike (`far_grass.wgsl`);
//! - every band within 8 levels (3.8 measured here; at 480 × 270 the cards are up to 13.5
//!   levels too bright after these 4 frames, while the reference's far blades settle, and
//!   within 7.4 after 30; they were 60 levels darker before they and the far ground took
//!   the blades' light);
//! - the thinned near field within the 5 levels and 30 % (1.9 levels and 7 %
//!   measured: the kept blades widen, `thinning_widen`, and keep the shape the full
//!   field's thinner blades have).
//!
//! Both frames light the blades forward (`render.deferred_grass = false`), as the cards were
//! calibrated against: with the prairie's 4x MSAA a forward fragment is lit at its pixel's
//! centre even where a sub-pixel blade covers only an edge sample, so the blades at 28-50 m
//! read about 20 levels brighter than with one sample, 2 x 2 or 4 x 4 supersampling, or the
//! deferred MSAA light (band 48 here: 148.8 forward, 124.7 deferred, 123.8 with one
//! sample). Against those the cards in that ring are up to 26 levels too bright: issue 27,
//! point 1, is open on it.

mod common;

use sward::compare::{bands, compare_bands, worst_band};

const SIZE: (u32, u32) = (240, 136);
const FRAMES: usize = 4;

fn prairie(sets: &[&str]) -> image::RgbaImage {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/prairie.ron");
    let mut sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    // The reference the cards were calibrated against (see above).
    sets.push("render.deferred_grass=false".into());
    let scene = sward::scene::load_scene_with_sets(&path, &sets).expect("prairie");
    let gpu = common::gpu();
    let session = sward::session::Session::new(scene, None, Some(&gpu)).expect("field");
    let (_, target) = common::draw_frames(&gpu, &session, SIZE, FRAMES, false, |_| {});
    target.read_image(&gpu).expect("image")
}

#[test]
fn billboards_and_the_far_ground_read_as_the_blades_they_replace() {
    let levels = prairie(&[]);
    let blades = prairie(&["culling.max_distance=50", "culling.distance=false"]);
    let diffs = compare_bands(&levels, &blades, 0..SIZE.1).expect("same size");
    for (d, b) in diffs.iter().zip(bands(&blades)) {
        println!(
            "band {:3}: luminance {:6.1} ({:+6.1}), contrast {:5.1} ({:+4.0} %)",
            d.top,
            b.luminance,
            d.luminance,
            b.contrast,
            100.0 * d.contrast
        );
    }
    let worst = worst_band(&diffs).expect("bands");
    println!("worst band: {worst:?}");
    // The ground below the horizon: the first band with texture in the reference.
    let horizon = bands(&blades)
        .iter()
        .position(|b| b.contrast > 3.0)
        .expect("a horizon");
    let far = diffs[horizon];
    assert!(
        far.luminance.abs() <= 5.0,
        "the far ground at the horizon: {far:?}"
    );
    let worst_luminance = diffs.iter().map(|d| d.luminance.abs()).fold(0.0, f64::max);
    assert!(
        worst_luminance <= 8.0,
        "a band {worst_luminance:.1} levels off: {worst:?}"
    );
    // The bottom third: blades in both, thinned in one.
    let near: Vec<_> = diffs.iter().filter(|d| d.top >= SIZE.1 * 2 / 3).collect();
    assert!(!near.is_empty());
    for d in near {
        assert!(d.luminance.abs() <= 5.0, "near band {d:?}");
        assert!(d.contrast.abs() <= 0.3, "near band {d:?}");
    }
}

/// The far ground's texture (issue 27, point 3): patches and clumps of lighter and darker
/// grass that average to the grass's colour. Seen from above with no blades or cards, at
/// 256 × 144 it shows (blocks of 8 × 8 pixels vary), and at 32 × 18 — where every octave
/// is finer than the pixels and fades out — the same ground has the same mean: the texture
/// moves nothing but the spread.
#[test]
fn the_far_ground_has_texture_that_averages_to_the_grass_colour() {
    let sets = [
        "render.billboard_distance=0",
        "culling.max_distance=0.5",
        "camera.eye=(-14.0, 20.0, 16.0)",
        "camera.target=(40.0, -19.0, -40.0)",
    ];
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/prairie.ron");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let scene = sward::scene::load_scene_with_sets(&path, &sets).expect("prairie");
    let gpu = common::gpu();
    let session = sward::session::Session::new(scene, None, Some(&gpu)).expect("field");
    let render = |size: (u32, u32)| {
        let (_, target) = common::draw_frames(&gpu, &session, size, 1, false, |_| {});
        target.read_image(&gpu).expect("image")
    };
    let fine = render((256, 144));
    let coarse = render((32, 18));
    // The bottom half is ground in both.
    let spread: f64 = bands(&fine)[9..].iter().map(|b| b.contrast).sum::<f64>() / 9.0;
    println!("ground's 8x8 block spread at 256x144: {spread:.2} levels");
    assert!(spread > 1.5, "the far ground shows no texture: {spread:.2}");
    let mean = |img: &image::RgbaImage, rows: std::ops::Range<u32>| {
        let mut sum = 0.0;
        let mut n = 0.0;
        for y in rows {
            for x in 0..img.width() {
                let p = img.get_pixel(x, y);
                sum +=
                    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
                n += 1.0;
            }
        }
        sum / n
    };
    let (a, b) = (mean(&fine, 72..144), mean(&coarse, 9..18));
    println!("ground's mean luminance: {a:.2} at 256x144, {b:.2} at 32x18");
    assert!((a - b).abs() < 2.0, "{a:.2} against {b:.2}");
}
