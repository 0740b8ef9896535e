//! Validation of a parsed [`Scene`]: every number finite and in range, direction vectors
//! normalised, relative image paths resolved.
//!
//! Serde only checks types; a scene with `density: -3` or `near: NaN` parses fine and would
//! then produce an empty frame, a GPU allocation failure or NaN blades far from the cause.
//! Validation catches it at load time and points at the line that holds the value, with the
//! allowed range in the message, e.g.
//! `scene.ron:5:9: field.density = -3 is out of range: allowed 0 < density <= 10000 blades/m²`.
//!
//! Every float must be finite (RON accepts `NaN`, `inf` and `-inf`). The allowed ranges:
//!
//! | field | allowed |
//! |---|---|
//! | `terrain.size` | 1 ≤ size ≤ 10000 m |
//! | `terrain.resolution` | 2 ≤ resolution ≤ 4097 vertices per side |
//! | `terrain.height: Noise` | 0 ≤ amplitude ≤ 1000 m, wavelength > 0 m, 1 ≤ octaves ≤ 12 |
//! | `terrain.height: Png` | path not empty, scale ≥ 0 m |
//! | `terrain.density_map` | not empty |
//! | `field.density` | 0 < density ≤ 10000 blades/m² |
//! | `field.height` | 0 < min ≤ max ≤ 10 m |
//! | `field.width` | 0 < min ≤ max ≤ 1 m |
//! | `field.stiffness` | 0 ≤ min ≤ max ≤ 1000 1/s |
//! | `field.bend` | 0 ≤ min ≤ max ≤ 90 degrees |
//! | `field.tuft_fraction` | 0 ≤ tuft_fraction ≤ 1 |
//! | `field.tuft_radius` | 0 < tuft_radius ≤ 10 m |
//! | `field.tip_threshold` | 0 ≤ tip_threshold < 1 |
//! | `field.patch_size` | a multiple of 64 (the workgroup size), 64 ≤ patch_size ≤ 65536 |
//! | `field.segments` | 1 ≤ segments ≤ 16 |
//! | `colliders[i]` | center finite, 0 < radius ≤ 1000 m |
//! | `colliders[i].motion: Velocity` | finite |
//! | `colliders[i].motion: Path` | ≥ 2 finite points, total length > 0, speed ≥ 0 m/s |
//! | `wind.directional` | direction non-zero, strength ≥ 0 m/s², 0 ≤ gust ≤ 4, wavelength > 0 m, speed ≥ 0 m/s |
//! | `wind.point` | position finite, strength ≥ 0 m/s², radius > 0 m, frequency ≥ 0 Hz |
//! | `wind.fluid` | 8 ≤ resolution ≤ 2048 cells per side, 0 ≤ pressure_iterations ≤ 1000, 0 ≤ vorticity ≤ 1000, 0 ≤ dissipation ≤ 100 1/s, 0 ≤ viscosity ≤ 10 m²/s, 1 ≤ diffusion_iterations ≤ 200, 0 ≤ response ≤ 100 1/s |
//! | `wind.global` | direction non-zero, 0 ≤ strength ≤ 1000 m/s² |
//! | `wind.downwash` | position finite, radius > 0 m, 0 ≤ strength ≤ 1000 m/s², motion as for colliders |
//! | `wind.guides[i]` | 0 ≤ strength ≤ 1000 m/s², 0 < radius ≤ terrain.size m, ≥ 1 point |
//! | `wind.guides[i].points[k]` | position finite and on the terrain (\|x\|, \|z\| ≤ terrain.size / 2); point 0 has no parent, every other point a parent < k at least 0.0001 m away; overrides as the guide's strength and radius |
//! | `physics.gravity_direction` | non-zero |
//! | `physics.gravity_acceleration`, `gravity_center_acceleration` | ≥ 0 m/s² |
//! | `physics.gravity_center` | finite |
//! | `physics.gravity_blend` | 0 ≤ gravity_blend ≤ 1 |
//! | `physics.mass` | ≥ 0 |
//! | `physics.collision_decay` | ≥ 0 1/s |
//! | `physics.collision_gain` | 0 ..= 1e6 1/m² |
//! | `physics.max_collision_strength` | 0 ..= 100 |
//! | `physics.stiffness_scale` | 0.05 ≤ stiffness_scale ≤ 4 |
//! | `physics.max_dt` | 0 < max_dt ≤ 1 s |
//! | `culling.orientation_threshold` | 0 ≤ orientation_threshold ≤ 1 |
//! | `culling.frustum_tolerance` | 0 ≤ frustum_tolerance ≤ 10 |
//! | `culling.distance_levels` | 1 ≤ distance_levels ≤ 64 |
//! | `culling.max_distance` | > 0 m |
//! | `culling.occlusion_bias` | 0 ≤ occlusion_bias ≤ 1 |
//! | `culling.grass_occlusion_bias` | 0 ≤ grass_occlusion_bias ≤ 1 |
//! | `culling.lod_near_px`, `lod_far_px` | 0 – 4096 px, near ≥ far × (1 + lod_morph) |
//! | `culling.lod_morph` | 0 ≤ lod_morph ≤ 1 |
//! | `culling.physics_throttle` | 1 – 64 frames |
//! | `culling.physics_radius` | 0 – 10⁴ m |
//! | `camera` | eye and target finite and distinct, 1 < fov_y < 179 degrees, 0 < near < far m |
//! | `render.sun_direction` | non-zero |
//! | `render.width_min_px`, `width_span_px` | ≥ 0 px |
//!
//! Direction vectors (`wind.directional.direction`, `wind.global.direction`,
//! `physics.gravity_direction`, `render.sun_direction`) are normalised in place. Relative image paths are rewritten in
//! place to the scene file's directory joined with the path, so that they do not depend on
//! the working directory of the process.
//!
//! The line and column of an error come from [`locate`], a small text scan for the field's
//! key: serde does not keep positions for values, and a second spanned parse would be far
//! more code for the same result.

use std::ops::Range as Span;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::types::{
    Camera, Culling, Field, Fluid, Guide, HeightSource, Motion, Physics, Range, Render, Scene,
    Sphere, Terrain, Wind,
};
use crate::error::{Error, Result};

/// Checks every value of `scene` (see the module docs for the ranges), normalises its
/// direction vectors and resolves its relative image paths against `path`'s directory.
///
/// `text` is the RON text `scene` was parsed from; it is only used to find the line and
/// column of an offending value. `path` names the scene file in errors.
///
/// Idempotent except for image paths when `path` is itself relative (resolving twice
/// prefixes the directory twice).
pub(crate) fn validate(scene: &mut Scene, text: &str, path: &Path) -> Result<()> {
    let check = Checker { text, path };
    terrain(&check, &mut scene.terrain)?;
    field(&check, &scene.field)?;
    for (i, sphere) in scene.colliders.iter().enumerate() {
        collider(&check, i, sphere)?;
    }
    // The guides must lie on the terrain, so the wind needs its (already checked) size.
    wind(&check, &mut scene.wind, scene.terrain.size)?;
    physics(&check, &mut scene.physics)?;
    culling(&check, &scene.culling)?;
    camera(&check, &scene.camera)?;
    render(&check, &mut scene.render)
}

fn terrain(check: &Checker, terrain: &mut Terrain) -> Result<()> {
    check.real(
        "terrain.size",
        terrain.size,
        Allowed::closed(1.0, 10000.0, "m"),
    )?;
    check.integer(
        "terrain.resolution",
        terrain.resolution,
        2,
        4097,
        "vertices per side",
    )?;
    match &mut terrain.height {
        HeightSource::Noise {
            seed: _,
            amplitude,
            wavelength,
            octaves,
        } => {
            let amplitude_range = Allowed::closed(0.0, 1000.0, "m");
            check.real("terrain.height.amplitude", *amplitude, amplitude_range)?;
            check.real(
                "terrain.height.wavelength",
                *wavelength,
                Allowed::above(0.0, "m"),
            )?;
            check.integer("terrain.height.octaves", *octaves, 1, 12, "")?;
        }
        HeightSource::Png { path, scale } => {
            check.image_path("terrain.height.path", path)?;
            check.real("terrain.height.scale", *scale, Allowed::at_least(0.0, "m"))?;
        }
        HeightSource::Flat => {}
    }
    if let Some(map) = &mut terrain.density_map {
        check.image_path("terrain.density_map", map)?;
    }
    Ok(())
}

fn field(check: &Checker, field: &Field) -> Result<()> {
    let density_range = Allowed::open_closed(0.0, 10000.0, "blades/m²");
    check.real("field.density", field.density, density_range)?;
    check.range(
        "field.height",
        field.height,
        Allowed::open_closed(0.0, 10.0, "m"),
    )?;
    check.range(
        "field.width",
        field.width,
        Allowed::open_closed(0.0, 1.0, "m"),
    )?;
    let stiffness_range = Allowed::closed(0.0, 1000.0, "1/s");
    check.range("field.stiffness", field.stiffness, stiffness_range)?;
    check.range(
        "field.bend",
        field.bend,
        Allowed::closed(0.0, 90.0, "degrees"),
    )?;
    let tuft_fraction = Allowed::closed(0.0, 1.0, "");
    check.real("field.tuft_fraction", field.tuft_fraction, tuft_fraction)?;
    let tuft_radius = Allowed::open_closed(0.0, 10.0, "m");
    check.real("field.tuft_radius", field.tuft_radius, tuft_radius)?;
    let tip_threshold = Allowed::closed_open(0.0, 1.0, "");
    check.real("field.tip_threshold", field.tip_threshold, tip_threshold)?;
    // Patches are dispatched as whole workgroups of 64 blades, so a patch must fill them.
    let patch = field.patch_size;
    if !(64..=65536).contains(&patch) || !patch.is_multiple_of(64) {
        return Err(check.error(
            "field.patch_size",
            format!(
                "field.patch_size = {patch} is out of range: allowed a multiple of 64 \
                 (the workgroup size) with 64 <= patch_size <= 65536 blades"
            ),
        ));
    }
    check.integer("field.segments", field.segments, 1, 16, "")
}

fn collider(check: &Checker, i: usize, sphere: &Sphere) -> Result<()> {
    let at = |name: &str| format!("colliders[{i}].{name}");
    check.finite(&at("center"), &tuple3(sphere.center))?;
    let radius_range = Allowed::open_closed(0.0, 1000.0, "m");
    check.real(&at("radius"), sphere.radius, radius_range)?;
    motion(check, &at("motion"), &sphere.motion)
}

fn wind(check: &Checker, wind: &mut Wind, terrain_size: f32) -> Result<()> {
    if let Some(d) = &mut wind.directional {
        let mut direction = [d.direction.0, d.direction.1];
        check.direction("wind.directional.direction", &mut direction)?;
        d.direction = direction.into();
        let strength_range = Allowed::at_least(0.0, "m/s²");
        check.real("wind.directional.strength", d.strength, strength_range)?;
        check.real(
            "wind.directional.gust",
            d.gust,
            Allowed::closed(0.0, 4.0, ""),
        )?;
        let wavelength_range = Allowed::above(0.0, "m");
        check.real(
            "wind.directional.wavelength",
            d.wavelength,
            wavelength_range,
        )?;
        check.real(
            "wind.directional.speed",
            d.speed,
            Allowed::at_least(0.0, "m/s"),
        )?;
    }
    if let Some(p) = &wind.point {
        check.finite("wind.point.position", &tuple3(p.position))?;
        check.real(
            "wind.point.strength",
            p.strength,
            Allowed::at_least(0.0, "m/s²"),
        )?;
        check.real("wind.point.radius", p.radius, Allowed::above(0.0, "m"))?;
        check.real(
            "wind.point.frequency",
            p.frequency,
            Allowed::at_least(0.0, "Hz"),
        )?;
    }
    fluid(check, &wind.fluid)?;
    if let Some(g) = &mut wind.global {
        let mut direction = [g.direction.0, g.direction.1];
        check.direction("wind.global.direction", &mut direction)?;
        g.direction = direction.into();
        let strength = Allowed::closed(0.0, 1000.0, "m/s²");
        check.real("wind.global.strength", g.strength, strength)?;
    }
    if let Some(d) = &wind.downwash {
        check.finite("wind.downwash.position", &tuple3(d.position))?;
        check.real("wind.downwash.radius", d.radius, Allowed::above(0.0, "m"))?;
        let strength = Allowed::closed(0.0, 1000.0, "m/s²");
        check.real("wind.downwash.strength", d.strength, strength)?;
        motion(check, "wind.downwash.motion", &d.motion)?;
    }
    for (i, g) in wind.guides.iter().enumerate() {
        guide(check, i, g, terrain_size)?;
    }
    Ok(())
}

fn fluid(check: &Checker, fluid: &Fluid) -> Result<()> {
    let at = |name: &str| format!("wind.fluid.{name}");
    check.integer(
        &at("resolution"),
        fluid.resolution,
        8,
        2048,
        "cells per side",
    )?;
    let iterations = fluid.pressure_iterations;
    check.integer(&at("pressure_iterations"), iterations, 0, 1000, "")?;
    let vorticity = Allowed::closed(0.0, 1000.0, "");
    check.real(&at("vorticity"), fluid.vorticity, vorticity)?;
    let dissipation = Allowed::closed(0.0, 100.0, "1/s");
    check.real(&at("dissipation"), fluid.dissipation, dissipation)?;
    let viscosity = Allowed::closed(0.0, 10.0, "m²/s");
    check.real(&at("viscosity"), fluid.viscosity, viscosity)?;
    let iterations = fluid.diffusion_iterations;
    check.integer(&at("diffusion_iterations"), iterations, 1, 200, "")?;
    let response = Allowed::closed(0.0, 100.0, "1/s");
    check.real(&at("response"), fluid.response, response)
}

/// A moving object's motion (`field` is its path, e.g. `colliders[0].motion` or
/// `wind.downwash.motion`). A path of coincident points has no direction to roll along
/// (and dividing by its length would give NaN positions).
fn motion(check: &Checker, field: &str, motion: &Motion) -> Result<()> {
    match motion {
        Motion::Static => Ok(()),
        Motion::Velocity(v) => check.finite(field, &tuple3(*v)),
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
                check.finite(&format!("{name}[{k}]"), &[p.0, p.1])?;
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
            let speed_range = Allowed::at_least(0.0, "m/s");
            check.real(&format!("{field}.speed"), *speed, speed_range)
        }
    }
}

/// One AGC guide: a tree of points on the terrain, root first, parents before children
/// (the order `sim::agc` relies on to switch the arrows on from the root outwards).
fn guide(check: &Checker, i: usize, guide: &Guide, terrain_size: f32) -> Result<()> {
    let at = |name: &str| format!("wind.guides[{i}].{name}");
    let strength = Allowed::closed(0.0, 1000.0, "m/s²");
    // A band wider than the terrain would push the whole grid: that is the global wind.
    let radius = Allowed::open_closed(0.0, terrain_size, "m");
    check.real(&at("strength"), guide.strength, strength)?;
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
        check.finite(&name, &[p.position.0, p.position.1])?;
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
            check.real(&point("strength"), s, strength)?;
        }
        if let Some(r) = p.radius {
            check.real(&point("radius"), r, radius)?;
        }
    }
    Ok(())
}

fn physics(check: &Checker, physics: &mut Physics) -> Result<()> {
    let mut direction = tuple3(physics.gravity_direction);
    check.direction("physics.gravity_direction", &mut direction)?;
    physics.gravity_direction = direction.into();
    let acceleration = Allowed::at_least(0.0, "m/s²");
    check.real(
        "physics.gravity_acceleration",
        physics.gravity_acceleration,
        acceleration,
    )?;
    check.finite("physics.gravity_center", &tuple3(physics.gravity_center))?;
    check.real(
        "physics.gravity_center_acceleration",
        physics.gravity_center_acceleration,
        acceleration,
    )?;
    let blend = Allowed::closed(0.0, 1.0, "");
    check.real("physics.gravity_blend", physics.gravity_blend, blend)?;
    check.real("physics.mass", physics.mass, Allowed::at_least(0.0, ""))?;
    let decay = Allowed::at_least(0.0, "1/s");
    check.real("physics.collision_decay", physics.collision_decay, decay)?;
    let gain = Allowed::closed(0.0, 1.0e6, "1/m²");
    check.real("physics.collision_gain", physics.collision_gain, gain)?;
    let ceiling = Allowed::closed(0.0, 100.0, "");
    check.real(
        "physics.max_collision_strength",
        physics.max_collision_strength,
        ceiling,
    )?;
    // Explicit Euler on the recovery term stays stable while s·scale·Δt < 2; with s up to
    // ~12 1/s and Δt ≤ 0.05 s a scale of 4 keeps that margin for the default fields.
    let scale = Allowed::closed(0.05, 4.0, "");
    check.real("physics.stiffness_scale", physics.stiffness_scale, scale)?;
    let max_dt = Allowed::open_closed(0.0, 1.0, "s");
    check.real("physics.max_dt", physics.max_dt, max_dt)
}

fn culling(check: &Checker, culling: &Culling) -> Result<()> {
    let threshold = Allowed::closed(0.0, 1.0, "");
    check.real(
        "culling.orientation_threshold",
        culling.orientation_threshold,
        threshold,
    )?;
    let tolerance = Allowed::closed(0.0, 10.0, "");
    check.real(
        "culling.frustum_tolerance",
        culling.frustum_tolerance,
        tolerance,
    )?;
    check.integer(
        "culling.distance_levels",
        culling.distance_levels,
        1,
        64,
        "",
    )?;
    let max_distance = Allowed::above(0.0, "m");
    check.real("culling.max_distance", culling.max_distance, max_distance)?;
    let bias = Allowed::closed(0.0, 1.0, "");
    check.real("culling.occlusion_bias", culling.occlusion_bias, bias)?;
    check.real(
        "culling.grass_occlusion_bias",
        culling.grass_occlusion_bias,
        bias,
    )?;
    let pixels = Allowed::closed(0.0, 4096.0, "px");
    check.real("culling.lod_near_px", culling.lod_near_px, pixels)?;
    check.real("culling.lod_far_px", culling.lod_far_px, pixels)?;
    let morph = Allowed::closed(0.0, 1.0, "");
    check.real("culling.lod_morph", culling.lod_morph, morph)?;
    // The middle level's morph band must end below the near threshold, or a blade would
    // enter level 0 while its middle mesh is still part-way morphed and jump.
    let band_top = culling.lod_far_px * (1.0 + culling.lod_morph);
    if culling.lod_near_px < band_top {
        let message = format!(
            "culling.lod_near_px = {} is below lod_far_px × (1 + lod_morph) = {band_top}: \
             allowed lod_near_px >= {band_top}",
            culling.lod_near_px
        );
        return Err(check.error("culling.lod_near_px", message));
    }
    check.integer(
        "culling.physics_throttle",
        culling.physics_throttle,
        1,
        64,
        "frames",
    )?;
    let radius = Allowed::closed(0.0, 1.0e4, "m");
    check.real("culling.physics_radius", culling.physics_radius, radius)
}

fn camera(check: &Checker, camera: &Camera) -> Result<()> {
    check.finite("camera.eye", &tuple3(camera.eye))?;
    check.finite("camera.target", &tuple3(camera.target))?;
    // The view matrix needs a viewing direction.
    let (eye, target) = (Vec3::from(camera.eye), Vec3::from(camera.target));
    if unit(&(target - eye).to_array()).is_none() {
        return Err(check.error(
            "camera.target",
            format!(
                "camera.target = {} is the same point as camera.eye: the camera needs a \
                 direction to look in",
                show(&tuple3(camera.target))
            ),
        ));
    }
    check.real(
        "camera.fov_y",
        camera.fov_y,
        Allowed::open(1.0, 179.0, "degrees"),
    )?;
    check.real("camera.near", camera.near, Allowed::above(0.0, "m"))?;
    // The lower bound of `far` is another field, so the message names it.
    let far = camera.far;
    if !(far.is_finite() && far > camera.near) {
        let problem = if far.is_finite() {
            "is out of range"
        } else {
            "is not a finite number"
        };
        let message = format!(
            "camera.far = {far} {problem}: allowed far > near = {} m",
            camera.near
        );
        return Err(check.error("camera.far", message));
    }
    Ok(())
}

fn render(check: &Checker, render: &mut Render) -> Result<()> {
    let mut sun = tuple3(render.sun_direction);
    check.direction("render.sun_direction", &mut sun)?;
    render.sun_direction = sun.into();
    let px = Allowed::at_least(0.0, "px");
    check.real("render.width_min_px", render.width_min_px, px)?;
    check.real("render.width_span_px", render.width_span_px, px)
}

fn tuple3(v: (f32, f32, f32)) -> [f32; 3] {
    [v.0, v.1, v.2]
}

/// `(a, b, c)`, as the vector is written in RON.
fn show(v: &[f32]) -> String {
    let parts: Vec<String> = v.iter().map(f32::to_string).collect();
    format!("({})", parts.join(", "))
}

/// `v` scaled to unit length, or `None` if it is zero (or not finite). Dividing by the
/// largest component first keeps the length from overflowing for huge components or
/// underflowing to zero for tiny ones.
fn unit(v: &[f32]) -> Option<Vec<f32>> {
    let scale = v.iter().fold(0.0f32, |m, c| m.max(c.abs()));
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let scaled: Vec<f32> = v.iter().map(|c| c / scale).collect();
    let length = scaled.iter().map(|c| c * c).sum::<f32>().sqrt();
    Some(scaled.iter().map(|c| c / length).collect())
}

/// One end of an allowed interval.
#[derive(Clone, Copy, Debug)]
enum Bound {
    Unbounded,
    Inclusive(f32),
    Exclusive(f32),
}

/// The allowed interval of a float field, with the unit shown in messages.
#[derive(Clone, Copy, Debug)]
struct Allowed {
    low: Bound,
    high: Bound,
    unit: &'static str,
}

impl Allowed {
    /// `low <= x <= high`
    const fn closed(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Inclusive(low),
            high: Bound::Inclusive(high),
            unit,
        }
    }
    /// `low < x <= high`
    const fn open_closed(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Exclusive(low),
            high: Bound::Inclusive(high),
            unit,
        }
    }
    /// `low <= x < high`
    const fn closed_open(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Inclusive(low),
            high: Bound::Exclusive(high),
            unit,
        }
    }
    /// `low < x < high`
    const fn open(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Exclusive(low),
            high: Bound::Exclusive(high),
            unit,
        }
    }
    /// `x >= low`
    const fn at_least(low: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Inclusive(low),
            high: Bound::Unbounded,
            unit,
        }
    }
    /// `x > low`
    const fn above(low: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Exclusive(low),
            high: Bound::Unbounded,
            unit,
        }
    }

    fn contains(&self, x: f32) -> bool {
        let above_low = match self.low {
            Bound::Unbounded => true,
            Bound::Inclusive(low) => x >= low,
            Bound::Exclusive(low) => x > low,
        };
        let below_high = match self.high {
            Bound::Unbounded => true,
            Bound::Inclusive(high) => x <= high,
            Bound::Exclusive(high) => x < high,
        };
        above_low && below_high
    }

    /// E.g. `0 < density <= 10000 blades/m²` or `speed >= 0 m/s`.
    fn describe(&self, name: &str) -> String {
        let mut text = match (self.low, self.high) {
            (Bound::Unbounded, Bound::Unbounded) => format!("{name} finite"),
            (low, Bound::Unbounded) => match low {
                Bound::Inclusive(v) => format!("{name} >= {v}"),
                Bound::Exclusive(v) => format!("{name} > {v}"),
                Bound::Unbounded => unreachable!("handled above"),
            },
            (Bound::Unbounded, high) => match high {
                Bound::Inclusive(v) => format!("{name} <= {v}"),
                Bound::Exclusive(v) => format!("{name} < {v}"),
                Bound::Unbounded => unreachable!("handled above"),
            },
            (low, high) => {
                let low = match low {
                    Bound::Inclusive(v) => format!("{v} <="),
                    Bound::Exclusive(v) => format!("{v} <"),
                    Bound::Unbounded => unreachable!("handled above"),
                };
                let high = match high {
                    Bound::Inclusive(v) => format!("<= {v}"),
                    Bound::Exclusive(v) => format!("< {v}"),
                    Bound::Unbounded => unreachable!("handled above"),
                };
                format!("{low} {name} {high}")
            }
        };
        if !self.unit.is_empty() {
            text.push(' ');
            text.push_str(self.unit);
        }
        text
    }
}

/// The name a range message uses for a field: its last key (`density`), or the last two
/// for the parts of a [`Range`] (`height.min`), without array indices.
fn short_name(field: &str) -> String {
    let strip = |s: &str| s.split('[').next().unwrap_or(s).to_owned();
    let mut keys = field.rsplit('.');
    let last = strip(keys.next().unwrap_or(field));
    match keys.next() {
        Some(parent) if last == "min" || last == "max" => format!("{}.{last}", strip(parent)),
        _ => last,
    }
}

/// Builds errors that point into the scene text.
struct Checker<'a> {
    text: &'a str,
    path: &'a Path,
}

impl Checker<'_> {
    /// An [`Error::Scene`] at the place where `field` (a dotted path such as
    /// `colliders[1].radius`) is written.
    fn error(&self, field: &str, message: String) -> Error {
        let (line, column) = locate(self.text, field);
        Error::Scene {
            path: self.path.to_path_buf(),
            line,
            column,
            message,
        }
    }

    fn real(&self, field: &str, value: f32, allowed: Allowed) -> Result<()> {
        let problem = if !value.is_finite() {
            "is not a finite number"
        } else if !allowed.contains(value) {
            "is out of range"
        } else {
            return Ok(());
        };
        let range = allowed.describe(&short_name(field));
        let message = format!("{field} = {value} {problem}: allowed {range}");
        Err(self.error(field, message))
    }

    fn integer(&self, field: &str, value: u32, low: u32, high: u32, unit: &str) -> Result<()> {
        if (low..=high).contains(&value) {
            return Ok(());
        }
        let name = short_name(field);
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        let message =
            format!("{field} = {value} is out of range: allowed {low} <= {name} <= {high}{unit}");
        Err(self.error(field, message))
    }

    /// Both ends of `range` within `allowed`, and `min <= max`.
    fn range(&self, field: &str, range: Range, allowed: Allowed) -> Result<()> {
        self.real(&format!("{field}.min"), range.min, allowed)?;
        self.real(&format!("{field}.max"), range.max, allowed)?;
        if range.min > range.max {
            let message = format!(
                "{field}: min = {} is greater than max = {}: allowed min <= max",
                range.min, range.max
            );
            return Err(self.error(&format!("{field}.max"), message));
        }
        Ok(())
    }

    /// Every component finite (positions, velocities: any finite value is meaningful).
    fn finite(&self, field: &str, components: &[f32]) -> Result<()> {
        if components.iter().all(|c| c.is_finite()) {
            return Ok(());
        }
        let message = format!(
            "{field} = {} is not finite: every component must be a finite number",
            show(components)
        );
        Err(self.error(field, message))
    }

    /// A finite, non-zero direction, normalised in place. Already normalised vectors are left
    /// bit for bit as they are, so that validating twice changes nothing.
    fn direction(&self, field: &str, components: &mut [f32]) -> Result<()> {
        self.finite(field, components)?;
        let Some(unit) = unit(components) else {
            let message = format!(
                "{field} = {} has zero length: a direction must be non-zero (it is normalised \
                 on load)",
                show(components)
            );
            return Err(self.error(field, message));
        };
        let length_squared: f32 = components.iter().map(|c| c * c).sum();
        if (length_squared - 1.0).abs() > 1e-6 {
            components.copy_from_slice(&unit);
        }
        Ok(())
    }

    /// A non-empty image path, made relative to the scene file's directory in place.
    fn image_path(&self, field: &str, image: &mut String) -> Result<()> {
        if image.trim().is_empty() {
            let message = format!("{field} is empty: name a PNG file");
            return Err(self.error(field, message));
        }
        let relative = Path::new(image.as_str());
        if relative.is_absolute() {
            return Ok(());
        }
        let dir = self.path.parent().unwrap_or(Path::new(""));
        let joined = dir.join(relative);
        // The scene types hold paths as `String`; a lossy conversion would silently name a
        // different file, so refuse instead.
        let Some(joined) = joined.to_str() else {
            let message = format!(
                "{field} = {image:?}: the scene's directory {} is not valid UTF-8; use an \
                 absolute path",
                dir.display()
            );
            return Err(self.error(field, message));
        };
        *image = joined.to_owned();
        Ok(())
    }
}

/// Finds where `field` (a dotted path of keys, with `[i]` for array elements, e.g.
/// `field.height.min` or `colliders[1].motion.speed`) is written in the RON `text`, as a
/// 1-based `(line, column)` (column in characters).
///
/// Each key is searched only inside the value of the key before it, so `field.height` is
/// not confused with `terrain.height`; within that value the least nested occurrence wins
/// (so that `Some((..))` wrappers and enum variants are looked through, but a deeper key of
/// the same name is not taken). Comments and string contents are ignored. When a key is
/// not written (its value is the default) the position of the nearest enclosing key that
/// is written is returned, or `(1, 1)` if there is none.
fn locate(text: &str, field: &str) -> (usize, usize) {
    let code = mask(text);
    let mut region = 0..code.len();
    let mut found = None;
    for segment in field.split('.') {
        let (name, index) = match segment.split_once('[') {
            Some((name, rest)) => (name, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (segment, None),
        };
        let Some((key, value)) = find_key(&code, region.clone(), name) else {
            break;
        };
        found = Some(key);
        region = value_span(&code, value, region.end);
        if let Some(index) = index {
            let Some(element) = nth_element(&code, region.clone(), index) else {
                break;
            };
            found = Some(element.start);
            region = element;
        }
    }
    found.map_or((1, 1), |offset| line_column(text, offset))
}

/// `text` as bytes with comments and the contents of strings replaced by spaces (newlines
/// kept), so that brackets, commas and keys inside them are not seen. Byte offsets are
/// unchanged.
fn mask(text: &str) -> Vec<u8> {
    let bytes = text.as_bytes();
    let mut code = bytes.to_vec();
    let len = bytes.len();
    let at = |i: usize, s: &[u8]| bytes[i..].starts_with(s);
    let mut blank = |span: Span<usize>| {
        for b in &mut code[span] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
    };
    let mut i = 0;
    while i < len {
        let start = i;
        if at(i, b"//") {
            i = bytes[i..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(len, |n| i + n);
        } else if at(i, b"/*") {
            // RON block comments nest.
            let mut depth = 0usize;
            while i < len {
                if at(i, b"/*") {
                    depth += 1;
                    i += 2;
                } else if at(i, b"*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if bytes[i] == b'"' {
            i += 1;
            while i < len {
                match bytes[i] {
                    b'\\' => i += 2,
                    b'"' => {
                        i += 1;
                        break;
                    }
                    _ => i += 1,
                }
            }
        } else if bytes[i] == b'r' && (i == 0 || !is_ident(bytes[i - 1])) {
            // A raw string r"..." or r#"..."#: no escapes, ends at `"` plus as many `#`.
            let hashes = bytes[i + 1..].iter().take_while(|&&b| b == b'#').count();
            if bytes.get(i + 1 + hashes) != Some(&b'"') {
                i += 1;
                continue;
            }
            let mut close = vec![b'"'];
            close.extend(std::iter::repeat_n(b'#', hashes));
            i += 2 + hashes;
            while i < len && !at(i, &close) {
                i += 1;
            }
            i = (i + close.len()).min(len);
        } else {
            i += 1;
            continue;
        }
        blank(start..i.min(len));
    }
    code
}

fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

fn is_open(b: u8) -> bool {
    matches!(b, b'(' | b'[' | b'{')
}

fn is_close(b: u8) -> bool {
    matches!(b, b')' | b']' | b'}')
}

/// The least nested occurrence of `name:` as a key in `code[region]`: the offset of the key
/// and the offset just after its colon.
fn find_key(code: &[u8], region: Span<usize>, name: &str) -> Option<(usize, usize)> {
    let name = name.as_bytes();
    let mut depth = 0i32;
    let mut best: Option<(i32, usize, usize)> = None;
    for i in region.clone() {
        let b = code[i];
        if is_open(b) {
            depth += 1;
        } else if is_close(b) {
            depth -= 1;
        }
        if !code[i..region.end].starts_with(name) || (i > 0 && is_ident(code[i - 1])) {
            continue;
        }
        let mut j = i + name.len();
        if j < region.end && is_ident(code[j]) {
            continue;
        }
        while j < region.end && code[j].is_ascii_whitespace() {
            j += 1;
        }
        if j < region.end && code[j] == b':' && best.is_none_or(|(d, ..)| depth < d) {
            best = Some((depth, i, j + 1));
        }
    }
    best.map(|(_, key, value)| (key, value))
}

/// The span of the value that starts at (or after whitespace from) `start`: up to the comma
/// or closing bracket that ends it, at most up to `end`.
fn value_span(code: &[u8], start: usize, end: usize) -> Span<usize> {
    let mut i = start;
    while i < end && code[i].is_ascii_whitespace() {
        i += 1;
    }
    let first = i;
    let mut depth = 0usize;
    while i < end {
        let b = code[i];
        if is_open(b) {
            depth += 1;
        } else if is_close(b) {
            if depth == 0 {
                break;
            }
            depth -= 1;
        } else if b == b',' && depth == 0 {
            break;
        }
        i += 1;
    }
    first..i
}

/// The span of element `n` (0-based) of the first `[...]` list in `code[region]`.
fn nth_element(code: &[u8], region: Span<usize>, n: usize) -> Option<Span<usize>> {
    let open = region.start + code[region.clone()].iter().position(|&b| b == b'[')?;
    let mut depth = 0usize;
    let mut index = 0;
    let mut element: Option<usize> = None;
    for (i, &b) in code.iter().enumerate().take(region.end).skip(open + 1) {
        let ends_element = depth == 0 && (b == b',' || b == b']');
        if element.is_none() && !b.is_ascii_whitespace() && !ends_element {
            element = Some(i);
        }
        if ends_element {
            if let Some(start) = element.take() {
                if index == n {
                    return Some(start..i);
                }
                index += 1;
            }
            if b == b']' {
                return None;
            }
        } else if is_open(b) {
            depth += 1;
        } else if is_close(b) {
            depth = depth.saturating_sub(1);
        }
    }
    None
}

/// The 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |n| n + 1);
    let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
    // Count characters, not bytes: skip UTF-8 continuation bytes.
    let column = 1 + before[line_start..]
        .iter()
        .filter(|&&b| b & 0xC0 != 0x80)
        .count();
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DirectionalWind, Downwash, GlobalWind, GuidePoint, PointWind};

    const PATH: &str = "/scenes/meadow.ron";

    fn check(scene: &mut Scene) -> Result<()> {
        validate(scene, "()", Path::new(PATH))
    }

    fn message(result: Result<()>) -> String {
        match result {
            Err(Error::Scene { message, .. }) => message,
            other => panic!("expected a scene error, got {other:?}"),
        }
    }

    /// The error message for the default scene changed by `edit`.
    fn rejected(edit: impl FnOnce(&mut Scene)) -> String {
        let mut scene = Scene::default();
        edit(&mut scene);
        message(check(&mut scene))
    }

    #[test]
    fn default_scene_is_valid() {
        let mut scene = Scene::default();
        check(&mut scene).unwrap();
        // Also with the optional parts that are off by default switched on.
        scene.wind.point = Some(PointWind::default());
        scene.colliders.push(Sphere {
            center: (0.0, 0.5, 0.0),
            radius: 0.5,
            motion: Motion::Static,
        });
        check(&mut scene).unwrap();
    }

    #[test]
    fn validation_is_idempotent() {
        let mut once = Scene::default();
        once.wind.directional = Some(DirectionalWind {
            direction: (3.0, 4.0),
            ..DirectionalWind::default()
        });
        once.physics.gravity_direction = (0.0, -9.81, 0.5);
        check(&mut once).unwrap();
        assert_eq!(
            once.wind.directional.as_ref().unwrap().direction,
            (0.6, 0.8)
        );
        let mut twice = once.clone();
        check(&mut twice).unwrap();
        assert_eq!(once, twice);
    }

    #[test]
    fn directions_are_normalised_and_must_be_non_zero() {
        let mut scene = Scene::default();
        scene.render.sun_direction = (0.0, 1e30, 0.0);
        scene.physics.gravity_direction = (1e-30, 0.0, 0.0);
        check(&mut scene).unwrap();
        assert_eq!(scene.render.sun_direction, (0.0, 1.0, 0.0));
        assert_eq!(scene.physics.gravity_direction, (1.0, 0.0, 0.0));

        let m = rejected(|s| s.physics.gravity_direction = (0.0, 0.0, 0.0));
        assert!(
            m.starts_with("physics.gravity_direction = (0, 0, 0) has zero length"),
            "{m}"
        );
        let m = rejected(|s| s.wind.directional.as_mut().unwrap().direction = (0.0, -0.0));
        assert!(
            m.starts_with("wind.directional.direction = (0, -0) has zero length"),
            "{m}"
        );
        let m = rejected(|s| s.render.sun_direction = (f32::NAN, 1.0, 0.0));
        assert!(
            m.starts_with("render.sun_direction = (NaN, 1, 0) is not finite"),
            "{m}"
        );
    }

    #[test]
    fn out_of_range_values_name_field_and_range() {
        type Edit = Box<dyn FnOnce(&mut Scene)>;
        let cases: Vec<(Edit, &str)> = vec![
            (
                Box::new(|s| s.terrain.size = 0.5),
                "terrain.size = 0.5 is out of range: allowed 1 <= size <= 10000 m",
            ),
            (
                Box::new(|s| s.terrain.resolution = 1),
                "terrain.resolution = 1 is out of range: allowed 2 <= resolution <= 4097 vertices per side",
            ),
            (
                Box::new(|s| {
                    s.terrain.height = HeightSource::Noise {
                        seed: 0,
                        amplitude: 1.0,
                        wavelength: 10.0,
                        octaves: 13,
                    }
                }),
                "terrain.height.octaves = 13 is out of range: allowed 1 <= octaves <= 12",
            ),
            (
                Box::new(|s| s.field.height.min = 0.0),
                "field.height.min = 0 is out of range: allowed 0 < height.min <= 10 m",
            ),
            (
                Box::new(|s| s.field.width = Range::new(0.05, 0.02)),
                "field.width: min = 0.05 is greater than max = 0.02: allowed min <= max",
            ),
            (
                Box::new(|s| s.field.bend.max = 91.0),
                "field.bend.max = 91 is out of range: allowed 0 <= bend.max <= 90 degrees",
            ),
            (
                Box::new(|s| s.field.tip_threshold = 1.0),
                "field.tip_threshold = 1 is out of range: allowed 0 <= tip_threshold < 1",
            ),
            (
                Box::new(|s| s.field.segments = 17),
                "field.segments = 17 is out of range: allowed 1 <= segments <= 16",
            ),
            (
                Box::new(|s| s.physics.max_dt = 0.0),
                "physics.max_dt = 0 is out of range: allowed 0 < max_dt <= 1 s",
            ),
            (
                Box::new(|s| s.wind.directional.as_mut().unwrap().gust = -0.1),
                "wind.directional.gust = -0.1 is out of range: allowed 0 <= gust <= 4",
            ),
            (
                Box::new(|s| {
                    s.wind.point = Some(PointWind {
                        radius: 0.0,
                        ..PointWind::default()
                    })
                }),
                "wind.point.radius = 0 is out of range: allowed radius > 0 m",
            ),
            (
                Box::new(|s| s.culling.distance_levels = 0),
                "culling.distance_levels = 0 is out of range: allowed 1 <= distance_levels <= 64",
            ),
            (
                Box::new(|s| s.camera.fov_y = 179.0),
                "camera.fov_y = 179 is out of range: allowed 1 < fov_y < 179 degrees",
            ),
            (
                Box::new(|s| s.camera.far = 0.05),
                "camera.far = 0.05 is out of range: allowed far > near = 0.1 m",
            ),
            (
                Box::new(|s| s.render.width_span_px = -1.0),
                "render.width_span_px = -1 is out of range: allowed width_span_px >= 0 px",
            ),
            (
                Box::new(|s| s.physics.mass = f32::INFINITY),
                "physics.mass = inf is not a finite number: allowed mass >= 0",
            ),
        ];
        for (edit, expected) in cases {
            assert_eq!(rejected(edit), expected);
        }
    }

    #[test]
    fn patch_size_must_fill_workgroups() {
        for bad in [0, 32, 100, 65536 + 64] {
            let m = rejected(|s| s.field.patch_size = bad);
            assert!(m.starts_with("field.patch_size = "), "{m}");
            assert!(m.contains("multiple of 64"), "{m}");
        }
        for good in [64, 128, 65536] {
            let mut scene = Scene::default();
            scene.field.patch_size = good;
            check(&mut scene).unwrap();
        }
    }

    #[test]
    fn colliders_are_checked() {
        let sphere = |motion| Sphere {
            center: (0.0, 0.5, 0.0),
            radius: 0.5,
            motion,
        };
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
        let path = |points: Vec<(f32, f32)>, speed| Motion::Path {
            points,
            speed,
            looped: false,
        };
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

    /// A guide root (0, 0) → (4, 0) → (4, 4), strength 5, radius 1.
    fn guide() -> Guide {
        let point = |position, parent| GuidePoint {
            position,
            parent,
            strength: None,
            radius: None,
        };
        Guide {
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
            "wind.downwash.radius = 0 is out of range: allowed radius > 0 m"
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
    fn camera_eye_and_target_must_differ() {
        let m = rejected(|s| s.camera.target = s.camera.eye);
        assert!(m.contains("same point as camera.eye"), "{m}");
    }

    #[test]
    fn relative_image_paths_are_resolved_against_the_scene_directory() {
        let mut scene = Scene::default();
        scene.terrain.height = HeightSource::Png {
            path: "maps/height.png".into(),
            scale: 3.0,
        };
        scene.terrain.density_map = Some("/abs/density.png".into());
        check(&mut scene).unwrap();
        let HeightSource::Png { path, .. } = &scene.terrain.height else {
            unreachable!()
        };
        assert_eq!(Path::new(path), Path::new("/scenes/maps/height.png"));
        assert_eq!(
            scene.terrain.density_map.as_deref(),
            Some("/abs/density.png")
        );

        // A scene given by a bare file name: the images are in the working directory.
        let mut scene = Scene::default();
        scene.terrain.density_map = Some("d.png".into());
        validate(&mut scene, "()", Path::new("meadow.ron")).unwrap();
        assert_eq!(scene.terrain.density_map.as_deref(), Some("d.png"));

        let m = rejected(|s| s.terrain.density_map = Some(" ".into()));
        assert_eq!(m, "terrain.density_map is empty: name a PNG file");
    }

    #[test]
    fn error_points_at_the_value_in_the_text() {
        let text = "(\n  field: (\n    height: (min: 0.5, max: 0.2),\n  ),\n)";
        let mut scene = Scene::default();
        scene.field.height = Range::new(0.5, 0.2);
        match validate(&mut scene, text, Path::new(PATH)) {
            Err(Error::Scene {
                line,
                column,
                message,
                ..
            }) => {
                assert_eq!((line, column), (3, 24), "{message}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn locate_finds_keys_inside_their_section() {
        let text = "(\n    field: (\n        density: -3,\n    ),\n)";
        assert_eq!(locate(text, "field.density"), (3, 9));
        assert_eq!(locate(text, "field"), (2, 5));

        // `height` is a key of both `terrain` and `field`.
        let text = "(\n terrain: (height: Noise(seed: 1, amplitude: 2, wavelength: 3, octaves: 4)),\n field: (height: (min: 0.1, max: 0.2)),\n)";
        assert_eq!(locate(text, "field.height.min"), (3, 19));
        assert_eq!(locate(text, "field.height.max"), (3, 29));
        assert_eq!(locate(text, "terrain.height.amplitude"), (2, 35));
        assert_eq!(locate(text, "terrain.height"), (2, 12));
    }

    #[test]
    fn locate_falls_back_to_the_enclosing_key() {
        let text = "(\n  terrain: (size: 4.0),\n  field: (\n    seed: 3,\n  ),\n)";
        // `density` took its default: report the `field` section.
        assert_eq!(locate(text, "field.density"), (3, 3));
        // `density` is written only in another section: still the `field` section.
        let text2 = "(\n  field: (),\n  physics: (mass: 1.0),\n)";
        assert_eq!(locate(text2, "field.mass"), (2, 3));
        // No `camera` section at all: the start of the file.
        assert_eq!(locate(text, "camera.near"), (1, 1));
        assert_eq!(locate("", "camera.near"), (1, 1));
    }

    #[test]
    fn locate_ignores_comments_and_strings() {
        let text = "( // field: (density: 1)\n  terrain: (density_map: \"field: (density: 2)\"),\n  /* field: /* nested */ density: 3 */\n  field: (density: 4),\n)";
        assert_eq!(locate(text, "field.density"), (4, 11));
        let text = "(terrain: (density_map: r#\"a\"b field:\"#), field: (density: 4))";
        assert_eq!(locate(text, "field.density"), (1, 51));
    }

    #[test]
    fn locate_finds_list_elements_and_looks_through_some() {
        let text = "(\n  colliders: [\n    (center: (0, 0, 0), radius: 1),\n    (\n      center: (1, 0, 0),\n      radius: -1,\n      motion: Path(points: [(0, 0)], speed: 1, looped: false),\n    ),\n  ],\n  wind: (directional: Some((\n    strength: -1,\n  ))),\n)";
        assert_eq!(locate(text, "colliders[0].radius"), (3, 25));
        assert_eq!(locate(text, "colliders[1].radius"), (6, 7));
        assert_eq!(locate(text, "colliders[1].motion.points"), (7, 20));
        assert_eq!(locate(text, "colliders[1].motion.speed"), (7, 38));
        // The element exists but does not write the key: the element itself.
        assert_eq!(locate(text, "colliders[0].motion"), (3, 5));
        // No such element: the list's key.
        assert_eq!(locate(text, "colliders[2].radius"), (2, 3));
        assert_eq!(locate(text, "wind.directional.strength"), (11, 5));
    }

    #[test]
    fn locate_prefers_the_least_nested_key_and_whole_words() {
        // `max` inside `field.height` must not be taken for `culling.max_distance`'s
        // neighbour, and `max_distance` must not match `max`.
        let text =
            "(culling: (max_distance: 5, distance_levels: 2), field: (height: (max: 1), max: 2))";
        assert_eq!(locate(text, "culling.max"), (1, 2));
        assert_eq!(locate(text, "field.max"), (1, 76));
    }

    #[test]
    fn line_column_counts_characters() {
        let text = "(\n  /* é */ field: ()\n)";
        assert_eq!(locate(text, "field"), (2, 11));
        assert_eq!(line_column("ab\ncd", 0), (1, 1));
        assert_eq!(line_column("ab\ncd", 4), (2, 2));
        assert_eq!(line_column("ab", 99), (1, 3));
    }

    #[test]
    fn short_names() {
        assert_eq!(short_name("field.density"), "density");
        assert_eq!(short_name("field.height.min"), "height.min");
        assert_eq!(short_name("colliders[3].radius"), "radius");
        assert_eq!(short_name("colliders[3].motion.points[2]"), "points");
        assert_eq!(short_name("size"), "size");
    }
}
