//! The camera: eye, target and lens, turned into the view-projection matrix (right-handed,
//! depth 0..1 as wgpu expects).

use glam::{Mat4, Vec3};

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// World position of the camera (m).
    pub eye: Vec3,
    /// World point the camera looks at (m); the view direction is `target − eye`.
    pub target: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    /// Distance to the near clip plane (m, > 0); maps to depth 0.
    pub near: f32,
    /// Distance to the far clip plane (m); maps to depth 1.
    pub far: f32,
}

impl CameraView {
    /// From the scene's camera block.
    pub fn from_scene(c: &crate::scene::Camera) -> Self {
        Self {
            eye: c.eye.into(),
            target: c.target.into(),
            fov_y: c.fov_y,
            near: c.near,
            far: c.far,
        }
    }

    /// The view-projection matrix for a viewport of the given aspect ratio.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let forward = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        // Looking straight up or down needs another up vector for look_at.
        let up = if forward.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, up);
        // wgpu's clip space is DirectX's: depth in [0, 1], y up.
        let proj = glam::camera::rh::proj::directx::perspective(
            self.fov_y.to_radians(),
            aspect.max(1e-4),
            self.near,
            self.far,
        );
        proj * view
    }

    /// The view-projection of the same camera moved to the origin: applied to positions
    /// relative to the eye, it keeps their precision far from the world origin (the
    /// terrain is drawn this way; its vertices are world positions minus the eye).
    pub fn view_proj_relative(&self, aspect: f32) -> Mat4 {
        Self {
            eye: Vec3::ZERO,
            target: self.target - self.eye,
            ..*self
        }
        .view_proj(aspect)
    }
}

/// How far back (s) the camera behind an object looks for the way it came: a path's corner
/// turns the view over this long instead of at once.
pub const FOLLOW_LAG: f32 = 0.75;

/// The view of `base`'s lens from behind object `follow.object` of `objects` at `time`
/// (`camera.follow`): `distance` behind its origin along the way it moved over the last
/// [`FOLLOW_LAG`] seconds (its facing while it stands), `height` above it, looking at the
/// point `look_height` above it; the eye at least 0.3 m above the terrain. `base` unchanged
/// when the object does not exist.
pub fn follow_view(
    base: &CameraView,
    follow: &crate::scene::CameraFollow,
    objects: &[crate::scene::MeshObject],
    terrain: &crate::field::HeightField,
    time: f32,
) -> CameraView {
    use crate::sim::colliders::{object_origin, object_transform};
    let Some(o) = objects.get(follow.object as usize) else {
        return *base;
    };
    let now = object_origin(o, terrain, time);
    let before = object_origin(o, terrain, (time - FOLLOW_LAG).max(0.0));
    let mut way = glam::Vec2::new(now.x - before.x, now.z - before.z);
    if way.length_squared() < 1e-6 {
        let f = object_transform(o, terrain, time).transform_vector3(Vec3::Z);
        way = glam::Vec2::new(f.x, f.z);
    }
    let way = way.normalize_or(glam::Vec2::Y);
    let mut eye = now - Vec3::new(way.x, 0.0, way.y) * follow.distance + Vec3::Y * follow.height;
    eye.y = eye.y.max(terrain.height(eye.x, eye.z) + 0.3);
    let target = now + Vec3::Y * follow.look_height;
    if !(eye.is_finite() && target.is_finite()) || eye.distance_squared(target) < 1e-8 {
        return *base;
    }
    CameraView {
        eye,
        target,
        ..*base
    }
}

/// The clip-space crop that shows the part of a view from normalised x = `x0` to the right
/// edge (x = 1) across a whole target: applied after the projection, it scales and shifts
/// x so that [`x0`, 1] maps to [-1, 1] and leaves y, z and w alone. A pixel's world point
/// is the one the uncropped view shows at the same place of the part, so a window that
/// draws its 3D view beside a panel keeps its camera, picking and blade sizes. x0 = -1
/// is the identity.
pub fn crop_x(x0: f32) -> Mat4 {
    let x0 = x0.clamp(-1.0, 0.99);
    let scale = 2.0 / (1.0 - x0);
    let centre = (1.0 + x0) * 0.5;
    // x' = scale * (x - centre * w): column-major, the translation scales w.
    Mat4::from_cols(
        glam::Vec4::new(scale, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, 1.0, 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, 1.0, 0.0),
        glam::Vec4::new(-scale * centre, 0.0, 0.0, 1.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The camera behind an object on a path: behind it along its way, at the heights
    /// asked, above the ground; turning at a corner over FOLLOW_LAG; the base camera when
    /// the object does not exist.
    #[test]
    fn the_follow_camera_stays_behind_the_object_along_its_way() {
        use crate::scene::{CameraFollow, MeshObject, Motion};
        let terrain = crate::field::HeightField::flat(200.0, 3);
        let walker = MeshObject {
            mesh: "walker.gltf".into(),
            motion: Motion::Path {
                points: vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)],
                speed: 1.0,
                looped: false,
            },
            ..Default::default()
        };
        let base = CameraView {
            eye: Vec3::new(50.0, 5.0, 50.0),
            target: Vec3::ZERO,
            fov_y: 50.0,
            near: 0.1,
            far: 100.0,
        };
        let follow = CameraFollow {
            object: 0,
            distance: 4.0,
            height: 2.0,
            look_height: 1.0,
        };
        let objects = [walker];
        // At 5 s it is at (5, 0) going +x: the eye 4 m back along x, 2 m up.
        let v = follow_view(&base, &follow, &objects, &terrain, 5.0);
        assert!(
            (v.eye - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-4,
            "{}",
            v.eye
        );
        assert!((v.target - Vec3::new(5.0, 1.0, 0.0)).length() < 1e-4);
        assert_eq!((v.fov_y, v.near, v.far), (50.0, 0.1, 100.0));
        // Past the corner by more than the lag, it looks along +z.
        let v = follow_view(&base, &follow, &objects, &terrain, 12.0);
        assert!(
            (v.eye - Vec3::new(10.0, 2.0, -2.0)).length() < 1e-4,
            "{}",
            v.eye
        );
        // Just past the corner, the view is turning: between the two.
        let v = follow_view(&base, &follow, &objects, &terrain, 10.3);
        let back = (v.target - v.eye) * Vec3::new(1.0, 0.0, 1.0);
        assert!(back.x > 0.0 && back.z > 0.0, "{back}");
        // A camera under the ground is lifted; a missing object leaves the base camera.
        let low = CameraFollow {
            height: -5.0,
            ..follow.clone()
        };
        assert!(follow_view(&base, &low, &objects, &terrain, 5.0).eye.y >= 0.3 - 1e-6);
        let gone = CameraFollow {
            object: 3,
            ..follow
        };
        assert_eq!(follow_view(&base, &gone, &objects, &terrain, 5.0), base);
    }

    /// The cropped view shows at each pixel of its part what the whole view shows at the
    /// same window pixel: a point at normalised x in [x0, 1] lands at (x - x0) / (1 - x0)
    /// across the part, y and depth unchanged.
    #[test]
    fn a_crop_shows_the_same_points_at_the_same_window_pixels() {
        let cam = CameraView {
            eye: Vec3::new(1.0, 2.0, 5.0),
            target: Vec3::new(0.0, 0.0, 0.0),
            fov_y: 55.0,
            near: 0.1,
            far: 100.0,
        };
        let full = cam.view_proj(16.0 / 9.0);
        let x0 = -0.46;
        let cropped = crop_x(x0) * full;
        for p in [
            Vec3::new(0.3, 0.1, -0.4),
            Vec3::new(-1.0, 0.5, 1.0),
            Vec3::new(2.0, -0.2, 0.0),
        ] {
            let a = full.project_point3(p);
            let b = cropped.project_point3(p);
            let expected = (a.x - x0) / (1.0 - x0) * 2.0 - 1.0;
            assert!((b.x - expected).abs() < 1e-5, "{a} {b}");
            assert!((b.y - a.y).abs() < 1e-6 && (b.z - a.z).abs() < 1e-6);
        }
        assert!(crop_x(-1.0).abs_diff_eq(Mat4::IDENTITY, 1e-6));
    }
}
