//! A wind grid that follows the camera (`wind.fluid.extent > 0`, issue 13 point 4): when
//! the camera's cell leaves the grid's centre cell, the grid moves by whole cells. The
//! scroll kernel (`fluid_scroll.wgsl`, twin `FluidCpu::scroll`) copies every face and
//! pressure cell that stays to its new index and gives the entering ones the old grid's
//! edge values, then the results are copied back into the solver's buffers. Guides,
//! obstacles and the downwash are in world coordinates and the step converts them with the
//! grid's current corner, so they stay anchored in the world; the blades, the billboards
//! and the overlay read the same corner, so the wind they see does not jump.

use super::kernels::{module, Kernel, Slot};
use crate::gpu::queries::PassQueries;
use bytemuck::{Pod, Zeroable};

/// The scroll kernel's uniforms (`Scroll` in `fluid_scroll.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct ScrollParams {
    /// The grid corner's move in cells.
    pub shift: [i32; 2],
    pub resolution: u32,
    pub layers: u32,
}

const _: () = assert!(std::mem::size_of::<ScrollParams>() == 16);

/// Invocations per workgroup of the scroll.
const WORKGROUP: u32 = 64;
/// Largest workgroup count per dimension every adapter allows.
const MAX_GROUPS: u32 = 65_535;

/// The scroll kernel, its uniforms and its two bind groups (one per pressure buffer that
/// may hold the latest solve).
pub(super) struct Scroller {
    kernel: Kernel,
    params: wgpu::Buffer,
    groups: [wgpu::BindGroup; 2],
}

impl Scroller {
    /// `faces`: the state (read) and a scratch buffer (written); `pressure`: the two
    /// pressure buffers of the solver.
    pub fn new(
        device: &wgpu::Device,
        faces: [&wgpu::Buffer; 2],
        pressure: [&wgpu::Buffer; 2],
    ) -> Self {
        let m = module(device, "scroll");
        let kernel = Kernel::new(
            device,
            &m,
            "scroll",
            "scroll_grid",
            &[
                Slot::Uniform,
                Slot::Read,
                Slot::Write,
                Slot::Read,
                Slot::Write,
            ],
        );
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward.fluid.scroll.params"),
            size: std::mem::size_of::<ScrollParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let groups = [0, 1].map(|c| {
            kernel.bind(
                device,
                &format!("scroll.pressure_{c}"),
                &[&params, faces[0], faces[1], pressure[c], pressure[1 - c]],
            )
        });
        Self {
            kernel,
            params,
            groups,
        }
    }

    /// Records a scroll by `shift` cells of an `n`² grid of `layers` layers whose latest
    /// pressure is `pressure[current]`, and the copies back into `faces[0]` and
    /// `pressure[current]`.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        shift: [i32; 2],
        n: u32,
        layers: u32,
        faces: [&wgpu::Buffer; 2],
        pressure: [&wgpu::Buffer; 2],
        current: usize,
        work: PassQueries<'_>,
    ) {
        let p = ScrollParams {
            shift,
            resolution: n,
            layers,
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        // Every face (the cells are fewer).
        let invocations = 2 * layers * n * (n + 1) + (layers + 1) * n * n;
        let groups = invocations.div_ceil(WORKGROUP);
        let x = groups.min(MAX_GROUPS);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sward.fluid.scroll"),
                timestamp_writes: None,
            });
            work.begin(&mut pass);
            pass.set_pipeline(&self.kernel.pipeline);
            pass.set_bind_group(0, &self.groups[current], &[]);
            pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
            work.end(&mut pass);
        }
        let face_bytes = u64::from(invocations) * 4;
        encoder.copy_buffer_to_buffer(faces[1], 0, faces[0], 0, face_bytes);
        let cell_bytes = u64::from(layers * n * n) * 4;
        encoder.copy_buffer_to_buffer(pressure[1 - current], 0, pressure[current], 0, cell_bytes);
    }
}
