//! Which levels of detail a shadow cascade's grass casters can have. Each cascade draws the
//! blades the cull kept, level by level (the cull's visible lists); a blade's level follows
//! its projected height, `height · lod[0] / distance`, against the cull's thresholds
//! (`lod[1]`, `lod[2]` px). A cascade whose slice covers distances `[a, b]` from the camera
//! receives shadows from blades between `a − reach` and `b + reach` (`reach`: how far the
//! tallest blade's shadow falls sideways under this sun), whose projected heights lie
//! between `h_min · lod[0] / (b + reach)` and `h_max · lod[0] / (a − reach)`: the levels
//! that range meets are drawn, the others are not. The near cascade then draws its few
//! near blades instead of every blade in view: on the nature view at 1280×720, the nearest
//! cascade draws the 12,729 blades of level 0 instead of all 46,712.

use glam::Vec3;

use crate::sim::layout::LOD_LEVELS;

/// Longest sideways reach of a blade's shadow considered (m): at a grazing sun it would
/// be unbounded, and such shadows are filtered to nothing long before.
const MAX_REACH: f32 = 5.0;

/// The levels a cascade over distances `(a, b)` draws, for blades of heights
/// `(h_min, h_max)` under a sun in direction `sun` with the cull's `lod` parameters
/// (`[px per metre, level-0 threshold, level-1 threshold, _]`; thresholds of 0: no levels,
/// every blade is level 0).
pub fn levels(
    (a, b): (f32, f32),
    (h_min, h_max): (f32, f32),
    sun: Vec3,
    lod: [f32; 4],
) -> [bool; LOD_LEVELS] {
    if b.partial_cmp(&a) != Some(std::cmp::Ordering::Greater) || h_max.is_nan() || h_max <= 0.0 {
        return [false; LOD_LEVELS];
    }
    let sin = sun.normalize_or(Vec3::Y).y.clamp(0.05, 1.0);
    let reach = (h_max * (1.0 - sin * sin).sqrt() / sin).min(MAX_REACH);
    let near = (a - reach).max(1e-3);
    let far = b + reach;
    // Projected heights of the blades that can cast here, in pixels.
    let lo = h_min.max(0.0) * lod[0] / far;
    let hi = h_max * lod[0] / near;
    // Level 0 at and above lod[1] px, level 1 at and above lod[2], else level 2.
    let level_of = |px: f32| -> usize {
        if px >= lod[1] {
            0
        } else if px >= lod[2] {
            1
        } else {
            2
        }
    };
    // Projected height falls as the level rises: the tallest nearest blade has the
    // finest level, the shortest farthest one the coarsest.
    let (finest, coarsest) = (level_of(hi), level_of(lo));
    std::array::from_fn(|l| (finest..=coarsest).contains(&l))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 720 px high at 50° field of view; thresholds 24 and 8 px.
    const LOD: [f32; 4] = [772.0, 24.0, 8.0, 0.3];

    fn level_of(h: f32, d: f32) -> usize {
        let px = h * LOD[0] / d;
        if px >= LOD[1] {
            0
        } else if px >= LOD[2] {
            1
        } else {
            2
        }
    }

    #[test]
    fn every_blade_that_can_cast_into_a_cascade_has_a_drawn_level() {
        let sun = Vec3::new(0.4, 0.6, 0.3);
        let heights = (0.3, 0.9);
        for (a, b) in [(0.0, 7.1), (7.1, 18.5), (18.5, 25.0), (2.0, 60.0)] {
            let drawn = levels((a, b), heights, sun, LOD);
            // Blades over the slice widened by the reach, at every height: their level
            // (the cull's rule) is drawn.
            let s = sun.normalize().y;
            let reach = (heights.1 * (1.0 - s * s).sqrt() / s).min(MAX_REACH);
            for i in 0..=100 {
                let d = ((a - reach).max(1e-3))
                    + (b + reach - (a - reach).max(1e-3)) * i as f32 / 100.0;
                for j in 0..=10 {
                    let h = heights.0 + (heights.1 - heights.0) * j as f32 / 10.0;
                    assert!(
                        drawn[level_of(h, d)],
                        "({a}, {b}): h {h} at {d} m: {drawn:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_near_cascade_leaves_the_far_levels_out() {
        let sun = Vec3::new(0.0, 1.0, 0.0);
        // Overhead sun: no sideways reach. Blades up to 0.9 m within 7 m are at least
        // 0.3 · 772 / 7 = 33 px high: level 0 only.
        assert_eq!(
            levels((0.0, 7.0), (0.3, 0.9), sun, LOD),
            [true, false, false]
        );
        // From 30 m on, at most 0.9 · 772 / 30 = 23 px: never level 0.
        assert_eq!(
            levels((30.0, 80.0), (0.3, 0.9), sun, LOD),
            [false, true, true]
        );
        // An empty slice draws nothing.
        assert_eq!(levels((25.0, 25.0), (0.3, 0.9), sun, LOD), [false; 3]);
        // Without levels of detail (thresholds 0) every blade is level 0.
        assert_eq!(
            levels((0.0, 80.0), (0.3, 0.9), sun, [772.0, 0.0, 0.0, 0.0]),
            [true, false, false]
        );
    }
}
