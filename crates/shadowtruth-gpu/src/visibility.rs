//! The camera view rendered with the shadow test in a fragment shader: every pixel reads its
//! surface point and normal from the reference G-buffer (so that it scores the same points as
//! the CPU) and the shadow map, and writes its visibility to an R32Float target.

use super::readback::read_f32_texture;
use super::{GpuDepthMap, GpuDevice, GpuError, GpuTechnique};
use bytemuck::{Pod, Zeroable};
use shadowtruth::raster::{LightView, Projection};
use shadowtruth::trace::GBuffer;
use wgpu::util::DeviceExt;

/// `Params` of `visibility.wgsl`, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    clip_from_world: [f32; 16],
    view_z_row: [f32; 4],
    to_light: [f32; 4],
    light_position: [f32; 4],
    width: u32,
    height: u32,
    resolution: u32,
    technique: u32,
    bias_depth: f32,
    bias_world: f32,
    scale_texels: f32,
    one_minus_n_dot_l: u32,
    kernel_size: u32,
    perspective: u32,
    ortho_texel_world: f32,
    tan_half_fov: f32,
    near: f32,
    far: f32,
    pad: [u32; 2],
}

impl Params {
    fn new(view: &LightView, gbuffer: &GBuffer, technique: GpuTechnique) -> Self {
        let m = view.light_from_world;
        let mut p = Params {
            clip_from_world: view.clip_from_world.to_cols_array(),
            view_z_row: [m.x_axis.z, m.y_axis.z, m.z_axis.z, m.w_axis.z],
            to_light: view.to_light.map_or([0.0; 4], |l| l.extend(1.0).to_array()),
            light_position: view.position.map_or([0.0; 4], |l| l.extend(1.0).to_array()),
            width: gbuffer.width,
            height: gbuffer.height,
            resolution: view.resolution,
            near: view.near,
            far: view.far,
            ..Params::zeroed()
        };
        match view.projection {
            Projection::Orthographic { .. } => p.ortho_texel_world = view.texel_world_size(glam::Vec3::ZERO),
            Projection::Perspective { tan_half_fov } => (p.perspective, p.tan_half_fov) = (1, tan_half_fov),
            Projection::Paraboloid => unreachable!("shade_visibility refuses paraboloids"),
        }
        match technique {
            GpuTechnique::Plain => p.technique = 0,
            GpuTechnique::ConstantDepth { bias_depth } => (p.technique, p.bias_depth) = (1, bias_depth),
            GpuTechnique::ConstantWorld { bias_world } => (p.technique, p.bias_world) = (2, bias_world),
            GpuTechnique::NormalOffset { scale_texels, one_minus_n_dot_l } => {
                (p.technique, p.scale_texels, p.one_minus_n_dot_l) =
                    (3, scale_texels, one_minus_n_dot_l as u32)
            }
            GpuTechnique::PcfBox { size, bias_depth } => {
                (p.technique, p.kernel_size, p.bias_depth) = (4, size, bias_depth)
            }
            GpuTechnique::PcfBilinear { bias_depth } => (p.technique, p.bias_depth) = (5, bias_depth),
        }
        p
    }
}

/// Visibility of every camera pixel, row by row from the top (1 lit, 0 shadowed; pixels the
/// G-buffer does not evaluate are 1), as `shadowtruth::shade_technique` returns it.
pub fn shade_visibility(
    gpu: &GpuDevice,
    gbuffer: &GBuffer,
    view: &LightView,
    map: &GpuDepthMap,
    technique: GpuTechnique,
) -> Result<Vec<f32>, GpuError> {
    let (width, height) = (gbuffer.width, gbuffer.height);
    let pixels = gbuffer.pixel_count();
    let bytes = pixels as u64 * 16;
    if width == 0 || height == 0 || width.max(height) > gpu.max_texture_side() {
        return Err(GpuError(format!("a {width}×{height} view does not fit the GPU's textures")));
    }
    if bytes > gpu.limits.max_storage_buffer_binding_size {
        return Err(GpuError(format!("a {width}×{height} view does not fit the GPU's storage buffers")));
    }
    if view.projection == Projection::Paraboloid {
        return Err(GpuError(crate::depth_map::PARABOLOID.into()));
    }
    if map.resolution != view.resolution {
        return Err(GpuError("the depth map is not of the light view's resolution".into()));
    }
    let (positions, normals) = pixel_buffers(gbuffer);
    let storage = |label, data: &[[f32; 4]]| {
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let (positions, normals) = (storage("positions", &positions), storage("normals", &normals));
    let uniform = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: bytemuck::bytes_of(&Params::new(view, gbuffer, technique)),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("visibility"),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let sampler = compare_sampler(gpu);
    let pipeline = shade_pipeline(gpu);
    let map_view = map.texture.create_view(&Default::default());
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("visibility"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: positions.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: normals.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&map_view) },
            wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&sampler) },
        ],
    });
    draw_fullscreen(gpu, &pipeline, &bind_group, &target.create_view(&Default::default()));
    read_f32_texture(gpu, &target, wgpu::TextureAspect::All, width, height)
}

/// Clamp to the edge and compare `reference ≤ texel` with bilinear weights: D3D10+ hardware PCF,
/// the CPU's `Kernel::Bilinear` (src/technique/kernel.rs).
fn compare_sampler(gpu: &GpuDevice) -> wgpu::Sampler {
    gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("compare"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    })
}

/// One full-screen triangle into `target_view` (cleared to 1, lit), submitted.
fn draw_fullscreen(
    gpu: &GpuDevice,
    pipeline: &wgpu::RenderPipeline,
    bind_group: &wgpu::BindGroup,
    target_view: &wgpu::TextureView,
) {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("visibility"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
}

/// Per camera pixel: (position, 1) where the pixel is evaluated, else zeros; and the normal.
fn pixel_buffers(gbuffer: &GBuffer) -> (Vec<[f32; 4]>, Vec<[f32; 4]>) {
    let mut positions = vec![[0.0f32; 4]; gbuffer.pixel_count()];
    let mut normals = vec![[0.0f32; 4]; gbuffer.pixel_count()];
    for &i in &gbuffer.evaluated {
        let i = i as usize;
        positions[i] = gbuffer.position[i].extend(1.0).to_array();
        normals[i] = gbuffer.normal[i].extend(0.0).to_array();
    }
    (positions, normals)
}

fn shade_pipeline(gpu: &GpuDevice) -> wgpu::RenderPipeline {
    let module = gpu.device.create_shader_module(wgpu::include_wgsl!("visibility.wgsl"));
    gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("visibility"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("shade"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: wgpu::TextureFormat::R32Float,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
