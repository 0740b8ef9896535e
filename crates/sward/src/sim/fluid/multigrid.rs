//! The multigrid pressure solve on the GPU (`shaders/fluid_multigrid.wgsl`): a hierarchy of
//! grids, each half the previous one's side, with their own pressure, right-hand side and
//! face weights, and the bind groups of every dispatch of a V-cycle. Level 0 is the solver's
//! own pressure (either buffer of the Jacobi ping-pong: the cycle runs in place on the one
//! that holds the warm start), divergence and weights.
//!
//! The levels, sweep counts and operator are those of the CPU twin,
//! [`crate::sim::reference::fluid::multigrid`]; see its docs for the choices.

use super::kernels::{module, Kernel, Slot};
use super::FluidConfig;
use crate::sim::reference::fluid::multigrid::{
    border_scale, coarsest_sweeps, level_scales, open_ghost, POST_SWEEPS, PRE_SWEEPS,
};
use crate::sim::wind_layout::{MgParams, FLUID_WORKGROUP};

/// One level below the finest: its grids.
struct Coarse {
    pressure: wgpu::Buffer,
    rhs: wgpu::Buffer,
    weights: wgpu::Buffer,
}

/// The bind groups of one level. `variant` 0/1 of level 0 binds pressure buffer 0/1; the
/// other levels have one variant.
struct LevelGroups {
    /// [variant][colour]
    smooth: Vec<[wgpu::BindGroup; 2]>,
    /// To the next level (absent on the coarsest): [variant].
    restrict: Vec<wgpu::BindGroup>,
    prolong: Vec<wgpu::BindGroup>,
    coarsen: Option<wgpu::BindGroup>,
}

/// The hierarchy, its kernels and bind groups.
pub(super) struct Multigrid {
    sizes: Vec<u32>,
    layers: u32,
    /// Per level, the uniforms of colour 0 and colour 1.
    params: Vec<[wgpu::Buffer; 2]>,
    coarse: Vec<Coarse>,
    groups: Vec<LevelGroups>,
    smooth: Kernel,
    restrict: Kernel,
    prolong: Kernel,
    coarsen: Kernel,
}

/// Level-0 buffers the solver owns.
pub(super) struct Finest<'a> {
    pub pressure: [&'a wgpu::Buffer; 2],
    pub divergence: &'a wgpu::Buffer,
    pub weights: &'a wgpu::Buffer,
}

fn groups_of(cells: u32) -> u32 {
    cells.div_ceil(FLUID_WORKGROUP)
}

impl Multigrid {
    pub fn new(device: &wgpu::Device, config: &FluidConfig, finest: Finest) -> Self {
        use Slot::{Read, Uniform, Write};
        let sizes = config.multigrid_levels();
        let m = module(device, "multigrid");
        // A 2D grid's columns are single cells: its smoother is built without the column
        // solve (`LAYERED` in fluid_multigrid.wgsl).
        let layered = if config.layers > 1 { 1.0 } else { 0.0 };
        let smooth = Kernel::specialised(
            device,
            &m,
            "mg_smooth",
            "smooth_colour",
            &[(0, Uniform), (1, Read), (2, Read), (3, Write)],
            &[("LAYERED", layered)],
        );
        let restrict = Kernel::with_bindings(
            device,
            &m,
            "mg_restrict",
            "restrict_residual",
            &[
                (0, Uniform),
                (1, Read),
                (2, Read),
                (3, Write),
                (4, Write),
                (5, Write),
            ],
        );
        let prolong = Kernel::with_bindings(
            device,
            &m,
            "mg_prolong",
            "prolong",
            &[(0, Uniform), (2, Read), (3, Write), (5, Write), (6, Write)],
        );
        let coarsen = Kernel::with_bindings(
            device,
            &m,
            "mg_coarsen",
            "coarsen_weights",
            &[(0, Uniform), (2, Read), (6, Write)],
        );
        let params: Vec<[wgpu::Buffer; 2]> = (0..sizes.len())
            .map(|l| {
                [0, 1].map(|colour| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&format!("sward.fluid.mg.level{l}.params{colour}")),
                        size: std::mem::size_of::<MgParams>() as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                })
            })
            .collect();
        let coarse: Vec<Coarse> = sizes[1..]
            .iter()
            .enumerate()
            .map(|(k, &s)| {
                let cells = u64::from(s) * u64::from(s) * u64::from(config.layers);
                let grid = |what: &str, bytes: u64| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&format!("sward.fluid.mg.level{}.{what}", k + 1)),
                        size: cells * bytes,
                        // COPY_SRC for tests that read a level back.
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                        mapped_at_creation: false,
                    })
                };
                Coarse {
                    pressure: grid("pressure", 4),
                    rhs: grid("rhs", 4),
                    weights: grid("weights", 32),
                }
            })
            .collect();
        // The grids of level l for pressure variant v.
        let level = |l: usize, v: usize| -> (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer) {
            if l == 0 {
                (finest.pressure[v], finest.divergence, finest.weights)
            } else {
                let c = &coarse[l - 1];
                (&c.pressure, &c.rhs, &c.weights)
            }
        };
        let groups = (0..sizes.len())
            .map(|l| {
                let variants = if l == 0 { 2 } else { 1 };
                let last = l + 1 == sizes.len();
                let smooth_groups = (0..variants)
                    .map(|v| {
                        let (p, f, w) = level(l, v);
                        [0, 1].map(|c| {
                            smooth.bind(
                                device,
                                &format!("mg.level{l}.smooth{c}.p{v}"),
                                &[&params[l][c], f, w, p],
                            )
                        })
                    })
                    .collect();
                let mut restrict_groups = Vec::new();
                let mut prolong_groups = Vec::new();
                let mut coarsen_group = None;
                if !last {
                    let next = &coarse[l];
                    for v in 0..variants {
                        let (p, f, w) = level(l, v);
                        restrict_groups.push(restrict.bind(
                            device,
                            &format!("mg.level{l}.restrict.p{v}"),
                            &[&params[l][0], f, w, p, &next.rhs, &next.pressure],
                        ));
                        prolong_groups.push(prolong.bind(
                            device,
                            &format!("mg.level{l}.prolong.p{v}"),
                            &[&params[l][0], w, p, &next.pressure, &next.weights],
                        ));
                    }
                    let (_, _, w) = level(l, 0);
                    coarsen_group = Some(coarsen.bind(
                        device,
                        &format!("mg.level{l}.coarsen"),
                        &[&params[l][0], w, &next.weights],
                    ));
                }
                LevelGroups {
                    smooth: smooth_groups,
                    restrict: restrict_groups,
                    prolong: prolong_groups,
                    coarsen: coarsen_group,
                }
            })
            .collect();
        Self {
            sizes,
            layers: config.layers,
            params,
            coarse,
            groups,
            smooth,
            restrict,
            prolong,
            coarsen,
        }
    }

    /// The side of every level, finest first.
    pub fn sizes(&self) -> &[u32] {
        &self.sizes
    }

    /// Bytes of GPU memory of the coarse levels and uniforms.
    pub fn gpu_bytes(&self) -> u64 {
        let grids: u64 = self
            .coarse
            .iter()
            .map(|c| c.pressure.size() + c.rhs.size() + c.weights.size())
            .sum();
        grids + self.params.len() as u64 * 2 * std::mem::size_of::<MgParams>() as u64
    }

    /// Writes every level's uniforms (the boundary can change between steps).
    pub fn prepare(&self, queue: &wgpu::Queue, config: &FluidConfig) {
        for (l, (&size, buffers)) in self.sizes.iter().zip(&self.params).enumerate() {
            let (h2, vertical) = level_scales(config, l);
            for (colour, buffer) in buffers.iter().enumerate() {
                let p = MgParams {
                    size,
                    boundary: config.boundary_id(),
                    h2,
                    colour: colour as u32,
                    border_scale: border_scale(l),
                    open_ghost: open_ghost(l + 1),
                    layers: config.layers,
                    vertical,
                };
                queue.write_buffer(buffer, 0, bytemuck::bytes_of(&p));
            }
        }
    }

    fn sweep(&self, pass: &mut wgpu::ComputePass, l: usize, variant: usize, sweeps: u32) {
        let m = self.sizes[l];
        let v = variant.min(self.groups[l].smooth.len() - 1);
        pass.set_pipeline(&self.smooth.pipeline);
        for _ in 0..sweeps {
            for colour in 0..2 {
                pass.set_bind_group(0, &self.groups[l].smooth[v][colour], &[]);
                pass.dispatch_workgroups(groups_of(m.div_ceil(2)), groups_of(m), 1);
            }
        }
    }

    /// Records `cycles` V-cycles on pressure buffer `variant` into an open compute pass.
    pub fn encode(&self, pass: &mut wgpu::ComputePass, variant: usize, cycles: u32) {
        let last = self.sizes.len() - 1;
        // The coarse weights follow this step's obstacles.
        pass.set_pipeline(&self.coarsen.pipeline);
        for l in 0..last {
            if let Some(g) = &self.groups[l].coarsen {
                let mc = self.sizes[l + 1];
                pass.set_bind_group(0, g, &[]);
                pass.dispatch_workgroups(groups_of(mc), groups_of(mc), self.layers);
            }
        }
        let var = |l: usize| if l == 0 { variant } else { 0 };
        for _ in 0..cycles {
            for l in 0..last {
                self.sweep(pass, l, var(l), PRE_SWEEPS);
                let mc = self.sizes[l + 1];
                pass.set_pipeline(&self.restrict.pipeline);
                pass.set_bind_group(0, &self.groups[l].restrict[var(l)], &[]);
                pass.dispatch_workgroups(groups_of(mc), groups_of(mc), self.layers);
            }
            self.sweep(pass, last, var(last), coarsest_sweeps(self.sizes[last]));
            for l in (0..last).rev() {
                let m = self.sizes[l];
                pass.set_pipeline(&self.prolong.pipeline);
                pass.set_bind_group(0, &self.groups[l].prolong[var(l)], &[]);
                pass.dispatch_workgroups(groups_of(m), groups_of(m), self.layers);
                self.sweep(pass, l, var(l), POST_SWEEPS);
            }
        }
    }
}
