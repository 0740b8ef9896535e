//! Rays through the frame (issue 27's bench and the window's picking): the world-space
//! ray under a pixel, the pixel of a world point, and the first point where a ray meets
//! the terrain. The window picks with them (`app::picking`); `sward bench --far-field`
//! names the ground distance of each band of rows with them.
//!
//! Rays and projections go through the renderer's own `view_proj`, so that what is picked
//! is exactly what is drawn. The matrix is inverted and applied in f64: the far plane is
//! thousands of near-plane distances away and f32 would lose the sub-pixel agreement
//! between [`screen_ray`] and [`project`].

use glam::{DVec3, DVec4, Mat4, Vec2, Vec3};

use crate::field::HeightField;
use crate::render::camera::CameraView;

/// A half-line in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts (m).
    pub origin: Vec3,
    /// Unit length.
    pub dir: Vec3,
}

impl Ray {
    /// The point `t` metres along the ray.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// Bisection stops once the bracket is this short (metres along the ray).
const BISECT_TOLERANCE: f32 = 1e-5;
/// Upper bound on march samples, so a pathological field (huge heights on a fine grid)
/// cannot stall a frame.
const MAX_MARCH_STEPS: usize = 1 << 20;

/// Viewport size with zero dimensions replaced by 1 (a minimised window).
fn viewport(size: (u32, u32)) -> (f64, f64) {
    (f64::from(size.0.max(1)), f64::from(size.1.max(1)))
}

/// The view-projection matrix the renderer uses for this viewport.
fn view_proj(view: &CameraView, size: (u32, u32)) -> Mat4 {
    let (w, h) = viewport(size);
    view.view_proj((w / h) as f32)
}

/// The ray from the near plane through pixel `cursor` (origin top-left, y down; pixel
/// centres at half-integers, as winit reports positions).
pub fn screen_ray(view: &CameraView, size: (u32, u32), cursor: Vec2) -> Ray {
    let fallback = Ray {
        origin: view.eye,
        dir: (view.target - view.eye).normalize_or(Vec3::NEG_Z),
    };
    let (w, h) = viewport(size);
    let inverse = view_proj(view, size).as_dmat4().inverse();
    let ndc_x = 2.0 * f64::from(cursor.x) / w - 1.0;
    let ndc_y = 1.0 - 2.0 * f64::from(cursor.y) / h;
    // wgpu depth: 0 on the near plane, 1 on the far plane.
    let near = inverse * DVec4::new(ndc_x, ndc_y, 0.0, 1.0);
    let far = inverse * DVec4::new(ndc_x, ndc_y, 1.0, 1.0);
    if near.w.abs() < 1e-300 || far.w.abs() < 1e-300 {
        return fallback;
    }
    let near = near.truncate() / near.w;
    let far = far.truncate() / far.w;
    let dir = (far - near).normalize_or_zero();
    if !(near.is_finite() && dir.is_finite()) || dir == DVec3::ZERO {
        return fallback;
    }
    Ray {
        origin: near.as_vec3(),
        dir: dir.as_vec3().normalize_or(fallback.dir),
    }
}

/// Pixel position of `world` (origin top-left, y down), or `None` when it is behind the
/// camera (or on the eye plane). Points outside the viewport still get a position.
pub fn project(view: &CameraView, size: (u32, u32), world: Vec3) -> Option<Vec2> {
    let (w, h) = viewport(size);
    let clip = view_proj(view, size).as_dmat4() * world.as_dvec3().extend(1.0);
    // w is the distance in front of the eye along the view axis.
    if clip.w.is_nan() || clip.w <= 1e-9 {
        return None;
    }
    let x = (clip.x / clip.w + 1.0) * 0.5 * w;
    let y = (1.0 - clip.y / clip.w) * 0.5 * h;
    let pixel = Vec2::new(x as f32, y as f32);
    pixel.is_finite().then_some(pixel)
}

/// Ray parameters where the ray is inside the axis-aligned box, if it crosses it.
fn slab(ray: &Ray, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let mut t0 = f32::NEG_INFINITY;
    let mut t1 = f32::INFINITY;
    for axis in 0..3 {
        let (o, d) = (ray.origin[axis], ray.dir[axis]);
        if d.abs() < 1e-12 {
            // Parallel to this pair of faces: inside for all t, or never.
            if o < min[axis] || o > max[axis] {
                return None;
            }
            continue;
        }
        let a = (min[axis] - o) / d;
        let b = (max[axis] - o) / d;
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1).then_some((t0, t1))
}

/// First point within `max_distance` of the ray origin where the ray goes from above the
/// terrain to on or below it, inside the terrain square. The ray is sampled every half
/// grid spacing (so no grid cell is skipped) between where it enters and leaves the
/// square's height range, and the crossing is bisected to 1e-5 m. A ray that starts
/// underground only counts a crossing after it has come out above the surface.
pub fn pick_terrain(ray: &Ray, terrain: &HeightField, max_distance: f32) -> Option<Vec3> {
    if !(ray.origin.is_finite() && ray.dir.is_finite()) || max_distance.is_nan() {
        return None;
    }
    let ray = Ray {
        origin: ray.origin,
        dir: ray.dir.try_normalize()?,
    };
    let half = 0.5 * terrain.size;
    let (lo, hi) = terrain.height_bounds();
    if !(half.is_finite() && half > 0.0 && lo.is_finite() && hi.is_finite()) {
        return None;
    }
    // A margin above and below so that a flat field is a slab with thickness, entered
    // strictly above the surface.
    let margin = 1e-2 + 1e-4 * (hi - lo);
    let (t_in, t_out) = slab(
        &ray,
        Vec3::new(-half, lo - margin, -half),
        Vec3::new(half, hi + margin, half),
    )?;
    let t_start = t_in.max(0.0);
    let t_end = t_out.min(max_distance);
    if t_start.is_nan() || t_end.is_nan() || t_start > t_end {
        return None;
    }
    let above = |t: f32| {
        let p = ray.at(t);
        p.y - terrain.height(p.x, p.z)
    };
    let step = 0.5 * terrain.spacing();
    let steps = if step > 0.0 {
        ((t_end - t_start) / step)
            .ceil()
            .clamp(1.0, MAX_MARCH_STEPS as f32) as usize
    } else {
        1
    };
    let mut prev_t = t_start;
    let mut prev_f = above(t_start);
    for i in 1..=steps {
        let t = t_start + (t_end - t_start) * (i as f32 / steps as f32);
        let f = above(t);
        if prev_f > 0.0 && f <= 0.0 {
            // The crossing lies in (prev_t, t]: keep `a` above and `b` on/below.
            let (mut a, mut b) = (prev_t, t);
            for _ in 0..64 {
                if b - a <= BISECT_TOLERANCE {
                    break;
                }
                let mid = 0.5 * (a + b);
                if mid <= a || mid >= b {
                    break; // f32 resolution reached
                }
                if above(mid) > 0.0 {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            let hit = ray.at(0.5 * (a + b));
            return hit.is_finite().then_some(hit);
        }
        prev_t = t;
        prev_f = f;
    }
    None
}
