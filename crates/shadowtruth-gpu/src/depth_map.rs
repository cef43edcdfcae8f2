//! The shadow map rendered by the device's rasterizer: Depth32Float, the light view's
//! `clip_from_world`, closed objects culled as `RasterSettings.culling` says (open ones never),
//! glPolygonOffset as the hardware depth bias (`DepthBiasState`).

use super::casters::{InstanceRun, check_mesh_fits, chunk_items, for_each_flat_chunk, instance_runs};
use super::readback::read_f32_texture;
use super::{GpuDevice, GpuError};
use shadowtruth::raster::{Culling, DepthFormat, DepthLayer, LightView, RasterSettings};
use shadowtruth::scene::Scene;
use wgpu::util::DeviceExt;

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Why a dual-paraboloid map is not drawn or shaded here: the shaders apply one matrix.
pub(crate) const PARABOLOID: &str =
    "a dual-paraboloid map is not a projective map: the GPU pipeline draws and shades projective maps only";

/// A shadow map on the device: an N×N Depth32Float texture, row 0 at the top of the map (largest
/// v), as `DepthLayer`.
pub struct GpuDepthMap {
    pub(crate) texture: wgpu::Texture,
    pub resolution: u32,
}

impl GpuDepthMap {
    /// Rasterizes every triangle of `scene` into the light's N×N map.
    pub fn render(
        gpu: &GpuDevice,
        scene: &Scene,
        view: &LightView,
        settings: &RasterSettings,
    ) -> Result<Self, GpuError> {
        Self::render_in_chunks(gpu, scene, view, settings, chunk_items(gpu.limits.max_buffer_size))
    }

    /// [`GpuDepthMap::render`], handing the device at most `chunk` flat triangles, `chunk`
    /// placements and `chunk` triangles of a placed mesh per draw (the same map for any chunk
    /// size).
    pub fn render_in_chunks(
        gpu: &GpuDevice,
        scene: &Scene,
        view: &LightView,
        settings: &RasterSettings,
        chunk: usize,
    ) -> Result<Self, GpuError> {
        if view.projection == shadowtruth::raster::Projection::Paraboloid {
            return Err(GpuError(PARABOLOID.into()));
        }
        let bias = depth_bias(settings)?;
        let map = GpuDepthMap::empty(gpu, view.resolution)?;
        let module = gpu.device.create_shader_module(wgpu::include_wgsl!("depth.wgsl"));
        let closed_cull = match settings.culling {
            Culling::None => None,
            Culling::BackFacesOfClosed => Some(wgpu::Face::Back),
            Culling::FrontFacesOfClosed => Some(wgpu::Face::Front),
        };
        // One explicit layout: the bind group must fit both pipelines (automatic layouts of two
        // pipelines are never compatible).
        let bind_layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("light"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("casters"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        let pipelines = [closed_cull, None].map(|cull| Casters {
            flat: caster_pipeline(gpu, &module, &layout, cull, bias, false),
            instanced: caster_pipeline(gpu, &module, &layout, cull, bias, true),
        });
        let uniform = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light"),
            contents: bytemuck::cast_slice(&view.clip_from_world.to_cols_array()),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("light"),
            layout: &bind_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() }],
        });
        let attachment = map.texture.create_view(&Default::default());
        // Cleared first, then each draw on top: a depth-only pass keeps the nearest fragment
        // whatever the order of draws.
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        drop(encoder.begin_render_pass(&depth_pass(&attachment, wgpu::LoadOp::Clear(1.0))));
        gpu.queue.submit([encoder.finish()]);
        let target = Target { gpu, attachment: &attachment, bind_group: &bind_group };
        let chunk = chunk.max(1);
        for (casters, closed) in pipelines.iter().zip([true, false]) {
            for_each_flat_chunk(scene, closed, chunk, |vertices| {
                let buffer =
                    target.buffer("casters", bytemuck::cast_slice(vertices), wgpu::BufferUsages::VERTEX);
                target.draw(&casters.flat, |pass| {
                    pass.set_vertex_buffer(0, buffer.slice(..));
                    pass.draw(0..vertices.len() as u32, 0..1);
                })
            })?;
            for run in instance_runs(scene, closed) {
                target.draw_instances(&casters.instanced, &run, chunk)?;
            }
        }
        Ok(map)
    }

    /// A depth map holding `layer`'s depths exactly (for shading a layer the CPU rasterized).
    pub fn upload(gpu: &GpuDevice, layer: &DepthLayer) -> Result<Self, GpuError> {
        let n = layer.resolution;
        let map = GpuDepthMap::empty(gpu, n)?;
        // Depth textures cannot be copied into: the layer goes to an R32Float texture and a
        // full-screen pass writes it out as fragment depth.
        let source = gpu.device.create_texture_with_data(
            &gpu.queue,
            &wgpu::TextureDescriptor {
                label: Some("layer"),
                size: wgpu::Extent3d { width: n, height: n, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&layer.depth),
        );
        let module = gpu.device.create_shader_module(wgpu::include_wgsl!("depth.wgsl"));
        let pipeline = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("upload"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth_state(wgpu::CompareFunction::Always, wgpu::DepthBiasState::default())),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("upload"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
        let source_view = source.create_view(&Default::default());
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("upload"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&source_view),
            }],
        });
        let attachment = map.texture.create_view(&Default::default());
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&depth_pass(&attachment, wgpu::LoadOp::Clear(1.0)));
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.queue.submit([encoder.finish()]);
        Ok(map)
    }

    /// The map's depths, as the CPU rasterizer stores an f32 layer.
    pub fn read_back(&self, gpu: &GpuDevice) -> Result<DepthLayer, GpuError> {
        let n = self.resolution;
        let depth = read_f32_texture(gpu, &self.texture, wgpu::TextureAspect::DepthOnly, n, n)?;
        Ok(DepthLayer { resolution: n, depth })
    }

    fn empty(gpu: &GpuDevice, resolution: u32) -> Result<Self, GpuError> {
        if resolution == 0 || resolution > gpu.max_texture_side() {
            return Err(GpuError(format!(
                "a {resolution}² shadow map does not fit the GPU (its textures go up to {}²)",
                gpu.max_texture_side()
            )));
        }
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d { width: resolution, height: resolution, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        Ok(GpuDepthMap { texture, resolution })
    }
}

/// The caster pipelines of one culling: flat triangles' and placed meshes'.
struct Casters {
    flat: wgpu::RenderPipeline,
    instanced: wgpu::RenderPipeline,
}

/// The map being drawn into, with the light's bind group.
struct Target<'a> {
    gpu: &'a GpuDevice,
    attachment: &'a wgpu::TextureView,
    bind_group: &'a wgpu::BindGroup,
}

impl Target<'_> {
    fn buffer(&self, label: &str, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    }

    /// One render pass with `pipeline` and the light bound, recorded by `record`, submitted and
    /// waited for: each draw's buffers are freed once drawn, so memory stays at one chunk.
    fn draw(
        &self,
        pipeline: &wgpu::RenderPipeline,
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<(), GpuError> {
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&depth_pass(self.attachment, wgpu::LoadOp::Load));
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, self.bind_group, &[]);
            record(&mut pass);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()
    }

    /// A run of placements of one mesh: its vertices once, then instanced draws of at most
    /// `chunk` placements and `chunk` of its triangles each.
    fn draw_instances(
        &self,
        pipeline: &wgpu::RenderPipeline,
        run: &InstanceRun,
        chunk: usize,
    ) -> Result<(), GpuError> {
        check_mesh_fits(run.mesh, self.gpu.limits.max_buffer_size)?;
        let positions =
            self.buffer("mesh", bytemuck::cast_slice(&run.positions()), wgpu::BufferUsages::VERTEX);
        let indices = run.indices();
        for corners in indices.chunks(3 * chunk) {
            let index_buffer =
                self.buffer("mesh indices", bytemuck::cast_slice(corners), wgpu::BufferUsages::INDEX);
            for placements in run.placements.chunks(chunk) {
                let placement_buffer =
                    self.buffer("placements", bytemuck::cast_slice(placements), wgpu::BufferUsages::VERTEX);
                self.draw(pipeline, |pass| {
                    pass.set_vertex_buffer(0, positions.slice(..));
                    pass.set_vertex_buffer(1, placement_buffer.slice(..));
                    pass.set_index_buffer(index_buffer.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..corners.len() as u32, 0, 0..placements.len() as u32);
                })?;
            }
        }
        Ok(())
    }
}

/// glPolygonOffset(factor, units) as the device's depth bias: the same `factor·m + units·r`
/// (Vulkan "Depth Bias"; r of a float buffer is 2^(e − 23) from the primitive's largest depth,
/// as `DepthFormat::F32`), with `units` a whole number since the device takes an integer.
fn depth_bias(settings: &RasterSettings) -> Result<wgpu::DepthBiasState, GpuError> {
    if settings.format != DepthFormat::F32 {
        return Err(GpuError(format!(
            "the GPU pipeline renders f32 depth maps only, not {}",
            settings.format.name()
        )));
    }
    let units = settings.slope_units;
    if units.fract() != 0.0 || units.abs() > i32::MAX as f32 {
        return Err(GpuError(format!("the GPU's depth bias takes whole units, not {units}")));
    }
    Ok(wgpu::DepthBiasState { constant: units as i32, slope_scale: settings.slope_factor, clamp: 0.0 })
}

fn depth_state(compare: wgpu::CompareFunction, bias: wgpu::DepthBiasState) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias,
    }
}

fn depth_pass<'a>(
    attachment: &'a wgpu::TextureView,
    load: wgpu::LoadOp<f32>,
) -> wgpu::RenderPassDescriptor<'a> {
    wgpu::RenderPassDescriptor {
        label: Some("shadow map"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: attachment,
            depth_ops: Some(wgpu::Operations { load, store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    }
}

/// The caster pipeline: counter-clockwise in (u, v) is a front face, as the CPU rasterizer's
/// facing (docs/conventions.md, "Rasterizer"); the nearest fragment wins. `instanced`: a placed
/// mesh's vertices (buffer 0) and one placement per instance (buffer 1).
fn caster_pipeline(
    gpu: &GpuDevice,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    cull_mode: Option<wgpu::Face>,
    bias: wgpu::DepthBiasState,
    instanced: bool,
) -> wgpu::RenderPipeline {
    let vertices = wgpu::VertexBufferLayout {
        array_stride: 12,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3],
    };
    let placements = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<super::casters::Placement>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &wgpu::vertex_attr_array![1 => Float32x4, 2 => Float32x4, 3 => Float32x4],
    };
    let (entry_point, buffers) = if instanced {
        ("caster_instanced", vec![Some(vertices), Some(placements)])
    } else {
        ("caster", vec![Some(vertices)])
    };
    gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("casters"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry_point),
            compilation_options: Default::default(),
            buffers: &buffers,
        },
        primitive: wgpu::PrimitiveState { front_face: wgpu::FrontFace::Ccw, cull_mode, ..Default::default() },
        depth_stencil: Some(depth_state(wgpu::CompareFunction::Less, bias)),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}
