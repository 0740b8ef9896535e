//! The far levels' light gain by the direction of view (issue 27, point 1;
//! `render::far_sectors`): the WGSL sectors against their CPU twins (which sectors a
//! direction lies between and the multiplier there, and a frame's next multipliers from
//! sums of every kind: measured, too few, bare ground, not finite).
//!
//! Measured on lavapipe: the multipliers within 2e-6 of the twin; the weights within 1e-5
//! (atan2 on the two sides). And in frames of the prairie: the cards and the far ground lit
//! by their direction's sector, the blades not; the sectors in view measured, those
//! behind the camera not.

mod common;

use glam::{Vec2, Vec4};
use sward::render::far_sectors::{self, sector_pair, SECTORS, SECTOR_SUMS};

/// A frame's sums that are not all alike: sectors measured with blades brighter or darker
/// than the model, some with few pixels, one on bare ground, some out of view.
fn frame_sums(seed: u32) -> [Vec4; SECTOR_SUMS] {
    let mut s = [Vec4::ZERO; SECTOR_SUMS];
    for k in 0..SECTORS {
        let h = ((k as u32 * 2_654_435_761) ^ seed.wrapping_mul(40_503)) % 1000;
        let x = h as f32 / 1000.0;
        if k % 5 == 4 {
            continue;
        }
        let pixels = 4.0 + 60.0 * x;
        let shown = (0.7 + 0.6 * x) * pixels;
        s[2 * k] = Vec4::new(shown, pixels, 0.6 * shown / (0.9 + 0.2 * x), pixels);
        let standing = if k == 6 { 0.3 * pixels } else { pixels };
        s[2 * k + 1] = Vec4::new((0.8 + 0.5 * x) * standing, standing, standing, pixels);
    }
    s
}

#[test]
fn the_gpu_sectors_match_their_twin() {
    let gpu = common::gpu();
    let mut points = Vec::new();
    for i in 0..720 {
        let a = (i as f32 * 0.5 + 0.123).to_radians();
        let d = Vec2::new(a.cos(), a.sin()) * (0.5 + (i % 7) as f32);
        points.push((d, 0.8 + 0.001 * i as f32, 1.3));
    }
    points.push((Vec2::ZERO, 1.2, 1.3));
    points.push((Vec2::new(f32::NAN, 1.0), 1.2, 0.0));
    points.push((Vec2::new(f32::INFINITY, 1.0), f32::NAN, -2.0));
    for (seed, previous, n) in [
        (1, [0.0; SECTORS], 0.0),
        (2, [1.1; SECTORS], 3.0),
        (3, std::array::from_fn(|k| 0.8 + 0.05 * k as f32), 12.0),
    ] {
        let sums = frame_sums(seed);
        let (pairs, next) = far_sectors::probe(&gpu, &points, &sums, &previous, (n, 0.25)).unwrap();
        for (p, (d, a, b)) in pairs.iter().zip(&points) {
            let (ca, cb, ct) = sector_pair(*d);
            let mut words = [0.0; SECTORS];
            words[ca] = *a;
            words[cb] = *b;
            let want = far_sectors::sector_gain(*d, &words);
            // At a sector's centre the two atan2s may fall either side (the words the
            // point carries are the GPU's pair's): none of these directions lies there.
            assert_eq!((p.0, p.1), (ca, cb), "{d} {p:?} {seed}");
            assert!((p.2 - ct).abs() < 1e-5, "{d}: {p:?} against {ct}");
            assert!((p.3 - want).abs() < 1e-5, "{d}: {} against {want}", p.3);
        }
        let twin = far_sectors::next_sectors(&sums, &previous, n, 0.25);
        for k in 0..SECTORS {
            assert!(
                (next[k] - twin[k]).abs() < 2e-6,
                "{seed} sector {k}: {} against {}",
                next[k],
                twin[k]
            );
        }
        // The frame moved the sectors it measured and kept the others.
        assert!(twin.iter().zip(&previous).any(|(a, b)| a != b));
        assert_eq!(twin[4], previous[4]);
    }
    // Not finite: every multiplier kept, on the GPU too.
    let mut bad = frame_sums(4);
    bad[2].x = f32::NAN;
    let previous = [1.2; SECTORS];
    let (_, next) = far_sectors::probe(&gpu, &points[..3], &bad, &previous, (4.0, 0.25)).unwrap();
    assert_eq!(next, previous);
}

/// Luminance (Rec. 709 of the 8-bit values) of a block of `img`.
fn block_mean(
    img: &image::RgbaImage,
    rows: std::ops::Range<u32>,
    cols: std::ops::Range<u32>,
) -> f64 {
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in rows {
        for x in cols.clone() {
            let p = img.get_pixel(x, y).0;
            sum += 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
            n += 1.0;
        }
    }
    sum / n
}

/// The prairie's first frame (no wind: the same blades in both) with the sectors set before
/// it, at 240 × 136.
fn first_frame(sectors: [f32; SECTORS]) -> image::RgbaImage {
    let gpu = common::gpu();
    let scene = common::prairie_scene(&["wind.source=Analytic", "wind.directional.strength=0.0"]);
    let session = sward::session::Session::new(scene, None, Some(&gpu)).expect("session");
    let (_, target) = common::draw_frames(&gpu, &session, (240, 136), 1, false, |r| {
        r.set_far_sectors(&gpu, &sectors);
    });
    target.read_image(&gpu).expect("read-back")
}

/// The cards and the far ground are lit by their direction's sector, and the blades are
/// not: the prairie looks along azimuth 315° with an 85° view, so sector 15 (centred on
/// 348.75°, 34° right of the view's centre) reaches from a little right of the centre to
/// the right edge. Raised to 1.5 it brightens the far field on the right and leaves the
/// left half and the blades at the camera's feet as they were (measured on lavapipe: +21.3
/// levels in the right quarter's far rows, 0.00 on the left and in the near rows; mirrored
/// directions would brighten the left).
#[test]
fn the_far_levels_are_lit_by_their_directions_sector() {
    let plain = first_frame([1.0; SECTORS]);
    let mut raised = [1.0; SECTORS];
    raised[15] = 1.5;
    let lit = first_frame(raised);
    let (w, h) = (plain.width(), plain.height());
    // The far rows: below the horizon, above the blades' reach.
    let far = 44..64;
    let left = block_mean(&lit, far.clone(), 0..w / 2) - block_mean(&plain, far.clone(), 0..w / 2);
    let right =
        block_mean(&lit, far.clone(), 3 * w / 4..w) - block_mean(&plain, far.clone(), 3 * w / 4..w);
    let near = block_mean(&lit, h * 3 / 4..h, 0..w) - block_mean(&plain, h * 3 / 4..h, 0..w);
    println!("far left {left:+.2}, far right {right:+.2}, near {near:+.2}");
    assert!(left.abs() < 0.5, "the left half moved by {left:.2} levels");
    assert!(
        right > 8.0,
        "the right quarter brightened by {right:.2} levels only"
    );
    assert!(near.abs() < 0.5, "the blades moved by {near:.2} levels");
}

/// After a few frames the sectors the view holds are measured and the others are not: the
/// measuring pass and the twin turn directions into sectors alike (azimuth from +x towards
/// +z). The prairie's view spans about 272° to 358°: sectors 12 to 15 lie in it, 2 to 9
/// behind the camera.
#[test]
fn the_sectors_in_view_are_measured_and_the_others_kept() {
    let gpu = common::gpu();
    let session = sward::session::Session::new(common::prairie_scene(&[]), None, Some(&gpu))
        .expect("session");
    let (r, _) = common::draw_frames(&gpu, &session, (240, 136), 6, false, |_| {});
    let m = r.far_calibration(&gpu).expect("read-back").sectors;
    println!("{m:?}");
    for k in 12..16 {
        assert!(m[k] > 0.0, "sector {k} in view not measured: {m:?}");
        assert!((0.6..=1.6).contains(&m[k]), "sector {k}: {m:?}");
    }
    for k in 2..10 {
        assert_eq!(m[k], 0.0, "sector {k} behind the camera measured: {m:?}");
    }
}
