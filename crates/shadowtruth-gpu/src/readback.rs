//! Reading a 32-bit-per-texel texture back: rows are copied padded to
//! `COPY_BYTES_PER_ROW_ALIGNMENT` (256 bytes) and unpadded here.

use super::{GpuDevice, GpuError};

/// The `width`×`height` f32 texels of `texture` (one 4-byte aspect: Depth32Float's depth or
/// R32Float), row 0 first.
pub fn read_f32_texture(
    gpu: &GpuDevice,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    width: u32,
    height: u32,
) -> Result<Vec<f32>, GpuError> {
    let row_bytes = width as u64 * 4;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
    let padded = row_bytes.div_ceil(align) * align;
    if padded * height as u64 > gpu.limits.max_buffer_size {
        return Err(GpuError(format!(
            "a {width}×{height} readback needs {} bytes, more than the adapter's buffer limit of {}",
            padded * height as u64,
            gpu.limits.max_buffer_size
        )));
    }
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded as u32),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    gpu.queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    gpu.wait()?;
    rx.recv()
        .map_err(|_| GpuError("the GPU read-back was dropped".into()))?
        .map_err(|e| GpuError(format!("the GPU read-back failed: {e}")))?;
    let data = slice.get_mapped_range().map_err(|e| GpuError(format!("the GPU read-back failed: {e}")))?;
    let mut out = Vec::with_capacity(width as usize * height as usize);
    for row in data.chunks_exact(padded as usize) {
        out.extend_from_slice(bytemuck::cast_slice::<u8, f32>(&row[..row_bytes as usize]));
    }
    drop(data);
    buffer.unmap();
    Ok(out)
}
