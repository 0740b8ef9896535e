//! The ranges and checks of what the viewer sees: `culling`, `camera` and `render`.

use glam::Vec3;

use super::allowed::{show, unit, Allowed, Integers, Rule};
use super::objects::POSITION;
use super::{tuple3, Checker};
use crate::error::Result;
use crate::scene::types::{Camera, Culling, Render, SelfShadow};

const FRACTION: Allowed = Allowed::closed(0.0, 1.0, "");
const FRUSTUM_TOLERANCE: Allowed = Allowed::closed(0.0, 10.0, "");
const DISTANCE_LEVELS: Integers = Integers::new(1, 64, "");
const MAX_DISTANCE: Allowed = Allowed::open_closed(0.0, 100000.0, "m");
const LOD_PIXELS: Allowed = Allowed::closed(0.0, 4096.0, "px");
const THROTTLE: Integers = Integers::new(1, 64, "frames");
const PHYSICS_RADIUS: Allowed = Allowed::closed(0.0, 1.0e4, "m");
const FOV: Allowed = Allowed::open(1.0, 179.0, "degrees");
/// A millimetre to a kilometre: depth precision is lost outside, not only accuracy.
const NEAR: Allowed = Allowed::closed(0.001, 1000.0, "m");
/// The far plane's upper bound; its lower bound is `near`.
const FAR_MAX: f32 = 1.0e6;
const FAR_TEXT: &str = "near < far <= 1000000 m";
const WIDTH_PIXELS: Allowed = Allowed::closed(0.0, 1024.0, "px");
const SHADE: Allowed = Allowed::closed(0.0, 2.0, "");
const BILLBOARD_DISTANCE: Allowed = Allowed::closed(0.0, 100000.0, "m");
const SHADE_GAIN: Allowed = Allowed::closed(0.0, 10.0, "");
const SHADE_OFFSET: Allowed = Allowed::closed(-2.0, 2.0, "");

/// The rules of every `culling`, `camera` and `render` value.
pub(super) const RULES: &[(&str, Rule)] = &[
    ("culling.patches", Rule::Bool),
    ("culling.orientation", Rule::Bool),
    ("culling.orientation_threshold", Rule::Real(FRACTION)),
    ("culling.frustum", Rule::Bool),
    ("culling.frustum_tolerance", Rule::Real(FRUSTUM_TOLERANCE)),
    ("culling.distance", Rule::Bool),
    ("culling.distance_levels", Rule::Integer(DISTANCE_LEVELS)),
    ("culling.max_distance", Rule::Real(MAX_DISTANCE)),
    ("culling.occlusion", Rule::Bool),
    ("culling.occlusion_bias", Rule::Real(FRACTION)),
    ("culling.grass_occlusion", Rule::Bool),
    ("culling.grass_occlusion_bias", Rule::Real(FRACTION)),
    ("culling.lod", Rule::Bool),
    (
        "culling.lod_near_px",
        Rule::Text("0 <= lod_near_px <= 4096 px and lod_near_px >= lod_far_px × (1 + lod_morph)"),
    ),
    ("culling.lod_far_px", Rule::Real(LOD_PIXELS)),
    ("culling.lod_morph", Rule::Real(FRACTION)),
    ("culling.physics_throttle", Rule::Integer(THROTTLE)),
    ("culling.physics_radius", Rule::Real(PHYSICS_RADIUS)),
    ("camera.eye", Rule::Vector(POSITION)),
    ("camera.target", Rule::Vector(POSITION)),
    ("camera.fov_y", Rule::Real(FOV)),
    ("camera.near", Rule::Real(NEAR)),
    ("camera.far", Rule::Text(FAR_TEXT)),
    (
        "camera.follow",
        Rule::Text(
            "None or Some((object: .., distance: .., height: .., look_height: ..)), each part \
             optional",
        ),
    ),
    (
        "camera.follow.object",
        Rule::Text("the index of one of the scene's objects, from 0"),
    ),
    ("camera.follow.distance", Rule::Real(FOLLOW_DISTANCE)),
    ("camera.follow.height", Rule::Real(FOLLOW_HEIGHT)),
    ("camera.follow.look_height", Rule::Real(FOLLOW_HEIGHT)),
    ("render.sun_direction", Rule::Direction),
    ("render.displacement", Rule::Bool),
    ("render.width_min_px", Rule::Real(WIDTH_PIXELS)),
    ("render.width_span_px", Rule::Real(WIDTH_PIXELS)),
    (
        "render.color_mode",
        Rule::Choice("one of Natural, Lod, Patch, Trail"),
    ),
    ("render.wireframe", Rule::Bool),
    ("render.deferred_grass", Rule::Bool),
    ("render.taa", Rule::Bool),
    (
        "render.self_shadow",
        Rule::Choice("Height, Cwd(min: .., max: .., c1: .., c2: ..) or Off"),
    ),
    ("render.self_shadow.min", Rule::Real(SHADE)),
    ("render.self_shadow.max", Rule::Text("min <= max <= 2")),
    ("render.self_shadow.c1", Rule::Real(SHADE_GAIN)),
    ("render.self_shadow.c2", Rule::Real(SHADE_OFFSET)),
    ("render.billboard_distance", Rule::Real(BILLBOARD_DISTANCE)),
    ("render.msaa", Rule::Choice(MSAA_TEXT)),
];

/// `render.msaa`: the sample counts a render pipeline may have.
const MSAA_TEXT: &str = "one of 1, 2, 4, 8 samples";

pub(super) fn culling(check: &Checker, culling: &Culling) -> Result<()> {
    let c = culling;
    check.real(
        "culling.orientation_threshold",
        c.orientation_threshold,
        FRACTION,
    )?;
    let tolerance = c.frustum_tolerance;
    check.real("culling.frustum_tolerance", tolerance, FRUSTUM_TOLERANCE)?;
    check.integer(
        "culling.distance_levels",
        c.distance_levels,
        DISTANCE_LEVELS,
    )?;
    check.real("culling.max_distance", c.max_distance, MAX_DISTANCE)?;
    check.real("culling.occlusion_bias", c.occlusion_bias, FRACTION)?;
    let grass_bias = c.grass_occlusion_bias;
    check.real("culling.grass_occlusion_bias", grass_bias, FRACTION)?;
    check.real("culling.lod_near_px", c.lod_near_px, LOD_PIXELS)?;
    check.real("culling.lod_far_px", c.lod_far_px, LOD_PIXELS)?;
    check.real("culling.lod_morph", c.lod_morph, FRACTION)?;
    // The middle level's morph band must end below the near threshold, or a blade would
    // enter level 0 while its middle mesh is still part-way morphed and jump.
    let band_top = c.lod_far_px * (1.0 + c.lod_morph);
    if c.lod_near_px < band_top {
        let message = format!(
            "culling.lod_near_px = {} is below lod_far_px × (1 + lod_morph) = {band_top}: \
             allowed lod_near_px >= {band_top}",
            c.lod_near_px
        );
        return Err(check.error("culling.lod_near_px", message));
    }
    check.integer("culling.physics_throttle", c.physics_throttle, THROTTLE)?;
    check.real("culling.physics_radius", c.physics_radius, PHYSICS_RADIUS)
}

const FOLLOW_DISTANCE: Allowed = Allowed::closed(0.1, 1000.0, "m");
const FOLLOW_HEIGHT: Allowed = Allowed::closed(-1000.0, 1000.0, "m");

/// `objects`: how many objects the scene has (what `camera.follow.object` may name).
pub(super) fn camera(check: &Checker, camera: &Camera, objects: usize) -> Result<()> {
    if let Some(f) = &camera.follow {
        if f.object as usize >= objects {
            let allowed = match objects {
                0 => "the scene has no objects to follow".to_string(),
                n => format!("allowed 0 to {} (the scene has {n} objects)", n - 1),
            };
            return Err(check.error(
                "camera.follow.object",
                format!(
                    "camera.follow.object = {} is out of range: {allowed}",
                    f.object
                ),
            ));
        }
        check.real("camera.follow.distance", f.distance, FOLLOW_DISTANCE)?;
        check.real("camera.follow.height", f.height, FOLLOW_HEIGHT)?;
        check.real("camera.follow.look_height", f.look_height, FOLLOW_HEIGHT)?;
    }
    check.vector("camera.eye", &tuple3(camera.eye), POSITION)?;
    check.vector("camera.target", &tuple3(camera.target), POSITION)?;
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
    check.real("camera.fov_y", camera.fov_y, FOV)?;
    check.real("camera.near", camera.near, NEAR)?;
    // The lower bound of `far` is another field, so the message names it.
    let far = camera.far;
    if !(far.is_finite() && far > camera.near && far <= FAR_MAX) {
        let problem = if far.is_finite() {
            "is out of range"
        } else {
            "is not a finite number"
        };
        let message = format!(
            "camera.far = {far} {problem}: allowed near < far <= {FAR_MAX} m (near = {} m)",
            camera.near
        );
        return Err(check.error("camera.far", message));
    }
    Ok(())
}

pub(super) fn render(check: &Checker, render: &mut Render) -> Result<()> {
    let mut sun = tuple3(render.sun_direction);
    check.direction("render.sun_direction", &mut sun)?;
    render.sun_direction = sun.into();
    check.real("render.width_min_px", render.width_min_px, WIDTH_PIXELS)?;
    check.real("render.width_span_px", render.width_span_px, WIDTH_PIXELS)?;
    if let SelfShadow::Cwd { min, max, c1, c2 } = render.self_shadow {
        check.real("render.self_shadow.min", min, SHADE)?;
        if !(max.is_finite() && max >= min && max <= 2.0) {
            return Err(check.error(
                "render.self_shadow.max",
                format!("render.self_shadow.max = {max} is out of range: allowed min <= max <= 2 (min is {min})"),
            ));
        }
        check.real("render.self_shadow.c1", c1, SHADE_GAIN)?;
        check.real("render.self_shadow.c2", c2, SHADE_OFFSET)?;
    }
    check.real(
        "render.billboard_distance",
        render.billboard_distance,
        BILLBOARD_DISTANCE,
    )?;
    if !crate::scene::limits::SAMPLE_COUNTS.contains(&render.msaa) {
        let message = format!(
            "render.msaa = {} is not a sample count: allowed {MSAA_TEXT}",
            render.msaa
        );
        return Err(check.error("render.msaa", message));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::tests::rejected;

    #[test]
    fn camera_eye_and_target_must_differ() {
        let m = rejected(|s| s.camera.target = s.camera.eye);
        assert!(m.contains("same point as camera.eye"), "{m}");
    }

    #[test]
    fn camera_and_pixels_are_bounded() {
        assert_eq!(
            rejected(|s| s.camera.far = 2e6),
            "camera.far = 2000000 is out of range: allowed near < far <= 1000000 m (near = \
             0.1 m)"
        );
        assert_eq!(
            rejected(|s| s.camera.near = 1e-38),
            "camera.near = 0.00000000000000000000000000000000000001 is out of range: allowed \
             0.001 <= near <= 1000 m"
        );
        let m = rejected(|s| s.camera.eye = (1e38, 0.0, 0.0));
        assert!(m.starts_with("camera.eye = (100000000000000000000000000000000000000, 0, 0) is out of range: allowed -100000 <= eye <= 100000 m for every component"), "{m}");
        assert_eq!(
            rejected(|s| s.render.width_min_px = 1e9),
            "render.width_min_px = 1000000000 is out of range: allowed 0 <= width_min_px <= \
             1024 px"
        );
        assert_eq!(
            rejected(|s| s.render.msaa = 3),
            "render.msaa = 3 is not a sample count: allowed one of 1, 2, 4, 8 samples"
        );
        assert_eq!(
            rejected(|s| s.culling.max_distance = 1e38),
            "culling.max_distance = 100000000000000000000000000000000000000 is out of range: \
             allowed 0 < max_distance <= 100000 m"
        );
    }
}
