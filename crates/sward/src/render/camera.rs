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
