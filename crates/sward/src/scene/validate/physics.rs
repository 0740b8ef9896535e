//! The ranges and checks of `physics`, the parameters of the blade update (Section 5).
//!
//! The bounds keep one step of the update finite: the largest force on a tip is the
//! gravity m·g·1.25 (with front gravity) ≤ 100 · 1000 · 1.25 m/s², plus recovery and
//! wind of the same order, times Δt ≤ 1 s; the validation of the update then pulls the tip
//! back to the blade's length, dividing by a height of at least 1 cm.

use super::allowed::{Allowed, Integers, Rule};
use super::objects::POSITION;
use super::{tuple3, Checker};
use crate::error::Result;
use crate::scene::types::Physics;

/// Up to a hundred g: an extreme planet, not an overflow.
const ACCELERATION: Allowed = Allowed::closed(0.0, 1000.0, "m/s²");
const BLEND: Allowed = Allowed::closed(0.0, 1.0, "");
/// The mass m of Eq. 4 multiplies the gravity (the update never divides by it): 0 makes
/// blades weightless; the default is 0.08.
const MASS: Allowed = Allowed::closed(0.0, 100.0, "");
const DECAY: Allowed = Allowed::closed(0.0, 1000.0, "1/s");
const GAIN: Allowed = Allowed::closed(0.0, 1.0e6, "1/m²");
const CEILING: Allowed = Allowed::closed(0.0, 100.0, "");
/// Explicit Euler on the recovery term stays stable while s·scale·Δt < 2; with s up to
/// ~12 1/s and Δt ≤ 0.05 s a scale of 4 keeps that margin for the default fields.
const STIFFNESS_SCALE: Allowed = Allowed::closed(0.05, 4.0, "");
const PRECISION_DISTANCE: Allowed = Allowed::closed(0.01, 100000.0, "m");
const MAX_DT: Allowed = Allowed::open_closed(0.0, 1.0, "s");
/// Verlet damping: 0 keeps every sway (the thesis), 100/s stops a blade within a step.
const DAMPING: Allowed = Allowed::closed(0.0, 100.0, "1/s");
const WIND_GAIN: Allowed = Allowed::closed(0.0, 100.0, "");
/// Eq. 11's y = Py − k1·Py² keeps rising along the blade (Py in [0, 1]) while k1 <= 0.5.
const K1: Allowed = Allowed::closed(0.0, 0.5, "");
const K2: Allowed = Allowed::closed(0.0, 2.0, "");
const LAMBDA: Allowed = Allowed::closed(0.0, 1.0, "");
/// Blade heights per m/s: 10 bends a blade flat in a 0.1 m/s breeze.
const FORCE: Allowed = Allowed::closed(0.0, 10.0, "s/m");
const CELL: Allowed = Allowed::closed(0.01, 1000.0, "m");
const ATT: Allowed = Allowed::closed(0.0, 1.0, "");
const THRESHOLD: Allowed = Allowed::closed(0.0, 1.0, "m");
use crate::scene::limits::MAX_GENERATIONS;
const GENERATIONS: Integers = Integers::new(1, MAX_GENERATIONS as u64, "");
const PROPAGATION_CELL: Allowed = Allowed::closed(0.01, 10.0, "m");
const PROPAGATION_EXTENT: Allowed = Allowed::closed(0.1, 1000.0, "m");
const TRAIL_RESOLUTION: Integers = Integers::new(4, 128, "texels");
const TRAIL_CACHE: Integers = Integers::new(0, 65536, "tiles");
/// Cells per side of the propagation grid at most: 2048² cells of 28 bytes are 112 MiB.
const MAX_PROPAGATION_CELLS: u32 = 2048;

/// The rules of every `physics` value.
pub(super) const RULES: &[(&str, Rule)] = &[
    ("physics.gravity_direction", Rule::Direction),
    ("physics.gravity_acceleration", Rule::Real(ACCELERATION)),
    ("physics.gravity_center", Rule::Vector(POSITION)),
    (
        "physics.gravity_center_acceleration",
        Rule::Real(ACCELERATION),
    ),
    ("physics.gravity_blend", Rule::Real(BLEND)),
    ("physics.mass", Rule::Real(MASS)),
    ("physics.collision_decay", Rule::Real(DECAY)),
    ("physics.collision_gain", Rule::Real(GAIN)),
    ("physics.max_collision_strength", Rule::Real(CEILING)),
    ("physics.stiffness_scale", Rule::Real(STIFFNESS_SCALE)),
    ("physics.max_dt", Rule::Real(MAX_DT)),
    ("physics.collisions", Rule::Bool),
    ("physics.collision_hierarchy", Rule::Bool),
    (
        "physics.hierarchy_precision_distance",
        Rule::Real(PRECISION_DISTANCE),
    ),
    ("physics.model", Rule::Choice("Jahrmann, Verlet or Cwd")),
    ("physics.verlet.damping", Rule::Real(DAMPING)),
    ("physics.verlet.wind_gain", Rule::Real(WIND_GAIN)),
    ("physics.cwd.k1", Rule::Real(K1)),
    ("physics.cwd.k2", Rule::Real(K2)),
    ("physics.cwd.lambda", Rule::Real(LAMBDA)),
    ("physics.cwd.force", Rule::Real(FORCE)),
    ("physics.cwd.cell_size", Rule::Real(CELL)),
    (
        "physics.propagation",
        Rule::Text(
            "None or Some((att: .., threshold: .., generations: .., cell_size: .., extent: ..)), \
             each part optional",
        ),
    ),
    ("physics.propagation.att", Rule::Real(ATT)),
    ("physics.propagation.threshold", Rule::Real(THRESHOLD)),
    (
        "physics.propagation.generations",
        Rule::Integer(GENERATIONS),
    ),
    (
        "physics.propagation.cell_size",
        Rule::Real(PROPAGATION_CELL),
    ),
    (
        "physics.propagation.extent",
        Rule::Text("0.1 <= extent <= 1000 m, at most 2048 cells per side (extent / cell_size)"),
    ),
    (
        "physics.trails",
        Rule::Text("None or Some((resolution: .., cache_tiles: ..)), each part optional"),
    ),
    ("physics.trails.resolution", Rule::Integer(TRAIL_RESOLUTION)),
    ("physics.trails.cache_tiles", Rule::Integer(TRAIL_CACHE)),
];

pub(super) fn physics(check: &Checker, physics: &mut Physics) -> Result<()> {
    let mut direction = tuple3(physics.gravity_direction);
    check.direction("physics.gravity_direction", &mut direction)?;
    physics.gravity_direction = direction.into();
    let p = &*physics;
    check.real(
        "physics.gravity_acceleration",
        p.gravity_acceleration,
        ACCELERATION,
    )?;
    check.vector(
        "physics.gravity_center",
        &tuple3(p.gravity_center),
        POSITION,
    )?;
    let center = p.gravity_center_acceleration;
    check.real("physics.gravity_center_acceleration", center, ACCELERATION)?;
    check.real("physics.gravity_blend", p.gravity_blend, BLEND)?;
    check.real("physics.mass", p.mass, MASS)?;
    check.real("physics.collision_decay", p.collision_decay, DECAY)?;
    check.real("physics.collision_gain", p.collision_gain, GAIN)?;
    check.real(
        "physics.hierarchy_precision_distance",
        p.hierarchy_precision_distance,
        PRECISION_DISTANCE,
    )?;
    let ceiling = p.max_collision_strength;
    check.real("physics.max_collision_strength", ceiling, CEILING)?;
    check.real(
        "physics.stiffness_scale",
        p.stiffness_scale,
        STIFFNESS_SCALE,
    )?;
    check.real("physics.max_dt", p.max_dt, MAX_DT)?;
    check.real("physics.verlet.damping", p.verlet.damping, DAMPING)?;
    check.real("physics.verlet.wind_gain", p.verlet.wind_gain, WIND_GAIN)?;
    check.real("physics.cwd.k1", p.cwd.k1, K1)?;
    check.real("physics.cwd.k2", p.cwd.k2, K2)?;
    check.real("physics.cwd.lambda", p.cwd.lambda, LAMBDA)?;
    check.real("physics.cwd.force", p.cwd.force, FORCE)?;
    check.real("physics.cwd.cell_size", p.cwd.cell_size, CELL)?;
    if let Some(t) = &p.trails {
        check.integer("physics.trails.resolution", t.resolution, TRAIL_RESOLUTION)?;
        check.integer("physics.trails.cache_tiles", t.cache_tiles, TRAIL_CACHE)?;
    }
    if let Some(q) = &p.propagation {
        check.real("physics.propagation.att", q.att, ATT)?;
        check.real("physics.propagation.threshold", q.threshold, THRESHOLD)?;
        check.integer(
            "physics.propagation.generations",
            q.generations,
            GENERATIONS,
        )?;
        check.real(
            "physics.propagation.cell_size",
            q.cell_size,
            PROPAGATION_CELL,
        )?;
        check.real("physics.propagation.extent", q.extent, PROPAGATION_EXTENT)?;
        let cells = (q.extent / q.cell_size).ceil();
        if cells > MAX_PROPAGATION_CELLS as f32 {
            return Err(check.error(
                "physics.propagation.extent",
                format!(
                    "physics.propagation.extent = {} is out of range: allowed at most \
                     {MAX_PROPAGATION_CELLS} cells per side, and extent / cell_size = {} / {} \
                     is {cells}",
                    q.extent, q.extent, q.cell_size
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::tests::rejected;

    #[test]
    fn model_parameters_are_bounded() {
        assert_eq!(
            rejected(|s| s.physics.cwd.k1 = 0.6),
            "physics.cwd.k1 = 0.6 is out of range: allowed 0 <= k1 <= 0.5"
        );
        assert_eq!(
            rejected(|s| s.physics.verlet.damping = f32::NAN),
            "physics.verlet.damping = NaN is not a finite number: allowed 0 <= damping <= 100 1/s"
        );
        assert!(rejected(|s| s.physics.cwd.force = -1.0).contains("0 <= force <= 10 s/m"));
        assert!(rejected(|s| s.physics.cwd.cell_size = 0.0).contains("cell_size"));
    }

    #[test]
    fn forces_and_mass_are_bounded() {
        assert_eq!(
            rejected(|s| s.physics.mass = 1e38),
            "physics.mass = 100000000000000000000000000000000000000 is out of range: allowed \
             0 <= mass <= 100"
        );
        assert_eq!(
            rejected(|s| s.physics.gravity_acceleration = 1001.0),
            "physics.gravity_acceleration = 1001 is out of range: allowed 0 <= \
             gravity_acceleration <= 1000 m/s²"
        );
        assert_eq!(
            rejected(|s| s.physics.gravity_center_acceleration = -1.0),
            "physics.gravity_center_acceleration = -1 is out of range: allowed 0 <= \
             gravity_center_acceleration <= 1000 m/s²"
        );
        assert_eq!(
            rejected(|s| s.physics.collision_decay = 1e30),
            "physics.collision_decay = 1000000000000000000000000000000 is out of range: \
             allowed 0 <= collision_decay <= 1000 1/s"
        );
        let m = rejected(|s| s.physics.gravity_center = (0.0, -1e6, 0.0));
        assert!(
            m.starts_with("physics.gravity_center = (0, -1000000, 0) is out of range"),
            "{m}"
        );
    }
}
