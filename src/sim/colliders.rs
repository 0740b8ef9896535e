//! Collider motion: where each sphere is at time t. Evaluated on the CPU once per frame
//! (a handful of spheres, not per-blade data) and uploaded as `vec4(centre, radius)`.

use glam::{Vec2, Vec3};

use crate::field::HeightField;
use crate::scene::{Motion, Sphere};

/// Centre and radius of every collider at time `time`, as the shaders read them.
pub fn spheres_at(colliders: &[Sphere], terrain: &HeightField, time: f32) -> Vec<[f32; 4]> {
    colliders
        .iter()
        .map(|s| {
            let c = position(s, terrain, time);
            [c.x, c.y, c.z, s.radius]
        })
        .collect()
}

/// Centre of one collider at `time`.
pub fn position(sphere: &Sphere, terrain: &HeightField, time: f32) -> Vec3 {
    let c = Vec3::from(sphere.center);
    match &sphere.motion {
        Motion::Static => c,
        Motion::Velocity(v) => c + Vec3::from(*v) * time,
        Motion::Path {
            points,
            speed,
            looped,
        } => {
            let p = along_path(points, *looped, speed * time);
            // Rolling: the ball rests on the ground below its centre.
            Vec3::new(p.x, terrain.height(p.x, p.y) + sphere.radius + c.y, p.y)
        }
    }
}

/// The point at arc length `s` along a polyline of (x, z) points; a looped path wraps, an
/// open one stops at its end.
pub fn along_path(points: &[(f32, f32)], looped: bool, s: f32) -> Vec2 {
    let pts: Vec<Vec2> = points.iter().map(|&(x, z)| Vec2::new(x, z)).collect();
    if pts.is_empty() {
        return Vec2::ZERO;
    }
    let mut segments: Vec<(Vec2, Vec2)> = pts.windows(2).map(|w| (w[0], w[1])).collect();
    if looped && pts.len() > 2 {
        segments.push((pts[pts.len() - 1], pts[0]));
    }
    let total: f32 = segments.iter().map(|(a, b)| a.distance(*b)).sum();
    if total <= 0.0 {
        return pts[0];
    }
    let mut s = if looped {
        s.rem_euclid(total)
    } else {
        s.clamp(0.0, total)
    };
    for (a, b) in &segments {
        let len = a.distance(*b);
        if s <= len {
            return a.lerp(*b, if len > 0.0 { s / len } else { 0.0 });
        }
        s -= len;
    }
    segments.last().map(|(_, b)| *b).unwrap_or(pts[0])
}
