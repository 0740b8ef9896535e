//! The ranges and checks of `wind`: the analytic directional and point winds, the fluid
//! grid and the forces that drive it (AGC guides, global wind, downwash).

use glam::Vec2;

use super::allowed::{show, Allowed, Integers, Rule};
use super::objects::{motion, motion_rules, POSITION};
use super::{tuple3, Checker};
use crate::error::Result;
use crate::scene::types::{Boundary, Fluid, Guide, PressureSolver, Wind};

/// Wind forces up to 1000 m/s² (a hundred g): far past a hurricane, and small enough that
/// a step of the update stays many orders from f32 overflow.
const FORCE: Allowed = Allowed::closed(0.0, 1000.0, "m/s²");
const GUST: Allowed = Allowed::closed(0.0, 4.0, "");
/// Gust waves shorter than 10 cm would alias on any field; longer than 100 km is a
/// constant wind.
const WAVELENGTH: Allowed = Allowed::closed(0.1, 100000.0, "m");
const SPEED: Allowed = Allowed::closed(0.0, 1000.0, "m/s");
/// The point wind and the downwash divide by their radius.
const RADIUS: Allowed = Allowed::closed(0.01, 10000.0, "m");
const FREQUENCY: Allowed = Allowed::closed(0.0, 100.0, "Hz");
const FLUID_RESOLUTION: Integers = Integers::new(8, 2048, "cells per side");
const PRESSURE_ITERATIONS: Integers = Integers::new(0, 1000, "");
/// One V-cycle already removes most of the divergence; 20 reach the f32 floor on any grid.
pub(crate) const MULTIGRID_CYCLES: Integers = Integers::new(1, 20, "");
const VORTICITY: Allowed = Allowed::closed(0.0, 1000.0, "");
const DISSIPATION: Allowed = Allowed::closed(0.0, 100.0, "1/s");
const VISCOSITY: Allowed = Allowed::closed(0.0, 10.0, "m²/s");
const DIFFUSION_ITERATIONS: Integers = Integers::new(1, 200, "");
const RESPONSE: Allowed = Allowed::closed(0.0, 100.0, "1/s");
const LAYERS: Integers = Integers::new(1, 16, "layers");
const LAYER_HEIGHT: Allowed = Allowed::closed(0.05, 100.0, "m");
const GROUND_DRAG: Allowed = Allowed::closed(0.0, 100.0, "1/s");
/// 0 (the terrain square) or the side of a grid that follows the camera, whose cells are
/// then at least MIN_CELL wide.
const EXTENT: Allowed = Allowed::closed(0.0, 100000.0, "m");
/// The smallest cell of a grid that follows the camera (m): a side of 1e-38 m made cells
/// of 1e-41 m, whose divisions by the cell size overflowed into a non-finite update.
const MIN_CELL: f32 = 0.01;
const GUIDE_RADIUS_TEXT: &str = "0 < radius <= terrain.size m";

/// The rules of every `wind` value.
pub(super) const RULES: &[(&str, Rule)] = &{
    let downwash = motion_rules!("wind.downwash.motion");
    [
        ("wind.source", Rule::Choice("one of Analytic, Fluid, Both")),
        (
            "wind.directional",
            Rule::Text(
                "None or (direction: .., strength: .., gust: .., wavelength: .., speed: ..)",
            ),
        ),
        ("wind.directional.direction", Rule::Direction),
        ("wind.directional.strength", Rule::Real(FORCE)),
        ("wind.directional.gust", Rule::Real(GUST)),
        ("wind.directional.wavelength", Rule::Real(WAVELENGTH)),
        ("wind.directional.speed", Rule::Real(SPEED)),
        (
            "wind.point",
            Rule::Text("None or (position: .., strength: .., radius: .., frequency: ..)"),
        ),
        ("wind.point.position", Rule::Vector(POSITION)),
        ("wind.point.strength", Rule::Real(FORCE)),
        ("wind.point.radius", Rule::Real(RADIUS)),
        ("wind.point.frequency", Rule::Real(FREQUENCY)),
        ("wind.fluid.resolution", Rule::Integer(FLUID_RESOLUTION)),
        (
            "wind.fluid.pressure_iterations",
            Rule::Integer(PRESSURE_ITERATIONS),
        ),
        (
            "wind.fluid.pressure_solver",
            Rule::Choice("one of Jacobi, Multigrid"),
        ),
        (
            "wind.fluid.multigrid_cycles",
            Rule::Integer(MULTIGRID_CYCLES),
        ),
        ("wind.fluid.warm_start", Rule::Bool),
        ("wind.fluid.vorticity", Rule::Real(VORTICITY)),
        ("wind.fluid.dissipation", Rule::Real(DISSIPATION)),
        ("wind.fluid.viscosity", Rule::Real(VISCOSITY)),
        (
            "wind.fluid.diffusion_iterations",
            Rule::Integer(DIFFUSION_ITERATIONS),
        ),
        (
            "wind.fluid.boundary",
            Rule::Choice("one of Closed, Open, Periodic"),
        ),
        (
            "wind.fluid.advection",
            Rule::Choice("one of SemiLagrangian, MacCormack"),
        ),
        ("wind.fluid.response", Rule::Real(RESPONSE)),
        ("wind.fluid.per_cell", Rule::Bool),
        ("wind.fluid.obstacles", Rule::Bool),
        ("wind.fluid.extent", Rule::Real(EXTENT)),
        ("wind.fluid.layers", Rule::Integer(LAYERS)),
        ("wind.fluid.layer_height", Rule::Real(LAYER_HEIGHT)),
        ("wind.fluid.ground_drag", Rule::Real(GROUND_DRAG)),
        (
            "wind.guides",
            Rule::Text("a list of guides (strength: .., radius: .., points: [..])"),
        ),
        ("wind.guides[].strength", Rule::Real(FORCE)),
        ("wind.guides[].radius", Rule::Text(GUIDE_RADIUS_TEXT)),
        (
            "wind.guides[].points",
            Rule::Text("at least 1 point (the root)"),
        ),
        (
            "wind.guides[].points[].position",
            Rule::Text("(x, z) on the terrain: -terrain.size/2 <= x, z <= terrain.size/2 m"),
        ),
        (
            "wind.guides[].points[].parent",
            Rule::Text("None for point 0, else the index of an earlier point"),
        ),
        ("wind.guides[].points[].strength", Rule::Real(FORCE)),
        (
            "wind.guides[].points[].radius",
            Rule::Text(GUIDE_RADIUS_TEXT),
        ),
        (
            "wind.global",
            Rule::Text("None or (direction: .., strength: ..)"),
        ),
        ("wind.global.direction", Rule::Direction),
        ("wind.global.strength", Rule::Real(FORCE)),
        (
            "wind.downwash",
            Rule::Text("None or (position: .., radius: .., strength: .., motion: ..)"),
        ),
        ("wind.downwash.position", Rule::Vector(POSITION)),
        ("wind.downwash.radius", Rule::Real(RADIUS)),
        ("wind.downwash.strength", Rule::Real(FORCE)),
        downwash[0],
        downwash[1],
        downwash[2],
        downwash[3],
        downwash[4],
    ]
};

pub(super) fn wind(check: &Checker, wind: &mut Wind, terrain_size: f32) -> Result<()> {
    if let Some(d) = &mut wind.directional {
        let mut direction = [d.direction.0, d.direction.1];
        check.direction("wind.directional.direction", &mut direction)?;
        d.direction = direction.into();
        check.real("wind.directional.strength", d.strength, FORCE)?;
        check.real("wind.directional.gust", d.gust, GUST)?;
        check.real("wind.directional.wavelength", d.wavelength, WAVELENGTH)?;
        check.real("wind.directional.speed", d.speed, SPEED)?;
    }
    if let Some(p) = &wind.point {
        check.vector("wind.point.position", &tuple3(p.position), POSITION)?;
        check.real("wind.point.strength", p.strength, FORCE)?;
        check.real("wind.point.radius", p.radius, RADIUS)?;
        check.real("wind.point.frequency", p.frequency, FREQUENCY)?;
    }
    fluid(check, &wind.fluid)?;
    if let Some(g) = &mut wind.global {
        let mut direction = [g.direction.0, g.direction.1];
        check.direction("wind.global.direction", &mut direction)?;
        g.direction = direction.into();
        check.real("wind.global.strength", g.strength, FORCE)?;
    }
    if let Some(d) = &wind.downwash {
        check.vector("wind.downwash.position", &tuple3(d.position), POSITION)?;
        check.real("wind.downwash.radius", d.radius, RADIUS)?;
        check.real("wind.downwash.strength", d.strength, FORCE)?;
        motion(check, "wind.downwash.motion", &d.motion)?;
    }
    for (i, g) in wind.guides.iter().enumerate() {
        guide(check, i, g, terrain_size)?;
    }
    Ok(())
}

fn fluid(check: &Checker, fluid: &Fluid) -> Result<()> {
    let at = |name: &str| format!("wind.fluid.{name}");
    check.integer(&at("resolution"), fluid.resolution, FLUID_RESOLUTION)?;
    let iterations = fluid.pressure_iterations;
    check.integer(&at("pressure_iterations"), iterations, PRESSURE_ITERATIONS)?;
    let cycles = fluid.multigrid_cycles;
    check.integer(&at("multigrid_cycles"), cycles, MULTIGRID_CYCLES)?;
    // Red-black Gauss–Seidel colours cells by the parity of i + j; across a periodic seam
    // of an odd grid two neighbours share a colour and would update at once.
    if fluid.pressure_solver == PressureSolver::Multigrid
        && fluid.boundary == Boundary::Periodic
        && fluid.resolution % 2 == 1
    {
        let name = at("resolution");
        let message = format!(
            "{name} = {} is odd: the Multigrid pressure solver with a Periodic boundary needs \
             an even resolution (or use pressure_solver: Jacobi)",
            fluid.resolution
        );
        return Err(check.error(&name, message));
    }
    check.real(&at("vorticity"), fluid.vorticity, VORTICITY)?;
    check.real(&at("dissipation"), fluid.dissipation, DISSIPATION)?;
    check.real(&at("viscosity"), fluid.viscosity, VISCOSITY)?;
    let iterations = fluid.diffusion_iterations;
    check.integer(
        &at("diffusion_iterations"),
        iterations,
        DIFFUSION_ITERATIONS,
    )?;
    check.real(&at("response"), fluid.response, RESPONSE)?;
    check.real(&at("extent"), fluid.extent, EXTENT)?;
    let min_extent = MIN_CELL * fluid.resolution as f32;
    if fluid.extent > 0.0 && fluid.extent < min_extent {
        let name = at("extent");
        let message = format!(
            "{name} = {} is out of range: allowed 0 (the terrain's square) or {min_extent} <= \
             extent <= 100000 m (cells of at least {MIN_CELL} m at wind.fluid.resolution = {})",
            fluid.extent, fluid.resolution
        );
        return Err(check.error(&name, message));
    }
    check.integer(&at("layers"), fluid.layers, LAYERS)?;
    check.real(&at("layer_height"), fluid.layer_height, LAYER_HEIGHT)?;
    check.real(&at("ground_drag"), fluid.ground_drag, GROUND_DRAG)?;
    // A grid that follows the camera has edges where the air enters and leaves; wrapping
    // them around would join air from opposite sides of the camera.
    if fluid.extent > 0.0 && fluid.boundary == Boundary::Periodic {
        let name = at("boundary");
        let message = format!(
            "{name} = Periodic does not go with wind.fluid.extent = {} (a grid that follows \
             the camera): allowed there are Open or Closed, or Periodic with extent 0",
            fluid.extent
        );
        return Err(check.error(&name, message));
    }
    Ok(())
}

/// One AGC guide: a tree of points on the terrain, root first, parents before children
/// (the order `sim::agc` relies on to switch the arrows on from the root outwards).
fn guide(check: &Checker, i: usize, guide: &Guide, terrain_size: f32) -> Result<()> {
    let at = |name: &str| format!("wind.guides[{i}].{name}");
    // A band wider than the terrain would push the whole grid: that is the global wind.
    let radius = Allowed::open_closed(0.0, terrain_size, "m");
    check.real(&at("strength"), guide.strength, FORCE)?;
    check.real(&at("radius"), guide.radius, radius)?;
    if guide.points.is_empty() {
        let name = at("points");
        let message = format!("{name} is empty: a guide needs at least its root point");
        return Err(check.error(&name, message));
    }
    let half = terrain_size / 2.0;
    for (k, p) in guide.points.iter().enumerate() {
        let point = |name: &str| at(&format!("points[{k}].{name}"));
        let name = point("position");
        let on_terrain = format!("-{half} ..= {half} on x and z");
        check.finite(&name, &[p.position.0, p.position.1], &on_terrain)?;
        if p.position.0.abs() > half || p.position.1.abs() > half {
            let message = format!(
                "{name} = {} is outside the terrain: allowed -{half} ..= {half} on x and z",
                show(&[p.position.0, p.position.1])
            );
            return Err(check.error(&name, message));
        }
        match (k, p.parent) {
            (0, None) => {}
            (0, Some(parent)) => {
                let name = point("parent");
                let message = format!(
                    "{name} = {parent}: point 0 is the root, where the flow starts, and has no \
                     parent"
                );
                return Err(check.error(&name, message));
            }
            (_, None) => {
                let name = point("parent");
                let message = format!(
                    "{name} is missing: every point but the root (point 0) names its parent, \
                     allowed 0 <= parent <= {}",
                    k - 1
                );
                let field = at(&format!("points[{k}]"));
                return Err(check.error(&field, message));
            }
            (_, Some(parent)) if parent >= k => {
                let name = point("parent");
                let message = format!(
                    "{name} = {parent} is out of range: allowed 0 <= parent <= {} (a parent \
                     comes before its children in the list)",
                    k - 1
                );
                return Err(check.error(&name, message));
            }
            (_, Some(parent)) => {
                let from = guide.points[parent].position;
                let length = Vec2::from(from).distance(Vec2::from(p.position));
                // An arrow's direction is its normalised segment: zero length gives NaN.
                if length < 1e-4 {
                    let message = format!(
                        "{name} = {} is within 0.0001 m of its parent, point {parent} at {}: \
                         an arrow needs a length > 0",
                        show(&[p.position.0, p.position.1]),
                        show(&[from.0, from.1])
                    );
                    return Err(check.error(&name, message));
                }
            }
        }
        if let Some(s) = p.strength {
            check.real(&point("strength"), s, FORCE)?;
        }
        if let Some(r) = p.radius {
            check.real(&point("radius"), r, radius)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::super::tests::{check, rejected, PATH};
    use crate::error::Error;
    use crate::scene::{
        DirectionalWind, Downwash, GlobalWind, Guide, GuidePoint, Motion, PointWind, Scene,
    };

    /// A guide root (0, 0) → (4, 0) → (4, 4), strength 5, radius 1.
    fn guide() -> Guide {
        let point = |position, parent| GuidePoint {
            position,
            parent,
            strength: None,
            radius: None,
        };
        Guide {
            started: 0.0,
            strength: 5.0,
            radius: 1.0,
            points: vec![
                point((0.0, 0.0), None),
                point((4.0, 0.0), Some(0)),
                point((4.0, 4.0), Some(1)),
            ],
        }
    }

    /// The error message for the default scene on a 32 m terrain with `guide()` changed by
    /// `edit`.
    fn rejected_guide(edit: impl FnOnce(&mut Guide)) -> String {
        rejected(|s| {
            s.terrain.size = 32.0;
            let mut g = guide();
            edit(&mut g);
            s.wind.guides = vec![guide(), g];
        })
    }

    #[test]
    fn fluid_wind_is_checked() {
        let mut scene = Scene::default();
        scene.wind.global = Some(GlobalWind {
            direction: (0.0, -2.0),
            strength: 3.0,
        });
        scene.wind.downwash = Some(Downwash {
            position: (0.0, 4.0, 0.0),
            radius: 3.0,
            strength: 10.0,
            motion: Motion::Path {
                points: vec![(0.0, 0.0), (5.0, 0.0)],
                speed: 1.0,
                looped: true,
            },
        });
        scene.wind.guides = vec![guide()];
        check(&mut scene).unwrap();
        assert_eq!(scene.wind.global.as_ref().unwrap().direction, (0.0, -1.0));

        assert_eq!(
            rejected(|s| s.wind.fluid.extent = 1e-38),
            format!(
                "wind.fluid.extent = 0.00000000000000000000000000000000000001 is out of range: \
                 allowed 0 (the terrain's square) or {} <= extent <= 100000 m (cells of at \
                 least 0.01 m at wind.fluid.resolution = {})",
                0.01 * Scene::default().wind.fluid.resolution as f32,
                Scene::default().wind.fluid.resolution
            )
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.resolution = 4096),
            "wind.fluid.resolution = 4096 is out of range: allowed 8 <= resolution <= 2048 \
             cells per side"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.diffusion_iterations = 0),
            "wind.fluid.diffusion_iterations = 0 is out of range: allowed 1 <= \
             diffusion_iterations <= 200"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.viscosity = 11.0),
            "wind.fluid.viscosity = 11 is out of range: allowed 0 <= viscosity <= 10 m²/s"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.multigrid_cycles = 0),
            "wind.fluid.multigrid_cycles = 0 is out of range: allowed 1 <= multigrid_cycles \
             <= 20"
        );
        assert_eq!(
            rejected(|s| {
                s.wind.fluid.boundary = crate::scene::Boundary::Periodic;
                s.wind.fluid.resolution = 101;
            }),
            "wind.fluid.resolution = 101 is odd: the Multigrid pressure solver with a Periodic \
             boundary needs an even resolution (or use pressure_solver: Jacobi)"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.layers = 0),
            "wind.fluid.layers = 0 is out of range: allowed 1 <= layers <= 16 layers"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.layers = 17),
            "wind.fluid.layers = 17 is out of range: allowed 1 <= layers <= 16 layers"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.layer_height = 0.0),
            "wind.fluid.layer_height = 0 is out of range: allowed 0.05 <= layer_height <= 100 m"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.ground_drag = -1.0),
            "wind.fluid.ground_drag = -1 is out of range: allowed 0 <= ground_drag <= 100 1/s"
        );
        assert_eq!(
            rejected(|s| s.wind.fluid.extent = -1.0),
            "wind.fluid.extent = -1 is out of range: allowed 0 <= extent <= 100000 m"
        );
        assert_eq!(
            rejected(|s| {
                s.wind.fluid.boundary = crate::scene::Boundary::Periodic;
                s.wind.fluid.extent = 64.0;
            }),
            "wind.fluid.boundary = Periodic does not go with wind.fluid.extent = 64 (a grid \
             that follows the camera): allowed there are Open or Closed, or Periodic with \
             extent 0"
        );
        let m = rejected(|s| s.wind.fluid.vorticity = f32::NAN);
        assert!(
            m.starts_with("wind.fluid.vorticity = NaN is not a finite"),
            "{m}"
        );
        let m = rejected(|s| {
            s.wind.global = Some(GlobalWind {
                direction: (0.0, 0.0),
                strength: 1.0,
            })
        });
        assert!(
            m.starts_with("wind.global.direction = (0, 0) has zero length"),
            "{m}"
        );
        let m = rejected(|s| {
            s.wind.downwash = Some(Downwash {
                position: (0.0, 4.0, 0.0),
                radius: 0.0,
                strength: 1.0,
                motion: Motion::Static,
            })
        });
        assert_eq!(
            m,
            "wind.downwash.radius = 0 is out of range: allowed 0.01 <= radius <= 10000 m"
        );
        let m = rejected(|s| {
            s.wind.downwash = Some(Downwash {
                position: (0.0, 4.0, 0.0),
                radius: 1.0,
                strength: 1.0,
                motion: Motion::Path {
                    points: vec![(1.0, 1.0)],
                    speed: 1.0,
                    looped: false,
                },
            })
        });
        assert_eq!(
            m,
            "wind.downwash.motion.points has 1 point(s): a path needs at least 2"
        );
    }

    #[test]
    fn guides_are_checked() {
        // Zero-length arrow: point 2 on top of its parent (within 0.1 mm).
        let m = rejected_guide(|g| g.points[2].position = (4.0, 0.00005));
        assert_eq!(
            m,
            "wind.guides[1].points[2].position = (4, 0.00005) is within 0.0001 m of its \
             parent, point 1 at (4, 0): an arrow needs a length > 0"
        );
        // Radius <= 0, for the guide and for a point's override.
        assert_eq!(
            rejected_guide(|g| g.radius = 0.0),
            "wind.guides[1].radius = 0 is out of range: allowed 0 < radius <= 32 m"
        );
        assert_eq!(
            rejected_guide(|g| g.points[1].radius = Some(-1.0)),
            "wind.guides[1].points[1].radius = -1 is out of range: allowed 0 < radius <= 32 m"
        );
        // Outside the terrain.
        assert_eq!(
            rejected_guide(|g| g.points[2].position = (50.0, 1.0)),
            "wind.guides[1].points[2].position = (50, 1) is outside the terrain: allowed \
             -16 ..= 16 on x and z"
        );
        // NaN anywhere in a guide.
        let m = rejected_guide(|g| g.points[1].position.1 = f32::NAN);
        assert!(
            m.starts_with("wind.guides[1].points[1].position = (4, NaN) is not finite"),
            "{m}"
        );
        let m = rejected_guide(|g| g.strength = f32::NAN);
        assert!(
            m.starts_with("wind.guides[1].strength = NaN is not a finite"),
            "{m}"
        );
        let m = rejected_guide(|g| g.points[2].strength = Some(f32::INFINITY));
        assert!(
            m.starts_with("wind.guides[1].points[2].strength = inf"),
            "{m}"
        );
        // Strength range, tree shape.
        let m = rejected_guide(|g| g.strength = 1001.0);
        assert!(m.ends_with("allowed 0 <= strength <= 1000 m/s²"), "{m}");
        let m = rejected_guide(|g| g.points.clear());
        assert!(m.starts_with("wind.guides[1].points is empty"), "{m}");
        let m = rejected_guide(|g| g.points[0].parent = Some(1));
        assert!(m.starts_with("wind.guides[1].points[0].parent = 1: point 0 is the root"));
        let m = rejected_guide(|g| g.points[2].parent = None);
        assert!(
            m.starts_with("wind.guides[1].points[2].parent is missing"),
            "{m}"
        );
        let m = rejected_guide(|g| g.points[1].parent = Some(2));
        assert!(
            m.starts_with(
                "wind.guides[1].points[1].parent = 2 is out of range: allowed 0 <= parent <= 0"
            ),
            "{m}"
        );
        let m = rejected_guide(|g| g.points[2].parent = Some(2));
        assert!(m.contains("allowed 0 <= parent <= 1"), "{m}");
    }

    #[test]
    fn guide_errors_point_at_their_line() {
        let text = "(\n  terrain: (size: 32.0),\n  wind: (guides: [\n    (strength: 1, radius: 1, points: [\n      (position: (0, 0)),\n    ]),\n    (strength: 1, radius: 1, points: [\n      (position: (0, 0)),\n      (position: (1, 0), parent: 0),\n      (position: (50, 1), parent: 1),\n    ]),\n  ]),\n)";
        let err = crate::scene::parse_scene(text, Path::new(PATH)).unwrap_err();
        match err {
            Error::Scene {
                line,
                column,
                message,
                ..
            } => {
                assert_eq!(
                    message,
                    "wind.guides[1].points[2].position = (50, 1) is outside the terrain: \
                     allowed -16 ..= 16 on x and z"
                );
                assert_eq!((line, column), (10, 8));
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn analytic_wind_forces_are_bounded() {
        assert_eq!(
            rejected(|s| s.wind.directional.as_mut().unwrap().strength = 1e38),
            "wind.directional.strength = 100000000000000000000000000000000000000 is out of \
             range: allowed 0 <= strength <= 1000 m/s²"
        );
        let point = |edit: fn(&mut PointWind)| {
            rejected(move |s| {
                let mut p = PointWind::default();
                edit(&mut p);
                s.wind.point = Some(p);
            })
        };
        assert_eq!(
            point(|p| p.strength = 1001.0),
            "wind.point.strength = 1001 is out of range: allowed 0 <= strength <= 1000 m/s²"
        );
        assert_eq!(
            point(|p| p.frequency = 1e9),
            "wind.point.frequency = 1000000000 is out of range: allowed 0 <= frequency <= \
             100 Hz"
        );
        assert_eq!(
            rejected(|s| s.wind.directional.as_mut().unwrap().wavelength = 0.01),
            "wind.directional.wavelength = 0.01 is out of range: allowed 0.1 <= wavelength \
             <= 100000 m"
        );
        let _ = DirectionalWind::default();
    }
}
