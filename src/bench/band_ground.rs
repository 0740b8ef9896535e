//! Where each 8-row band of a frame lies (`sward bench --far-field`): the median distance
//! from the camera to the ground its pixels show, so that a band that misses names the
//! level it stands in (the blades, the thinned blades among the first cards, the far ring,
//! the far field) instead of a row number that means nothing without the view.
//!
//! The rays are the window's picking rays (`sward::render::ray::screen_ray`, through the
//! renderer's own view-projection) marched over the scene's height field
//! (`pick_terrain`): the ground under the grass, not the blades' tips, which stand at most
//! a blade's height above it.

use glam::Vec2;

use sward::compare::BAND_ROWS;
use sward::field::HeightField;
use sward::render::camera::CameraView;
use sward::render::ray::{pick_terrain, screen_ray};

/// Columns sampled across each row of a band.
pub const COLUMNS: u32 = 32;

/// The share of a band's rays that must meet the ground for the band to have a distance:
/// below it the band is mostly sky, and the median of its few ground rays would name the
/// horizon's hills for a band that shows the sky.
pub const GROUND_SHARE: f32 = 0.5;

/// The median distance (m) from `view`'s eye to the ground each band of a `size` frame
/// shows, top to bottom (the bands of `compare::bands`, whole bands only), sampled at
/// every row's pixel centres in [`COLUMNS`] columns and marched out to `far` metres; `None`
/// for a band where fewer than [`GROUND_SHARE`] of the rays meet the ground.
pub fn band_ground_distances(
    view: &CameraView,
    size: (u32, u32),
    terrain: &HeightField,
    far: f32,
) -> Vec<Option<f32>> {
    let (w, h) = size;
    let columns = COLUMNS.min(w.max(1));
    (0..h / BAND_ROWS)
        .map(|band| {
            let mut hits = Vec::new();
            let mut rays = 0usize;
            for row in band * BAND_ROWS..(band + 1) * BAND_ROWS {
                for c in 0..columns {
                    let x = (c as f32 + 0.5) * w as f32 / columns as f32;
                    let ray = screen_ray(view, size, Vec2::new(x, row as f32 + 0.5));
                    rays += 1;
                    if let Some(p) = pick_terrain(&ray, terrain, far) {
                        hits.push(p.distance(view.eye));
                    }
                }
            }
            median_if_enough(hits, rays)
        })
        .collect()
}

/// The median of `hits` when they are at least [`GROUND_SHARE`] of `rays`.
fn median_if_enough(mut hits: Vec<f32>, rays: usize) -> Option<f32> {
    if hits.is_empty() || (hits.len() as f32) < GROUND_SHARE * rays as f32 {
        return None;
    }
    hits.sort_by(f32::total_cmp);
    let n = hits.len();
    Some(if n % 2 == 1 {
        hits[n / 2]
    } else {
        0.5 * (hits[n / 2 - 1] + hits[n / 2])
    })
}

/// A band's distance as the tables print it: metres, or "sky".
pub fn format_ground(d: Option<f32>) -> String {
    match d {
        Some(m) => format!("{m:.0}"),
        None => "sky".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A camera `eye_h` metres over a flat field, looking level along −z with a vertical
    /// field of view `fov` degrees.
    fn level_view(eye_h: f32, fov: f32) -> CameraView {
        CameraView {
            eye: Vec3::new(0.0, eye_h, 0.0),
            target: Vec3::new(0.0, eye_h, -10.0),
            fov_y: fov,
            near: 0.1,
            far: 1000.0,
        }
    }

    #[test]
    fn a_flat_field_lies_where_the_rows_rays_meet_the_plane() {
        // Over a flat field a ray through row y meets the ground at horizontal distance
        // eye_h / tan(angle below the horizon), angle = atan((y_ndc) tan(fov / 2)); the
        // band's median is its middle rows' (the columns' rays run farther off-centre,
        // by 1 / cos of their azimuth), so the check is on the band's range of rows.
        let (eye_h, fov, size) = (2.0, 60.0, (64u32, 64u32));
        let terrain = HeightField::flat(2000.0, 65);
        let view = level_view(eye_h, fov);
        let d = band_ground_distances(&view, size, &terrain, 1000.0);
        assert_eq!(d.len(), 8);
        // The top half of the frame looks above the horizon.
        for band in &d[..4] {
            assert_eq!(*band, None, "{d:?}");
        }
        let t = (0.5 * fov).to_radians().tan();
        let slant = |row: f32| {
            let y_ndc = 2.0 * row / size.1 as f32 - 1.0;
            let below = (y_ndc * t).atan();
            eye_h / below.sin()
        };
        for (band, got) in d.iter().enumerate().skip(4) {
            let got = got.expect("below the horizon the ground is hit");
            let top = (band as u32 * BAND_ROWS) as f32;
            // Nearest: the band's bottom row on the centre column; farthest: its top row
            // at the frame's edge (1 / cos of the edge's azimuth farther along the plane).
            let near = slant(top + BAND_ROWS as f32 - 0.5);
            let edge = (t * size.0 as f32 / size.1 as f32).atan();
            let far = slant(top + 0.5) / edge.cos();
            assert!(
                got >= near - 1e-3 && got <= far + 1e-3,
                "band {band}: {got} m, not within {near}-{far} m"
            );
        }
        // Down the frame the ground comes nearer.
        let below: Vec<f32> = d[4..].iter().map(|x| x.unwrap()).collect();
        assert!(below.windows(2).all(|p| p[1] < p[0]), "{below:?}");
    }

    #[test]
    fn a_band_mostly_of_sky_has_no_distance() {
        assert_eq!(median_if_enough(vec![10.0], 4), None);
        assert_eq!(median_if_enough(vec![], 4), None);
        assert_eq!(median_if_enough(vec![30.0, 10.0], 4), Some(20.0));
        assert_eq!(median_if_enough(vec![30.0, 10.0, 20.0], 4), Some(20.0));
    }
}
