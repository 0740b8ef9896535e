//! The far grass's light (issue 27, point 1): the CPU twin of `blade_light`
//! (`shaders/blade_shade.wgsl`) and of `far_grass_facings` (`shaders/far_grass.wgsl`), the
//! quadrature that lights the far ground and the billboards with the blades' own light,
//! and a probe that runs the WGSL at given points under a renderer's frame and light so
//! tests can hold the two together.

use glam::{Vec2, Vec3};
use wgpu::util::DeviceExt;

use super::light::canopy;
use super::Renderer;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::sim::layout::{FrameUniforms, LightUniforms};

fn v3(a: [f32; 4]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

/// The two parts of a point's light (`BladeLight`): the sky's, and the sun's when the sun
/// is not shadowed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BladeLight {
    /// Linear RGB light from the sky (ambient, scaled by ambient occlusion).
    pub ambient: Vec3,
    /// Linear RGB light from the sun (diffuse, translucency and specular), to be scaled
    /// by the shadow factor.
    pub sun: Vec3,
}

/// `blade_light`: the light a blade's point at `world` sends to the eye.
pub fn blade_light(
    (frame, light): (&FrameUniforms, &LightUniforms),
    world: Vec3,
    (flat_n, side): (Vec3, Vec3),
    uv: Vec2,
    albedo: Vec3,
    self_shade: f32,
) -> BladeLight {
    let sun = v3(frame.sun_dir);
    let to_eye = (v3(frame.camera_pos) - world).normalize();
    let [a, b] = light.shading;
    let v = uv.y;
    let n = (flat_n + side * (uv.x - 0.5) * 1.2 * a[0]).normalize();
    let open = (-0.35 * b[2] * (1.0 - v)).exp().max(0.12);
    let mut ao = 1.0 + (open - 1.0) * a[3];
    match frame.debug[1] as u32 {
        1 => ao = self_shade,
        2 => ao = 1.0,
        _ => {}
    }
    let sun_rgb = v3(light.sun);
    let diffuse = n.dot(sun).max(0.0);
    let behind = (-flat_n).dot(sun).max(0.0);
    let through = behind * (-to_eye).dot(sun).max(0.0).powf(2.0);
    let trans = (through * 0.9 + behind * 0.25) * a[1];
    let h = (sun + to_eye).normalize();
    let spec = n.dot(h).max(0.0).powf(12.0) * 0.22 * (0.3 + 0.7 * v) * a[2];
    BladeLight {
        ambient: albedo * v3(light.ambient) * 0.9 * ao,
        sun: albedo * sun_rgb * (diffuse * 1.6 * (0.55 + 0.45 * ao))
            + albedo * Vec3::new(1.0, 1.1, 0.4) * sun_rgb * trans * 1.4 * ao
            + sun_rgb * spec,
    }
}

/// How much brighter the grass reads, against the light model, per unit of the sine of the
/// view's elevation over it (twin of `FAR_ELEVATION_LIFT`): the model's light is scaled by
/// `1 + ELEVATION_LIFT · sin e`. Measured on the prairie against blades to 50 m (the blades'
/// ratio to the model, green, after 10-16 frames): from 19 m up 1.53 at 72° of elevation,
/// 1.40 at 56°, 1.33 at 45°, 1.26-1.30 at 25-30°; on the ground, settled without wind, the
/// ratio at 28-42 m (3-5°) 4 % under the one at 10-14 m (10-14°), once the coarsest level
/// of detail shades as the finest (`lod_chord`). Both are 0.3-0.4 per unit of sin e; the
/// far levels are calibrated on blades nearer, and seen steeper, than themselves, so without
/// it the prairie from 19 m up read 10-17 levels too bright past 40 m (every band within 5
/// levels with it, but one), and on the ground the far ring 4 % too bright.
pub const ELEVATION_LIFT: f32 = 0.35;

/// Twin of `drawn_quad_share` (far_grass.wgsl): Eq. 24's share of quads among the blades
/// at `p` whose width runs along `side`, under `frame`'s view, over the field's width
/// quartiles (`LightUniforms::canopy_widths`).
pub fn drawn_quad_share((frame, light): (&FrameUniforms, &LightUniforms), p: Vec3, side: Vec3) -> f32 {
    let [w_min, w_span, ..] = frame.width_correction;
    if w_span <= 0.0 {
        return 0.0;
    }
    let vp = glam::Mat4::from_cols_array_2d(&frame.view_proj);
    let viewport = Vec2::new(frame.viewport_time[0], frame.viewport_time[1]);
    let c = vp * p.extend(1.0);
    let mut share = 0.0;
    for k in 0..2 {
        let e = vp * (side * (0.5 * light.canopy_widths[k])).extend(0.0);
        let a = Vec2::new(c.x + e.x, c.y + e.y) / (c.w + e.w).max(1e-4) * 0.5 * viewport;
        let b = Vec2::new(c.x - e.x, c.y - e.y) / (c.w - e.w).max(1e-4) * 0.5 * viewport;
        share += 0.5 * canopy::quad_share((a - b).length(), w_min, w_span);
    }
    share
}

/// `far_grass_facings`: the sky's part and each of the four facings' sun part of the
/// grass around `p` (ground normal `ground_n`, far albedo `albedo`, mean wave `wave`),
/// lifted by the view's elevation ([`ELEVATION_LIFT`]).
pub fn far_grass_facings(
    (frame, light): (&FrameUniforms, &LightUniforms),
    p: Vec3,
    ground_n: Vec3,
    albedo: Vec3,
    wave: f32,
) -> (Vec3, [Vec3; 4]) {
    let to_eye = (v3(frame.camera_pos) - p).normalize();
    let sin_e = to_eye.dot(ground_n).max(0.02);
    let k = (0.5 * light.shading[1][2] / sin_e).max(1e-3);
    let span = 1.0 - (-k).exp();
    let mut t0 = to_eye - ground_n * to_eye.dot(ground_n);
    if t0.dot(t0) < 1e-8 {
        t0 = ground_n.cross(Vec3::Z);
    }
    let t0 = t0.normalize();
    let t1 = ground_n.cross(t0);
    let (mut ambient, mut sun) = (Vec3::ZERO, [Vec3::ZERO; 4]);
    // Each facing's width direction and the share of its blades drawn as quads.
    let facings: [(Vec3, Vec3, f32); 4] = std::array::from_fn(|j| {
        let phi = (j as f32 + 0.5) * std::f32::consts::FRAC_PI_4;
        let facing = phi.cos() * t0 + phi.sin() * t1;
        let side = ground_n.cross(facing).normalize();
        (facing, side, drawn_quad_share((frame, light), p, side))
    });
    for q in 0..2 {
        let depth = -(1.0 - (0.25 + 0.5 * q as f32) * span).ln() / k;
        for (j, sun_j) in sun.iter_mut().enumerate() {
            let (facing, side, quads) = facings[j];
            let v = canopy::drawn_canopy_v(&light.canopy, depth, quads);
            let still = albedo * ((0.55 + 0.7 * v) / (0.55 + 0.7 * 0.625));
            let paler = still * 1.7 + Vec3::new(0.04, 0.05, 0.02);
            let a = still + (paler - still) * (wave * 0.6);
            let s = frame.self_shadow;
            let self_shade = (v + s[3]).clamp(s[0], s[1]);
            let n = if facing.dot(to_eye) < 0.0 {
                -facing
            } else {
                facing
            };
            for h in 0..2 {
                let u = 0.2 + 0.6 * h as f32;
                let l = blade_light((frame, light), p, (n, side), Vec2::new(u, v), a, self_shade);
                ambient += l.ambient;
                *sun_j += l.sun;
            }
        }
    }
    let lift = 1.0 + ELEVATION_LIFT * sin_e;
    (ambient * 0.0625 * lift, sun.map(|s| s * 0.25 * lift))
}

/// One point of the probe: where, the ground's normal there, the albedo and the mean wave.
#[derive(Clone, Copy, Debug)]
pub struct FarPoint {
    /// World position of the point (m).
    pub p: Vec3,
    /// Unit normal of the ground at `p`.
    pub normal: Vec3,
    /// The far grass's linear RGB albedo there.
    pub albedo: Vec3,
    /// The blades' mean shading wave (`mean_wave`, 0 at rest): how far gusts turn the
    /// grass towards its paler side.
    pub wave: f32,
}

/// The WGSL `far_grass_facings` at `points` under `renderer`'s last frame (`frame`, its
/// uniforms) and light, read back from the GPU.
pub fn probe_far_grass(
    gpu: &Gpu,
    renderer: &Renderer,
    frame: &FrameUniforms,
    points: &[FarPoint],
) -> Result<Vec<(Vec3, [Vec3; 4])>> {
    let device = &gpu.device;
    let count = points.len().max(1);
    let mut flat: Vec<[f32; 12]> = points
        .iter()
        .map(|q| {
            [
                q.p.x, q.p.y, q.p.z, q.wave, q.normal.x, q.normal.y, q.normal.z, 0.0, q.albedo.x,
                q.albedo.y, q.albedo.z, 0.0,
            ]
        })
        .collect();
    flat.resize(count, [0.0; 12]);
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sward.far_grass_probe.points"),
        contents: bytemuck::cast_slice(&flat),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sward.far_grass_probe.frame"),
        contents: bytemuck::bytes_of(frame),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let out_size = (count * 5 * 16) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.far_grass_probe.out"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let module = crate::shaders::module(device, "far_grass_probe.wgsl");
    let c = wgpu::ShaderStages::COMPUTE;
    let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: c,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sward.far_grass_probe.layout"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: c,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            storage(1, true),
            storage(2, false),
        ],
    });
    let light_layout = super::light::layout(device);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("sward.far_grass_probe.pipeline_layout"),
        bind_group_layouts: &[Some(&layout), Some(&light_layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("sward.far_grass_probe"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.far_grass_probe.group"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let bytes = crate::gpu::run_probe(
        gpu,
        "sward.far_grass_probe",
        &pipeline,
        &[&group, renderer.light().group()],
        count,
        (&output, out_size),
    )?;
    let values: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    Ok(values
        .chunks_exact(5)
        .take(points.len())
        .map(|v| (v3(v[0]), [v3(v[1]), v3(v[2]), v3(v[3]), v3(v[4])]))
        .collect())
}
