//! Adapter and device selection: Vulkan only, since another backend (GL) would change the
//! rasterization rules the cross-check relies on, and a quiet fall-back would hide that.

use std::fmt;

/// How to get an adapter, for the error a machine without one gets.
pub const NO_ADAPTER_HELP: &str = "no Vulkan adapter found: install a Vulkan driver, for example \
Mesa's software rasterizer lavapipe (Debian and Ubuntu: `apt-get install mesa-vulkan-drivers libvulkan1`)";

/// An error of the GPU pipeline, with a message fit for the user.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuError(pub String);

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for GpuError {}

/// What a report records of the adapter a GPU run used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterRecord {
    pub name: String,
    pub driver: String,
    pub backend: String,
}

/// A Vulkan device and its queue, with the adapter's limits.
pub struct GpuDevice {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) limits: wgpu::Limits,
    info: wgpu::AdapterInfo,
}

impl GpuDevice {
    /// Runs `work` with the device's validation and out-of-memory errors returned as a
    /// `GpuError` (wgpu's default handler would panic on them).
    pub fn checked<T>(&self, work: impl FnOnce() -> Result<T, GpuError>) -> Result<T, GpuError> {
        let out_of_memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = work();
        let invalid = pollster::block_on(validation.pop());
        let exhausted = pollster::block_on(out_of_memory.pop());
        match invalid.or(exhausted) {
            Some(e) => Err(GpuError(format!("the device refused the work: {e}"))),
            None => result,
        }
    }

    /// The first Vulkan adapter (a hardware one preferred), with the adapter's own limits (the
    /// defaults would cap textures at 2048 texels).
    pub fn new() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = pollster::block_on(instance.request_adapter(&options))
            .map_err(|e| GpuError(format!("{NO_ADAPTER_HELP} ({e})")))?;
        let info = adapter.get_info();
        if info.backend != wgpu::Backend::Vulkan {
            return Err(GpuError(format!(
                "{NO_ADAPTER_HELP} (found a {:?} adapter, {})",
                info.backend, info.name
            )));
        }
        let limits = adapter.limits();
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("shadowtruth"),
            required_limits: limits.clone(),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
            .map_err(|e| GpuError(format!("the Vulkan adapter {} refused a device: {e}", info.name)))?;
        Ok(GpuDevice { device, queue, limits, info })
    }

    /// The adapter's name, driver and backend.
    pub fn adapter(&self) -> AdapterRecord {
        let driver = match (self.info.driver.is_empty(), self.info.driver_info.is_empty()) {
            (false, false) => format!("{} {}", self.info.driver, self.info.driver_info),
            (false, true) => self.info.driver.clone(),
            _ => self.info.driver_info.clone(),
        };
        AdapterRecord { name: self.info.name.clone(), driver, backend: "vulkan".into() }
    }

    /// The largest buffer the device takes, in bytes.
    pub fn max_buffer_size(&self) -> u64 {
        self.limits.max_buffer_size
    }

    /// The largest square texture side the device takes.
    pub fn max_texture_side(&self) -> u32 {
        self.limits.max_texture_dimension_2d
    }

    /// Waits until every submitted command has finished.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError(format!("the GPU did not finish: {e}")))
    }
}
