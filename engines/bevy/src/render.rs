//! The Bevy app: one camera rendering the shadow-only pass into an offscreen image, the view's
//! light with Bevy's shadow map, a fixed number of frames, and a read-back of the last.

use crate::material::{self, ShadowOnly};
use crate::options::{Filter, Fit, Settings};
use crate::view::{Light, View};
use crate::{cascade, scene};
use bevy::app::{AppExit, ScheduleRunnerPlugin};
use bevy::asset::RenderAssetUsages;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::pbr::{
    CascadeShadowConfigBuilder, Cascades, DirectionalLightShadowMap, MaterialPlugin, ShadowFilteringMethod,
    SimulationLightSystems,
};
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::camera::RenderTarget;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat, TextureUsages};
use bevy::render::settings::{Backends, RenderCreation, WgpuSettings};
use bevy::render::view::NoFrustumCulling;
use bevy_window::{ExitCondition, WindowPlugin};
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Frames rendered before the read-back: the first frames upload meshes and compile pipelines
/// (synchronously, see `RenderPlugin`); a fixed count keeps the result, `Temporal`'s per-frame
/// noise included, the same from run to run.
const WARMUP_FRAMES: u32 = 4;
/// Frames after which a read-back that has not arrived is an error.
const MAX_FRAMES: u32 = 64;
/// The read-back target: f32 RGBA, so the HDR intermediate's f16 values arrive unrounded.
const TARGET_FORMAT: TextureFormat = TextureFormat::Rgba32Float;

/// The raw pixels read back: RGBA f32 rows, each padded to wgpu's copy alignment.
pub struct Pixels {
    pub bytes: Vec<u8>,
    pub width: u32,
    pub height: u32,
    /// A directional light's map texel, world units (None for a spot light).
    pub texel_size_world: Option<f32>,
}

/// What the app hands back: the read-back bytes, and how many cascades `--fit export` wrote.
#[derive(Resource, Clone, Default)]
struct Capture {
    bytes: Arc<Mutex<Option<Vec<u8>>>>,
    fitted_cascades: Arc<AtomicUsize>,
    /// The directional map's texel size in world units, as Bevy samples it (f32 bits).
    texel_size_bits: Arc<AtomicU32>,
}

#[derive(Resource)]
struct Job {
    view: ViewParts,
    settings: Settings,
    objects: Mutex<Vec<scene::Object>>,
    target: Handle<Image>,
}

/// The parts of the view the systems need (`View` itself holds strings and options).
struct ViewParts {
    camera: crate::view::Camera,
    light: Light,
}

pub fn render(view: View, objects: Vec<scene::Object>, settings: Settings) -> Result<Pixels, String> {
    let (width, height) = (view.camera.width, view.camera.height);
    let directional = matches!(view.light, Light::Directional { .. });
    let capture = Capture::default();
    let mut app = App::new();
    app.add_plugins(default_plugins())
        .add_plugins(MaterialPlugin::<ShadowOnly>::default())
        .insert_resource(DirectionalLightShadowMap { size: settings.map_size_texels as usize })
        .insert_resource(capture.clone());
    material::add_shader(&mut app);
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(target_image(width, height));
    let view = ViewParts { camera: view.camera, light: view.light };
    app.insert_resource(Job { view, settings, objects: Mutex::new(objects), target });
    add_systems(&mut app, settings.fit);
    match app.run() {
        AppExit::Success => {}
        AppExit::Error(code) => return Err(format!("the Bevy app exited with code {code}")),
    }
    if settings.fit == Fit::Export && directional && capture.fitted_cascades.load(Ordering::Relaxed) == 0 {
        return Err(
            "--fit export: Bevy's cascade could not be replaced (bevy_pbr's Cascade layout changed?)".into(),
        );
    }
    let bytes = capture.bytes.lock().map_err(|_| "the read-back lock is poisoned")?.take();
    let bytes = bytes.ok_or(format!("no read-back after {MAX_FRAMES} frames"))?;
    let bits = capture.texel_size_bits.load(Ordering::Relaxed);
    let texel_size_world = (bits != 0).then(|| f32::from_bits(bits));
    Ok(Pixels { bytes, width, height, texel_size_world })
}

/// The scene's set-up, the read-back, and the cascade systems, which run between Bevy's fitting
/// of the cascades and its culling for them (bevy_pbr lib.rs orders those two sets).
fn add_systems(app: &mut App, fit: Fit) {
    app.add_systems(Startup, (spawn_camera, spawn_light, spawn_objects))
        .add_systems(Update, request_readback)
        .add_systems(
            PostUpdate,
            record_texel_size
                .after(SimulationLightSystems::UpdateDirectionalLightCascades)
                .before(SimulationLightSystems::UpdateLightFrusta),
        );
    if fit == Fit::Export {
        app.add_systems(
            PostUpdate,
            fit_cascades_to_export
                .after(SimulationLightSystems::UpdateDirectionalLightCascades)
                .before(SimulationLightSystems::UpdateLightFrusta)
                .before(record_texel_size),
        );
    }
}

/// Bevy's plugins without a window (no `bevy_window` feature: `ScheduleRunnerPlugin` loops),
/// on Vulkan (lavapipe where there is no GPU), with pipelines compiled in the frame that needs
/// them and rendering on the main thread so that the frame count is exact.
fn default_plugins() -> impl PluginGroup {
    let wgpu = WgpuSettings { backends: Some(Backends::VULKAN), ..default() };
    DefaultPlugins
        .set(RenderPlugin {
            render_creation: RenderCreation::Automatic(wgpu),
            synchronous_pipeline_compilation: true,
            ..default()
        })
        .set(ScheduleRunnerPlugin::run_loop(std::time::Duration::ZERO))
        .disable::<PipelinedRenderingPlugin>()
        .add(WindowPlugin {
            primary_window: None,
            exit_condition: ExitCondition::DontExit,
            close_when_requested: false,
        })
}

fn target_image(width: u32, height: u32) -> Image {
    let size = Extent3d { width, height, depth_or_array_layers: 1 };
    let mut image =
        Image::new_fill(size, TextureDimension::D2, &[0; 16], TARGET_FORMAT, RenderAssetUsages::default());
    image.texture_descriptor.usage |=
        TextureUsages::RENDER_ATTACHMENT | TextureUsages::COPY_SRC | TextureUsages::TEXTURE_BINDING;
    image
}

fn vec3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

fn spawn_camera(mut commands: Commands, job: Res<Job>) {
    let c = &job.view.camera;
    let filter = match job.settings.filter {
        Filter::Hardware2x2 => ShadowFilteringMethod::Hardware2x2,
        Filter::Gaussian => ShadowFilteringMethod::Gaussian,
        Filter::Temporal => ShadowFilteringMethod::Temporal,
    };
    commands.spawn((
        Camera3d::default(),
        Camera {
            target: RenderTarget::Image(job.target.clone().into()),
            // The HDR intermediate is Rgba16Float; without it Rgba8UnormSrgb.
            hdr: true,
            clear_color: ClearColorConfig::Custom(Color::NONE),
            ..default()
        },
        Projection::Perspective(PerspectiveProjection {
            fov: c.fov_y_rad,
            aspect_ratio: c.width as f32 / c.height as f32,
            near: c.near,
            far: c.far,
        }),
        Transform::from_translation(vec3(c.position)).looking_at(vec3(c.look_at), vec3(c.up)),
        // Raw values: no tone curve, no dither, no multisample blending of edge pixels.
        Tonemapping::None,
        DebandDither::Disabled,
        Msaa::Off,
        filter,
    ));
}

fn spawn_light(mut commands: Commands, job: Res<Job>) {
    let s = &job.settings;
    let up = vec3(job.view.light.shadow_map().eye_up());
    match &job.view.light {
        Light::Directional { direction, .. } => {
            let c = &job.view.camera;
            // One cascade over the camera's whole depth range: Bevy fits it to that frustum
            // slice (bevy_pbr light/mod.rs, calculate_cascade).
            let cascades = CascadeShadowConfigBuilder {
                num_cascades: 1,
                minimum_distance: c.near,
                maximum_distance: c.far,
                ..default()
            };
            commands.spawn((
                DirectionalLight {
                    shadows_enabled: true,
                    shadow_depth_bias: s.depth_bias,
                    shadow_normal_bias: s.normal_bias,
                    ..default()
                },
                // The map's x and y axes follow the light's rotation: the export's up keeps
                // them parallel to the export's.
                Transform::default().looking_to(vec3(*direction), up),
                cascades.build(),
            ));
        }
        Light::Spot { position, direction, cone_deg, near, far, .. } => {
            let outer_angle = (cone_deg / 2.0).to_radians();
            commands.spawn((
                SpotLight {
                    shadows_enabled: true,
                    shadow_depth_bias: s.depth_bias,
                    shadow_normal_bias: s.normal_bias,
                    outer_angle,
                    inner_angle: outer_angle,
                    range: *far,
                    shadow_map_near_z: *near,
                    ..default()
                },
                Transform::from_translation(vec3(*position)).looking_to(vec3(*direction), up),
            ));
        }
    }
}

fn spawn_objects(
    mut commands: Commands,
    job: Res<Job>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<ShadowOnly>>,
) {
    let spot = matches!(job.view.light, Light::Spot { .. });
    let objects = std::mem::take(&mut *job.objects.lock().expect("objects lock"));
    for object in objects {
        let material = ShadowOnly { double_sided: object.double_sided, spot };
        commands.spawn((
            Mesh3d(meshes.add(object.mesh)),
            MeshMaterial3d(materials.add(material)),
            // Every object is in view; culling only risks a missing caster at a frustum edge.
            NoFrustumCulling,
        ));
    }
}

/// At frame `WARMUP_FRAMES`, asks for the target's pixels; the first read-back ends the app.
fn request_readback(
    mut commands: Commands,
    job: Res<Job>,
    mut frame: Local<u32>,
    mut exit: EventWriter<AppExit>,
) {
    *frame += 1;
    if *frame == WARMUP_FRAMES {
        commands.spawn(Readback::texture(job.target.clone())).observe(
            |trigger: Trigger<ReadbackComplete>,
             capture: Res<Capture>,
             mut commands: Commands,
             mut exit: EventWriter<AppExit>| {
                let mut slot = capture.bytes.lock().expect("capture lock");
                if slot.is_none() {
                    *slot = Some(trigger.event().0.clone());
                    exit.write(AppExit::Success);
                }
                commands.entity(trigger.target()).despawn();
            },
        );
    }
    if *frame > MAX_FRAMES {
        exit.write(AppExit::Success);
    }
}

/// `--fit export`: replaces the cascade that `build_directional_light_cascades` fitted to the
/// camera with the exported map's box. `Cascade`'s fields are crate-private, so they are
/// written through its `Reflect` derive.
fn fit_cascades_to_export(job: Res<Job>, capture: Res<Capture>, mut lights: Query<&mut Cascades>) {
    let Light::Directional { shadow_map, .. } = &job.view.light else {
        return;
    };
    let Some(ortho) = shadow_map.ortho_box() else {
        return;
    };
    let fitted = cascade::ExportCascade::new(
        Mat4::from_cols_array(&shadow_map.view_from_world_column_major),
        ortho,
        job.settings.map_size_texels,
    );
    for mut cascades in &mut lights {
        let written = cascade::overwrite(cascades.bypass_change_detection(), &fitted);
        capture.fitted_cascades.fetch_add(written, Ordering::Relaxed);
        cascades.set_changed();
    }
}

/// Keeps the cascade's texel size for the report line: at `--fit cascade` it is Bevy's own.
fn record_texel_size(capture: Res<Capture>, mut lights: Query<&mut Cascades>) {
    for mut cascades in &mut lights {
        if let Some(size) = cascade::texel_size_world(cascades.bypass_change_detection()) {
            capture.texel_size_bits.store(size.to_bits(), Ordering::Relaxed);
        }
    }
}
