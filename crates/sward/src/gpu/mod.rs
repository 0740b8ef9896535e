//! GPU context: instance, adapter choice (auto, software, or by name), device and queue,
//! and the limit checks that run before any large allocation.

use std::str::FromStr;
use std::sync::{Arc, Mutex};

use crate::error::{Error, Result};

mod block_on;
pub mod queries;

pub use block_on::block_on;

/// Which adapter to use.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AdapterChoice {
    /// A hardware GPU if there is one, else a software (CPU) adapter.
    Auto,
    /// A CPU adapter (Mesa lavapipe / llvmpipe, WARP): the same pictures on any machine.
    Software,
    /// The first adapter whose name contains this text (case-insensitive).
    Name(String),
}

impl FromStr for AdapterChoice {
    type Err = std::convert::Infallible;
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "" | "auto" => AdapterChoice::Auto,
            "software" | "cpu" => AdapterChoice::Software,
            _ => AdapterChoice::Name(s.trim().to_string()),
        })
    }
}

/// The hint printed whenever no adapter can be found.
pub const INSTALL_HINT: &str = "install a Vulkan driver for your GPU, or Mesa's software \
Vulkan driver (on Debian/Ubuntu: apt-get install mesa-vulkan-drivers libvulkan1)";

/// An open device and what it can do. A clone shares the device, the queue and the error
/// slot (a renderer holding a clone reports into the same [`Gpu::check_errors`]).
#[derive(Clone)]
pub struct Gpu {
    /// The instance and adapter the device was opened on; `None` for a host's device
    /// ([`Gpu::from_host`]), which sward did not open.
    pub instance: Option<wgpu::Instance>,
    /// The adapter the device was opened on; `None` for a host's device.
    pub adapter: Option<wgpu::Adapter>,
    /// The open device.
    pub device: wgpu::Device,
    /// The device's queue, which every submission goes to.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend, device type and driver.
    pub info: wgpu::AdapterInfo,
    /// Whether timestamp queries were enabled (per-pass GPU times).
    pub timestamps: bool,
    /// Whether pipeline-statistics queries were enabled (per-pass work counters).
    pub pipeline_statistics: bool,
    /// The first error the device reported outside an error scope (wgpu's default handler
    /// would panic); `check_errors` turns it into an `Error`.
    errors: Arc<Mutex<Option<String>>>,
}

fn describe_info(info: &wgpu::AdapterInfo) -> String {
    format!(
        "{} ({:?}, {:?}, driver {} {})",
        info.name, info.device_type, info.backend, info.driver, info.driver_info
    )
}

impl Gpu {
    /// Opens the adapter `choice` names. The error lists the adapters that exist and says
    /// what to install when there are none.
    ///
    /// The native backends (Vulkan, Metal, DX12) are tried first and OpenGL only when none
    /// of their adapters matches: starting the GL backend loads EGL, which on a machine with
    /// Mesa's EGL but no DRI driver prints an error line on stderr although a Vulkan adapter
    /// is there. `WGPU_BACKEND` still narrows both.
    pub fn new(choice: &AdapterChoice) -> Result<Gpu> {
        let descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env;
        let native = descriptor().backends & !wgpu::Backends::GL;
        if !native.is_empty() {
            let mut d = descriptor();
            d.backends = native;
            let instance = wgpu::Instance::new(d);
            let adapters = block_on(instance.enumerate_adapters(native));
            if let Ok(adapter) = pick(adapters, choice) {
                return Self::from_adapter(instance, adapter);
            }
        }
        let instance = wgpu::Instance::new(descriptor());
        let adapters = block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let adapter = pick(adapters, choice)?;
        Self::from_adapter(instance, adapter)
    }

    /// Picks an adapter that can present to `surface` (the window), by `choice`, and opens
    /// a device on it.
    pub fn for_surface(
        instance: wgpu::Instance,
        surface: &wgpu::Surface<'_>,
        choice: &AdapterChoice,
    ) -> Result<Gpu> {
        let adapters = block_on(instance.enumerate_adapters(wgpu::Backends::all()))
            .into_iter()
            .filter(|a| a.is_surface_supported(surface))
            .collect();
        let adapter = pick(adapters, choice)?;
        Self::from_adapter(instance, adapter)
    }

    /// Opens a device on an adapter chosen elsewhere (the window picks one for its surface).
    pub fn from_adapter(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Gpu> {
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = wgpu::Features::empty();
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        // The work counters (`queries::WorkCounter`): each pass's shader invocations.
        let pipeline_statistics = adapter
            .features()
            .contains(wgpu::Features::PIPELINE_STATISTICS_QUERY);
        if pipeline_statistics {
            features |= wgpu::Features::PIPELINE_STATISTICS_QUERY;
        }
        // The panel's wireframe view draws the grass as lines where the adapter can.
        features |= adapter.features() & wgpu::Features::POLYGON_MODE_LINE;
        // With first-instance support the levels of detail draw in one multi-draw-indirect.
        features |= adapter.features() & wgpu::Features::INDIRECT_FIRST_INSTANCE;
        // MSAA beyond WebGPU's guaranteed 1× and 4× (2×, 8×) is adapter-specific.
        features |= adapter.features() & wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES;
        // Ask for everything the adapter offers: large fields need its full buffer sizes.
        let limits = adapter.limits();
        let (device, queue) = block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sward.device"),
            required_features: features,
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| Error::Gpu(format!("cannot open a device on {}: {e}", info.name)))?;
        let errors: Arc<Mutex<Option<String>>> = Arc::default();
        let slot = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            log::debug!("uncaptured wgpu error: {e}");
            let mut first = slot.lock().unwrap_or_else(|p| p.into_inner());
            first.get_or_insert_with(|| e.to_string());
        }));
        Ok(Gpu {
            instance: Some(instance),
            adapter: Some(adapter),
            device,
            queue,
            info,
            timestamps,
            pipeline_statistics,
            errors,
        })
    }

    /// A host's device and queue (`sward::embed`): sward records into them but leaves
    /// their error handling to the host (no uncaptured-error handler is installed, so
    /// [`Gpu::check_errors`] reports only what sward itself found) and times or counts
    /// nothing (the host's own profiler may wrap sward's calls).
    pub fn from_host(device: &wgpu::Device, queue: &wgpu::Queue) -> Gpu {
        Gpu {
            instance: None,
            adapter: None,
            info: device.adapter_info(),
            device: device.clone(),
            queue: queue.clone(),
            timestamps: false,
            pipeline_statistics: false,
            errors: Arc::default(),
        }
    }

    /// Fails with the first error the device reported outside an error scope (validation,
    /// out of memory, internal), if any. Call it after building the renderer, after each
    /// submitted frame and before writing outputs: an erroneous device never makes a
    /// picture or a dump, and never panics.
    pub fn check_errors(&self) -> Result<()> {
        let first = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        match first.as_ref() {
            None => Ok(()),
            Some(e) => Err(Error::Gpu(format!(
                "{} reported an error: {}",
                self.info.name,
                e.trim_end()
            ))),
        }
    }

    /// Records an error found outside the device's callbacks (a failed wait on a frame),
    /// so that the next [`Gpu::check_errors`] reports it; the first error is kept.
    pub fn report_error(&self, message: String) {
        let mut first = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        first.get_or_insert(message);
    }

    /// One line naming the adapter, for logs and reports.
    pub fn describe(&self) -> String {
        describe_info(&self.info)
    }

    /// Checks that a storage buffer of `bytes` for blades fits this device before it is
    /// allocated (the error says to use fewer blades).
    pub fn check_storage(&self, what: &str, bytes: u64) -> Result<()> {
        self.check_storage_or(
            what,
            bytes,
            "use fewer blades (lower field.density or a smaller terrain)",
        )
    }

    /// Checks that a storage buffer of `bytes` fits this device before it is allocated;
    /// `remedy` says what to change when it does not.
    pub fn check_storage_or(&self, what: &str, bytes: u64, remedy: &str) -> Result<()> {
        let limits = self.device.limits();
        let max = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if bytes > max {
            return Err(Error::Limits(format!(
                "{what} needs a {bytes}-byte storage buffer, but {} holds at most {max} bytes \
                 in one buffer; {remedy}",
                self.info.name
            )));
        }
        Ok(())
    }

    /// Checks that `count` workgroups fit one dispatch dimension.
    pub fn check_dispatch(&self, what: &str, workgroups: u32) -> Result<()> {
        let max = self.device.limits().max_compute_workgroups_per_dimension;
        if workgroups > max {
            return Err(Error::Limits(format!(
                "{what} needs {workgroups} workgroups in one dispatch, but {} allows {max}",
                self.info.name
            )));
        }
        Ok(())
    }

    /// Checks, before anything is allocated, that the frame's render targets at `size`
    /// with `samples` per pixel fit this device: each side within the largest texture, and
    /// the largest single target (the half-float scene colour at `samples` per pixel, 8
    /// bytes a sample) and the read-back within the largest buffer the device allocates
    /// (the size of one allocation it promises). `flag` names what set the size.
    pub fn check_frame_size(&self, flag: &str, size: (u32, u32), samples: u32) -> Result<()> {
        let (width, height) = size;
        self.check_texture(flag, width, height)?;
        let max = self.device.limits().max_buffer_size;
        let per_pixel = 8 * u64::from(samples.max(1));
        let bytes = u64::from(width) * u64::from(height) * per_pixel;
        if bytes > max {
            // The largest size of the same shape that fits.
            let scale = (max as f64 / bytes as f64).sqrt();
            let fit = |v: u32| ((f64::from(v) * scale).floor() as u32).max(1);
            return Err(Error::Limits(format!(
                "{flag} {width}x{height} needs a {bytes}-byte render target ({samples} \
                 sample(s) of 8 bytes a pixel), but {} allocates at most {max} bytes at once: \
                 the largest size of this shape it can hold is {}x{}{}",
                self.info.name,
                fit(width),
                fit(height),
                if samples > 1 {
                    " (or lower render.msaa)"
                } else {
                    ""
                }
            )));
        }
        Ok(())
    }

    /// Checks a 2D texture size against the device.
    pub fn check_texture(&self, what: &str, width: u32, height: u32) -> Result<()> {
        let max = self.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::Limits(format!(
                "{what} of {width}x{height} pixels is out of range: allowed 1..={max} per side on {}",
                self.info.name
            )));
        }
        Ok(())
    }
}

/// Downlevel capabilities sward needs, with what needs them (from the shaders and the
/// pipeline layouts in `src/render/` and `src/sim/`).
const NEEDED_DOWNLEVEL: &[(wgpu::DownlevelFlags, &str, &str)] = &[
    (
        wgpu::DownlevelFlags::COMPUTE_SHADERS,
        "COMPUTE_SHADERS",
        "compute shaders (blade update, culling, wind solver, depth pyramid)",
    ),
    (
        wgpu::DownlevelFlags::INDIRECT_EXECUTION,
        "INDIRECT_EXECUTION",
        "indirect dispatches and draws (the culled blades)",
    ),
    (
        wgpu::DownlevelFlags::VERTEX_STORAGE,
        "VERTEX_STORAGE",
        "storage buffers in vertex shaders (the grass reads the blades)",
    ),
    (
        wgpu::DownlevelFlags::FRAGMENT_STORAGE,
        "FRAGMENT_STORAGE",
        "storage buffers in fragment shaders (the wind overlay)",
    ),
    (
        wgpu::DownlevelFlags::NON_POWER_OF_TWO_MIPMAPPED_TEXTURES,
        "NON_POWER_OF_TWO_MIPMAPPED_TEXTURES",
        "mipmapped textures of any size (the depth pyramid)",
    ),
];

/// The limits sward needs: (name, the adapter's value, the least sward needs, what needs it).
fn needed_limits(l: &wgpu::Limits) -> [(&'static str, u64, u64, &'static str); 11] {
    [
        (
            "max_bind_groups",
            l.max_bind_groups.into(),
            2,
            "the blade cull",
        ),
        (
            "max_bindings_per_bind_group",
            l.max_bindings_per_bind_group.into(),
            8,
            "the blade update",
        ),
        (
            "max_storage_buffers_per_shader_stage",
            l.max_storage_buffers_per_shader_stage.into(),
            10,
            "the tile generation",
        ),
        (
            "max_storage_textures_per_shader_stage",
            l.max_storage_textures_per_shader_stage.into(),
            1,
            "the depth pyramid",
        ),
        (
            "max_uniform_buffers_per_shader_stage",
            l.max_uniform_buffers_per_shader_stage.into(),
            3,
            "the grass draw",
        ),
        (
            "max_compute_invocations_per_workgroup",
            l.max_compute_invocations_per_workgroup.into(),
            64,
            "workgroups of 64 and 8x8",
        ),
        (
            "max_compute_workgroup_size_x",
            l.max_compute_workgroup_size_x.into(),
            64,
            "workgroups of 64",
        ),
        (
            "max_compute_workgroup_size_y",
            l.max_compute_workgroup_size_y.into(),
            8,
            "workgroups of 8x8",
        ),
        (
            "max_compute_workgroups_per_dimension",
            l.max_compute_workgroups_per_dimension.into(),
            65_535,
            "the 2D blade dispatches",
        ),
        (
            "max_storage_buffer_binding_size",
            l.max_storage_buffer_binding_size,
            128 << 20,
            "the blade buffers",
        ),
        (
            "max_texture_dimension_2d",
            l.max_texture_dimension_2d.into(),
            2048,
            "render targets and the depth pyramid",
        ),
    ]
}

/// What an adapter lacks to run sward, one reason per item; empty when it can. Pure, so
/// that made-up adapters can be tested: `features` are those sward needs unconditionally
/// (none today: timestamps, wireframe and first-instance draws are optional).
pub fn unmet_needs(
    info: &wgpu::AdapterInfo,
    features: wgpu::Features,
    limits: &wgpu::Limits,
    downlevel: &wgpu::DownlevelCapabilities,
) -> Vec<String> {
    let mut unmet = Vec::new();
    match info.backend {
        wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12 => {}
        wgpu::Backend::Gl => unmet.push(
            "the OpenGL backend is not supported (its shaders cannot load from depth \
             textures, which the depth pyramid does; sward needs Vulkan, Metal or DX12)"
                .to_string(),
        ),
        other => unmet.push(format!(
            "the {other:?} backend is not supported (sward needs Vulkan, Metal or DX12)"
        )),
    }
    let required = wgpu::Features::empty();
    let missing = required - features;
    if !missing.is_empty() {
        unmet.push(format!("features {missing:?}"));
    }
    for (flag, name, why) in NEEDED_DOWNLEVEL {
        if !downlevel.flags.contains(*flag) {
            unmet.push(format!("{why} (downlevel flag {name})"));
        }
    }
    if downlevel.shader_model < wgpu::ShaderModel::Sm5 {
        unmet.push(format!(
            "shader model 5 (compute and storage buffers): it has {:?}",
            downlevel.shader_model
        ));
    }
    for (name, have, need, why) in needed_limits(limits) {
        if have < need {
            unmet.push(format!("{name} >= {need} for {why}: it has {have}"));
        }
    }
    unmet
}

/// Why `adapter` cannot run sward (empty: it can).
fn adapter_unmet(adapter: &wgpu::Adapter) -> Vec<String> {
    unmet_needs(
        &adapter.get_info(),
        adapter.features(),
        &adapter.limits(),
        &adapter.get_downlevel_capabilities(),
    )
}

fn pick(adapters: Vec<wgpu::Adapter>, choice: &AdapterChoice) -> Result<wgpu::Adapter> {
    if adapters.is_empty() {
        return Err(Error::NoAdapter(format!(
            "no GPU adapter found: {INSTALL_HINT}"
        )));
    }
    // Every adapter is vetted before any device is opened or anything is built on it.
    let vetted: Vec<(wgpu::Adapter, wgpu::AdapterInfo, Vec<String>)> = adapters
        .into_iter()
        .map(|a| {
            let unmet = adapter_unmet(&a);
            let info = a.get_info();
            (a, info, unmet)
        })
        .collect();
    let report = |list: &[(wgpu::Adapter, wgpu::AdapterInfo, Vec<String>)]| {
        list.iter()
            .map(|(_, info, unmet)| {
                if unmet.is_empty() {
                    describe_info(info)
                } else {
                    format!(
                        "{} cannot run sward: {}",
                        describe_info(info),
                        unmet.join(", ")
                    )
                }
            })
            .collect::<Vec<_>>()
            .join("; ")
    };
    let summary = report(&vetted);
    if let AdapterChoice::Name(n) = choice {
        // An adapter named explicitly is refused with what it lacks, not skipped.
        let needle = n.to_ascii_lowercase();
        let matches = |info: &wgpu::AdapterInfo| info.name.to_ascii_lowercase().contains(&needle);
        // The same device may come through several backends (Vulkan and GL): take one
        // that can serve, else refuse the first match with its reasons.
        let named = vetted
            .iter()
            .position(|(_, info, unmet)| matches(info) && unmet.is_empty())
            .or_else(|| vetted.iter().position(|(_, info, _)| matches(info)));
        return match named {
            Some(k) if vetted[k].2.is_empty() => {
                let mut vetted = vetted;
                Ok(vetted.swap_remove(k).0)
            }
            Some(k) => Err(Error::NoAdapter(format!(
                "adapter {} cannot run sward: {}; {INSTALL_HINT}",
                describe_info(&vetted[k].1),
                vetted[k].2.join(", ")
            ))),
            None => Err(Error::NoAdapter(format!(
                "no adapter whose name contains {n:?} among: {summary}; {INSTALL_HINT}"
            ))),
        };
    }
    let mut usable = vetted.into_iter().filter(|(_, _, unmet)| unmet.is_empty());
    let found = match choice {
        AdapterChoice::Auto => {
            // Prefer real hardware, then any CPU adapter.
            let rank = |info: &wgpu::AdapterInfo| match info.device_type {
                wgpu::DeviceType::DiscreteGpu => 0,
                wgpu::DeviceType::IntegratedGpu => 1,
                wgpu::DeviceType::VirtualGpu => 2,
                wgpu::DeviceType::Cpu => 3,
                wgpu::DeviceType::Other => 4,
            };
            usable.min_by_key(|(_, info, _)| rank(info))
        }
        AdapterChoice::Software => {
            usable.find(|(_, info, _)| info.device_type == wgpu::DeviceType::Cpu)
        }
        AdapterChoice::Name(_) => unreachable!("handled above"),
    };
    found.map(|(a, _, _)| a).ok_or_else(|| {
        let wanted = match choice {
            AdapterChoice::Software => "software (CPU) adapter",
            _ => "adapter",
        };
        Error::NoAdapter(format!(
            "no {wanted} that can run sward among: {summary}; {INSTALL_HINT}"
        ))
    })
}

/// Waits until the queue is idle (headless runs and read-backs).
pub fn wait_idle(device: &wgpu::Device) -> Result<()> {
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| Error::Gpu(format!("waiting for the GPU failed: {e}")))
}

/// Frames the CPU may record ahead of the GPU. wgpu queues every submission without
/// limit: a headless loop on a software adapter records a frame in a millisecond while
/// the adapter takes a hundred to run it, so without a bound every frame's command buffer
/// and upload staging wait in the queue.
pub const MAX_FRAMES_IN_FLIGHT: usize = 2;

/// Keeps at most [`MAX_FRAMES_IN_FLIGHT`] submitted frames unfinished: after each
/// submit, [`FramePacer::submitted`] waits for the frame that many submits back. Polling
/// there also lets wgpu free what finished frames held and run their map callbacks.
#[derive(Default)]
pub struct FramePacer {
    in_flight: std::collections::VecDeque<wgpu::SubmissionIndex>,
}

impl FramePacer {
    /// Records a frame's submission and waits for the oldest one beyond the bound. A
    /// failed wait (a lost device) is reported through [`Gpu::check_errors`], which every
    /// caller runs after a frame.
    pub fn submitted(&mut self, gpu: &Gpu, index: wgpu::SubmissionIndex) {
        self.in_flight.push_back(index);
        while self.in_flight.len() > MAX_FRAMES_IN_FLIGHT {
            let Some(oldest) = self.in_flight.pop_front() else {
                break;
            };
            let waited = gpu.device.poll(wgpu::PollType::Wait {
                submission_index: Some(oldest),
                timeout: None,
            });
            if let Err(e) = waited {
                gpu.report_error(format!("waiting for an earlier frame failed: {e}"));
                self.in_flight.clear();
            }
        }
    }
}

/// Runs a one-shot compute probe (the kernels that evaluate a shader function at given
/// points for its CPU twin's test): `pipeline` with `groups` bound from 0, one invocation
/// per point in workgroups of 64, then reads `output` (`size` bytes) back, blocking.
pub fn run_probe(
    gpu: &Gpu,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    groups: &[&wgpu::BindGroup],
    points: usize,
    (output, size): (&wgpu::Buffer, u64),
) -> Result<Vec<u8>> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        for (k, g) in groups.iter().enumerate() {
            pass.set_bind_group(k as u32, *g, &[]);
        }
        pass.dispatch_workgroups((points.max(1) as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let bytes = read_buffer(gpu, output, size)?;
    // A kernel that failed to build (a WGSL error) runs as nothing and reads back zeros:
    // the device's error, not the zeros, is the answer.
    gpu.check_errors()?;
    Ok(bytes)
}

/// Runs a probe kernel of the WGSL file `shader` (entry `probe`, 64 invocations per
/// workgroup, its layout taken from the shader): `inputs` become read storage buffers at
/// bindings 0, 1, …, the output one `vec4<f32>` per point at the next binding. Returns the
/// `points` outputs. For the tests that hold a WGSL function to its CPU twin.
pub fn run_vec4_probe(
    gpu: &Gpu,
    label: &str,
    shader: &str,
    inputs: &[&[u8]],
    points: usize,
) -> Result<Vec<[f32; 4]>> {
    use wgpu::util::DeviceExt;
    let device = &gpu.device;
    let count = points.max(1);
    let buffers: Vec<wgpu::Buffer> = inputs
        .iter()
        .map(|bytes| {
            // A binding may not be empty.
            let mut data = bytes.to_vec();
            data.resize(data.len().max(16), 0);
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &data,
                usage: wgpu::BufferUsages::STORAGE,
            })
        })
        .collect();
    let out_size = (count * 16) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let module = crate::shaders::module(device, shader);
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module: &module,
        entry_point: Some("probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .chain(std::iter::once(&output))
        .enumerate()
        .map(|(k, b)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let bytes = run_probe(gpu, label, &pipeline, &[&group], count, (&output, out_size))?;
    Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)[..points].to_vec())
}

/// Copies a buffer back to the host (blocking). `buffer` needs COPY_SRC usage.
pub fn read_buffer(gpu: &Gpu, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward.readback"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("sward.readback"),
        });
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    gpu.queue.submit([encoder.finish()]);
    map_and_read(gpu, &staging)
}

/// Maps a MAP_READ buffer and copies out its bytes.
pub fn map_and_read(gpu: &Gpu, staging: &wgpu::Buffer) -> Result<Vec<u8>> {
    let slice = staging.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    wait_idle(&gpu.device)?;
    rx.recv()
        .map_err(|e| Error::Gpu(format!("read-back was dropped: {e}")))?
        .map_err(|e| Error::Gpu(format!("read-back failed: {e}")))?;
    let data = slice
        .get_mapped_range()
        .map_err(|e| Error::Gpu(format!("read-back mapping failed: {e}")))?
        .to_vec();
    staging.unmap();
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lavapipe_like() -> (wgpu::AdapterInfo, wgpu::Limits, wgpu::DownlevelCapabilities) {
        let mut info = wgpu::AdapterInfo::new(wgpu::DeviceType::Cpu, wgpu::Backend::Vulkan);
        info.name = "llvmpipe (LLVM 19.1.7, 256 bits)".into();
        (
            info,
            // WebGPU's defaults but for the storage buffers per stage, of which lavapipe and
            // every desktop Vulkan, Metal and DX12 driver offer 16 or more (WebGPU's
            // default of 8 is below the tile generation's 10).
            wgpu::Limits {
                max_storage_buffers_per_shader_stage: 16,
                ..wgpu::Limits::default()
            },
            wgpu::DownlevelCapabilities::default(),
        )
    }

    #[test]
    fn a_complete_vulkan_adapter_meets_every_need() {
        let (info, limits, downlevel) = lavapipe_like();
        let unmet = unmet_needs(&info, wgpu::Features::empty(), &limits, &downlevel);
        assert!(unmet.is_empty(), "{unmet:?}");
        for backend in [wgpu::Backend::Metal, wgpu::Backend::Dx12] {
            let info = wgpu::AdapterInfo::new(wgpu::DeviceType::DiscreteGpu, backend);
            assert!(unmet_needs(&info, wgpu::Features::empty(), &limits, &downlevel).is_empty());
        }
    }

    #[test]
    fn gl_is_refused_with_its_reason() {
        let (_, limits, downlevel) = lavapipe_like();
        let info = wgpu::AdapterInfo::new(wgpu::DeviceType::Cpu, wgpu::Backend::Gl);
        let unmet = unmet_needs(&info, wgpu::Features::empty(), &limits, &downlevel);
        assert_eq!(unmet.len(), 1, "{unmet:?}");
        assert!(
            unmet[0].contains("OpenGL backend is not supported"),
            "{unmet:?}"
        );
        assert!(unmet[0].contains("depth"), "{unmet:?}");
        let noop = wgpu::AdapterInfo::new(wgpu::DeviceType::Other, wgpu::Backend::Noop);
        let unmet = unmet_needs(&noop, wgpu::Features::empty(), &limits, &downlevel);
        assert!(
            unmet[0].contains("Noop backend is not supported"),
            "{unmet:?}"
        );
    }

    #[test]
    fn a_webgl2_class_adapter_lacks_compute_indirect_and_storage() {
        let info = wgpu::AdapterInfo::new(wgpu::DeviceType::IntegratedGpu, wgpu::Backend::Gl);
        let downlevel = wgpu::DownlevelCapabilities {
            flags: wgpu::DownlevelFlags::empty(),
            shader_model: wgpu::ShaderModel::Sm4,
            ..Default::default()
        };
        let limits = wgpu::Limits::downlevel_webgl2_defaults();
        let unmet = unmet_needs(&info, wgpu::Features::empty(), &limits, &downlevel);
        let text = unmet.join("\n");
        for want in [
            "OpenGL",
            "COMPUTE_SHADERS",
            "INDIRECT_EXECUTION",
            "VERTEX_STORAGE",
            "FRAGMENT_STORAGE",
            "NON_POWER_OF_TWO_MIPMAPPED_TEXTURES",
            "shader model 5",
            "max_storage_buffers_per_shader_stage >= 10 for the tile generation: it has 0",
            "max_compute_invocations_per_workgroup >= 64",
            "max_storage_textures_per_shader_stage",
        ] {
            assert!(text.contains(want), "{want} missing from:\n{text}");
        }
    }

    #[test]
    fn each_limit_below_need_is_named() {
        let (info, limits, downlevel) = lavapipe_like();
        let mut l = limits.clone();
        l.max_storage_buffers_per_shader_stage = 7;
        l.max_compute_workgroup_size_x = 32;
        l.max_bind_groups = 1;
        let unmet = unmet_needs(&info, wgpu::Features::empty(), &l, &downlevel);
        assert_eq!(unmet.len(), 3, "{unmet:?}");
        assert!(unmet[0].starts_with("max_bind_groups >= 2"), "{unmet:?}");
        assert!(unmet
            .iter()
            .any(|u| u
                == "max_storage_buffers_per_shader_stage >= 10 for the tile generation: it has 7"));
        assert!(unmet
            .iter()
            .any(|u| u.starts_with("max_compute_workgroup_size_x >= 64")));
        // What every desktop Vulkan, Metal and DX12 adapter offers is enough.
        assert!(needed_limits(&limits)
            .iter()
            .all(|(_, have, need, _)| have >= need));
    }
}
