//! GPU context: instance, adapter choice (auto, software, or by name), device and queue,
//! and the limit checks that run before any large allocation.

use std::str::FromStr;

use crate::error::{Error, Result};

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

/// An open device and what it can do.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// Whether timestamp queries were enabled (per-pass GPU times).
    pub timestamps: bool,
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
    pub fn new(choice: &AdapterChoice) -> Result<Gpu> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
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
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
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
        // The panel's wireframe view draws the grass as lines where the adapter can.
        features |= adapter.features() & wgpu::Features::POLYGON_MODE_LINE;
        // With first-instance support the levels of detail draw in one multi-draw-indirect.
        features |= adapter.features() & wgpu::Features::INDIRECT_FIRST_INSTANCE;
        // Ask for everything the adapter offers: large fields need its full buffer sizes.
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sward.device"),
            required_features: features,
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| Error::Gpu(format!("cannot open a device on {}: {e}", info.name)))?;
        Ok(Gpu {
            instance,
            adapter,
            device,
            queue,
            info,
            timestamps,
        })
    }

    /// One line naming the adapter, for logs and reports.
    pub fn describe(&self) -> String {
        describe_info(&self.info)
    }

    /// Checks that a storage buffer of `bytes` fits this device before it is allocated.
    pub fn check_storage(&self, what: &str, bytes: u64) -> Result<()> {
        let limits = self.device.limits();
        let max = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if bytes > max {
            return Err(Error::Limits(format!(
                "{what} needs a {bytes}-byte storage buffer, but {} holds at most {max} bytes \
                 in one buffer; use fewer blades (lower field.density or a smaller terrain)",
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

fn pick(adapters: Vec<wgpu::Adapter>, choice: &AdapterChoice) -> Result<wgpu::Adapter> {
    if adapters.is_empty() {
        return Err(Error::NoAdapter(format!(
            "no GPU adapter found: {INSTALL_HINT}"
        )));
    }
    let names: Vec<String> = adapters
        .iter()
        .map(|a| describe_info(&a.get_info()))
        .collect();
    let is_cpu = |a: &wgpu::Adapter| a.get_info().device_type == wgpu::DeviceType::Cpu;
    let found = match choice {
        AdapterChoice::Auto => {
            // Prefer real hardware, then any CPU adapter; skip GL when Vulkan/Metal/DX12 exist
            // because compute and indirect draws are weaker there.
            let rank = |a: &wgpu::Adapter| {
                let info = a.get_info();
                let device = match info.device_type {
                    wgpu::DeviceType::DiscreteGpu => 0,
                    wgpu::DeviceType::IntegratedGpu => 1,
                    wgpu::DeviceType::VirtualGpu => 2,
                    wgpu::DeviceType::Cpu => 3,
                    wgpu::DeviceType::Other => 4,
                };
                let backend = if info.backend == wgpu::Backend::Gl {
                    1
                } else {
                    0
                };
                (backend, device)
            };
            adapters.into_iter().min_by_key(rank)
        }
        AdapterChoice::Software => adapters.into_iter().find(is_cpu),
        AdapterChoice::Name(n) => {
            let needle = n.to_ascii_lowercase();
            adapters
                .into_iter()
                .find(|a| a.get_info().name.to_ascii_lowercase().contains(&needle))
        }
    };
    found.ok_or_else(|| {
        let wanted = match choice {
            AdapterChoice::Auto => "usable adapter".to_string(),
            AdapterChoice::Software => "software (CPU) adapter".to_string(),
            AdapterChoice::Name(n) => format!("adapter whose name contains {n:?}"),
        };
        Error::NoAdapter(format!(
            "no {wanted} among: {}; {INSTALL_HINT}",
            names.join("; ")
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
