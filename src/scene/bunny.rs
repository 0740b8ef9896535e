//! A bunny made of sphere colliders, for the paper's nature scene (Jahrmann & Wimmer 2017,
//! Section 7.1: "a bunny model, which is represented by 1000 collision spheres").
//!
//! The paper fits spheres to a mesh; sward has no mesh loader, so the bunny is built from
//! a few ellipsoids (body, head, two long ears, tail, front paws, hind feet) whose surfaces
//! are covered with overlapping spheres. Only the surface is covered: the grass meets the
//! outside of an object, and a shell reads as the object's shape when the colliders are
//! drawn. The counts per part are fixed so that the whole bunny is exactly
//! [`BUNNY_SPHERES`] spheres.
//!
//! `assets/scenes/nature.ron` holds the output of [`bunny_spheres`] pasted in by
//! [`bunny_ron`]; the test `nature_scene_holds_the_generated_bunny` keeps the two in step.

use glam::{Quat, Vec3};

use super::types::{Motion, Sphere};

/// Spheres in one bunny (the paper's count).
pub const BUNNY_SPHERES: usize = 1000;

/// One ellipsoid of the bunny in its local frame (unit scale: about 1.3 m tall with the
/// ears, standing on y = 0, looking along +x).
struct Part {
    centre: Vec3,
    /// Semi-axes before the rotation.
    radii: Vec3,
    /// Rotation of the ellipsoid about its centre (ears lean back and out).
    rotation: Quat,
    spheres: usize,
}

fn parts() -> [Part; 9] {
    let none = Quat::IDENTITY;
    // Ears lean back (about z) and away from the middle (about x) like a hare's.
    let ear = |side: f32| Part {
        centre: Vec3::new(0.26, 1.02, 0.09 * side),
        radii: Vec3::new(0.075, 0.27, 0.04),
        rotation: Quat::from_rotation_z(0.3) * Quat::from_rotation_x(0.3 * side),
        spheres: 95,
    };
    let paw = |side: f32| Part {
        centre: Vec3::new(0.33, 0.06, 0.11 * side),
        radii: Vec3::new(0.1, 0.06, 0.06),
        rotation: none,
        spheres: 20,
    };
    let foot = |side: f32| Part {
        centre: Vec3::new(-0.12, 0.07, 0.2 * side),
        radii: Vec3::new(0.2, 0.07, 0.085),
        rotation: none,
        spheres: 25,
    };
    [
        // The body sits slightly nose-up, as a resting rabbit's back slopes.
        Part {
            centre: Vec3::new(-0.04, 0.36, 0.0),
            radii: Vec3::new(0.44, 0.33, 0.3),
            rotation: Quat::from_rotation_z(0.18),
            spheres: 460,
        },
        Part {
            centre: Vec3::new(0.37, 0.7, 0.0),
            radii: Vec3::new(0.21, 0.18, 0.17),
            rotation: Quat::from_rotation_z(-0.2),
            spheres: 220,
        },
        ear(1.0),
        ear(-1.0),
        Part {
            centre: Vec3::new(-0.48, 0.36, 0.0),
            radii: Vec3::splat(0.1),
            rotation: none,
            spheres: 40,
        },
        paw(1.0),
        paw(-1.0),
        foot(1.0),
        foot(-1.0),
    ]
}

/// Surface area of an ellipsoid (Knud Thomsen's approximation, within about 1 %), to size
/// the spheres so that neighbours overlap whatever the part's proportions.
fn ellipsoid_area(r: Vec3) -> f32 {
    const P: f32 = 1.6075;
    let (a, b, c) = (r.x, r.y, r.z);
    let mean = ((a * b).powf(P) + (a * c).powf(P) + (b * c).powf(P)) / 3.0;
    4.0 * std::f32::consts::PI * mean.powf(1.0 / P)
}

/// Covers one part with `part.spheres` spheres: centres on a Fibonacci lattice over the
/// ellipsoid (even spacing without seams or poles), pulled in along the normal so that the
/// outer surface of the spheres follows the ellipsoid instead of bulging past it.
fn cover(part: &Part, out: &mut Vec<(Vec3, f32)>) {
    let n = part.spheres;
    let spacing = (ellipsoid_area(part.radii) / n as f32).sqrt();
    // 0.8 of the spacing makes neighbouring spheres overlap by about 60 %: no gaps that a
    // blade tip could slip through.
    let radius = 0.8 * spacing;
    let inset = (0.5 * radius).min(0.5 * part.radii.min_element());
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    for i in 0..n {
        let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
        let ring = (1.0 - y * y).max(0.0).sqrt();
        let phi = golden * i as f32;
        let unit = Vec3::new(ring * phi.cos(), y, ring * phi.sin());
        let surface = unit * part.radii;
        // The ellipsoid's normal is the gradient of x²/a² + y²/b² + z²/c².
        let normal = (surface / (part.radii * part.radii)).normalize_or(Vec3::Y);
        let local = surface - normal * inset;
        out.push((part.centre + part.rotation * local, radius));
    }
}

/// The bunny's spheres: standing on the horizontal plane through `center` (no sphere
/// reaches below `center.y`), looking along +x, `scale` times the unit size (about 1.3 m
/// tall, 1.1 m long). Exactly [`BUNNY_SPHERES`] static spheres.
pub fn bunny_spheres(center: Vec3, scale: f32) -> Vec<Sphere> {
    let mut local = Vec::with_capacity(BUNNY_SPHERES);
    for part in parts() {
        cover(&part, &mut local);
    }
    local
        .into_iter()
        .map(|(c, r)| {
            // Feet and paws touch the ground; lift any sphere that would sink below it.
            let c = Vec3::new(c.x, c.y.max(r), c.z);
            let world = center + c * scale;
            Sphere {
                center: (world.x, world.y, world.z),
                radius: r * scale,
                motion: Motion::Static,
            }
        })
        .collect()
}

/// The spheres as RON collider entries, one per line with millimetre precision, ready to be
/// pasted into a scene's `colliders: [...]`.
pub fn bunny_ron(center: Vec3, scale: f32) -> String {
    let mut text = String::new();
    for s in bunny_spheres(center, scale) {
        text.push_str(&format!(
            "        (center: ({:.3}, {:.3}, {:.3}), radius: {:.3}),\n",
            s.center.0, s.center.1, s.center.2, s.radius
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where `assets/scenes/nature.ron` puts its bunny, and how large.
    const NATURE_XZ: (f32, f32) = (3.0, -4.0);
    const NATURE_SCALE: f32 = 3.2;
    /// How far the bunny's plane sits below the lowest ground under it, so that it stands in
    /// the grass rather than hovering over a dip.
    const NATURE_SINK: f32 = 0.05;

    #[test]
    fn thousand_finite_spheres_on_or_above_the_plane() {
        let center = Vec3::new(1.0, 2.0, -3.0);
        let spheres = bunny_spheres(center, 2.5);
        assert_eq!(spheres.len(), BUNNY_SPHERES);
        for (i, s) in spheres.iter().enumerate() {
            let c = [s.center.0, s.center.1, s.center.2, s.radius];
            assert!(c.iter().all(|v| v.is_finite()), "sphere {i}: {c:?}");
            assert!(s.radius > 0.0, "sphere {i}: radius {}", s.radius);
            assert!(
                s.center.1 - s.radius >= center.y - 1e-4,
                "sphere {i} reaches below the plane: {c:?}"
            );
            assert_eq!(s.motion, Motion::Static);
        }
    }

    #[test]
    fn shape_has_body_head_ears_and_tail() {
        let spheres = bunny_spheres(Vec3::ZERO, 1.0);
        let top = spheres
            .iter()
            .map(|s| s.center.1 + s.radius)
            .fold(f32::MIN, f32::max);
        // Ears make the bunny taller than long.
        assert!((1.2..1.5).contains(&top), "height {top}");
        let ear_tips = |side: f32| {
            spheres
                .iter()
                .filter(|s| s.center.1 > 1.0 && s.center.2 * side > 0.0)
                .count()
        };
        assert!(ear_tips(1.0) > 10 && ear_tips(-1.0) > 10, "two ears");
        // The tail sticks out behind the body.
        assert!(spheres.iter().any(|s| s.center.0 < -0.5));
        // Symmetric about the x/y plane: as much bunny on each side.
        let left = spheres.iter().filter(|s| s.center.2 > 1e-3).count();
        let right = spheres.iter().filter(|s| s.center.2 < -1e-3).count();
        assert!(left.abs_diff(right) <= 10, "{left} vs {right}");
    }

    #[test]
    fn scale_and_centre_map_linearly() {
        let a = bunny_spheres(Vec3::ZERO, 1.0);
        let b = bunny_spheres(Vec3::new(5.0, 1.0, -2.0), 3.0);
        for (s, t) in a.iter().zip(&b) {
            assert!((t.radius - 3.0 * s.radius).abs() < 1e-5);
            assert!((t.center.0 - (5.0 + 3.0 * s.center.0)).abs() < 1e-4);
            assert!((t.center.1 - (1.0 + 3.0 * s.center.1)).abs() < 1e-4);
        }
    }

    /// The bunny's plane in the nature scene: the lowest ground under its footprint, less
    /// a little.
    fn nature_center(scene: &crate::scene::Scene) -> Vec3 {
        let terrain = crate::field::HeightField::from_scene(&scene.terrain).expect("terrain");
        let (x, z) = NATURE_XZ;
        let mut low = f32::INFINITY;
        for i in -8..=8 {
            for k in -8..=8 {
                let (dx, dz) = (
                    i as f32 * 0.1 * NATURE_SCALE,
                    k as f32 * 0.05 * NATURE_SCALE,
                );
                low = low.min(terrain.height(x + dx, z + dz));
            }
        }
        Vec3::new(x, low - NATURE_SINK, z)
    }

    fn nature_scene() -> crate::scene::Scene {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/nature.ron");
        crate::scene::load_scene(&path).expect("nature.ron loads")
    }

    #[test]
    fn nature_scene_holds_the_generated_bunny() {
        let scene = nature_scene();
        let expected = bunny_spheres(nature_center(&scene), NATURE_SCALE);
        assert!(
            scene.colliders.len() >= BUNNY_SPHERES + 2,
            "bunny and two balls"
        );
        for (i, (got, want)) in scene.colliders.iter().zip(&expected).enumerate() {
            let d = [
                got.center.0 - want.center.0,
                got.center.1 - want.center.1,
                got.center.2 - want.center.2,
                got.radius - want.radius,
            ];
            assert!(
                d.iter().all(|v| v.abs() <= 1e-3),
                "collider {i} differs from bunny_spheres: {got:?} vs {want:?}; regenerate with \
                 `cargo test --release --lib print_nature_bunny -- --ignored --nocapture`"
            );
        }
    }

    /// Prints the nature scene's bunny colliders (the RON lines pasted into
    /// `assets/scenes/nature.ron`).
    #[test]
    #[ignore = "prints the RON for assets/scenes/nature.ron"]
    fn print_nature_bunny() {
        let center = nature_center(&nature_scene());
        print!("{}", bunny_ron(center, NATURE_SCALE));
    }
}
