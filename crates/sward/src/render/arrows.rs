//! The AGC guides drawn in 3D above the grass: every arrow of [`crate::sim::agc::arrows`] as
//! a shaft that follows the terrain plus a pyramid head, and every guide point as a small
//! octahedron, all floating [`ARROW_LIFT`] metres above the ground so that the grass (at
//! most 0.75 m tall by default) does not hide them.
//!
//! The mesh is built on the CPU ([`ArrowMesh::build`]) because it changes only when the
//! guides, the selection or the hover change, and it is tiny (a few hundred triangles per
//! guide). [`ArrowPass`] uploads it and draws it over a finished frame, depth tested against
//! the frame's depth buffer so that hills and colliders in front still hide the arrows.
//!
//! Shading is flat: every face has its own vertices with the face normal, and the shader
//! lights them with Lambert + ambient so that the shapes read as solids, not as flat blots.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

use super::draw::DEPTH_FORMAT;
use crate::field::HeightField;
use crate::gpu::Gpu;
use crate::scene::Guide;
use crate::shaders;
use crate::sim::agc::{arrows, Arrow, GuideId, PointId};
use crate::sim::update::uniform_entry;

/// Metres above the terrain where arrows and guide points float (blades are ≤ 0.75 m by
/// default, so the guides stay above a meadow at rest).
pub const ARROW_LIFT: f32 = 0.9;
/// Side of the shaft's square section, in metres.
pub const SHAFT_WIDTH: f32 = 0.12;
/// Longest straight piece of a shaft: longer shafts are split so that they follow hills.
pub const MAX_PIECE_LENGTH: f32 = 1.0;
/// Most pieces one shaft is split into; a longer shaft gets longer pieces (this only bounds
/// the mesh of absurdly long arrows).
pub const MAX_PIECES: usize = 4096;
/// Longest head, in metres.
pub const HEAD_MAX_LENGTH: f32 = 0.7;
/// A head is at most this fraction of its arrow's length, so short arrows keep a shaft.
pub const HEAD_FRACTION: f32 = 0.4;
/// Width of the head's base across the arrow, in metres.
pub const HEAD_WIDTH: f32 = 0.45;
/// Height of the head's base, in metres. The head is a flattened pyramid (a rectangular
/// base, wide across the arrow, a little thicker than the shaft): it reads as an arrowhead
/// from above, where guides are edited, and its lowest point stays near the shaft's, so it
/// does not dip into the grass.
pub const HEAD_THICKNESS: f32 = 0.16;
/// Tip-to-tip size of a guide point's octahedron, in metres.
pub const POINT_SIZE: f32 = 0.18;
/// Size of the selected point.
pub const SELECTED_POINT_SIZE: f32 = 0.32;
/// Size of the point under the mouse.
pub const HOVERED_POINT_SIZE: f32 = 0.24;
/// Strength (m/s²) at the yellow end of [`strength_color`]'s ramp.
pub const FULL_SCALE_STRENGTH: f32 = 20.0;
/// Light that faces turned away from the sun still get, as a fraction of full light.
pub const AMBIENT: f32 = 0.35;

/// Colour of ordinary guide points (linear RGB).
pub const POINT_COLOR: [f32; 4] = [0.85, 0.85, 0.85, 1.0];
/// Colour of a guide's root, where its flow starts: cyan, which the strength ramp never
/// produces.
pub const ROOT_COLOR: [f32; 4] = [0.15, 0.9, 0.95, 1.0];
/// Colour of the selected point: white-yellow.
pub const SELECTED_COLOR: [f32; 4] = [1.0, 1.0, 0.65, 1.0];
/// An arrow the AGC sequence has not switched on yet: a dim grey, so that the arrows that
/// push the air stand out (`ArrowMesh::build_at`).
pub const OFF_COLOR: [f32; 4] = [0.35, 0.35, 0.38, 1.0];

/// One vertex of the arrow mesh (world position, face normal, linear RGBA colour).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub struct ArrowVertex {
    /// World-space position in metres (`@location(0) position` in `arrows.wgsl`).
    pub position: [f32; 3],
    /// Unit outward normal of the face this vertex belongs to (`@location(1) normal`).
    pub normal: [f32; 3],
    /// Linear RGBA colour, alpha 1 (`@location(2) color`).
    pub color: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<ArrowVertex>() == 40);

/// Uniforms of `arrows.wgsl` (`ArrowUniforms` there).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct ArrowUniforms {
    view_proj: [[f32; 4]; 4],
    /// xyz: unit direction towards the sun; w: ambient light.
    light: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<ArrowUniforms>() == 80);

/// The triangles of all guides, ready to upload (a triangle list, counter-clockwise
/// front faces, outward normals).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ArrowMesh {
    /// Vertices, each face with its own copies so that shading stays flat.
    pub vertices: Vec<ArrowVertex>,
    /// Triangle-list indices into [`ArrowMesh::vertices`], three per triangle.
    pub indices: Vec<u32>,
}

/// The colour of an arrow of `strength` m/s²: a hue ramp blue → magenta → red → yellow over
/// 0..=[`FULL_SCALE_STRENGTH`] (hue 240° up to 420° = 60° linearly, full saturation and
/// value), clamped at both ends; NaN counts as 0. Linear RGB, alpha 1.
pub fn strength_color(strength: f32) -> [f32; 4] {
    let s = if strength.is_nan() { 0.0 } else { strength };
    let t = (s / FULL_SCALE_STRENGTH).clamp(0.0, 1.0);
    // Three legs of 60° each, from blue (240°) up through magenta and red to yellow
    // (420° = 60°): the ramp never passes through green or cyan, so an arrow of any
    // strength stands out against grass.
    let x = t * 3.0;
    let (r, g, b) = if x < 1.0 {
        (x, 0.0, 1.0) // blue → magenta
    } else if x < 2.0 {
        (1.0, 0.0, 2.0 - x) // magenta → red
    } else {
        (1.0, x - 2.0, 0.0) // red → yellow
    };
    [r, g, b, 1.0]
}

/// Where a guide point's marker floats: [`ARROW_LIFT`] above the highest terrain under its
/// default-size octahedron (picking can aim at this).
pub fn point_center(terrain: &HeightField, position: (f32, f32)) -> Vec3 {
    let c = Vec2::from(position);
    let y = footprint_top(terrain, c, &[Vec2::X, Vec2::Y], 0.5 * POINT_SIZE) + ARROW_LIFT;
    Vec3::new(c.x, y, c.y)
}

/// The highest terrain at `c` and at `c ± half·axis` for each axis. Placing a part's
/// centre [`ARROW_LIFT`] above this keeps every vertex of it, which lies above one of these
/// samples, at least that lift minus the part's half height above the ground, even on a
/// slope.
fn footprint_top(terrain: &HeightField, c: Vec2, axes: &[Vec2], half: f32) -> f32 {
    let mut top = terrain.height(c.x, c.y);
    for &a in axes {
        for p in [c + a * half, c - a * half] {
            top = top.max(terrain.height(p.x, p.y));
        }
    }
    top
}

fn lift(v: Vec2, y: f32) -> Vec3 {
    Vec3::new(v.x, y, v.y)
}

impl ArrowMesh {
    /// Builds the mesh of every arrow and point of `guides` on `terrain`. `selection` and
    /// `hover` name a point (guide, point); ids that do not exist are ignored. Points with a
    /// non-finite position are skipped, as are the arrows [`arrows`] skips.
    pub fn build(
        guides: &[Guide],
        terrain: &HeightField,
        selection: Option<(GuideId, PointId)>,
        hover: Option<(GuideId, PointId)>,
    ) -> Self {
        Self::build_at(guides, terrain, selection, hover, None)
    }

    /// [`ArrowMesh::build`] showing which arrows are on at scene time `time`: an arrow the
    /// sequence has not reached yet is grey ([`OFF_COLOR`]), one ramping up blends from grey
    /// to its strength colour. `None` draws every arrow as on.
    pub fn build_at(
        guides: &[Guide],
        terrain: &HeightField,
        selection: Option<(GuideId, PointId)>,
        hover: Option<(GuideId, PointId)>,
        time: Option<f32>,
    ) -> Self {
        let mut mesh = Self::default();
        for arrow in arrows(guides) {
            let on = time.map_or(1.0, |t| arrow.activation(t));
            mesh.add_arrow(&arrow, terrain, on);
        }
        for (g, guide) in guides.iter().enumerate() {
            for (i, p) in guide.points.iter().enumerate() {
                if !(p.position.0.is_finite() && p.position.1.is_finite()) {
                    continue;
                }
                let id = Some((g, i));
                let base = if i == 0 { ROOT_COLOR } else { POINT_COLOR };
                let (size, color) = if id == selection {
                    (SELECTED_POINT_SIZE, SELECTED_COLOR)
                } else if id == hover {
                    // Half-way to white: the same kind of point, lit up.
                    (HOVERED_POINT_SIZE, base.map(|c| 0.5 + 0.5 * c))
                } else {
                    (POINT_SIZE, base)
                };
                mesh.add_point(terrain, p.position, size, color);
            }
        }
        mesh
    }

    /// True when there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// Adds one triangle, ordered so that it faces `outward` (counter-clockwise seen from
    /// there), with its face normal.
    fn tri(&mut self, a: Vec3, b: Vec3, c: Vec3, color: [f32; 4], outward: Vec3) {
        let mut n = (b - a).cross(c - a);
        let (b, c) = if n.dot(outward) < 0.0 {
            n = -n;
            (c, b)
        } else {
            (b, c)
        };
        let normal = n.normalize_or(outward.normalize_or(Vec3::Y)).to_array();
        let first = self.vertices.len() as u32;
        for p in [a, b, c] {
            self.vertices.push(ArrowVertex {
                position: p.to_array(),
                normal,
                color,
            });
        }
        self.indices.extend([first, first + 1, first + 2]);
    }

    /// Adds a planar quad `a b c d` (in order around it) facing `outward`.
    fn quad(&mut self, q: [Vec3; 4], color: [f32; 4], outward: Vec3) {
        // The diagonals' cross product is the quad's normal even if the order is reversed.
        let mut n = (q[2] - q[0]).cross(q[3] - q[1]);
        let q = if n.dot(outward) < 0.0 {
            n = -n;
            [q[0], q[3], q[2], q[1]]
        } else {
            q
        };
        let normal = n.normalize_or(outward.normalize_or(Vec3::Y)).to_array();
        let first = self.vertices.len() as u32;
        for p in q {
            self.vertices.push(ArrowVertex {
                position: p.to_array(),
                normal,
                color,
            });
        }
        self.indices
            .extend([first, first + 1, first + 2, first, first + 2, first + 3]);
    }

    fn add_arrow(&mut self, arrow: &Arrow, terrain: &HeightField, on: f32) {
        let length = arrow.start.distance(arrow.end);
        if !(length.is_finite() && length > 0.0) {
            return;
        }
        let dir = (arrow.end - arrow.start) / length;
        // Horizontal, to the left of the arrow: the section stays upright on slopes.
        let side = Vec2::new(-dir.y, dir.x);
        let full = strength_color(arrow.strength);
        let on = on.clamp(0.0, 1.0);
        let color: [f32; 4] = std::array::from_fn(|i| OFF_COLOR[i] + (full[i] - OFF_COLOR[i]) * on);
        let head_length = (HEAD_FRACTION * length).min(HEAD_MAX_LENGTH);
        let base = arrow.end - dir * head_length;
        let shaft_length = length - head_length;
        let pieces = ((shaft_length / MAX_PIECE_LENGTH).ceil() as usize).clamp(1, MAX_PIECES);
        let half = 0.5 * SHAFT_WIDTH;
        let head_half = 0.5 * HEAD_WIDTH;
        let up = Vec3::Y;
        let side3 = Vec3::new(side.x, 0.0, side.y);

        // The shaft's centre line: rings at equal steps, each lifted above its footprint.
        let centers: Vec<Vec3> = (0..=pieces)
            .map(|i| {
                let c = arrow.start.lerp(base, i as f32 / pieces as f32);
                let mut top = footprint_top(terrain, c, &[side], half);
                if i == pieces {
                    // This ring meets the head's base: clear the head's footprint too.
                    top = top.max(footprint_top(terrain, c, &[side], head_half));
                }
                lift(c, top + ARROW_LIFT)
            })
            .collect();
        let ring = |c: Vec3| {
            [
                c + side3 * half + up * half,
                c - side3 * half + up * half,
                c - side3 * half - up * half,
                c + side3 * half - up * half,
            ]
        };
        let first = ring(centers[0]);
        let back = -lift(dir, 0.0);
        self.quad(first, color, back);
        for w in centers.windows(2) {
            let (r0, r1) = (ring(w[0]), ring(w[1]));
            let mid = 0.5 * (w[0] + w[1]);
            for k in 0..4 {
                let k1 = (k + 1) % 4;
                let face = [r0[k], r0[k1], r1[k1], r1[k]];
                let centre = 0.25 * (face[0] + face[1] + face[2] + face[3]);
                self.quad(face, color, centre - mid);
            }
        }

        // The head: a pyramid from the shaft's last ring to the arrow's end.
        let b = centers[pieces];
        let apex = lift(
            arrow.end,
            terrain.height(arrow.end.x, arrow.end.y) + ARROW_LIFT,
        );
        let hh = 0.5 * HEAD_THICKNESS;
        let corners = [
            b + side3 * head_half + up * hh,
            b - side3 * head_half + up * hh,
            b - side3 * head_half - up * hh,
            b + side3 * head_half - up * hh,
        ];
        self.quad(corners, color, back);
        let centroid = 0.8 * b + 0.2 * apex;
        for k in 0..4 {
            let (p, q) = (corners[k], corners[(k + 1) % 4]);
            let face_centre = (p + q + apex) / 3.0;
            self.tri(p, q, apex, color, face_centre - centroid);
        }
    }

    fn add_point(
        &mut self,
        terrain: &HeightField,
        position: (f32, f32),
        size: f32,
        color: [f32; 4],
    ) {
        let r = 0.5 * size;
        let c2 = Vec2::from(position);
        let y = footprint_top(terrain, c2, &[Vec2::X, Vec2::Y], r) + ARROW_LIFT;
        let c = lift(c2, y);
        let (x, z) = (Vec3::X * r, Vec3::Z * r);
        let ring = [c + x, c + z, c - x, c - z];
        for tip in [c + Vec3::Y * r, c - Vec3::Y * r] {
            for k in 0..4 {
                let (p, q) = (ring[k], ring[(k + 1) % 4]);
                let face_centre = (p + q + tip) / 3.0;
                self.tri(p, q, tip, color, face_centre - c);
            }
        }
    }
}

/// Draws an [`ArrowMesh`] over a finished frame (see the module docs).
pub struct ArrowPass {
    /// Samples per pixel of the targets the pipeline draws into.
    pub samples: u32,
    pipeline: wgpu::RenderPipeline,
    group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Capacities of the buffers, in vertices and indices.
    vertex_capacity: usize,
    index_capacity: usize,
    index_count: u32,
}

/// Vertices / indices the buffers start with; they grow in powers of two.
const INITIAL_CAPACITY: usize = 1024;

fn vertex_buffer(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.arrows.vertices"),
        size: (capacity * std::mem::size_of::<ArrowVertex>()) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn index_buffer(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.arrows.indices"),
        size: (capacity * std::mem::size_of::<u32>()) as u64,
        usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl ArrowPass {
    /// The pipeline for colour targets of `color_format` with a [`DEPTH_FORMAT`] depth
    /// buffer, both of `samples` samples (the renderer's MSAA), and empty buffers.
    pub fn new(gpu: &Gpu, color_format: wgpu::TextureFormat, samples: u32) -> Self {
        let device = &gpu.device;
        let module = shaders::module(device, "arrows.wgsl");
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sward.arrows.layout"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT)],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.arrows.uniforms"),
            size: std::mem::size_of::<ArrowUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.arrows.group"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sward.arrows.pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("sward.arrows.pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<ArrowVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            // The mesh is closed and wound counter-clockwise outwards: back faces are never
            // visible, so culling them halves the fragments.
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: Some(wgpu::Face::Back),
                ..Default::default()
            },
            // LessEqual and depth writes: the arrows hide each other correctly and are
            // hidden by whatever the frame drew in front of them.
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: color_format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self {
            samples,
            pipeline,
            group,
            uniforms,
            vertices: vertex_buffer(device, INITIAL_CAPACITY),
            indices: index_buffer(device, INITIAL_CAPACITY),
            vertex_capacity: INITIAL_CAPACITY,
            index_capacity: INITIAL_CAPACITY,
            index_count: 0,
        }
    }

    /// Uploads `mesh` (growing the buffers when it does not fit) and the camera and light.
    /// `sun_dir` points towards the sun; it need not be normalised. A mesh larger than the
    /// device's largest buffer is not drawn (a warning is logged).
    pub fn prepare(&mut self, gpu: &Gpu, mesh: &ArrowMesh, view_proj: Mat4, sun_dir: Vec3) {
        let device = &gpu.device;
        let max = device.limits().max_buffer_size;
        let vertex_bytes = std::mem::size_of_val(mesh.vertices.as_slice()) as u64;
        let index_bytes = std::mem::size_of_val(mesh.indices.as_slice()) as u64;
        if vertex_bytes > max || index_bytes > max || mesh.indices.len() > u32::MAX as usize {
            log::warn!(
                "arrow mesh of {} vertices is larger than the device's buffers: not drawn",
                mesh.vertices.len()
            );
            self.index_count = 0;
            return;
        }
        if mesh.vertices.len() > self.vertex_capacity {
            self.vertex_capacity = mesh.vertices.len().next_power_of_two();
            self.vertices = vertex_buffer(device, self.vertex_capacity);
        }
        if mesh.indices.len() > self.index_capacity {
            self.index_capacity = mesh.indices.len().next_power_of_two();
            self.indices = index_buffer(device, self.index_capacity);
        }
        if !mesh.is_empty() {
            gpu.queue
                .write_buffer(&self.vertices, 0, bytemuck::cast_slice(&mesh.vertices));
            gpu.queue
                .write_buffer(&self.indices, 0, bytemuck::cast_slice(&mesh.indices));
        }
        self.index_count = mesh.indices.len() as u32;
        let u = ArrowUniforms {
            view_proj: view_proj.to_cols_array_2d(),
            light: sun_dir.normalize_or(Vec3::Y).extend(AMBIENT).to_array(),
        };
        gpu.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
    }

    /// Whether the last prepared mesh has nothing to draw ([`ArrowPass::encode`] then
    /// records no pass).
    pub fn is_empty(&self) -> bool {
        self.index_count == 0
    }

    /// Records a render pass that draws the prepared mesh over `color`, depth tested
    /// (LessEqual) against `depth` and writing it; both are loaded, never cleared. Records
    /// nothing when the mesh is empty.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        q: crate::gpu::queries::PassQueries,
    ) {
        if self.index_count == 0 {
            return;
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward.arrows"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: q.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        q.begin(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
        q.end(&mut pass);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::GuidePoint;

    fn point(position: (f32, f32), parent: Option<usize>, strength: Option<f32>) -> GuidePoint {
        GuidePoint {
            position,
            parent,
            strength,
            radius: None,
        }
    }

    /// root → A, A → B, A → C, each arrow with its own strength (so its own colour).
    fn branching() -> Guide {
        Guide {
            started: 0.0,
            strength: 2.0,
            radius: 1.0,
            points: vec![
                point((-6.0, 0.0), None, None),
                point((-1.0, 0.5), Some(0), None),
                point((4.0, 4.0), Some(1), Some(10.0)),
                point((3.5, -5.0), Some(1), Some(19.0)),
            ],
        }
    }

    /// Hills of ±1.5 m with a wavelength of about 6 m: steep enough that a section lifted
    /// above its centre only would dip below the lift at its edges.
    fn hilly() -> HeightField {
        let (size, resolution) = (32.0, 65u32);
        let mut field = HeightField::flat(size, resolution);
        for j in 0..resolution {
            for i in 0..resolution {
                let v = field.vertex(i, j);
                field.heights[(j * resolution + i) as usize] =
                    1.5 * (v.x * 1.1).sin() * (v.z * 0.9 + 0.3).cos();
            }
        }
        field
    }

    fn count_color(mesh: &ArrowMesh, color: [f32; 4]) -> usize {
        mesh.vertices.iter().filter(|v| v.color == color).count()
    }

    /// Vertices of one arrow: start cap, 4 faces per shaft piece, head base, 4 head sides.
    fn arrow_vertices(arrow: &Arrow) -> usize {
        let length = arrow.start.distance(arrow.end);
        let shaft = length - (HEAD_FRACTION * length).min(HEAD_MAX_LENGTH);
        let pieces = (shaft / MAX_PIECE_LENGTH).ceil() as usize;
        4 + 16 * pieces + 4 + 12
    }

    const OCTAHEDRON_VERTICES: usize = 24;

    /// The editor's view shows which arrows are on: before the front reaches an arrow it is
    /// grey, after the ramp it has its strength colour.
    #[test]
    fn arrows_not_yet_on_are_grey() {
        let mut guide = branching();
        guide.started = 2.0;
        let guides = vec![guide];
        let terrain = HeightField::flat(32.0, 9);
        let list = arrows(&guides);
        let total: usize = list.iter().map(arrow_vertices).sum();
        let before = ArrowMesh::build_at(&guides, &terrain, None, None, Some(1.0));
        assert_eq!(count_color(&before, OFF_COLOR), total);
        let after = ArrowMesh::build_at(&guides, &terrain, None, None, Some(60.0));
        assert_eq!(count_color(&after, OFF_COLOR), 0);
        for a in &list {
            assert_eq!(
                count_color(&after, strength_color(a.strength)),
                arrow_vertices(a)
            );
        }
        // Just after the start: the root's arrows ramp, the deeper ones are still grey.
        let ramping = ArrowMesh::build_at(&guides, &terrain, None, None, Some(2.0 + 1e-3));
        let deep: usize = list
            .iter()
            .filter(|a| a.start_distance > 0.0)
            .map(arrow_vertices)
            .sum();
        assert_eq!(count_color(&ramping, OFF_COLOR), deep);
    }

    #[test]
    fn a_branching_guide_has_three_arrows_and_four_points() {
        let guides = vec![branching()];
        let terrain = HeightField::flat(32.0, 9);
        let mesh = ArrowMesh::build(&guides, &terrain, None, None);
        let list = arrows(&guides);
        assert_eq!(list.len(), 3);
        let arrow_total: usize = list.iter().map(arrow_vertices).sum();
        assert_eq!(mesh.vertices.len(), arrow_total + 4 * OCTAHEDRON_VERTICES);
        // Each arrow in its own colour; one root and three ordinary points.
        for a in &list {
            assert_eq!(
                count_color(&mesh, strength_color(a.strength)),
                arrow_vertices(a)
            );
        }
        assert_eq!(count_color(&mesh, ROOT_COLOR), OCTAHEDRON_VERTICES);
        assert_eq!(count_color(&mesh, POINT_COLOR), 3 * OCTAHEDRON_VERTICES);
        // The first arrow (5.02 m) is split into ≤ 1 m pieces: 5.02 − 0.7 = 4.32 → 5.
        assert_eq!(arrow_vertices(&list[0]), 4 + 16 * 5 + 16);
        assert!(!mesh.is_empty());
        assert!(ArrowMesh::build(&[], &terrain, None, None).is_empty());
    }

    #[test]
    fn indices_are_in_range_and_triangles_face_outwards() {
        let guides = vec![branching()];
        let mesh = ArrowMesh::build(&guides, &hilly(), Some((0, 2)), Some((0, 0)));
        assert_eq!(mesh.indices.len() % 3, 0);
        assert!(mesh
            .indices
            .iter()
            .all(|&i| (i as usize) < mesh.vertices.len()));
        // Every triangle's winding (counter-clockwise = front) agrees with its normal, which
        // is what back-face culling in the pass relies on.
        for t in mesh.indices.chunks(3) {
            let [a, b, c] =
                [t[0], t[1], t[2]].map(|i| Vec3::from(mesh.vertices[i as usize].position));
            let n = Vec3::from(mesh.vertices[t[0] as usize].normal);
            let geometric = (b - a).cross(c - a);
            assert!(geometric.dot(n) > 0.0, "{a} {b} {c} {n}");
            assert!((n.length() - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn everything_floats_above_hilly_terrain() {
        let terrain = hilly();
        let mut guide = branching();
        // A long arrow over several hills.
        guide.points.push(point((-14.0, -12.0), Some(0), Some(5.0)));
        let guides = vec![guide];
        for (selection, hover, half) in [
            (None, None, 0.5 * POINT_SIZE),
            (Some((0, 1)), Some((0, 3)), 0.5 * SELECTED_POINT_SIZE),
        ] {
            let mesh = ArrowMesh::build(&guides, &terrain, selection, hover);
            // The largest half height of any part: point, shaft (0.06) or head (0.08).
            let half = half.max(0.5 * HEAD_THICKNESS).max(0.5 * SHAFT_WIDTH);
            for v in &mesh.vertices {
                let [x, y, z] = v.position;
                let floor = terrain.height(x, z) + ARROW_LIFT - half;
                assert!(y >= floor - 1e-4, "vertex {:?} below {floor}", v.position);
            }
        }
        // Shaft vertices alone stay within the shaft's half width of the lift.
        let mesh = ArrowMesh::build(&guides, &terrain, None, None);
        let shaft_color = strength_color(5.0);
        for v in mesh.vertices.iter().filter(|v| v.color == shaft_color) {
            let [x, y, z] = v.position;
            let floor = terrain.height(x, z) + ARROW_LIFT - 0.5 * HEAD_THICKNESS;
            assert!(y >= floor - 1e-4);
        }
    }

    #[test]
    fn selected_and_hovered_points_stand_out() {
        let guides = vec![branching()];
        let terrain = HeightField::flat(32.0, 9);
        let plain = ArrowMesh::build(&guides, &terrain, None, None);
        let selected = ArrowMesh::build(&guides, &terrain, Some((0, 2)), None);
        assert_eq!(count_color(&selected, SELECTED_COLOR), OCTAHEDRON_VERTICES);
        assert_eq!(count_color(&plain, SELECTED_COLOR), 0);
        assert_ne!(SELECTED_COLOR, POINT_COLOR);
        assert_ne!(SELECTED_COLOR, ROOT_COLOR);
        // The selected octahedron is bigger: its top vertex is higher.
        let top = |m: &ArrowMesh, c: [f32; 4]| {
            m.vertices
                .iter()
                .filter(|v| v.color == c)
                .map(|v| v.position[1])
                .fold(f32::MIN, f32::max)
        };
        let flat_top = ARROW_LIFT + 0.5 * SELECTED_POINT_SIZE;
        assert!((top(&selected, SELECTED_COLOR) - flat_top).abs() < 1e-5);
        // Hovering the root lights it up and enlarges it a little; the selection wins.
        let hovered = ArrowMesh::build(&guides, &terrain, None, Some((0, 0)));
        assert_eq!(count_color(&hovered, ROOT_COLOR), 0);
        let lit = ROOT_COLOR.map(|c| 0.5 + 0.5 * c);
        assert!((top(&hovered, lit) - (ARROW_LIFT + 0.5 * HOVERED_POINT_SIZE)).abs() < 1e-5);
        let both = ArrowMesh::build(&guides, &terrain, Some((0, 0)), Some((0, 0)));
        assert_eq!(count_color(&both, SELECTED_COLOR), OCTAHEDRON_VERTICES);
        // Ids that do not exist change nothing.
        let missing = ArrowMesh::build(&guides, &terrain, Some((3, 0)), Some((0, 99)));
        assert_eq!(missing, plain);
    }

    /// Hue in degrees of a fully saturated colour.
    fn hue(c: [f32; 4]) -> f32 {
        let [r, g, b, _] = c;
        let max = r.max(g).max(b);
        let min = r.min(g).min(b);
        let d = max - min;
        assert!(d > 0.99, "not fully saturated: {c:?}");
        let h = if max == r {
            60.0 * ((g - b) / d)
        } else if max == g {
            60.0 * ((b - r) / d + 2.0)
        } else {
            60.0 * ((r - g) / d + 4.0)
        };
        h.rem_euclid(360.0)
    }

    #[test]
    fn strength_color_ramps_from_blue_to_yellow_and_clamps() {
        let third = 20.0 / 3.0;
        let close = |a: [f32; 4], b: [f32; 4]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5);
        assert_eq!(strength_color(0.0), [0.0, 0.0, 1.0, 1.0]);
        assert!(close(strength_color(third), [1.0, 0.0, 1.0, 1.0]));
        assert!(close(strength_color(2.0 * third), [1.0, 0.0, 0.0, 1.0]));
        assert_eq!(strength_color(20.0), [1.0, 1.0, 0.0, 1.0]);
        // Unwrapped hue: 240° rising to 420°, never through green or cyan (90°..210°).
        let mut last = 240.0 - 1e-3;
        for i in 0..=200 {
            let s = i as f32 * 0.1;
            let mut h = hue(strength_color(s));
            if h < 180.0 {
                h += 360.0;
            }
            assert!(h >= last - 1e-3, "hue falls at {s}: {h} < {last}");
            assert!((h - (240.0 + 180.0 * s / 20.0)).abs() < 1e-2, "{s}: {h}");
            last = h;
        }
        assert_eq!(strength_color(-3.0), strength_color(0.0));
        assert_eq!(strength_color(f32::NAN), strength_color(0.0));
        assert_eq!(strength_color(500.0), strength_color(20.0));
        assert_eq!(strength_color(f32::INFINITY), strength_color(20.0));
    }

    #[test]
    fn point_center_matches_the_octahedron() {
        let terrain = hilly();
        let guides = vec![branching()];
        let mesh = ArrowMesh::build(&guides, &terrain, None, None);
        let c = point_center(&terrain, guides[0].points[0].position);
        let root: Vec<Vec3> = mesh
            .vertices
            .iter()
            .filter(|v| v.color == ROOT_COLOR)
            .map(|v| Vec3::from(v.position))
            .collect();
        let mean = root.iter().sum::<Vec3>() / root.len() as f32;
        assert!(mean.distance(c) < 1e-4, "{mean} vs {c}");
    }
}
