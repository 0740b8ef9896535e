//! Collider motion: where each sphere is at time t, the scene's own and those packed into
//! mesh objects (which move with their object). Evaluated on the CPU once per frame (at
//! most `MAX_SPHERES` spheres, not per-blade data) and uploaded as `vec4(centre, radius)`.

use glam::{Vec2, Vec3};

use crate::field::HeightField;
use crate::mesh::pack::Packing;
use crate::scene::{MeshObject, Motion, Sphere};
use crate::sim::wind_layout::ObstacleGpu;

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

/// Where a mesh object's origin is at `time`: at its translation, moved by its velocity,
/// or along its path with `translation.y` above the ground under it.
pub fn object_origin(object: &MeshObject, terrain: &HeightField, time: f32) -> Vec3 {
    if let Some(pose) = &object.pose {
        return pose.origin;
    }
    let t = Vec3::from(object.translation);
    match &object.motion {
        Motion::Static => t,
        Motion::Velocity(v) => t + Vec3::from(*v) * time,
        Motion::Path {
            points,
            speed,
            looped,
        } => {
            let p = along_path(points, *looped, speed * time);
            Vec3::new(p.x, terrain.height(p.x, p.y) + t.y, p.y)
        }
    }
}

/// The object-to-world transform of `object` at `time`: placed at [`object_origin`], and
/// for a rolling object on a path turned by the distance travelled over its rolling
/// radius about the horizontal axis across its heading.
pub fn object_transform(object: &MeshObject, terrain: &HeightField, time: f32) -> glam::Mat4 {
    let origin = object_origin(object, terrain, time);
    let rest = object.transform_at(origin);
    if let Some(pose) = &object.pose {
        return turned(origin, pose.yaw, rest);
    }
    let Motion::Path {
        points,
        speed,
        looped,
    } = &object.motion
    else {
        return rest;
    };
    let radius = object.translation.1;
    if object.animation.is_some() && !object.rolls {
        // A character walks facing its way: its +z turned to the path's heading.
        let s = speed * time;
        let ahead = along_path(points, *looped, s + 0.01);
        let behind = along_path(points, *looped, s - 0.01);
        let heading = ahead - behind;
        if heading.length_squared() < 1e-12 {
            return rest;
        }
        return turned(origin, heading.x.atan2(heading.y), rest);
    }
    if !object.rolls || radius <= 0.0 {
        return rest;
    }
    // Distance travelled (clamped at an open path's end) and the heading there.
    let s = speed * time;
    let ahead = along_path(points, *looped, s + 0.01);
    let behind = along_path(points, *looped, s - 0.01);
    let heading = (ahead - behind).normalize_or_zero();
    let travelled = path_distance(points, *looped, s);
    let axis = Vec3::Y.cross(Vec3::new(heading.x, 0.0, heading.y));
    if axis.length_squared() < 1e-12 {
        return rest;
    }
    // Whole turns change nothing: reduced to one turn the angle stays exact and finite
    // however far the object has rolled (validation keeps the radius ≥ 1 mm).
    let angle = (travelled / radius).rem_euclid(std::f32::consts::TAU);
    let angle = if angle.is_finite() { angle } else { 0.0 };
    let roll = glam::Quat::from_axis_angle(axis.normalize(), angle);
    glam::Mat4::from_translation(origin)
        * glam::Mat4::from_quat(roll)
        * glam::Mat4::from_translation(-origin)
        * rest
}

/// `rest` turned by `yaw` about the vertical through `origin`: the object's +z then faces
/// (sin yaw, 0, cos yaw).
fn turned(origin: Vec3, yaw: f32, rest: glam::Mat4) -> glam::Mat4 {
    glam::Mat4::from_translation(origin)
        * glam::Mat4::from_quat(glam::Quat::from_rotation_y(yaw))
        * glam::Mat4::from_translation(-origin)
        * rest
}

/// How far along a path an object has gone at arc length `s` (an open path stops at its
/// end; a looped one keeps counting).
fn path_distance(points: &[(f32, f32)], looped: bool, s: f32) -> f32 {
    if looped {
        return s.max(0.0);
    }
    let total: f32 = points
        .windows(2)
        .map(|w| Vec2::from(w[0]).distance(Vec2::from(w[1])))
        .sum();
    s.clamp(0.0, total)
}

/// The time into its animation an animated object is at `time` seconds into the scene: on
/// a `Path` with a `stride`, the distance travelled over the stride in cycles of the
/// animation's `duration` (a walk keeps pace with the ground); a steered object's pose
/// sets it; otherwise `time`.
pub fn animation_time(object: &MeshObject, duration: f32, time: f32) -> f32 {
    if let Some(pose) = &object.pose {
        return pose.animation_time;
    }
    match &object.motion {
        Motion::Path {
            points,
            speed,
            looped,
        } if object.stride > 0.0 => {
            path_distance(points, *looped, speed * time) / object.stride * duration
        }
        _ => time,
    }
}

/// The spheres of every packed object at `time` (`packings[i]` is object i's packing in
/// its mesh's units, `None` without a collider), as `vec4(centre, radius)` in the world.
pub fn object_spheres_at(
    objects: &[MeshObject],
    packings: &[Option<Packing>],
    terrain: &HeightField,
    time: f32,
) -> Vec<[f32; 4]> {
    let mut out = Vec::new();
    for (object, packing) in objects.iter().zip(packings) {
        let Some(packing) = packing else { continue };
        let m = object_transform(object, terrain, time);
        // An animated object's spheres take its pose first (its legs' spheres swing).
        let posed = packing.rig.as_ref().map(|r| {
            let duration = r.mesh.animations[r.animation].duration;
            r.posed(&packing.spheres, animation_time(object, duration, time))
        });
        for s in posed.as_deref().unwrap_or(&packing.spheres) {
            let c = m.transform_point3(Vec3::new(s[0], s[1], s[2]));
            out.push([c.x, c.y, c.z, s[3] * object.scale]);
        }
    }
    out
}

/// The packed objects' spheres as obstacles of the wind at `time`, each with the velocity
/// of a central difference over ±1/120 s (as the colliders' in `agc::fluid_forces`).
pub fn object_obstacles(
    objects: &[MeshObject],
    packings: &[Option<Packing>],
    terrain: &HeightField,
    time: f32,
) -> Vec<ObstacleGpu> {
    const H: f32 = 1.0 / 120.0;
    let t0 = (time - H).max(0.0).min(time);
    let t1 = t0 + 2.0 * H;
    let (a, b, now) = (
        object_spheres_at(objects, packings, terrain, t0),
        object_spheres_at(objects, packings, terrain, t1),
        object_spheres_at(objects, packings, terrain, time),
    );
    // A steered object stands still in the scene's clock: its pose carries its velocity.
    let steered: Vec<Vec3> = objects
        .iter()
        .zip(packings)
        .filter_map(|(o, p)| p.as_ref().map(|p| (o, p.spheres.len())))
        .flat_map(|(o, n)| std::iter::repeat_n(o.pose.map_or(Vec3::ZERO, |pose| pose.velocity), n))
        .collect();
    now.iter()
        .zip(a.iter().zip(&b))
        .zip(&steered)
        .map(|((s, (a, b)), carried)| {
            let v =
                (Vec3::new(b[0], b[1], b[2]) - Vec3::new(a[0], a[1], a[2])) / (t1 - t0) + *carried;
            ObstacleGpu {
                circle: [s[0], s[2], s[3], s[1] - terrain.height(s[0], s[2])],
                velocity: [v.x, v.z, v.y, 0.0],
            }
        })
        .collect()
}
