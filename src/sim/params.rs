//! Turns the scene's physics, wind and culling settings into the uniform blocks the
//! shaders (and their CPU twins) read.

use glam::{Mat4, Vec3};

use super::layout::{
    CullParams, SimParams, TEST_DISTANCE, TEST_FRUSTUM, TEST_ORIENTATION, TEST_PATCH,
    WIND_ANALYTIC, WIND_FLUID,
};
use crate::scene::{Culling, Physics, Wind, WindSource};

/// Update uniforms for one step of `dt` seconds (already clamped) at time `time`.
pub fn sim_params(
    physics: &Physics,
    wind: &Wind,
    terrain_size: f32,
    dt: f32,
    time: f32,
    blade_count: u32,
    sphere_count: u32,
) -> SimParams {
    let gd = Vec3::from(physics.gravity_direction).normalize_or_zero();
    let gc = physics.gravity_center;
    let mut p = SimParams {
        gravity_dir: [gd.x, gd.y, gd.z, physics.gravity_acceleration],
        gravity_center: [gc.0, gc.1, gc.2, physics.gravity_center_acceleration],
        dt,
        time,
        mass: physics.mass,
        gravity_blend: physics.gravity_blend,
        collision_decay: physics.collision_decay,
        collision_gain: physics.collision_gain,
        max_eta: physics.max_collision_strength,
        stiffness_scale: physics.stiffness_scale,
        blade_count,
        sphere_count,
        collisions: physics.collisions as u32,
        ..Default::default()
    };
    if let Some(d) = &wind.directional {
        let dir = glam::Vec2::from(d.direction).normalize_or_zero();
        p.wind_dir = [dir.x, dir.y, d.strength, d.gust];
        p.wind_wave = [d.wavelength, d.speed, 0.0, 0.0];
    } else {
        p.wind_wave = [1.0, 0.0, 0.0, 0.0];
    }
    let uses_fluid = wind.source != WindSource::Analytic;
    let mask = match wind.source {
        WindSource::Analytic => WIND_ANALYTIC,
        WindSource::Fluid => WIND_FLUID,
        WindSource::Both => WIND_ANALYTIC | WIND_FLUID,
    };
    // Without the fluid the update still binds a one-cell dummy grid.
    let resolution = if uses_fluid {
        wind.fluid.resolution.max(1)
    } else {
        1
    };
    let half = terrain_size * 0.5;
    p.fluid_grid = [
        -half,
        -half,
        terrain_size / resolution as f32,
        wind.fluid.response,
    ];
    p.fluid_info = [resolution, mask, wind.fluid.per_cell as u32, 0];
    if let Some(s) = &wind.point {
        p.point_wind = [s.position.0, s.position.1, s.position.2, s.strength];
        p.point_wind_shape = [s.radius, s.frequency, 0.0, 0.0];
    }
    p
}

/// The bit mask of enabled cull tests.
pub fn cull_tests(culling: &Culling) -> u32 {
    let mut t = 0;
    if culling.patches {
        t |= TEST_PATCH;
    }
    if culling.orientation {
        t |= TEST_ORIENTATION;
    }
    if culling.frustum {
        t |= TEST_FRUSTUM;
    }
    if culling.distance {
        t |= TEST_DISTANCE;
    }
    t
}

/// Cull uniforms for a camera.
pub fn cull_params(
    culling: &Culling,
    view_proj: Mat4,
    camera: Vec3,
    blade_count: u32,
    patch_size: u32,
    index_count: u32,
) -> CullParams {
    CullParams {
        view_proj: view_proj.to_cols_array_2d(),
        camera_pos: [camera.x, camera.y, camera.z, 1.0],
        blade_count,
        patch_size,
        tests: cull_tests(culling),
        distance_levels: culling.distance_levels,
        orientation_threshold: culling.orientation_threshold,
        frustum_tolerance: culling.frustum_tolerance,
        max_distance: culling.max_distance,
        index_count,
    }
}
