//! The grass vertex shader's blade geometry against Jahrmann & Wimmer's equations, written
//! here from the paper: the curve point and edges (Eq. 21), the quad's interpolation
//! (Eq. 22), the 3D displacement d = w n (0.5 − |u − 0.5| (1 − v)) (Eq. 23) and the width
//! correction Φ = 1 − min(max((w_p − w_min) / w_span, 0), 1) (Eq. 24). The shader's own
//! `blade_point` runs on the adapter through a small compute entry added to
//! `shaders/grass.wgsl`, for blades of several widths, bends and pixel widths.
//!
//! Measured: the GPU matches this twin within 7.6e-8 m; the tolerance is 1e-6 m.
//! The paper prints Eq. 24's blend as t (1 − Φ) + u Φ²; sward blends linearly,
//! t (1 − Φ) + u Φ, which keeps the paper's two limits (Φ = 0: the shape, Φ = 1: a quad).
//! The test checks those limits for the shader and the linear blend in between.

mod common;

use bytemuck::Zeroable;
use glam::{Mat4, Vec3};
use sward::sim::layout::{Blade, SimParams, VerletState};
use sward::sim::reference::blade_frame;
use wgpu::util::DeviceExt;

/// GPU against twin, in metres (measured 7.6e-8).
const TOLERANCE: f32 = 1e-6;
/// The viewport of the probe, in pixels.
const VIEWPORT: (f32, f32) = (1000.0, 1000.0);
/// Clip space is world x and y times this (an orthographic view down −z): a blade whose
/// width lies along x is `width × SCALE × 0.5 × 1000` pixels wide.
const SCALE: f32 = 0.1;
/// Shapes of Eq. 22 by index: quad and triangle.
const QUAD: f32 = 0.0;
const TRIANGLE: f32 = 1.0;

struct Case {
    blade: Blade,
    /// (shape, τ, segments, displacement on).
    shape: [f32; 4],
    /// (w_min, w_span) in pixels; w_span 0: no correction.
    correction: [f32; 2],
}

/// The Frame uniform (common.wgsl `Frame`) for a case, as bytes.
fn frame_bytes(case: &Case) -> Vec<u8> {
    let view_proj = Mat4::from_scale(Vec3::new(SCALE, SCALE, 0.0));
    let mut f: Vec<f32> = Vec::new();
    f.extend(view_proj.to_cols_array());
    f.extend(view_proj.to_cols_array()); // inv_view_proj, unused here
    f.extend([0.0, 0.0, 10.0, 1.0]); // camera_pos
    f.extend([0.0, 1.0, 0.0, 0.0]); // sun_dir
    f.extend([VIEWPORT.0, VIEWPORT.1, 0.0, 0.0]); // viewport_time
    f.extend(case.shape);
    f.extend([case.correction[0], case.correction[1], 0.0, 0.0]);
    f.extend([0.0; 4]); // debug
    f.extend([0.0; 4]); // self_shadow
    f.extend([0.0; 4]); // thinning: off
    f.extend([0.0; 4]); // thinning_reach
    bytemuck::cast_slice(&f).to_vec()
}

/// Eq. 21-24 from the paper for one vertex (u, v), with sward's linear blend in Eq. 24.
fn twin(case: &Case, u: f32, v: f32) -> Vec3 {
    let b = &case.blade;
    let v0 = Vec3::from_slice(&b.v0_dir[..3]);
    let v1 = Vec3::from_slice(&b.v1_height[..3]);
    let v2 = Vec3::from_slice(&b.v2_width[..3]);
    let w = b.v2_width[3];
    let up = Vec3::from_slice(&b.up_stiffness[..3]);
    // Eq. 21: De Casteljau on the quadratic, the edge points and the normal.
    let a = v0 + v * (v1 - v0);
    let bb = v1 + v * (v2 - v1);
    let c = a + v * (bb - a);
    let (t1, _) = blade_frame(up, b.v0_dir[3]);
    let c0 = c - 0.5 * w * t1;
    let c1 = c + 0.5 * w * t1;
    // An upright blade's v1 and v2 coincide: at its tip the tangent vanishes and the
    // blade's up stands in (as in the shader).
    let t0 = (bb - a).try_normalize().unwrap_or(up);
    let n = t0.cross(t1).normalize();
    // Eq. 22.
    let mut t = if case.shape[0] == TRIANGLE {
        u + 0.5 * v - u * v
    } else {
        u
    };
    // Eq. 24: the blade's width in pixels through the probe's view.
    if case.correction[1] > 0.0 {
        let px = |p: Vec3| glam::Vec2::new(p.x, p.y) * SCALE * 0.5 * VIEWPORT.0;
        let wp = (px(c1) - px(c0)).length();
        let phi = 1.0 - ((wp - case.correction[0]) / case.correction[1]).clamp(0.0, 1.0);
        t = t * (1.0 - phi) + u * phi;
    }
    let mut p = (1.0 - t) * c0 + t * c1;
    // Eq. 23.
    if case.shape[3] > 0.5 {
        p += w * n * (0.5 - (u - 0.5).abs() * (1.0 - v));
    }
    p
}

/// The shader's `blade_point` for every (u, v) of `uv`, for one case.
fn gpu_points(gpu: &sward::gpu::Gpu, case: &Case, uv: &[[f32; 2]]) -> Vec<Vec3> {
    let source = sward::shaders::source("grass.wgsl")
        + r#"
@group(1) @binding(0) var<storage, read> probe_in: array<vec2<f32>>;
@group(1) @binding(1) var<storage, read_write> probe_out: array<vec4<f32>>;
@compute @workgroup_size(1)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let q = probe_in[id.x];
    let p = blade_point(blades[0], blade_ctx(blades[0]), 0u, q.x, q.y, 0.0);
    probe_out[id.x] = vec4<f32>(p.p, 0.0);
}
"#;
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("sward.test.blade_shape"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("sward.test.blade_shape"),
        layout: None,
        module: &module,
        entry_point: Some("probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let buffer = |label: &str, bytes: &[u8], usage: wgpu::BufferUsages| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage,
        })
    };
    let storage = wgpu::BufferUsages::STORAGE;
    let frame = buffer("sward.test.frame", &frame_bytes(case), storage);
    let blades = buffer(
        "sward.test.blades",
        bytemuck::bytes_of(&case.blade),
        storage,
    );
    let params = buffer(
        "sward.test.params",
        bytemuck::bytes_of(&SimParams::zeroed()),
        wgpu::BufferUsages::UNIFORM,
    );
    let wind = buffer("sward.test.wind", &[0u8; 16], storage);
    let verlet = buffer(
        "sward.test.verlet",
        bytemuck::bytes_of(&VerletState::zeroed()),
        storage,
    );
    let traits = buffer(
        "sward.test.traits",
        bytemuck::bytes_of(&sward::field::clumps::FieldTraits::zeroed()),
        wgpu::BufferUsages::UNIFORM,
    );
    let input: Vec<f32> = uv.iter().flatten().copied().collect();
    let probe_in = buffer("sward.test.probe_in", bytemuck::cast_slice(&input), storage);
    let out_size = (uv.len() * 16) as u64;
    let probe_out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.test.probe_out"),
        size: out_size,
        usage: storage | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    fn entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
        wgpu::BindGroupEntry {
            binding,
            resource: b.as_entire_binding(),
        }
    }
    let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.test.blade_shape.scene"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            entry(0, &frame),
            entry(1, &blades),
            entry(6, &params),
            entry(7, &wind),
            entry(8, &verlet),
            entry(10, &traits),
        ],
    });
    let probe_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.test.blade_shape.probe"),
        layout: &pipeline.get_bind_group_layout(1),
        entries: &[entry(0, &probe_in), entry(1, &probe_out)],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &scene_group, &[]);
        pass.set_bind_group(1, &probe_group, &[]);
        pass.dispatch_workgroups(uv.len() as u32, 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    gpu.check_errors().expect("no GPU error");
    let bytes = sward::gpu::read_buffer(gpu, &probe_out, out_size).expect("read back");
    bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)
        .iter()
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect()
}

/// A blade rooted at the origin growing along +y, bent towards +z by `bend` metres at the
/// tip, its width along x (direction angle 0 with up = +y gives the width along x).
fn blade(height: f32, width: f32, bend: f32) -> Blade {
    let up = Vec3::Y;
    let (t1, _) = blade_frame(up, 0.0);
    assert!((t1.abs() - Vec3::X).length() < 1e-6, "width along x: {t1}");
    Blade {
        v0_dir: [0.0, 0.0, 0.0, 0.0],
        v1_height: [0.0, height, 0.0, height],
        v2_width: [0.0, height - 0.3 * bend.abs(), bend, width],
        up_stiffness: [0.0, 1.0, 0.0, 10.0],
    }
}

fn grid() -> Vec<[f32; 2]> {
    let mut uv = Vec::new();
    for row in 0..=8 {
        for u in [0.0, 0.25, 0.5, 0.75, 1.0] {
            uv.push([u, row as f32 / 8.0]);
        }
    }
    uv
}

#[test]
fn blade_points_follow_equations_21_to_24() {
    let gpu = common::gpu();
    let uv = grid();
    let mut worst = 0.0f32;
    let mut cases = Vec::new();
    for (height, width, bend) in [(0.5, 0.04, 0.0), (0.8, 0.1, 0.3), (0.3, 0.02, -0.2)] {
        for shape in [QUAD, TRIANGLE] {
            for displacement in [0.0, 1.0] {
                // No correction; a correction whose band holds this blade's pixel width
                // (Φ between 0 and 1); and one below which every blade is a quad.
                for correction in [[0.0, 0.0], [0.5, 4.0], [50.0, 1.0]] {
                    cases.push(Case {
                        blade: blade(height, width, bend),
                        shape: [shape, 0.5, 8.0, displacement],
                        correction,
                    });
                }
            }
        }
    }
    for case in &cases {
        let got = gpu_points(&gpu, case, &uv);
        for (q, p) in uv.iter().zip(&got) {
            let want = twin(case, q[0], q[1]);
            let e = (want - *p).length();
            worst = worst.max(e);
            assert!(
                e < TOLERANCE,
                "shape {:?} correction {:?} at {q:?}: GPU {p} against the paper's {want}",
                case.shape,
                case.correction
            );
        }
    }
    eprintln!("worst difference from the paper's equations: {worst:e} m");
}

/// Invariants the paper states: with the 3D displacement the cross-section is a "v" with
/// about a right angle and the unfolded width grows by √2 at the root; the tip is not
/// displaced sideways; and a blade under w_min pixels is drawn as a quad whatever its shape.
#[test]
fn displacement_and_width_correction_keep_the_papers_promises() {
    let gpu = common::gpu();
    let straight = blade(0.5, 0.04, 0.0);
    let with_displacement = Case {
        blade: straight,
        shape: [QUAD, 0.5, 8.0, 1.0],
        correction: [0.0, 0.0],
    };
    let root = gpu_points(
        &gpu,
        &with_displacement,
        &[[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]],
    );
    let unfolded = root[0].distance(root[1]) + root[1].distance(root[2]);
    let ratio = unfolded / 0.04;
    assert!(
        (ratio - 2f32.sqrt()).abs() < 1e-3,
        "unfolded width × {ratio}"
    );
    let angle = (root[0] - root[1])
        .normalize()
        .angle_between((root[2] - root[1]).normalize())
        .to_degrees();
    assert!((angle - 90.0).abs() < 0.1, "cross-section angle {angle}°");
    // At the tip every point moves alike: the width is the shape's, no depth.
    let tip = gpu_points(
        &gpu,
        &with_displacement,
        &[[0.0, 1.0], [0.5, 1.0], [1.0, 1.0]],
    );
    assert!(
        (tip[1] - 0.5 * (tip[0] + tip[2])).length() < 1e-6,
        "{tip:?}"
    );
    // A triangle 2 pixels wide (0.04 m × 0.1 × 0.5 × 1000) under w_min = 50: a quad.
    let thin = Case {
        blade: straight,
        shape: [TRIANGLE, 0.5, 8.0, 0.0],
        correction: [50.0, 1.0],
    };
    let quad = Case {
        shape: [QUAD, 0.5, 8.0, 0.0],
        correction: [0.0, 0.0],
        ..thin
    };
    let uv = grid();
    for (a, b) in gpu_points(&gpu, &thin, &uv)
        .iter()
        .zip(gpu_points(&gpu, &quad, &uv))
    {
        assert!((*a - b).length() < 1e-6, "{a} against the quad's {b}");
    }
}
