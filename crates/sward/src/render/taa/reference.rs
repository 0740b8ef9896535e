//! The TAA pass's CPU twin (`shaders/taa.wgsl`, `fs_taa`), and a frame of the pass read
//! back from the GPU to check it against ([`TaaFrame`], [`super::TaaPass::read_frame`]).
//!
//! The twin follows the shader step by step in f32: the neighbourhood's box narrowed to
//! mean ± σ, the surface's point from the depth and the inverted jittered view, the
//! moving colliders' and the blade's motion, the last view's projection, the Catmull-Rom read of the history as five bilinear
//! reads (clamped to the edge, as the sampler is), the clamp in the compressed space and
//! the blend in linear radiance.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::TaaUniforms;
use crate::sim::layout::Blade;

/// One TAA frame's inputs and outputs as the GPU held them (row-major texels).
#[derive(Clone, Debug)]
pub struct TaaFrame {
    /// Width and height of every image here, in pixels.
    pub size: (u32, u32),
    /// The uniforms the pass was run with.
    pub uniforms: TaaUniforms,
    /// This frame's radiance (before the pass).
    pub scene: Vec<[f32; 4]>,
    /// This frame's depth buffer (device depth, 0 near to 1 far), one value per pixel.
    pub depth: Vec<f32>,
    /// The visibility buffer, where the grass was deferred.
    pub vis: Option<Vec<[u32; 4]>>,
    /// The blade buffer the pass read (this frame's blade positions).
    pub blades: Vec<Blade>,
    /// The blades' control points at the last frame, slot for slot with `blades`
    /// (`up_stiffness` zeroed: not kept).
    pub prev_blades: Vec<Blade>,
    /// The history the pass read.
    pub history: Vec<[f32; 4]>,
    /// What the pass wrote.
    pub output: Vec<[f32; 4]>,
}

/// The shader's constants (twins of `taa.wgsl`'s).
const MOVING_BLEND: f32 = 0.3;
const MOVING_PIXELS: f32 = 2.0;
const ON_SPHERE: f32 = 0.05;

fn squash(c: Vec3) -> Vec3 {
    c / (1.0 + c.max_element())
}

fn unsquash(c: Vec3) -> Vec3 {
    c / (1.0 - c.max_element()).max(1e-4)
}

/// The twin's result at one pixel (rgb, alpha).
pub fn pixel(f: &TaaFrame, x: u32, y: u32) -> [f32; 4] {
    let u = &f.uniforms;
    let (w, h) = f.size;
    let at = |x: i32, y: i32| {
        (y.clamp(0, h as i32 - 1) as u32 * w + x.clamp(0, w as i32 - 1) as u32) as usize
    };
    let scene = |x: i32, y: i32| Vec4::from(f.scene[at(x, y)]);
    let current = scene(x as i32, y as i32);
    let now = squash(current.truncate().max(Vec3::ZERO));
    let (mut lo, mut hi) = (now, now);
    let (mut m1, mut m2) = (Vec3::ZERO, Vec3::ZERO);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let c = squash(
                scene(x as i32 + dx, y as i32 + dy)
                    .truncate()
                    .max(Vec3::ZERO),
            );
            lo = lo.min(c);
            hi = hi.max(c);
            m1 += c;
            m2 += c * c;
        }
    }
    let mean = m1 / 9.0;
    let sigma = (m2 / 9.0 - mean * mean).max(Vec3::ZERO).sqrt();
    let lo = lo.max(mean - sigma);
    let hi = hi.min(mean + sigma);
    let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
    let found = history_uv(f, x, y, centre);
    let mut blend = 1.0;
    let mut past = now;
    if found.z > 0.5 {
        past = squash(history_cubic(f, Vec2::new(found.x, found.y)));
        blend = u.params[0];
        if u.jitter[2] > 0.5 {
            past = past.clamp(lo, hi);
            let size = Vec2::new(u.params[2], u.params[3]);
            let moved = (Vec2::new(found.x, found.y) * size - centre).length();
            blend = blend + (MOVING_BLEND - blend) * (moved / MOVING_PIXELS).clamp(0.0, 1.0);
        }
    }
    let past = unsquash(past);
    let out = past + (current.truncate().max(Vec3::ZERO) - past) * blend;
    [out.x, out.y, out.z, current.w]
}

/// `history_uv` of the shader.
fn history_uv(f: &TaaFrame, x: u32, y: u32, centre: Vec2) -> Vec3 {
    let u = &f.uniforms;
    let size = Vec2::new(u.params[2], u.params[3]);
    let i = (y * f.size.0 + x) as usize;
    let d = f.depth[i];
    let ndc = Vec2::new(centre.x / size.x * 2.0 - 1.0, 1.0 - centre.y / size.y * 2.0);
    let inv = Mat4::from_cols_array_2d(&u.inv_view_proj);
    let w = inv * Vec4::new(ndc.x, ndc.y, d, 1.0);
    let mut p = w.truncate() / w.w;
    let none = Vec3::ZERO;
    if u.eye_shift[3] < 0.5 {
        return none;
    }
    for k in 0..u.jitter[3] as usize {
        let now = Vec4::from(u.moving[2 * k]);
        if (p.distance(now.truncate()) - now.w).abs() <= ON_SPHERE * now.w {
            p += Vec4::from(u.moving[2 * k + 1]).truncate() - now.truncate();
            break;
        }
    }
    if u.params[1] > 0.5 {
        if let Some(vis) = &f.vis {
            let v = vis[i];
            if v[3] == 1 && f32::from_bits(v[2]) == d {
                let b = &f.blades[v[0] as usize];
                let pb = &f.prev_blades[v[0] as usize];
                if b.v0_dir != pb.v0_dir {
                    return none;
                }
                let t = (v[1] >> 16) as f32 / 65535.0;
                let v1 = Vec3::from_slice(&pb.v1_height[..3]) - Vec3::from_slice(&b.v1_height[..3]);
                let v2 = Vec3::from_slice(&pb.v2_width[..3]) - Vec3::from_slice(&b.v2_width[..3]);
                p += 2.0 * t * (1.0 - t) * v1 + t * t * v2;
            }
        }
    }
    let then = p + Vec3::from_slice(&u.eye_shift[..3]);
    let c = Mat4::from_cols_array_2d(&u.prev_view_proj) * then.extend(1.0);
    if c.w <= 0.0 {
        return none;
    }
    let ndc_then = Vec2::new(c.x, c.y) / c.w + Vec2::new(u.jitter[0], u.jitter[1]);
    let uv = Vec2::new(ndc_then.x * 0.5 + 0.5, 0.5 - ndc_then.y * 0.5);
    if uv.x < 0.0 || uv.y < 0.0 || uv.x > 1.0 || uv.y > 1.0 {
        return none;
    }
    Vec3::new(uv.x, uv.y, 1.0)
}

/// A bilinear read of the history at `uv`, clamped to the edge (the sampler's).
fn bilinear(f: &TaaFrame, uv: Vec2) -> Vec3 {
    let (w, h) = (f.size.0 as i32, f.size.1 as i32);
    let p = uv * Vec2::new(w as f32, h as f32) - 0.5;
    let base = p.floor();
    let t = p - base;
    let texel = |dx: i32, dy: i32| {
        let x = (base.x as i32 + dx).clamp(0, w - 1);
        let y = (base.y as i32 + dy).clamp(0, h - 1);
        Vec4::from(f.history[(y * w + x) as usize]).truncate()
    };
    let top = texel(0, 0).lerp(texel(1, 0), t.x);
    let bottom = texel(0, 1).lerp(texel(1, 1), t.x);
    top.lerp(bottom, t.y)
}

/// `history_cubic` of the shader: Catmull-Rom as five bilinear reads.
fn history_cubic(f: &TaaFrame, uv: Vec2) -> Vec3 {
    let size = Vec2::new(f.uniforms.params[2], f.uniforms.params[3]);
    let p = uv * size;
    let tc = (p - 0.5).floor() + 0.5;
    let t = p - tc;
    let w0 = t * (-0.5 + t * (1.0 - 0.5 * t));
    let w1 = 1.0 + t * t * (-2.5 + 1.5 * t);
    let w2 = t * (0.5 + t * (2.0 - 1.5 * t));
    let w3 = t * t * (-0.5 + 0.5 * t);
    let w12 = w1 + w2;
    let t0 = (tc - 1.0) / size;
    let t3 = (tc + 2.0) / size;
    let t12 = (tc + w2 / w12) / size;
    let reads = [
        (Vec2::new(t12.x, t0.y), w12.x * w0.y),
        (Vec2::new(t0.x, t12.y), w0.x * w12.y),
        (t12, w12.x * w12.y),
        (Vec2::new(t3.x, t12.y), w3.x * w12.y),
        (Vec2::new(t12.x, t3.y), w12.x * w3.y),
    ];
    let (mut sum, mut total) = (Vec3::ZERO, 0.0);
    for (at, weight) in reads {
        sum += bilinear(f, at) * weight;
        total += weight;
    }
    (sum / total).max(Vec3::ZERO)
}

/// The twin over the whole frame, row-major.
pub fn frame(f: &TaaFrame) -> Vec<[f32; 4]> {
    let mut colours = Vec::with_capacity(f.output.len());
    for y in 0..f.size.1 {
        for x in 0..f.size.0 {
            colours.push(pixel(f, x, y));
        }
    }
    colours
}

/// A half-float's value (the scene target and the history are half floats).
pub fn f16_to_f32(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_decode() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert!(f16_to_f32(0x7c00).is_infinite());
    }
}
