//! The command-line actions as library functions (so tests drive them without a process):
//! `render` simulates and draws frames into a PNG, `simulate` dumps blade states as JSON.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::gpu::{AdapterChoice, Gpu};
use crate::output::Outputs;
use crate::render::camera::CameraView;
use crate::render::target::{Target, COLOR_FORMAT};
use crate::render::timing::PASSES;
use crate::embed::{FrameInputs, GrassRenderer, WorldTarget};
use crate::render::Renderer;
use crate::scene::{load_scene_with_sets, parse_scene_with_sets, Scene};
use crate::scene::{BladeModel, WindSource};
use crate::session::Session;
use crate::sim::agc;
use crate::sim::colliders::spheres_at;
use crate::sim::fluid::{FluidConfig, FluidState};
use crate::sim::layout::{Blade, BladeState, VerletState};
use crate::sim::params::sim_params;
use crate::sim::reference;
use crate::sim::reference::fluid::FluidCpu;

/// The default scene, built into the binary so `sward` runs from any directory.
pub const DEFAULT_SCENE: &str = crate::embed::MEADOW_SCENE;
/// The name the built-in scene's errors and logs use.
pub const DEFAULT_SCENE_PATH: &str = "assets/scenes/meadow.ron";

/// Loads `path`, or the built-in meadow when `None`, with the command line's `--set
/// PATH=VALUE` overrides applied and validated like the file's own values.
pub fn load(path: Option<&Path>, sets: &[String]) -> Result<Scene> {
    match path {
        // A scene that cannot be read at all is the flag's fault: the message names it.
        Some(p) => load_scene_with_sets(p, sets).map_err(|e| match e {
            Error::Read { ref path, .. } if path == p => Error::Invalid(format!("--scene: {e}")),
            other => other,
        }),
        None => parse_scene_with_sets(DEFAULT_SCENE, Path::new(DEFAULT_SCENE_PATH), sets),
    }
}

/// Options of `sward render`.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// `--scene FILE`: the RON scene to render; `None` renders the built-in meadow.
    pub scene: Option<PathBuf>,
    /// `--set PATH=VALUE` overrides of the scene (`--eye` / `--target` arrive as
    /// `camera.eye=…` / `camera.target=…`).
    pub sets: Vec<String>,
    /// Image size in pixels, (width, height); checked against the adapter's texture limits.
    pub size: (u32, u32),
    /// Frames to simulate and render, 1..=100000 (`MAX_FRAMES`); the last one is saved.
    pub frames: u32,
    /// Time step per frame in seconds, 0 < dt <= 1.
    pub dt: f32,
    /// Path of the PNG the last frame is written to.
    pub out: PathBuf,
    /// Print per-pass GPU times (timestamp queries), the cull counters and the last frame's
    /// work counters.
    pub timings: bool,
    /// `--trace FILE`: a Chrome trace of every frame's GPU passes.
    pub trace: Option<PathBuf>,
    /// Which GPU adapter to open.
    pub adapter: AdapterChoice,
    /// Draws the wind velocity and the AGC arrows over the frame.
    pub wind_overlay: bool,
    /// `--pressure-iterations N`: overrides `wind.fluid.pressure_iterations` (0..=1000).
    pub pressure_iterations: Option<u32>,
    /// `--wind-resolution N`: overrides `wind.fluid.resolution` (8..=2048 cells per side).
    pub wind_resolution: Option<u32>,
}

impl RenderOptions {
    /// `sward` with no arguments: the default meadow to `meadow.png`.
    pub fn default_meadow(adapter: AdapterChoice) -> Self {
        Self {
            scene: None,
            sets: Vec::new(),
            size: (1280, 720),
            frames: 90,
            dt: 1.0 / 30.0,
            out: PathBuf::from("meadow.png"),
            timings: false,
            trace: None,
            adapter,
            wind_overlay: false,
            pressure_iterations: None,
            wind_resolution: None,
        }
    }
}

/// Most frames `sward render` runs (and steps `sward simulate` takes): a count a user can
/// wait for, and one that stops a typo such as 4294967295 from running for ever.
pub const MAX_FRAMES: u32 = 100_000;

/// Checks a count flag against `1..=MAX_FRAMES`; the error names the flag and the range.
pub fn check_count(flag: &str, value: u32) -> Result<()> {
    if !(1..=MAX_FRAMES).contains(&value) {
        return Err(Error::Invalid(format!(
            "{flag} {value} is out of range: allowed 1..={MAX_FRAMES}"
        )));
    }
    Ok(())
}

fn check_dt(dt: f32) -> Result<()> {
    if !(dt.is_finite() && dt > 0.0 && dt <= 1.0) {
        return Err(Error::Invalid(format!(
            "--dt {dt} is out of range: allowed 0 < dt <= 1 s"
        )));
    }
    Ok(())
}

fn open_gpu(choice: &AdapterChoice) -> Result<Gpu> {
    let gpu = Gpu::new(choice)?;
    eprintln!("adapter: {}", gpu.describe());
    Ok(gpu)
}

/// One frame of `renderer` into `target` through the embedding API
/// ([`GrassRenderer::render_world`]), submitted and paced as the window's; step `dt`.
pub fn world_frame(
    gpu: &Gpu,
    renderer: &mut GrassRenderer,
    dt: f32,
    camera: CameraView,
    target: &Target,
) -> Result<()> {
    world_frame_with(gpu, renderer, dt, camera, &[], target)
}

/// [`world_frame`] with moving colliders of the caller's pressing the grass (and the
/// wind), as a host's.
pub fn world_frame_with(
    gpu: &Gpu,
    renderer: &mut GrassRenderer,
    dt: f32,
    camera: CameraView,
    colliders: &[crate::embed::Collider],
    target: &Target,
) -> Result<()> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.frame"),
        });
    let inputs = FrameInputs {
        camera,
        size: (target.width, target.height),
        dt,
        colliders,
        depth: None,
        wind: None,
    };
    let views = WorldTarget {
        color: &target.color_view,
        depth: &target.depth_view,
    };
    renderer.render_world(&gpu.device, &gpu.queue, &mut encoder, &inputs, &views)?;
    let index = gpu.queue.submit([encoder.finish()]);
    renderer.renderer.frame_submitted(gpu, index);
    gpu.check_errors()
}

/// Runs `sward render`.
pub fn render(o: &RenderOptions) -> Result<()> {
    check_dt(o.dt)?;
    check_count("--frames", o.frames)?;
    let mut outputs = Outputs::new();
    if let Some(scene) = &o.scene {
        outputs.input("--scene", scene)?;
    }
    outputs.add("--out", &o.out)?;
    if let Some(path) = &o.trace {
        outputs.add("--trace", path)?;
    }
    let mut scene = load(o.scene.as_deref(), &o.sets)?;
    apply_wind_overrides(&mut scene, o.pressure_iterations, o.wind_resolution)?;
    let gpu = open_gpu(&o.adapter)?;
    Target::check_size(&gpu, "--size", o.size, scene.render.msaa)?;
    let target = Target::new(&gpu, o.size.0, o.size.1)?;
    let camera = CameraView::from_scene(&scene.camera);
    // The headless frames are drawn through the embedding API, as a host draws them.
    let mut world = GrassRenderer::world_of(gpu.clone(), scene, COLOR_FORMAT)?;
    eprintln!("{}", world.describe_field());
    if o.wind_overlay {
        world.renderer.enable_overlay(&gpu, COLOR_FORMAT);
    }
    let timestamps = o.trace.is_some() && world.renderer.record_trace();
    gpu.check_errors()?;
    let mut sums = [0.0f64; PASSES.len()];
    let mut wind_sums: Vec<(&'static str, f64)> = Vec::new();
    let mut timed = 0u32;
    let mut last = None;
    for k in 0..o.frames {
        // The last frame's work is counted (the counts are the same every frame of a still
        // view; counting adds a coverage pass, so the timed frames before it are not).
        if o.timings && k + 1 == o.frames && !world.renderer.count_work(&gpu, true) {
            println!("work counters: the adapter has no pipeline-statistics queries");
        }
        // A camera that follows an object goes where the object will be this frame.
        let view = world.renderer.scene_camera(&camera, o.dt);
        world_frame(&gpu, &mut world, o.dt, view, &target)?;
        if o.timings {
            let stats = world.renderer.stats(&gpu)?;
            if let Some(ms) = stats.pass_ms {
                for (s, m) in sums.iter_mut().zip(ms) {
                    *s += m;
                }
                timed += 1;
            }
            if let Some(w) = &stats.wind_ms {
                if wind_sums.is_empty() {
                    wind_sums = w.iter().map(|(n, _)| (*n, 0.0)).collect();
                }
                for (s, (_, m)) in wind_sums.iter_mut().zip(w) {
                    s.1 += m;
                }
            }
            last = Some(stats);
        }
    }
    let image = target.read_image(&gpu)?;
    outputs.write_png(&o.out, &image)?;
    if let Some(path) = &o.trace {
        let scopes = world.renderer.take_trace(&gpu)?;
        let tracks = [crate::render::timing::TraceTrack {
            name: "sward render".into(),
            scopes,
        }];
        crate::render::timing::write_trace(&mut outputs, path, &tracks, timestamps)?;
    }
    outputs.commit()?;
    eprintln!(
        "wrote {} ({}x{}, {} frames)",
        o.out.display(),
        o.size.0,
        o.size.1,
        o.frames
    );
    if o.timings {
        let stats = match last {
            Some(s) => s,
            None => world.renderer.stats(&gpu)?,
        };
        let c = stats.counters;
        println!("adapter: {}", gpu.describe());
        println!(
            "blades: {} total, {} drawn (LOD {:?}, {} late), culled: {} patch, {} orientation, {} frustum, {} distance, {} occlusion ({} by grass)",
            world.renderer.buffers.count,
            c.drawn(),
            c.per_level(),
            c.drawn_late(),
            c.culled_patch,
            c.culled_orientation,
            c.culled_frustum,
            c.culled_distance,
            c.culled_occlusion,
            c.culled_occlusion_grass
        );
        let chunk = u64::from(crate::sim::layout::UPDATE_CHUNK);
        println!(
            "patches: {} visible, {} stepped ({} throttled); blades stepped: {} ({} at the throttled rate), tested one by one: {}",
            c.visible_patches,
            c.updated_patches,
            c.throttled_patches,
            u64::from(c.updated_chunks) * chunk,
            u64::from(c.throttled_chunks) * chunk,
            u64::from(c.visible_chunks) * chunk
        );
        println!(
            "blades reset (non-finite state, since start): {}",
            stats.blades_reset_nonfinite
        );
        match world.renderer.far_gain(&gpu)? {
            Some(g) => println!(
                "far levels' light gain (measured against the blades): \
                 {:.3} {:.3} {:.3}",
                g.x, g.y, g.z
            ),
            None => println!("far levels' light gain: not measured (none in view)"),
        }
        let far = world.renderer.far_calibration(&gpu)?;
        let (ratio, contrast) = (far.ratio, far.contrast);
        println!(
            "blades against the far light model: {:.3} {:.3} {:.3} (running mean); cards' \
             contrast gain: {contrast:.3}",
            ratio.x, ratio.y, ratio.z
        );
        println!(
            "far field's distance gain (times the light gain): {:.3}",
            far.distance
        );
        println!(
            "gusts' mean bend at the edge of the blades' reach (0 calm, 1 bent two thirds \
             of the height): {:.3}",
            far.bend
        );
        let shown: Vec<String> = far
            .sectors
            .iter()
            .map(|&m| if m > 0.0 { format!("{m:.3}") } else { "-".into() })
            .collect();
        println!(
            "far levels by direction (times the light gain; {} sectors of azimuth from +x \
             towards +z, - not measured): {}",
            crate::render::far_sectors::SECTORS,
            shown.join(" ")
        );
        if timed > 0 {
            let wind_total: f64 = wind_sums.iter().map(|(_, s)| s).sum::<f64>() / timed as f64;
            let total: f64 = sums.iter().sum::<f64>() / timed as f64 + wind_total;
            for (name, s) in &wind_sums {
                let ms = s / timed as f64;
                println!(
                    "gpu wind.{name:<10}: {ms:9.3} ms  ({:5.1} %)",
                    100.0 * ms / total.max(1e-12)
                );
            }
            for (name, s) in PASSES.iter().zip(sums) {
                let ms = s / timed as f64;
                println!(
                    "gpu {name:<15}: {ms:9.3} ms  ({:5.1} %)",
                    100.0 * ms / total.max(1e-12)
                );
            }
            println!(
                "gpu {:<15}: {total:9.3} ms (mean of {timed} frames)",
                "total"
            );
        } else {
            println!("gpu timings: the adapter has no timestamp queries");
        }
        if let Some(work) = world.renderer.read_work(&gpu)? {
            for line in crate::render::work::table(&work, world.renderer.samples()) {
                println!("{line}");
            }
        }
    }
    Ok(())
}

/// Options of `sward simulate`.
#[derive(Clone, Debug)]
pub struct SimulateOptions {
    /// `--scene FILE`: the RON scene to simulate; `None` uses the built-in meadow.
    pub scene: Option<PathBuf>,
    /// `--set PATH=VALUE` overrides of the scene.
    pub sets: Vec<String>,
    /// Update steps to run, 1..=100000 (`MAX_FRAMES`).
    pub steps: u32,
    /// Time step in seconds, 0 < dt <= 1.
    pub dt: f32,
    /// Path of the JSON file the initial and final blades are written to.
    pub dump: PathBuf,
    /// Run the CPU twin of the update instead of the GPU kernels (no adapter is opened).
    pub cpu: bool,
    /// `--blades N`: replace the scene's field with about N blades on a flat square
    /// (1..=50000000); `None` keeps the scene's field.
    pub blades: Option<usize>,
    /// Which GPU adapter to open (unused with `cpu`).
    pub adapter: AdapterChoice,
    /// Writes the wind grid after the last step.
    pub dump_wind: Option<PathBuf>,
    /// `--pressure-iterations N`: overrides `wind.fluid.pressure_iterations` (0..=1000).
    pub pressure_iterations: Option<u32>,
    /// `--wind-resolution N`: overrides `wind.fluid.resolution` (8..=2048 cells per side).
    pub wind_resolution: Option<u32>,
}

/// One blade as `sward simulate` writes it. A Verlet blade (`physics.model: Verlet`) is a
/// cubic: `v0`..`v3` are its four control points (root, P1, P2, tip); the others' `v2` is
/// the tip and `v3` is absent.
#[derive(Serialize)]
pub struct BladeJson {
    /// Root position in metres.
    pub v0: [f32; 3],
    /// Middle control point in metres (P1 of a Verlet blade's cubic).
    pub v1: [f32; 3],
    /// Tip of a quadratic blade in metres, or P2 of a Verlet blade's cubic.
    pub v2: [f32; 3],
    /// Tip of a Verlet blade's cubic in metres; absent for the other models.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub v3: Option<[f32; 3]>,
    /// The blade's local up vector: the normal of the ground (or object surface) at its
    /// root.
    pub up: [f32; 3],
    /// Blade height h in metres.
    pub height: f32,
    /// Blade width w at the base in metres.
    pub width: f32,
    /// Stiffness s of Eq. 3, in 1/s.
    pub stiffness: f32,
    /// Collision strength η (Eq. 2): 0 untouched, 1 or more a full trail.
    pub eta: f32,
}

impl BladeJson {
    /// The record of a blade and its state as stored (v0, v1, v2 of the quadratic, no
    /// `v3`).
    pub fn new(b: &Blade, s: &BladeState) -> Self {
        let xyz = |a: [f32; 4]| [a[0], a[1], a[2]];
        Self {
            v0: xyz(b.v0_dir),
            v1: xyz(b.v1_height),
            v2: xyz(b.v2_width),
            v3: None,
            up: xyz(b.up_stiffness),
            height: b.v1_height[3],
            width: b.v2_width[3],
            stiffness: b.up_stiffness[3],
            eta: s.rest_eta[3],
        }
    }
}

impl BladeJson {
    /// A Verlet blade with its state: the four control points of its cubic.
    pub fn verlet(b: &Blade, s: &BladeState, v: &VerletState) -> Self {
        let p = crate::sim::verlet::control_points(b, v);
        Self {
            v1: p[1].into(),
            v2: p[2].into(),
            v3: Some(p[3].into()),
            ..Self::new(b, s)
        }
    }
}

#[derive(Serialize)]
struct Dump {
    initial: Vec<BladeJson>,
    #[serde(rename = "final")]
    last: Vec<BladeJson>,
    /// The blade model the run stepped (`physics.model`), after the blades so that the
    /// dump still opens with `initial`.
    model: &'static str,
}

fn to_json(blades: &[Blade], states: &[BladeState]) -> Vec<BladeJson> {
    blades
        .iter()
        .zip(states)
        .map(|(b, s)| BladeJson::new(b, s))
        .collect()
}

/// The blades as `simulate` dumps them: Verlet blades (`physics.model: Verlet`) with the
/// four points of their cubic from `verlet` (a blade without a state there is one not yet
/// stepped), the others as quadratics.
fn blades_json(
    model: BladeModel,
    blades: &[Blade],
    states: &[BladeState],
    verlet: &[VerletState],
) -> Vec<BladeJson> {
    if model != BladeModel::Verlet {
        return to_json(blades, states);
    }
    let fresh = VerletState::default();
    blades
        .iter()
        .zip(states)
        .enumerate()
        .map(|(k, (b, s))| BladeJson::verlet(b, s, verlet.get(k).unwrap_or(&fresh)))
        .collect()
}

/// Runs the CPU twin for `steps` steps of `dt` from time 0 (same clock and collider motion
/// as the GPU path).
pub fn simulate_cpu(session: &Session, steps: u32, dt: f32) -> CpuRun {
    let (blades, states) = (session.field.blades.clone(), session.field.states.clone());
    simulate_cpu_from(session, blades, states, steps, dt)
}

/// `simulate_cpu` from other blades and states than the session's field (same count).
pub fn simulate_cpu_from(
    session: &Session,
    mut blades: Vec<Blade>,
    mut states: Vec<BladeState>,
    steps: u32,
    dt: f32,
) -> CpuRun {
    let mut blades_reset_nonfinite = 0u64;
    let scene = &session.scene;
    let mut verlet = if scene.physics.model == BladeModel::Verlet {
        vec![VerletState::default(); blades.len()]
    } else {
        Vec::new()
    };
    let dt = dt.clamp(0.0, scene.physics.max_dt);
    let mut time = 0.0f32;
    let mut fluid = (scene.wind.source != WindSource::Analytic).then(|| {
        FluidCpu::new(&FluidConfig::from_scene(
            &scene.wind.fluid,
            scene.terrain.size,
        ))
    });
    let mut wind = None;
    let carried = &session.field.carried;
    let mut previous = vec![glam::Mat4::IDENTITY; carried.objects.len()];
    for _ in 0..steps {
        time += dt;
        // The grass of moving objects goes with them first, as the GPU's carry pass does.
        if !carried.is_empty() {
            let (_, motions) = crate::sim::carry::step(
                carried,
                &scene.objects,
                &session.terrain,
                time,
                &mut previous,
            );
            crate::sim::carry::carry_cpu(&mut blades, &mut states, &carried.blades, &motions);
        }
        let mut spheres = spheres_at(&scene.colliders, &session.terrain, time);
        spheres.extend(crate::sim::colliders::object_spheres_at(
            &scene.objects,
            &session.packings,
            &session.terrain,
            time,
        ));
        // Same order as the GPU frame: the wind moves, then the blades read it.
        if let Some(f) = &mut fluid {
            let mut forces = agc::fluid_forces(scene, &session.terrain, time);
            if scene.wind.fluid.obstacles {
                forces
                    .obstacles
                    .extend(crate::sim::colliders::object_obstacles(
                        &scene.objects,
                        &session.packings,
                        &session.terrain,
                        time,
                    ));
            }
            f.step(dt, &forces);
            wind = Some(f.state());
        }
        let mut params = sim_params(
            &scene.physics,
            &scene.wind,
            scene.terrain.size,
            dt,
            time,
            blades.len() as u32,
            spheres.len() as u32,
        );
        if scene.collision_hierarchy() {
            let eye = glam::Vec3::from(scene.camera.eye);
            let nodes = crate::sim::bvh::build(&spheres);
            crate::sim::bvh::fill_params(&mut params, &nodes, true, eye);
        }
        let zero = [[0.0f32; 2]];
        let grid = reference::WindGrid {
            velocity: wind
                .as_ref()
                .map(|w| w.velocity.as_slice())
                .unwrap_or(&zero),
        };
        crate::sim::propagation::fill_params(
            &mut params,
            scene.physics.propagation.as_ref(),
            glam::Vec3::from(scene.camera.eye),
        );
        let spec = crate::sim::propagation::GridSpec::from_params(&params);
        let mut splat = spec.map(crate::sim::propagation::Splat::new);
        let resets = match scene.physics.model {
            BladeModel::Jahrmann => reference::update_all_splat(
                &mut blades,
                &mut states,
                &params,
                &spheres,
                &grid,
                splat.as_mut(),
            ),
            BladeModel::Verlet => crate::sim::verlet::update_all(
                &mut blades,
                &mut states,
                &mut verlet,
                &params,
                &spheres,
                &grid,
                splat.as_mut(),
            ),
            BladeModel::Cwd => crate::sim::cwd::pose_all(&mut blades, &mut states, &params, &grid),
        };
        blades_reset_nonfinite += u64::from(resets);
        // The propagation follows the update, as on the GPU (Jahrmann's blades only).
        if let (Some(splat), Some(spec)) = (&splat, &spec) {
            let field = crate::sim::propagation::propagate(splat, &params);
            if scene.physics.model == BladeModel::Jahrmann {
                crate::sim::propagation::apply_all(&mut blades, &mut states, &field, spec, &params);
            }
        }
    }
    CpuRun {
        blades,
        states,
        verlet,
        wind,
        blades_reset_nonfinite,
    }
}

/// What `simulate_cpu` ends with.
pub struct CpuRun {
    /// The blades after the last step.
    pub blades: Vec<Blade>,
    /// The blades' states (rest tip and collision strength η) after the last step.
    pub states: Vec<BladeState>,
    /// The Verlet states (`physics.model: Verlet`; else empty).
    pub verlet: Vec<VerletState>,
    /// The wind grid after the last step, when the scene uses the fluid.
    pub wind: Option<FluidState>,
    /// Blades reset to their rest pose because their new state was non-finite or absurd,
    /// summed over the steps.
    pub blades_reset_nonfinite: u64,
}

/// The wind grid as `--dump-wind` writes it: the staggered grid's face velocities after the
/// step (u on the (W + 1) · H vertical faces, v on the W · (H + 1) horizontal ones), the
/// solid mask and the pressure per cell, all row-major with x fastest, so that anyone can
/// compute the divergence (u[j(W+1)+i+1] − u[j(W+1)+i] + v[(j+1)W+i] − v[jW+i]) / h.
/// A 3D grid (`layers` > 1) stacks those arrays layer by layer (layer 0 at the ground first)
/// and adds `w` on the W · H faces of each of the layers + 1 horizontal planes (index
/// kWH + jW + i; the ground and the top are 0) and `layer_height` dy, the divergence gaining
/// (w[(k+1)WH + jW + i] − w[kWH + jW + i]) / dy.
#[derive(Serialize)]
struct WindJson<'a> {
    grid: &'static str,
    width: u32,
    height: u32,
    cell_size: f32,
    origin: [f32; 2],
    u: &'a [f32],
    v: &'a [f32],
    solid: Vec<u8>,
    pressure: &'a [f32],
    #[serde(skip_serializing_if = "Option::is_none")]
    layers: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    layer_height: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    w: Option<&'a [f32]>,
}

fn wind_json(path: &Path, state: &FluidState) -> Result<Vec<u8>> {
    let json = WindJson {
        grid: "staggered",
        width: state.resolution,
        height: state.resolution,
        cell_size: state.cell_size,
        origin: state.origin,
        u: &state.u,
        v: &state.v,
        solid: state.solid.iter().map(|&s| u8::from(s != 0)).collect(),
        pressure: &state.pressure,
        layers: (state.layers > 1).then_some(state.layers),
        layer_height: (state.layers > 1).then_some(state.layer_height),
        w: (state.layers > 1).then_some(state.w.as_slice()),
    };
    serde_json::to_vec(&json).map_err(|e| Error::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Applies the command-line wind overrides to a loaded scene.
pub fn apply_wind_overrides(
    scene: &mut Scene,
    pressure_iterations: Option<u32>,
    resolution: Option<u32>,
) -> Result<()> {
    if let Some(n) = pressure_iterations {
        if n > 1000 {
            return Err(Error::Invalid(format!(
                "--pressure-iterations {n} is out of range: allowed 0..=1000"
            )));
        }
        scene.wind.fluid.pressure_iterations = n;
    }
    if let Some(n) = resolution {
        if !(8..=2048).contains(&n) {
            return Err(Error::Invalid(format!(
                "--wind-resolution {n} is out of range: allowed 8..=2048"
            )));
        }
        scene.wind.fluid.resolution = n;
    }
    Ok(())
}

/// Runs `sward simulate`.
pub fn simulate(o: &SimulateOptions) -> Result<()> {
    check_dt(o.dt)?;
    check_count("--steps", o.steps)?;
    // Every output is checked before the run and renamed into place only when all of them
    // are written: a failing --dump-wind leaves an existing --dump as it was.
    let mut outputs = Outputs::new();
    if let Some(scene) = &o.scene {
        outputs.input("--scene", scene)?;
    }
    outputs.add("--dump", &o.dump)?;
    if let Some(p) = &o.dump_wind {
        outputs.add("--dump-wind", p)?;
    }
    let mut scene = load(o.scene.as_deref(), &o.sets)?;
    apply_wind_overrides(&mut scene, o.pressure_iterations, o.wind_resolution)?;
    if o.dump_wind.is_some() && scene.wind.source == WindSource::Analytic {
        return Err(Error::Invalid(
            "--dump-wind needs the fluid: the scene's wind.source is Analytic (use Fluid or Both)"
                .into(),
        ));
    }
    let mut wind_state = None;
    let resets: u64;
    let verlet: Vec<VerletState>;
    let (session, (blades, states)) = if o.cpu {
        let mut session = Session::new(scene, o.blades, None)?;
        session.fill_tiles_cpu()?;
        let run = simulate_cpu(&session, o.steps, o.dt);
        wind_state = run.wind;
        resets = run.blades_reset_nonfinite;
        verlet = run.verlet;
        (session, (run.blades, run.states))
    } else {
        let gpu = open_gpu(&o.adapter)?;
        let mut session = Session::new(scene, o.blades, Some(&gpu))?;
        let mut renderer = Renderer::from_session(&gpu, &session, COLOR_FORMAT)?;
        if session.tiles.is_some() {
            // The initial state of a streamed field is the pool the GPU generated.
            (session.field.blades, session.field.states) = renderer.buffers.read(&gpu)?;
        }
        for _ in 0..o.steps {
            renderer.step(&gpu, o.dt);
            gpu.check_errors()?;
        }
        resets = renderer.blades_reset_nonfinite(&gpu)?.into();
        let out = renderer.buffers.read(&gpu)?;
        verlet = renderer.buffers.read_verlet(&gpu)?;
        if let Some(f) = &renderer.fluid {
            wind_state = Some(f.read_state(&gpu)?);
        }
        gpu.check_errors()?;
        (session, out)
    };
    if let Some(line) = crate::sim::health::resets_line(resets) {
        eprintln!("{line}");
    }
    crate::sim::health::check_dump(
        &o.dump,
        (&session.field.blades, &session.field.states),
        (&blades, &states),
    )?;
    let model = session.scene.physics.model;
    let dump = Dump {
        model: model.name(),
        // Not stepped yet: a Verlet blade's cubic is then its quadratic raised in degree.
        initial: blades_json(model, &session.field.blades, &session.field.states, &[]),
        last: blades_json(model, &blades, &states, &verlet),
    };
    let text = serde_json::to_vec(&dump).map_err(|e| Error::Write {
        path: o.dump.clone(),
        message: e.to_string(),
    })?;
    outputs.write(&o.dump, &text)?;
    if let (Some(path), Some(state)) = (&o.dump_wind, &wind_state) {
        outputs.write(path, &wind_json(path, state)?)?;
    }
    outputs.commit()?;
    if let (Some(path), Some(state)) = (&o.dump_wind, &wind_state) {
        eprintln!("wrote {} ({}² wind grid)", path.display(), state.resolution);
    }
    eprintln!(
        "wrote {} ({} blades, {} steps; blades reset from a non-finite state: {resets})",
        o.dump.display(),
        blades.len(),
        o.steps
    );
    Ok(())
}
