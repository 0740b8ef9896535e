//! The ranges and checks of moving objects: `colliders` and the [`Motion`] they share with
//! `wind.downwash`.

use glam::Vec2;

use super::allowed::{Allowed, Rule};
use super::{tuple3, Checker};
use crate::error::Result;
use crate::scene::types::{Motion, Sphere};

/// Where things may be: ten times the largest terrain in every direction. Further out f32
/// positions lose the centimetres a blade needs, and squared distances stay far from
/// overflow.
pub(super) const POSITION: Allowed = Allowed::closed(-100000.0, 100000.0, "m");
/// Speeds up to 1000 m/s (three times the speed of sound) keep a collider within
/// `POSITION` of its start for minutes and its swept sphere finite.
const VELOCITY: Allowed = Allowed::closed(-1000.0, 1000.0, "m/s");
pub(super) const SPEED: Allowed = Allowed::closed(0.0, 1000.0, "m/s");
const RADIUS: Allowed = Allowed::open_closed(0.0, 1000.0, "m");
pub(super) const MOTION_TEXT: &str =
    "Static, Velocity((x, y, z)) or Path(points: [(x, z), ..], speed: .., looped: ..)";

/// The rules of a motion at `prefix` (e.g. `colliders[].motion`), for the tables.
macro_rules! motion_rules {
    ($prefix:literal) => {
        [
            ($prefix, Rule::Choice(super::objects::MOTION_TEXT)),
            (
                concat!($prefix, ".points"),
                Rule::Text(
                    "at least 2 (x, z) points with -100000 <= x, z <= 100000 m, not all at one \
                     place",
                ),
            ),
            (
                concat!($prefix, ".points[]"),
                Rule::Vector(super::objects::POSITION),
            ),
            (
                concat!($prefix, ".speed"),
                Rule::Real(super::objects::SPEED),
            ),
            (concat!($prefix, ".looped"), Rule::Bool),
        ]
    };
}
pub(super) use motion_rules;

/// The rules of every collider value.
pub(super) const RULES: &[(&str, Rule)] = &{
    let motion = motion_rules!("colliders[].motion");
    [
        (
            "colliders",
            Rule::Text("a list of spheres (center: (x, y, z), radius: .., motion: ..)"),
        ),
        (
            "colliders[]",
            Rule::Text("(center: (x, y, z), radius: .., motion: ..)"),
        ),
        ("colliders[].center", Rule::Vector(POSITION)),
        ("colliders[].radius", Rule::Real(RADIUS)),
        motion[0],
        motion[1],
        motion[2],
        motion[3],
        motion[4],
    ]
};

pub(super) fn collider(check: &Checker, i: usize, sphere: &Sphere) -> Result<()> {
    let at = |name: &str| format!("colliders[{i}].{name}");
    check.vector(&at("center"), &tuple3(sphere.center), POSITION)?;
    check.real(&at("radius"), sphere.radius, RADIUS)?;
    motion(check, &at("motion"), &sphere.motion)
}

/// A moving object's motion (`field` is its path, e.g. `colliders[0].motion` or
/// `wind.downwash.motion`). A path of coincident points has no direction to roll along
/// (and dividing by its length would give NaN positions).
pub(super) fn motion(check: &Checker, field: &str, motion: &Motion) -> Result<()> {
    match motion {
        Motion::Static => Ok(()),
        Motion::Velocity(v) => check.vector(field, &tuple3(*v), VELOCITY),
        Motion::Path {
            points,
            speed,
            looped: _,
        } => {
            let name = format!("{field}.points");
            if points.len() < 2 {
                return Err(check.error(
                    &name,
                    format!(
                        "{name} has {} point(s): a path needs at least 2",
                        points.len()
                    ),
                ));
            }
            for (k, p) in points.iter().enumerate() {
                check.vector(&format!("{name}[{k}]"), &[p.0, p.1], POSITION)?;
            }
            // Coincident points give no direction to move along.
            let length: f32 = points
                .windows(2)
                .map(|w| Vec2::from(w[0]).distance(Vec2::from(w[1])))
                .sum();
            if length <= 0.0 {
                return Err(check.error(
                    &name,
                    format!("{name}: all points coincide: a path needs a length > 0 m"),
                ));
            }
            check.real(&format!("{field}.speed"), *speed, SPEED)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::rejected;
    use crate::scene::{Motion, Sphere};

    fn sphere(motion: Motion) -> Sphere {
        Sphere {
            center: (0.0, 0.5, 0.0),
            radius: 0.5,
            motion,
        }
    }

    fn path(points: Vec<(f32, f32)>, speed: f32) -> Motion {
        Motion::Path {
            points,
            speed,
            looped: false,
        }
    }

    #[test]
    fn colliders_are_checked() {
        let m = rejected(|s| {
            s.colliders.push(sphere(Motion::Static));
            s.colliders.push(Sphere {
                radius: -1.0,
                ..sphere(Motion::Static)
            });
        });
        assert_eq!(
            m,
            "colliders[1].radius = -1 is out of range: allowed 0 < radius <= 1000 m"
        );
        let m = rejected(|s| s.colliders.push(sphere(path(vec![(0.0, 0.0)], 1.0))));
        assert_eq!(
            m,
            "colliders[0].motion.points has 1 point(s): a path needs at least 2"
        );
        let m = rejected(|s| {
            s.colliders
                .push(sphere(path(vec![(1.0, 1.0), (1.0, 1.0)], 1.0)))
        });
        assert!(m.contains("all points coincide"), "{m}");
        let m = rejected(|s| {
            s.colliders
                .push(sphere(path(vec![(0.0, 0.0), (1.0, f32::NAN)], 1.0)))
        });
        assert!(
            m.starts_with("colliders[0].motion.points[1] = (1, NaN)"),
            "{m}"
        );
        let m = rejected(|s| {
            s.colliders
                .push(sphere(path(vec![(0.0, 0.0), (1.0, 0.0)], -2.0)))
        });
        assert!(m.starts_with("colliders[0].motion.speed = -2"), "{m}");
        let m = rejected(|s| {
            s.colliders
                .push(sphere(Motion::Velocity((f32::INFINITY, 0.0, 0.0))))
        });
        assert!(
            m.starts_with("colliders[0].motion = (inf, 0, 0) is not finite"),
            "{m}"
        );
    }

    #[test]
    fn positions_and_velocities_are_bounded() {
        let m = rejected(|s| {
            s.colliders.push(Sphere {
                center: (0.0, 2e5, 0.0),
                ..sphere(Motion::Static)
            })
        });
        assert_eq!(
            m,
            "colliders[0].center = (0, 200000, 0) is out of range: allowed -100000 <= center \
             <= 100000 m for every component"
        );
        let m = rejected(|s| s.colliders.push(sphere(Motion::Velocity((0.0, 0.0, 1e38)))));
        assert_eq!(
            m,
            "colliders[0].motion = (0, 0, 100000000000000000000000000000000000000) is out of \
             range: allowed -1000 <= motion <= 1000 m/s for every component"
        );
        let m = rejected(|s| {
            s.colliders
                .push(sphere(path(vec![(0.0, 0.0), (1.0, 0.0)], 1001.0)))
        });
        assert_eq!(
            m,
            "colliders[0].motion.speed = 1001 is out of range: allowed 0 <= speed <= 1000 m/s"
        );
    }
}
