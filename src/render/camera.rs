//! The camera: eye, target and lens, turned into the view-projection matrix (right-handed,
//! depth 0..1 as wgpu expects).

use glam::{Mat4, Vec3};

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    pub eye: Vec3,
    pub target: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    pub near: f32,
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
