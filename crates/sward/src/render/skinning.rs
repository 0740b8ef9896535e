//! The animated mesh objects' skinning pass (issue 29, point 1): for each object with an
//! `animation`, the joints' skinning matrices at the scene's time are computed on the CPU
//! (a few dozen matrices: `mesh::skin::SkinnedMesh::joint_matrices`) and uploaded, and one
//! compute dispatch (`skin.wgsl`) poses its vertices into the object's vertex buffer before
//! the frame's first draw, so the occluder, shadow and colour passes all see this frame's
//! pose. Per-vertex work stays on the GPU; the buffers are made once at load.

use wgpu::util::DeviceExt;

use super::objects::ObjectsPass;
use crate::gpu::queries::PassQueries;
use crate::mesh::skin::SkinnedMesh;

/// Vertices per workgroup of `skin.wgsl`.
const GROUP: u32 = 64;

/// One animated object on the GPU.
struct Skinned {
    /// The scene object it is (an index into `objects`).
    object: usize,
    mesh: SkinnedMesh,
    /// The animation it plays (index into `mesh.animations`).
    animation: usize,
    /// The joints' skinning matrices, rewritten each frame.
    joints: wgpu::Buffer,
    group: wgpu::BindGroup,
    vertices: u32,
}

/// Every animated object's skinning.
pub struct SkinningPass {
    pipeline: wgpu::ComputePipeline,
    objects: Vec<Skinned>,
}

impl SkinningPass {
    /// Builds the buffers of each object of `skins` that has one (`None` when none does);
    /// `objects` holds the vertex buffers the pass writes.
    pub fn new(
        device: &wgpu::Device,
        skins: &[Option<(SkinnedMesh, usize)>],
        objects: &ObjectsPass,
    ) -> Option<Self> {
        if skins.iter().all(Option::is_none) {
            return None;
        }
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.skinning"),
            // The shader's own layout: bind pose, influences, joints read; vertices written.
            layout: None,
            module: &crate::shaders::module(device, "skin.wgsl"),
            entry_point: Some("skin"),
            compilation_options: Default::default(),
            cache: None,
        });
        let layout = pipeline.get_bind_group_layout(0);
        let objects = skins
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.as_ref().map(|s| (i, s)))
            .filter_map(|(i, (mesh, animation))| {
                let target = objects.vertex_buffer(i)?;
                let rest: Vec<f32> = mesh
                    .positions
                    .iter()
                    .zip(&mesh.normals)
                    .flat_map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]])
                    .collect();
                let influence: Vec<u32> = mesh
                    .joint_indices
                    .iter()
                    .zip(&mesh.weights)
                    .flat_map(|(j, w)| {
                        let j = j.map(u32::from);
                        [j[0], j[1], j[2], j[3]]
                            .into_iter()
                            .chain(w.iter().map(|x| x.to_bits()))
                    })
                    .collect();
                let rest = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("sward.skinning.{i}.rest")),
                    contents: bytemuck::cast_slice(&rest),
                    usage: wgpu::BufferUsages::STORAGE,
                });
                let influence = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("sward.skinning.{i}.influence")),
                    contents: bytemuck::cast_slice(&influence),
                    usage: wgpu::BufferUsages::STORAGE,
                });
                let joints = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&format!("sward.skinning.{i}.joints")),
                    size: (mesh.joints.len() * 64) as u64,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("sward.skinning.{i}.group")),
                    layout: &layout,
                    entries: &[
                        entry(0, &rest),
                        entry(1, &influence),
                        entry(2, &joints),
                        entry(3, target),
                    ],
                });
                Some(Skinned {
                    object: i,
                    vertices: mesh.positions.len() as u32,
                    mesh: mesh.clone(),
                    animation: *animation,
                    joints,
                    group,
                })
            })
            .collect();
        Some(Self { pipeline, objects })
    }

    /// The length in seconds of the animation scene object `object` plays, if it is one of
    /// the skinned ones.
    pub fn duration(&self, object: usize) -> Option<f32> {
        self.objects
            .iter()
            .find(|o| o.object == object)
            .map(|o| o.mesh.animations[o.animation].duration)
    }

    /// Uploads each object's skinning matrices at `time` seconds into the scene (its
    /// animation looped, at the pace of its path with a `stride`:
    /// `sim::colliders::animation_time`); `objects` are the scene's.
    pub fn prepare(&self, queue: &wgpu::Queue, objects: &[crate::scene::MeshObject], time: f32) {
        for o in &self.objects {
            let duration = o.mesh.animations[o.animation].duration;
            let t = objects.get(o.object).map_or(time, |object| {
                crate::sim::colliders::animation_time(object, duration, time)
            });
            let joints = o.mesh.joint_matrices(Some(o.animation), t);
            let data: Vec<[f32; 16]> = joints.iter().map(|m| m.to_cols_array()).collect();
            queue.write_buffer(&o.joints, 0, bytemuck::cast_slice(&data));
        }
    }

    /// Records the dispatches that pose every animated object's vertices.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, q: PassQueries) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward.skinning"),
            timestamp_writes: q.compute_writes(),
        });
        q.begin(&mut pass);
        pass.set_pipeline(&self.pipeline);
        for o in &self.objects {
            pass.set_bind_group(0, &o.group, &[]);
            pass.dispatch_workgroups(o.vertices.div_ceil(GROUP), 1, 1);
        }
        q.end(&mut pass);
    }
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
