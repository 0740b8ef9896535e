//! What a host hands sward every frame ([`FrameInputs`]: camera, size, time step, its
//! moving colliders, its depth, the wind) and the checks every frame's inputs pass before
//! anything is recorded, for [`super::GrassRenderer::prepare`] and
//! [`super::GrassRenderer::render_world`] alike: an input out of range is an error naming
//! the field and the allowed range, never a panic or a broken frame.

use glam::{Vec2, Vec3};

use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::render::camera::CameraView;

/// A moving object of the host that pushes the grass (and the wind, where the scene has
/// the fluid solver).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collider {
    /// World position of the sphere's centre (m).
    pub center: Vec3,
    /// Radius (m).
    pub radius: f32,
    /// Velocity (m/s).
    pub velocity: Vec3,
}

/// The directional wind this frame (replaces the scene's `wind.directional` direction and
/// strength; its gusts are kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindInput {
    /// Direction in the x/z plane (any length but zero).
    pub direction: Vec2,
    /// Mean force in m/s² (0 to 1000).
    pub strength: f32,
}

/// What a frame needs from the host.
pub struct FrameInputs<'a> {
    /// The camera the host draws with (its projection: [`CameraView::view_proj`]).
    pub camera: CameraView,
    /// The size in pixels of the host's colour and depth attachments.
    pub size: (u32, u32),
    /// Seconds since the last frame (0 to 1; larger steps are clamped by the simulation).
    pub dt: f32,
    /// The host's moving objects this frame (at most [`crate::scene::limits::MAX_SPHERES`] spheres
    /// with the scene's own).
    pub colliders: &'a [Collider],
    /// The host's depth after its opaque pass (a view of a texture with `TEXTURE_BINDING`
    /// usage and the descriptor's sample count): blades behind the host's objects are
    /// culled before they are drawn. `None`: no occlusion.
    pub depth: Option<&'a wgpu::TextureView>,
    /// The directional wind, when the host steers it.
    pub wind: Option<WindInput>,
}

/// Refuses inputs that would make the frame meaningless or unsafe.
pub(super) fn check_inputs(inputs: &FrameInputs, gpu: &Gpu) -> Result<()> {
    let c = &inputs.camera;
    let finite = c.eye.is_finite() && c.target.is_finite() && c.fov_y.is_finite();
    if !finite || c.eye == c.target {
        return Err(Error::Invalid(format!(
            "camera eye {:?} and target {:?} must be finite and apart",
            c.eye, c.target
        )));
    }
    let lens =
        c.fov_y > 0.0 && c.fov_y < 180.0 && c.near > 0.0 && c.far > c.near && c.far.is_finite();
    if !lens {
        return Err(Error::Invalid(format!(
            "camera fov_y {} (allowed 0 < fov_y < 180 degrees), near {} and far {} \
             (allowed 0 < near < far, finite)",
            c.fov_y, c.near, c.far
        )));
    }
    gpu.check_texture("the host's target", inputs.size.0, inputs.size.1)?;
    if !(inputs.dt.is_finite() && (0.0..=1.0).contains(&inputs.dt)) {
        return Err(Error::Invalid(format!(
            "dt {} is out of range: allowed 0 <= dt <= 1 s",
            inputs.dt
        )));
    }
    for (i, k) in inputs.colliders.iter().enumerate() {
        let ok = k.center.is_finite()
            && k.velocity.is_finite()
            && k.radius.is_finite()
            && k.radius > 0.0
            && k.radius <= 1000.0;
        if !ok {
            return Err(Error::Invalid(format!(
                "colliders[{i}]: centre {:?}, radius {} and velocity {:?} must be finite, \
                 with 0 < radius <= 1000 m",
                k.center, k.radius, k.velocity
            )));
        }
    }
    if let Some(w) = inputs.wind {
        let ok = w.direction.is_finite()
            && w.direction.length() > 1e-6
            && w.strength.is_finite()
            && (0.0..=1000.0).contains(&w.strength);
        if !ok {
            return Err(Error::Invalid(format!(
                "wind: direction {:?} must be finite and not zero, strength {} within \
                 0..=1000 m/s²",
                w.direction, w.strength
            )));
        }
    }
    Ok(())
}

/// Refuses a texture a frame would use wrongly: `what` names it in the error; its size must
/// be `size`, its sample count `samples`, its format one of `formats` (an sRGB format and
/// its linear twin count as one) and its usage include `usage`.
pub(super) fn check_view(
    what: &str,
    view: &wgpu::TextureView,
    size: (u32, u32),
    samples: u32,
    formats: &[wgpu::TextureFormat],
    usage: wgpu::TextureUsages,
) -> Result<()> {
    let t = view.texture();
    let (w, h) = (t.width(), t.height());
    if (w, h) != size {
        return Err(Error::Invalid(format!(
            "{what} is {w}x{h} pixels: it must be the frame's size, {}x{}",
            size.0, size.1
        )));
    }
    if t.sample_count() != samples {
        return Err(Error::Invalid(format!(
            "{what} has {} samples per pixel: it must have {samples}",
            t.sample_count()
        )));
    }
    let linear = t.format().remove_srgb_suffix();
    if !formats.iter().any(|f| f.remove_srgb_suffix() == linear) {
        return Err(Error::Invalid(format!(
            "{what} is {:?}: allowed {formats:?}",
            t.format()
        )));
    }
    if !t.usage().contains(usage) {
        return Err(Error::Invalid(format!(
            "{what} has usage {:?}: it needs {usage:?}",
            t.usage()
        )));
    }
    Ok(())
}
