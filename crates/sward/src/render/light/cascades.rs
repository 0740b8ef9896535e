//! The sun's shadow cascades: the view from the near plane to `shadows.distance` split into
//! slices (Zhang et al.'s practical split: a blend of logarithmic and uniform), each covered
//! by an orthographic view from the sun around the slice's bounding sphere. The sphere does
//! not change size as the camera turns, and its centre is snapped to whole texels in the
//! sun's view, so that the shadow edges stay put while the camera moves (no shimmering).

use glam::{Mat4, Vec3, Vec4};

use crate::render::camera::CameraView;

/// The blend towards logarithmic splits.
const SPLIT_LAMBDA: f32 = 0.75;
/// How far beyond a slice's sphere, towards the sun, casters still land in its map (m).
pub const CASTER_REACH: f32 = 150.0;

/// One cascade: its sun view-projection, far distance from the camera and texel size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    /// The sun's orthographic view-projection for this slice, world to clip (depth 0..1).
    pub view_proj: Mat4,
    /// Far end of the slice: distance from the camera along its axis (m).
    pub far: f32,
    /// Side of one shadow-map texel in the world (m): the sphere's diameter over the
    /// resolution.
    pub texel: f32,
    /// The slice's bounding sphere (before snapping): where the map is centred and how far
    /// it reaches.
    pub centre: Vec3,
    /// Radius of the slice's bounding sphere (m), rounded up to 1/16 m.
    pub radius: f32,
}

/// The far distance of each of `count` slices between `near` and `far`.
pub fn splits(near: f32, far: f32, count: u32) -> Vec<f32> {
    let n = near.max(0.01);
    let f = far.max(n * 1.01);
    (1..=count)
        .map(|i| {
            let t = i as f32 / count as f32;
            let log = n * (f / n).powf(t);
            let uniform = n + (f - n) * t;
            SPLIT_LAMBDA * log + (1.0 - SPLIT_LAMBDA) * uniform
        })
        .collect()
}

/// The rotation of the sun's view: looking along −sun.
pub fn sun_view(sun: Vec3) -> Mat4 {
    let up = if sun.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    glam::camera::rh::view::look_to_mat4(Vec3::ZERO, -sun, up)
}

/// The cascades of a camera with aspect ratio `aspect`, for a sun in direction `sun`, a map
/// of `resolution` texels per side, out to `distance` metres in `count` slices.
pub fn cascades(
    camera: &CameraView,
    aspect: f32,
    sun: Vec3,
    resolution: u32,
    distance: f32,
    count: u32,
) -> Vec<Cascade> {
    let forward = (camera.target - camera.eye).normalize_or(Vec3::NEG_Z);
    let far_limit = distance.min(camera.far);
    let ends = splits(camera.near, far_limit, count);
    let tan_y = (camera.fov_y.to_radians() * 0.5).tan();
    let tan_x = tan_y * aspect.max(1e-4);
    let view = sun_view(sun);
    let mut start = camera.near;
    ends.iter()
        .map(|&end| {
            // The slice's bounding sphere, from its depth range alone (not its rotation):
            // on the axis at the point nearest to both ends' corners.
            let diag2 = 1.0 + tan_x * tan_x + tan_y * tan_y;
            let (a, b) = (start, end);
            // Centre distance c on the axis that minimises the larger corner distance.
            let c = ((b * b - a * a) * diag2 / (2.0 * (b - a))).clamp(a, b);
            let r_near = ((c - a).powi(2) + a * a * (diag2 - 1.0)).sqrt();
            let r_far = ((b - c).powi(2) + b * b * (diag2 - 1.0)).sqrt();
            // Rounded up to 1/16 m so float noise in the split does not resize the map.
            let radius = (r_near.max(r_far) * 16.0).ceil() / 16.0;
            let centre = camera.eye + forward * c;
            start = end;
            let texel = 2.0 * radius / resolution as f32;
            let mut lc = view * centre.extend(1.0);
            lc.x = (lc.x / texel).round() * texel;
            lc.y = (lc.y / texel).round() * texel;
            let near = -(lc.z + radius + CASTER_REACH);
            let far = -(lc.z - radius);
            let proj = glam::camera::rh::proj::directx::orthographic(
                lc.x - radius,
                lc.x + radius,
                lc.y - radius,
                lc.y + radius,
                near,
                far,
            );
            Cascade {
                view_proj: proj * view,
                far: end,
                texel,
                centre,
                radius,
            }
        })
        .collect()
}

/// Whether the CPU's shadow test puts `p` in the shadow of a sphere (centre, radius) for a
/// sun in direction `sun`: the ray from `p` towards the sun meets the sphere. The
/// reference the rendered shadows are tested against.
pub fn sphere_shadows(p: Vec3, sun: Vec3, centre: Vec3, radius: f32) -> bool {
    let to_c = centre - p;
    let along = to_c.dot(sun);
    along > 0.0 && (to_c - sun * along).length_squared() < radius * radius
}

/// Where `p` lands in a cascade: texture coordinates and depth (the shader's lookup).
pub fn project(cascade: &Cascade, p: Vec3) -> (f32, f32, f32) {
    let c: Vec4 = cascade.view_proj * p.extend(1.0);
    (c.x * 0.5 + 0.5, 0.5 - c.y * 0.5, c.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(eye: Vec3, target: Vec3) -> CameraView {
        CameraView {
            eye,
            target,
            fov_y: 50.0,
            near: 0.1,
            far: 300.0,
        }
    }

    #[test]
    fn slices_cover_the_view_and_grow() {
        let s = splits(0.1, 80.0, 3);
        assert_eq!(s.len(), 3);
        assert!((s[2] - 80.0).abs() < 1e-3);
        assert!(s[0] < s[1] - s[0] && s[1] - s[0] < s[2] - s[1], "{s:?}");
    }

    #[test]
    fn every_point_of_a_slice_lands_inside_its_map() {
        let cam = camera(Vec3::new(3.0, 2.0, 5.0), Vec3::new(-4.0, 0.5, -9.0));
        let sun = Vec3::new(-0.4, 0.6, 0.5).normalize();
        let cs = cascades(&cam, 16.0 / 9.0, sun, 1024, 60.0, 3);
        let vp = cam.view_proj(16.0 / 9.0);
        let inv = vp.inverse();
        let mut start = cam.near;
        for c in &cs {
            // Corners of the slice, through the inverse view-projection.
            for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                let ray = inv.project_point3(Vec3::new(x, y, 1.0)) - cam.eye;
                let dir = ray.normalize();
                let forward = (cam.target - cam.eye).normalize();
                for d in [start, c.far] {
                    let p = cam.eye + dir * (d / dir.dot(forward));
                    let (u, v, z) = project(c, p);
                    assert!(
                        (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v),
                        "{u} {v}"
                    );
                    assert!((0.0..=1.0).contains(&z), "{z}");
                }
            }
            start = c.far;
        }
    }

    #[test]
    fn snapped_cascades_move_by_whole_texels() {
        let sun = Vec3::new(-0.4, 0.6, 0.5).normalize();
        let a = cascades(
            &camera(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 1.0, -10.0)),
            1.5,
            sun,
            512,
            50.0,
            2,
        );
        let b = cascades(
            &camera(Vec3::new(0.013, 2.0, 0.0), Vec3::new(0.013, 1.0, -10.0)),
            1.5,
            sun,
            512,
            50.0,
            2,
        );
        for (ca, cb) in a.iter().zip(&b) {
            // A fixed world point moves by a whole number of texels in the map.
            let p = Vec3::new(1.0, 0.0, -5.0);
            let (ua, va, _) = project(ca, p);
            let (ub, vb, _) = project(cb, p);
            let res = 512.0;
            for d in [(ua - ub) * res, (va - vb) * res] {
                assert!((d - d.round()).abs() < 1e-2, "{d}");
            }
        }
    }

    #[test]
    fn sphere_shadow_reference() {
        let sun = Vec3::Y;
        assert!(sphere_shadows(
            Vec3::ZERO,
            sun,
            Vec3::new(0.0, 2.0, 0.0),
            0.5
        ));
        assert!(!sphere_shadows(
            Vec3::new(0.6, 0.0, 0.0),
            sun,
            Vec3::new(0.0, 2.0, 0.0),
            0.5
        ));
        assert!(!sphere_shadows(
            Vec3::new(0.0, 3.0, 0.0),
            sun,
            Vec3::new(0.0, 2.0, 0.0),
            0.5
        ));
    }
}
