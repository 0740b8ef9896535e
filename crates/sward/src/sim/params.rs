//! Turns the scene's physics, wind and culling settings into the uniform blocks the
//! shaders (and their CPU twins) read.

use glam::{Mat4, Vec3};

use super::layout::{
    CullParams, SimParams, LOD_LEVELS, TEST_DISTANCE, TEST_FRUSTUM, TEST_GRASS_OCCLUSION,
    TEST_OCCLUSION, TEST_ORIENTATION, TEST_PATCH, WIND_ANALYTIC, WIND_FLUID,
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
        // The camera and the tree are the caller's (`bvh::fill_params`).
        bvh_camera: [0.0, 0.0, 0.0, physics.hierarchy_precision_distance],
        bvh_info: [physics.collision_hierarchy as u32, 0, 0, 0],
        model: [
            physics.model.id() as f32,
            physics.verlet.damping,
            physics.cwd.cell_size,
            physics.verlet.wind_gain,
        ],
        cwd: [
            physics.cwd.k1,
            physics.cwd.k2,
            physics.cwd.lambda,
            physics.cwd.force,
        ],
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
    let layers = if uses_fluid {
        wind.fluid.layers.max(1)
    } else {
        1
    };
    p.fluid_info = [resolution, mask, wind.fluid.per_cell as u32, layers];
    p.fluid_layer_height = wind.fluid.layer_height;
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
    if culling.occlusion {
        t |= TEST_OCCLUSION;
        if culling.grass_occlusion {
            t |= TEST_GRASS_OCCLUSION;
        }
    }
    t
}

/// What the cull uniforms need besides the scene's settings: the culling camera, the
/// viewport, the field's layout, the level-of-detail meshes and the depth pyramid.
#[derive(Clone, Copy, Debug)]
pub struct CullInputs {
    /// View-projection matrix of the culling camera (world to clip).
    pub view_proj: Mat4,
    /// Position of the culling camera in world metres.
    pub camera: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    /// Near plane distance of the culling camera in metres.
    pub near: f32,
    /// Far plane distance of the culling camera in metres.
    pub far: f32,
    /// Viewport height in pixels (sets the pixels per metre of the level-of-detail test).
    pub viewport_height: u32,
    /// Blades in the blade buffer.
    pub blade_count: u32,
    /// Blades per patch.
    pub patch_size: u32,
    /// Patches in the field.
    pub patch_count: u32,
    /// Segments of each level's blade mesh (near, middle, far).
    pub lod_segments: [u32; LOD_LEVELS],
    /// Index count and first index of each level's mesh in the shared index buffer.
    pub lod_index_count: [u32; LOD_LEVELS],
    /// First index of each level's mesh in the shared index buffer.
    pub lod_first_index: [u32; LOD_LEVELS],
    /// Frame number; picks which throttled patches update this frame.
    pub frame: u32,
    /// Depth pyramid: width, height, levels, 1 = built this frame (0 turns the test off).
    pub hiz: [u32; 4],
    /// Spheres uploaded this frame, and whether collisions are on (the broad phase).
    pub sphere_count: u32,
    /// Whether sphere collisions are on.
    pub collisions: bool,
}

fn pad4(a: [u32; LOD_LEVELS]) -> [u32; 4] {
    [a[0], a[1], a[2], 0]
}

/// Cull uniforms for a camera.
pub fn cull_params(culling: &Culling, inputs: &CullInputs) -> CullParams {
    let mut tests = cull_tests(culling);
    if inputs.hiz[3] == 0 {
        tests &= !(TEST_OCCLUSION | TEST_GRASS_OCCLUSION);
    }
    let half_fov = (inputs.fov_y.to_radians() * 0.5).max(1e-4);
    let px_per_m = inputs.viewport_height as f32 / (2.0 * half_fov.tan());
    // Without levels of detail every blade is "near": thresholds of 0 pixels.
    let (near_px, far_px) = if culling.lod {
        (culling.lod_near_px, culling.lod_far_px)
    } else {
        (0.0, 0.0)
    };
    let c = inputs.camera;
    CullParams {
        view_proj: inputs.view_proj.to_cols_array_2d(),
        camera_pos: [c.x, c.y, c.z, 1.0],
        blade_count: inputs.blade_count,
        patch_size: inputs.patch_size,
        tests,
        distance_levels: culling.distance_levels,
        orientation_threshold: culling.orientation_threshold,
        frustum_tolerance: culling.frustum_tolerance,
        max_distance: culling.max_distance,
        patch_count: inputs.patch_count,
        lod_index_count: pad4(inputs.lod_index_count),
        lod_first_index: pad4(inputs.lod_first_index),
        lod_segments: pad4(inputs.lod_segments),
        lod: [px_per_m, near_px, far_px, culling.lod_morph],
        physics_throttle: culling.physics_throttle.max(1),
        frame: inputs.frame,
        physics_radius: culling.physics_radius,
        occlusion_bias: culling.occlusion_bias,
        hiz: inputs.hiz,
        clip: [inputs.near, inputs.far, culling.grass_occlusion_bias, 0.0],
        collide: [inputs.sphere_count, inputs.collisions as u32, 0, 0],
        // The hierarchy's, from `bvh::fill_cull_params` where there is one.
        bvh: [0.0; 4],
    }
}

/// Δt of a throttled patch's step: `throttle` frames' worth, capped at `max_dt` so that
/// the explicit step stays stable (the patch then runs a little slow while out of view).
pub fn throttled_dt(dt: f32, throttle: u32, max_dt: f32) -> f32 {
    (dt * throttle.max(1) as f32).min(max_dt.max(dt))
}
