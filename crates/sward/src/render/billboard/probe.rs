//! The probe that runs the billboard placement and sway kernels (`billboard_probe.wgsl`)
//! over every card of the grid and reads them back: the GPU side of the twin test.

use wgpu::util::DeviceExt;

use super::{BillboardParams, Card};
use crate::error::Result;
use crate::field::HeightField;
use crate::gpu::{read_buffer, Gpu};
use crate::render::{clipmap, terrain as terrain_gpu};
use crate::shaders;
use crate::sim::layout::SimParams;
use crate::sim::update::{compute_storage_entry, uniform_entry};

/// What the probe read back for one card: the placement and the top offset of a card of
/// its height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probed {
    /// The card as `card_at` placed it on the GPU (the twin of [`super::place_card`]).
    pub card: Card,
    /// The offset of the card's top (m) from `top_offset` for a card `scale` times the
    /// card height tall (the twin of [`super::top_offset`]).
    pub top: glam::Vec3,
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// Runs the probe over every card of `params`' grid, with the wind of `sim` (and the fluid
/// grid `wind_grid`, one cell when unused), the colliders `spheres` and the trail map
/// `trails` (its words; empty: none).
pub fn probe_cards(
    gpu: &Gpu,
    terrain: &HeightField,
    params: &BillboardParams,
    sim: &SimParams,
    wind_grid: &[[f32; 2]],
    spheres: &[[f32; 4]],
    trails: &[u32],
) -> Result<Vec<Probed>> {
    let device = &gpu.device;
    let c = wgpu::ShaderStages::COMPUTE;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sward.billboard_probe.layout"),
        entries: &[
            crate::render::draw::read_storage(1, c),
            compute_storage_entry(2, true),
            uniform_entry(3, c),
            compute_storage_entry(6, true),
            uniform_entry(7, c),
            compute_storage_entry(8, true),
            compute_storage_entry(10, false),
            compute_storage_entry(11, true),
        ],
    });
    let terrain_params = terrain_gpu::params_buffer(device, "sward.billboard_probe.terrain");
    let u = clipmap::terrain_uniforms(terrain, false, (0.0, 1.0), glam::Vec3::ZERO, 1.0, 0.0);
    gpu.queue
        .write_buffer(&terrain_params, 0, bytemuck::bytes_of(&u));
    let grid = terrain_gpu::grid_buffer(device, terrain);
    let init = |label, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let uniform = wgpu::BufferUsages::UNIFORM;
    let storage = wgpu::BufferUsages::STORAGE;
    let bb = init(
        "sward.billboard_probe.params",
        bytemuck::bytes_of(params),
        uniform,
    );
    let sim_buf = init(
        "sward.billboard_probe.sim",
        bytemuck::bytes_of(sim),
        uniform,
    );
    let wind = if wind_grid.is_empty() {
        vec![[0.0f32; 2]]
    } else {
        wind_grid.to_vec()
    };
    let wind_buf = init(
        "sward.billboard_probe.wind",
        bytemuck::cast_slice(&wind),
        storage,
    );
    let mut sph = spheres.to_vec();
    sph.push([0.0; 4]);
    let sph_buf = init(
        "sward.billboard_probe.spheres",
        bytemuck::cast_slice(&sph),
        storage,
    );
    let mut trail_words = trails.to_vec();
    trail_words.resize(
        trail_words
            .len()
            .max(crate::field::trails::HEADER_WORDS as usize),
        0,
    );
    let trail_buf = init(
        "sward.billboard_probe.trails",
        bytemuck::cast_slice(&trail_words),
        storage,
    );
    let count = u64::from(params.levels[0]) * u64::from(params.levels[2]).pow(2);
    let out_size = count * 3 * 16;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.billboard_probe.out"),
        size: out_size.max(16),
        usage: storage | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sward.billboard_probe.group"),
        layout: &layout,
        entries: &[
            entry(1, &terrain_params),
            entry(2, &grid),
            entry(3, &bb),
            entry(6, &sph_buf),
            entry(7, &sim_buf),
            entry(8, &wind_buf),
            entry(10, &out),
            entry(11, &trail_buf),
        ],
    });
    let module = shaders::module(device, "billboard_probe.wgsl");
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("sward.billboard_probe.pipeline_layout"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("sward.billboard_probe"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("sward.billboard_probe"),
    });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.billboard_probe"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((count as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let bytes = read_buffer(gpu, &out, out_size)?;
    let v: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    Ok(v.chunks(3)
        .map(|c| Probed {
            card: Card {
                pos: glam::Vec3::new(c[0][0], c[0][1], c[0][2]),
                fade: c[0][3],
                level: c[2][3] as u32,
                variant: c[1][0] as u32,
                scale: c[1][1],
                mirror: c[1][2],
                accept: c[1][3],
            },
            top: glam::Vec3::new(c[2][0], c[2][1], c[2][2]),
        })
        .collect())
}

/// One case of the height profile's probe (`card_profile_probe.wgsl`): the bands' means
/// and a height for `profile_at`, a row band and its light for `profile_luma`.
#[derive(Clone, Copy, Debug)]
pub struct ProfileCase {
    /// The bands' means, from the top.
    pub means: [f32; super::atlas::PROFILE_ROWS],
    /// The height looked up (0 the strip's top row, 1 its bottom).
    pub y: f32,
    /// A row band to light.
    pub row: super::atlas::ProfileRow,
    /// The sky's light on it (rgb).
    pub light: glam::Vec3,
    /// The sun's light for each facing (rgb).
    pub sun: [glam::Vec3; super::atlas::FACINGS],
}

/// Runs the WGSL height profile (`profile_at`, `profile_luma`) on the GPU for each case:
/// (profile_at, profile_luma) per case, for the test against the twins in `atlas`.
pub fn probe_profile(gpu: &Gpu, cases: &[ProfileCase]) -> Result<Vec<(f32, f32)>> {
    let v = |p: glam::Vec3| [p.x, p.y, p.z, 0.0];
    let flat: Vec<[f32; 4]> = cases
        .iter()
        .flat_map(|c| {
            let m = c.means;
            let mut out = vec![
                [m[0], m[1], m[2], m[3]],
                [m[4], m[5], m[6], m[7]],
                [c.y, 0.0, 0.0, 0.0],
                c.row.colour,
            ];
            out.extend(c.row.facing);
            out.push(v(c.light));
            out.extend(c.sun.map(v));
            out
        })
        .collect();
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.card_profile_probe",
        "card_profile_probe.wgsl",
        &[bytemuck::cast_slice(&flat)],
        cases.len(),
    )?;
    Ok(out.iter().map(|o| (o[0], o[1])).collect())
}
