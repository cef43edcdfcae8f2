//! The GPU pipeline: the shadow map rendered by a Vulkan device's own rasterizer and the shadow
//! test run in a fragment shader over the reference G-buffer's surface points, so that its output
//! is scored exactly like the CPU techniques'. `tests/gpu_pipeline.rs` cross-checks both halves
//! against the CPU (docs/conventions.md, "GPU pipeline").
//!
//! - `device.rs`: the adapter (Vulkan only) and device, with a clear error when there is none;
//! - `casters.rs`: the scene's triangles streamed to the device in chunks of bounded size;
//! - `depth_map.rs`: the depth map (Depth32Float, the light's `clip_from_world`, per-object
//!   culling, hardware depth bias), read back to a `DepthLayer` or uploaded from one;
//! - `technique.rs`: the techniques the shader implements and their parameters;
//! - `visibility.rs`: the camera-view pass writing visibility to an R32Float target;
//! - `readback.rs`: texture-to-buffer copies with padded rows.

mod casters;
mod depth_map;
mod device;
mod readback;
mod technique;
mod visibility;

pub use depth_map::GpuDepthMap;
pub use device::{AdapterRecord, GpuDevice, GpuError, NO_ADAPTER_HELP};
pub use technique::GpuTechnique;
pub use visibility::shade_visibility;
