//! The levels that stand for the blades far away (issue 27, point 1): the prairie as it
//! ships (blades to 28 m, thinned by Eq. 20, then billboards, then the far ground) against
//! the same frame with blades out to 50 m and no thinning, compared in bands of 8 rows
//! (`compare::compare_bands`: mean luminance and 8 × 8 block contrast).
//!
//! The target is 5 levels and 30 % in every band. What holds today, and is held
//! here so that it cannot slide back (measured at 240 × 136 and 480 × 270):
//! - the far ground at the horizon, where both frames show it, within 5 levels: the
//!   billboards and the far ground are lit alike (`far_grass.wgsl`);
//! - every band within the 5 levels (`RING_BOUND`, see below; they were 60 levels
//!   darker before they and the far ground took the blades' light);
//! - every textured band's contrast within the 30 % (`CONTRAST_BOUND`);
//! - the far ground within the 5 levels and 30 % of the cards it takes over from
//!   (the cards brought in to 100 m against 300 m);
//! - the thinned near field within the 5 levels and 30 % (1.9 levels and 7 %
//!   measured: the kept blades widen, `thinning_widen_at`, and keep the shape the full
//!   field's thinner blades have).
//!
//! With the prairie's 4x MSAA the blades are lit deferred (`render::deferred`), as they are
//! drawn by default since the deferred light took MSAA: once per pixel, at a sample the
//! blade covers. The cards were calibrated against the forward MSAA light, which lights a
//! pixel's fragment at its centre even off a sub-pixel blade and made the blades at 28-50 m
//! about 20 levels brighter than one sample, 2 x 2 or 4 x 4 supersampling and the deferred
//! light show them (band 48 here: 148.8 forward, 125.3 deferred, 123.8 with one sample).
//! Against the blades as they are, the cards in that ring read up to 23.9 levels too bright.
//!
//! Since `render::far_gain` the cards and the far ground are calibrated by measurement.
//! First on the light model (`far_grass_light`): they read 1.02-1.14 times the model, and
//! the gain took that out, which left the ring 8.5 and 13.4 levels too bright (bands 48 and
//! 56), because the model is not the blades. Now on the blades: the far levels aim at the
//! model times the blades' own ratio to it, measured just inside the reach, and the cards'
//! texels, sampled three mip levels sharper than their footprint, are moved from their
//! mean with the contrast the blades have (the contrast gain; under a fifth of the mean the
//! move bends towards black instead of clipping at it). Measured here: every band whose
//! reference has texture within 12 % of its contrast (67 % flatter before), band 40 7.6
//! levels dark (the ridge past the reference's blades), bands 48 and 56 7.3 and 8.5 bright
//! (where the thinned blades' last levels stand in front of the first cards; 6.7 and 7.5
//! while the move clipped at black, which lowered the cards' mean as the contrast gain
//! rose). The cards' texels were moved from the card's one mean, and the tops a distant
//! eye sees are lighter than it: the cards' mean rose with the contrast gain, faster than
//! the light gain, which averages, could follow in the first frames. Moved from their
//! layer's height profile at their height (`card_profile.wgsl`), every band is within 3.4
//! levels after these 4 frames (band 96; band 48 +2.8), and `RING_BOUND` is the 5.

mod common;

use common::print_bands;
use sward::compare::{bands, compare_bands, worst_band};

const SIZE: (u32, u32) = (240, 136);
const FRAMES: usize = 4;
/// Every band's luminance difference, at most (levels): the 5. Measured 2.8 (band
/// 64) since each of a pixel's first two blades takes its own light under 4x MSAA; 2.8
/// (band 96) with the light gain by direction (`far_sectors`), 3.4 since the cards' contrast
/// moves their texels about their height profile; the ring
/// where the cards take over from the blades was 8.4 before, 8.5 with the levels
/// calibrated on the blades, 13.4 on the light model and 23.9 before either.
const RING_BOUND: f64 = 5.0;
/// A band's contrast difference, at most, where the reference has texture (8 x 8 blocks
/// varying by `TEXTURED` levels or more): the 30 % (measured 12 %).
const CONTRAST_BOUND: f64 = 0.3;
const TEXTURED: f64 = 10.0;
/// The far ground against the cards from 85 m on, a band's luminance difference at most:
/// the 5 levels (measured 3.0 in band 48, cards of 0.5 m cells against 1.5 m; the
/// bands where one frame shows the ground, 32 and 40, +0.6 and -1.2).
const HORIZON_LUMINANCE: f64 = 5.0;
/// ... and its contrast's, where the cards' band has texture (`HORIZON_TEXTURED`): the
/// issue's 30 % (measured -16 % in band 32, the horizon, and -5 % in band 40).
const HORIZON_CONTRAST: f64 = 0.3;
/// 8 × 8 spread that counts as texture in that comparison (levels): low enough to take
/// in the hazy horizon band (8.6), where the far ground shows.
const HORIZON_TEXTURED: f64 = 3.0;
/// Frames of the TAA comparison.
const TAA_FRAMES: usize = 16;
/// A band's contrast difference with TAA, at most, where the reference has texture: the
/// issue's 30 %. The ring just past the blades (band 48) was flatter with TAA than without
/// while the contrast gain matched the spread of single pixels across the rings (−29.7 %
/// to −31 %, its luminance −9.6 to −13.3 levels); matching the local contrast of 4 × 4
/// texels in the frame's radiance (`block_contrast`) it reads +3 % (−15.3 levels, the
/// far levels' light with TAA), and the other bands are within 25 %.
const TAA_CONTRAST_BOUND: f64 = 0.3;

fn prairie(sets: &[&str]) -> image::RgbaImage {
    prairie_after(sets, FRAMES)
}

fn prairie_after(sets: &[&str], frames: usize) -> image::RgbaImage {
    common::prairie_frame(sets, SIZE, frames)
}

/// With TAA the far levels are calibrated on the blades as the history shows them (the
/// near ring read in the history, the far ring in the frame, `far_gain_common.wgsl`): the
/// history smooths the swaying blades more than the still cards, and measured before it
/// the cards' texture was 35-51 % above the blades' (480 × 270, 16 and 30 frames). Both
/// frames with TAA, after `TAA_FRAMES` (the history settles over about ten).
#[test]
fn with_taa_the_cards_vary_as_the_blades_shown() {
    let taa = ["render.msaa=1", "render.taa=true"];
    let levels = prairie_after(&taa, TAA_FRAMES);
    let blades = prairie_after(
        &[
            taa[0],
            taa[1],
            "culling.max_distance=50",
            "culling.distance=false",
        ],
        TAA_FRAMES,
    );
    let diffs = compare_bands(&levels, &blades, 0..SIZE.1).expect("same size");
    print_bands(&diffs, &blades);
    for (d, b) in diffs.iter().zip(bands(&blades)) {
        if b.contrast >= TEXTURED {
            assert!(
                d.contrast.abs() <= TAA_CONTRAST_BOUND,
                "band contrast {d:?}"
            );
        }
    }
}

#[test]
fn billboards_and_the_far_ground_read_as_the_blades_they_replace() {
    let levels = prairie(&[]);
    let blades = prairie(&["culling.max_distance=50", "culling.distance=false"]);
    let diffs = compare_bands(&levels, &blades, 0..SIZE.1).expect("same size");
    print_bands(&diffs, &blades);
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
        worst_luminance <= RING_BOUND,
        "a band {worst_luminance:.1} levels off: {worst:?}"
    );
    // The cards' texture varies as the blades it stands for do.
    for (d, b) in diffs.iter().zip(bands(&blades)) {
        if b.contrast >= TEXTURED {
            assert!(d.contrast.abs() <= CONTRAST_BOUND, "band contrast {d:?}");
        }
    }
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
    let scene = common::prairie_scene(&sets);
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

/// Point 1's second comparison: the far ground against the cards it takes over from. The
/// issue pushes the billboard radius out to the horizon; from the prairie's camera the
/// hills end the view inside the prairie's 300 m (pushed to the far plane, the frame is
/// the same in every pixel: `sward bench --far-field` says so), and from 50 m up the
/// ground beyond 300 m lies in the haze (a few hundred pixels at 480 × 270 moved by a
/// tenth of a level). So the far ground is brought in instead: the cards to 100 m (ground
/// from 85 m, where they fade out) against the prairie's cards to 300 m, bands of rows
/// that show the ground in one frame and cards in the other. Measured at 240 × 136:
/// every band within `HORIZON_LUMINANCE` levels and the textured bands' contrast within
/// `HORIZON_CONTRAST`.
#[test]
fn the_far_ground_reads_as_the_cards_it_takes_over_from() {
    let cards = prairie(&[]);
    let ground = prairie(&["render.billboard_distance=100"]);
    let differing = sward::compare::differing_pixels(&ground, &cards).expect("same size");
    println!("pixels that differ: {differing}");
    // The comparison measures something: the two frames differ.
    assert!(differing > 1000, "only {differing} pixels differ");
    let diffs = compare_bands(&ground, &cards, 0..SIZE.1).expect("same size");
    print_bands(&diffs, &cards);
    for (d, b) in diffs.iter().zip(bands(&cards)) {
        assert!(d.luminance.abs() <= HORIZON_LUMINANCE, "band {d:?}");
        if b.contrast >= HORIZON_TEXTURED {
            assert!(d.contrast.abs() <= HORIZON_CONTRAST, "band contrast {d:?}");
        }
    }
}
