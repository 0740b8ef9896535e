//! Validation of a parsed [`Scene`]: every number finite and in range, direction vectors
//! normalised, relative image paths resolved.
//!
//! Serde only checks types; a scene with `density: -3` or `near: NaN` parses fine and would
//! then produce an empty frame, a GPU allocation failure or NaN blades far from the cause.
//! Validation catches it at load time and points at the line that holds the value, with the
//! allowed range in the message, e.g.
//! `scene.ron:5:9: field.density = -3 is out of range: allowed 0 < density <= 10000 blades/m²`.
//!
//! Every float must be finite (RON accepts `NaN`, `inf` and `-inf`), and every range is
//! closed or bounded on both sides: a force of 1e38 m/s² is "a number ≥ 0" but overflows the
//! first update step into NaN blades. The bounds are chosen so that any valid scene keeps
//! the blade update finite (see the `physics` section's notes). The allowed ranges:
//!
//! | field | allowed |
//! |---|---|
//! | `terrain.size` | 1 ≤ size ≤ 10000 m |
//! | `terrain.resolution` | 2 ≤ resolution ≤ 4097 vertices per side |
//! | `terrain.height: Noise` | 0 ≤ amplitude ≤ 1000 m, 0.01 ≤ wavelength ≤ 100000 m, 1 ≤ octaves ≤ 12 |
//! | `terrain.height: Png` | path not empty, 0 ≤ scale ≤ 1000 m |
//! | `terrain.density_map` | not empty |
//! | `terrain.unbounded` | true or false |
//! | `field.density` | 0 < density ≤ 10000 blades/m² |
//! | `field.height` | 0.01 ≤ min ≤ max ≤ 10 m |
//! | `field.width` | 0 < min ≤ max ≤ 1 m |
//! | `field.stiffness` | 0 ≤ min ≤ max ≤ 1000 1/s |
//! | `field.bend` | 0 ≤ min ≤ max ≤ 90 degrees |
//! | `field.tuft_fraction` | 0 ≤ tuft_fraction ≤ 1 |
//! | `field.tuft_radius` | 0 < tuft_radius ≤ 10 m |
//! | `field.tip_threshold` | 0 ≤ tip_threshold < 1 |
//! | `field.patch_size` | a multiple of 64 (the workgroup size), 64 ≤ patch_size ≤ 65536 |
//! | `field.segments` | 1 ≤ segments ≤ 16 |
//! | `field.tile_size` | 0 (whole field at start) or 0.5 ≤ tile_size ≤ 1000 m |
//! | positions: `colliders[i].center`, `wind.point.position`, `wind.downwash.position`, `physics.gravity_center`, `camera.eye`, `camera.target`, path points | every component in −100000 ..= 100000 m |
//! | `colliders[i]` | 0 < radius ≤ 1000 m |
//! | `objects[i]` | mesh a .obj, .gltf or .glb file; translation in −100000 ..= 100000 m, rotation in −360 ..= 360 degrees, 0.001 ≤ scale ≤ 1000, colour components in 0 ..= 1; animation None or the name of an animation of a skinned .gltf / .glb (checked when the session loads the file) |
//! | `colliders[i].motion: Velocity` | every component in −1000 ..= 1000 m/s |
//! | `colliders[i].motion: Path` | ≥ 2 points, total length > 0, 0 ≤ speed ≤ 1000 m/s |
//! | `wind.directional` | direction non-zero, 0 ≤ strength ≤ 1000 m/s², 0 ≤ gust ≤ 4, 0.1 ≤ wavelength ≤ 100000 m, 0 ≤ speed ≤ 1000 m/s |
//! | `wind.point` | 0 ≤ strength ≤ 1000 m/s², 0.01 ≤ radius ≤ 10000 m, 0 ≤ frequency ≤ 100 Hz |
//! | `wind.fluid` | 8 ≤ resolution ≤ 2048 cells per side, 0 ≤ pressure_iterations ≤ 1000, 1 ≤ multigrid_cycles ≤ 20 (Multigrid + Periodic: even resolution), 0 ≤ vorticity ≤ 1000, 0 ≤ dissipation ≤ 100 1/s, 0 ≤ viscosity ≤ 10 m²/s, 1 ≤ diffusion_iterations ≤ 200, 0 ≤ response ≤ 100 1/s |
//! | `wind.global` | direction non-zero, 0 ≤ strength ≤ 1000 m/s² |
//! | `wind.downwash` | 0.01 ≤ radius ≤ 10000 m, 0 ≤ strength ≤ 1000 m/s², motion as for colliders |
//! | `wind.guides[i]` | 0 ≤ strength ≤ 1000 m/s², 0 < radius ≤ terrain.size m, ≥ 1 point |
//! | `wind.guides[i].points[k]` | position finite and on the terrain (\|x\|, \|z\| ≤ terrain.size / 2); point 0 has no parent, every other point a parent < k at least 0.0001 m away; overrides as the guide's strength and radius |
//! | `physics.gravity_direction` | non-zero |
//! | `physics.gravity_acceleration`, `gravity_center_acceleration` | 0 ≤ acceleration ≤ 1000 m/s² |
//! | `physics.gravity_blend` | 0 ≤ gravity_blend ≤ 1 |
//! | `physics.mass` | 0 ≤ mass ≤ 100 (a factor on gravity, Eq. 4) |
//! | `physics.collision_decay` | 0 ≤ collision_decay ≤ 1000 1/s |
//! | `physics.collision_gain` | 0 ..= 1e6 1/m² |
//! | `physics.max_collision_strength` | 0 ..= 100 |
//! | `physics.stiffness_scale` | 0.05 ≤ stiffness_scale ≤ 4 |
//! | `physics.max_dt` | 0 < max_dt ≤ 1 s |
//! | `culling.orientation_threshold` | 0 ≤ orientation_threshold ≤ 1 |
//! | `culling.frustum_tolerance` | 0 ≤ frustum_tolerance ≤ 10 |
//! | `culling.distance_levels` | 1 ≤ distance_levels ≤ 64 |
//! | `culling.max_distance` | 0 < max_distance ≤ 100000 m |
//! | `culling.occlusion_bias` | 0 ≤ occlusion_bias ≤ 1 |
//! | `culling.grass_occlusion_bias` | 0 ≤ grass_occlusion_bias ≤ 1 |
//! | `culling.lod_near_px`, `lod_far_px` | 0 – 4096 px, near ≥ far × (1 + lod_morph) |
//! | `culling.lod_morph` | 0 ≤ lod_morph ≤ 1 |
//! | `culling.physics_throttle` | 1 – 64 frames |
//! | `culling.physics_radius` | 0 – 10⁴ m |
//! | `camera` | eye and target distinct, 1 < fov_y < 179 degrees, 0.001 ≤ near ≤ 1000 m, near < far ≤ 10⁶ m; `follow`: an object of the scene, distance 0.1 – 1000 m, heights ±1000 m |
//! | `render.sun_direction` | non-zero |
//! | `render.width_min_px`, `width_span_px` | 0 – 1024 px |
//! | `render.msaa` | one of 1, 2, 4, 8 samples (4 by default; the adapter may give fewer) |
//! | `light` | time_of_day 0 – 24 h, latitude ±89°, day_of_year 1 – 366, turbidity 1.7 – 10, exposure ±16 stops; shadows: 1 – 4 cascades of 64 – 8192 texels, distance ≤ 10⁴ m; shading strengths 0 – 2 (see `light.rs`) |
//!
//! The same ranges, as data, are the `RULES` tables of the section modules ([`allowed_for`]
//! reads them): parser errors and `--set` errors quote them, so each range is written once.
//!
//! Direction vectors (`wind.directional.direction`, `wind.global.direction`,
//! `physics.gravity_direction`, `render.sun_direction`) are normalised in place. Relative
//! image paths are rewritten in place to the scene file's directory joined with the path,
//! so that they do not depend on the working directory of the process.
//!
//! The line and column of an error come from [`locate::locate`], a small text scan for the
//! field's key. Values that came from a `--set PATH=VALUE` argument have no line: their
//! errors are [`Error::Set`] naming the argument.

mod allowed;
mod catalogue;
mod light;
pub(crate) mod locate;
mod meshes;
mod objects;
mod physics;
mod terrain_field;
mod view;
mod wind;

use std::path::Path;

use self::allowed::{generic_path, show, unit, Allowed, Integers, Rule};
use self::locate::{field_value, locate};
use super::types::{Range, Scene};
use crate::error::{Error, Result};

/// A field set by a `--set PATH=VALUE` argument: errors about it name the argument.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SetField {
    /// The field path, e.g. `field.density`.
    pub(crate) path: String,
    /// The argument as given, `PATH=VALUE`.
    pub(crate) arg: String,
}

/// Checks every value of `scene` (see the module docs for the ranges), normalises its
/// direction vectors and resolves its relative image paths against `path`'s directory.
///
/// `text` is the RON text `scene` was parsed from; it is only used to find the line and
/// column of an offending value. `path` names the scene file in errors.
///
/// Idempotent except for image paths when `path` is itself relative (resolving twice
/// prefixes the directory twice).
pub(crate) fn validate(scene: &mut Scene, text: &str, path: &Path) -> Result<()> {
    validate_with_sets(scene, text, path, &[])
}

/// [`validate`] for a scene whose fields `sets` were replaced by `--set` arguments: errors
/// about those fields name the argument instead of a line of `text`.
pub(crate) fn validate_with_sets(
    scene: &mut Scene,
    text: &str,
    path: &Path,
    sets: &[SetField],
) -> Result<()> {
    let check = Checker { text, path, sets };
    terrain_field::terrain(&check, &mut scene.terrain)?;
    terrain_field::field(&check, "field", &scene.field)?;
    for (i, sphere) in scene.colliders.iter().enumerate() {
        objects::collider(&check, i, sphere)?;
    }
    for (i, object) in scene.objects.iter_mut().enumerate() {
        meshes::object(&check, i, object)?;
        if let Some(grass) = &object.grass {
            let name = format!("objects[{i}].grass");
            terrain_field::field(&check, &name, grass)?;
        }
    }
    // The packed spheres join the colliders in the update pass's fixed list.
    let packed = meshes::packed_spheres(&scene.objects);
    let total = scene.colliders.len() + packed;
    if packed > 0 && total > crate::scene::limits::MAX_SPHERES {
        let last = scene
            .objects
            .iter()
            .rposition(|o| o.collider.packing().is_some())
            .unwrap_or(0);
        let name = format!("objects[{last}].collider");
        let message = format!(
            "{name}: the objects' sphere packings ({packed} spheres) and the {} colliders \
             make {total} spheres; allowed at most {} in all (what the update pass takes): \
             lower the packings' counts (e.g. {name}=Spheres((count: 100)))",
            scene.colliders.len(),
            crate::scene::limits::MAX_SPHERES
        );
        return Err(check.error(&name, message));
    }
    // The guides must lie on the terrain, so the wind needs its (already checked) size.
    wind::wind(&check, &mut scene.wind, scene.terrain.size)?;
    physics::physics(&check, &mut scene.physics)?;
    view::culling(&check, &scene.culling)?;
    view::camera(&check, &scene.camera, scene.objects.len())?;
    view::render(&check, &mut scene.render)?;
    light::light(&check, &scene.light)
}

/// The rule of the field at `path` (`colliders[2].radius`, `field.height.min`), if the
/// scene has such a field.
pub use catalogue::{field_rules, FieldRule, RuleKind};

/// Every `(path, rule)` of the sections' tables.
fn all_rules() -> impl Iterator<Item = (&'static str, Rule)> {
    [
        terrain_field::RULES,
        objects::RULES,
        meshes::RULES,
        wind::RULES,
        physics::RULES,
        view::RULES,
        light::RULES,
    ]
    .into_iter()
    .flat_map(|t| t.iter().copied())
}

pub(crate) fn rule_for(path: &str) -> Option<Rule> {
    let mut generic = generic_path(path);
    // An object's grass has the scene field's fields and rules.
    if let Some(rest) = generic.strip_prefix("objects[].grass.") {
        generic = format!("field.{rest}");
    }
    let find = |p: &str| {
        all_rules()
            .find(|(name, _)| *name == p)
            .map(|(_, rule)| rule)
    };
    if let Some(rule) = find(&generic) {
        return Some(rule);
    }
    // The ends of a `Range` share its rule.
    let (parent, last) = generic.rsplit_once('.')?;
    match (last, find(parent)?) {
        ("min" | "max", rule @ Rule::Range(_)) => Some(rule),
        _ => None,
    }
}

/// What the field at `path` may hold, as error messages quote it after "allowed" (e.g.
/// `2 <= resolution <= 4097 vertices per side`), or `None` if there is no such field.
pub(crate) fn allowed_for(path: &str) -> Option<String> {
    rule_for(path).map(|rule| rule.describe(path))
}

fn tuple3(v: (f32, f32, f32)) -> [f32; 3] {
    [v.0, v.1, v.2]
}

/// Builds errors that point into the scene text (or at the `--set` argument).
struct Checker<'a> {
    text: &'a str,
    path: &'a Path,
    sets: &'a [SetField],
}

impl Checker<'_> {
    /// An error at the place where `field` (a dotted path such as `colliders[1].radius`)
    /// is written: the `--set` argument that set it, else its line in the scene text.
    fn error(&self, field: &str, message: String) -> Error {
        if let Some(set) = self.set_for(field) {
            return Error::Set {
                arg: set.arg.clone(),
                message,
            };
        }
        let (line, column) = locate(self.text, field);
        Error::Scene {
            path: self.path.to_path_buf(),
            line,
            column,
            message,
        }
    }

    /// The last `--set` that set `field`, a field inside it or one around it; failing that,
    /// when the file does not write `field`, the last one that set a sibling (a range's
    /// `min` when its `max` is reported, `near` when `far` is).
    fn set_for(&self, field: &str) -> Option<&SetField> {
        let inside = |outer: &str, inner: &str| {
            inner == outer
                || inner
                    .strip_prefix(outer)
                    .is_some_and(|rest| rest.starts_with('.') || rest.starts_with('['))
        };
        let related = self
            .sets
            .iter()
            .rev()
            .find(|s| inside(&s.path, field) || inside(field, &s.path));
        if related.is_some() || self.sets.is_empty() {
            return related;
        }
        if field_value(self.text, field).is_some() {
            return None;
        }
        let parent = |p: &str| p.rsplit_once('.').map(|(a, _)| a.to_owned());
        self.sets
            .iter()
            .rev()
            .find(|s| parent(&s.path) == parent(field))
    }

    fn real(&self, field: &str, value: f32, allowed: Allowed) -> Result<()> {
        let problem = if !value.is_finite() {
            "is not a finite number"
        } else if !allowed.contains(value) {
            "is out of range"
        } else {
            return Ok(());
        };
        let range = allowed.describe(&allowed::short_name(field));
        let message = format!("{field} = {value} {problem}: allowed {range}");
        Err(self.error(field, message))
    }

    fn integer(&self, field: &str, value: impl Into<u64>, allowed: Integers) -> Result<()> {
        let value = value.into();
        if (allowed.low..=allowed.high).contains(&value) {
            return Ok(());
        }
        let range = allowed.describe(&allowed::short_name(field));
        let message = format!("{field} = {value} is out of range: allowed {range}");
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

    /// Every component finite; `allowed` says what else the field needs.
    fn finite(&self, field: &str, components: &[f32], allowed: &str) -> Result<()> {
        if components.iter().all(|c| c.is_finite()) {
            return Ok(());
        }
        let message = format!(
            "{field} = {} is not finite: every component must be a finite number, allowed \
             {allowed}",
            show(components)
        );
        Err(self.error(field, message))
    }

    /// Every component finite and within `allowed` (positions, velocities).
    fn vector(&self, field: &str, components: &[f32], allowed: Allowed) -> Result<()> {
        self.finite(field, components, &Rule::Vector(allowed).describe(field))?;
        if components.iter().all(|&c| allowed.contains(c)) {
            return Ok(());
        }
        let message = format!(
            "{field} = {} is out of range: allowed {}",
            show(components),
            Rule::Vector(allowed).describe(field)
        );
        Err(self.error(field, message))
    }

    /// A finite, non-zero direction, normalised in place. Already normalised vectors are left
    /// bit for bit as they are, so that validating twice changes nothing.
    fn direction(&self, field: &str, components: &mut [f32]) -> Result<()> {
        self.finite(field, components, &Rule::Direction.describe(field))?;
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
        self.file_path(field, image, "a PNG file")
    }

    /// A non-empty path of `what` (e.g. "a PNG file"), made relative to the scene file's
    /// directory in place.
    fn file_path(&self, field: &str, image: &mut String, what: &str) -> Result<()> {
        if image.trim().is_empty() {
            let message = format!("{field} is empty: name {what}");
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DirectionalWind, HeightSource, Motion, PointWind, Range, Sphere};

    pub(super) const PATH: &str = "/scenes/meadow.ron";

    pub(super) fn check(scene: &mut Scene) -> Result<()> {
        validate(scene, "()", Path::new(PATH))
    }

    fn message(result: Result<()>) -> String {
        match result {
            Err(Error::Scene { message, .. }) => message,
            other => panic!("expected a scene error, got {other:?}"),
        }
    }

    /// The error message for the default scene changed by `edit`.
    pub(super) fn rejected(edit: impl FnOnce(&mut Scene)) -> String {
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
                "field.height.min = 0 is out of range: allowed 0.01 <= height.min <= 10 m",
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
                "wind.point.radius = 0 is out of range: allowed 0.01 <= radius <= 10000 m",
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
                "camera.far = 0.05 is out of range: allowed near < far <= 1000000 m (near = 0.1 m)",
            ),
            (
                Box::new(|s| s.camera.follow = Some(crate::scene::CameraFollow::default())),
                "camera.follow.object = 0 is out of range: the scene has no objects to follow",
            ),
            (
                Box::new(|s| {
                    s.objects = vec![crate::scene::MeshObject {
                        mesh: "x.obj".into(),
                        ..Default::default()
                    }];
                    s.camera.follow = Some(crate::scene::CameraFollow {
                        object: 1,
                        ..Default::default()
                    });
                }),
                "camera.follow.object = 1 is out of range: allowed 0 to 0 (the scene has 1 objects)",
            ),
            (
                Box::new(|s| {
                    s.objects = vec![crate::scene::MeshObject {
                        mesh: "x.obj".into(),
                        ..Default::default()
                    }];
                    s.camera.follow = Some(crate::scene::CameraFollow {
                        distance: 0.0,
                        ..Default::default()
                    });
                }),
                "camera.follow.distance = 0 is out of range: allowed 0.1 <= distance <= 1000 m",
            ),
            (
                Box::new(|s| s.render.width_span_px = -1.0),
                "render.width_span_px = -1 is out of range: allowed 0 <= width_span_px <= 1024 px",
            ),
            (
                Box::new(|s| s.physics.mass = f32::INFINITY),
                "physics.mass = inf is not a finite number: allowed 0 <= mass <= 100",
            ),
        ];
        for (edit, expected) in cases {
            assert_eq!(rejected(edit), expected);
        }
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

    /// Every leaf value of a scene with every part switched on has a rule, so that parser
    /// and `--set` errors can always give the allowed values.
    #[test]
    fn every_field_has_a_rule() {
        use crate::scene::{Downwash, GlobalWind, Guide, GuidePoint};
        let mut scene = Scene::default();
        scene.wind.point = Some(PointWind::default());
        scene.wind.global = Some(GlobalWind {
            direction: (1.0, 0.0),
            strength: 1.0,
        });
        let path = Motion::Path {
            points: vec![(0.0, 0.0), (1.0, 0.0)],
            speed: 1.0,
            looped: false,
        };
        scene.wind.downwash = Some(Downwash {
            position: (0.0, 1.0, 0.0),
            radius: 1.0,
            strength: 1.0,
            motion: path.clone(),
        });
        scene.wind.guides.push(Guide {
            started: 0.0,
            strength: 1.0,
            radius: 1.0,
            points: vec![GuidePoint {
                position: (0.0, 0.0),
                parent: Some(0),
                strength: Some(1.0),
                radius: Some(1.0),
            }],
        });
        scene.terrain.density_map = Some("d.png".into());
        let sphere = |motion| Sphere {
            center: (0.0, 0.0, 0.0),
            radius: 1.0,
            motion,
        };
        scene.colliders = vec![sphere(Motion::Velocity((1.0, 0.0, 0.0))), sphere(path)];
        let mut leaves = Vec::new();
        for height in [
            HeightSource::Flat,
            HeightSource::Png {
                path: "h.png".into(),
                scale: 1.0,
            },
            Scene::default().terrain.height,
        ] {
            scene.terrain.height = height;
            let text = ron::ser::to_string(&scene).unwrap();
            let code = locate::mask(&text);
            collect_leaves(&code, 0..code.len(), String::new(), &mut leaves);
        }
        assert!(leaves.len() > 100, "{leaves:?}");
        for leaf in leaves {
            assert!(allowed_for(&leaf).is_some(), "no rule for {leaf}");
        }
        assert_eq!(
            allowed_for("colliders[3].radius").as_deref(),
            Some("0 < radius <= 1000 m")
        );
        assert_eq!(allowed_for("field.densty"), None);
    }

    /// The paths of the lists and of the values in `span` that are not structs.
    fn collect_leaves(
        code: &[u8],
        span: std::ops::Range<usize>,
        path: String,
        out: &mut Vec<String>,
    ) {
        let span = locate::inside_some(code, span.clone()).unwrap_or(span);
        if let Some(fields) = locate::struct_fields(code, span.clone()) {
            // A section's own errors (`field: 3`) quote `ron`'s "expected `(` for struct".
            for (key, value) in fields {
                let child = if path.is_empty() {
                    key
                } else {
                    format!("{path}.{key}")
                };
                collect_leaves(code, value, child, out);
            }
        } else if let Some(elements) = locate::list_elements(code, span) {
            out.push(path.clone());
            for (i, element) in elements.into_iter().enumerate() {
                collect_leaves(code, element, format!("{path}[{i}]"), out);
            }
        } else {
            out.push(path);
        }
    }
}
