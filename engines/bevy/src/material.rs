//! The shadow-only material: Bevy's default mesh vertex shader, and a fragment shader that
//! writes Bevy's own shadow lookup (`shadow_only.wgsl`).

use bevy::asset::{Asset, Assets, Handle, weak_handle};
use bevy::pbr::{Material, MaterialPipeline, MaterialPipelineKey};
use bevy::prelude::{App, Shader};
use bevy::reflect::TypePath;
use bevy::render::mesh::MeshVertexBufferLayoutRef;
use bevy::render::render_resource::{
    AsBindGroup, Face, RenderPipelineDescriptor, ShaderRef, SpecializedMeshPipelineError,
};

const SHADER: Handle<Shader> = weak_handle!("5b0a3f43-6c8e-4f0e-9d61-2f7c1b9e8a10");

/// One object's material: its sidedness (the export's `closed` / `open`) and the light's kind.
#[derive(Asset, TypePath, AsBindGroup, Clone, Debug)]
#[bind_group_data(ShadowOnlyKey)]
pub struct ShadowOnly {
    pub double_sided: bool,
    pub spot: bool,
}

/// What the pipeline is specialized on.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct ShadowOnlyKey {
    double_sided: bool,
    spot: bool,
}

impl From<&ShadowOnly> for ShadowOnlyKey {
    fn from(m: &ShadowOnly) -> Self {
        ShadowOnlyKey { double_sided: m.double_sided, spot: m.spot }
    }
}

impl Material for ShadowOnly {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(SHADER)
    }

    /// Culls as `StandardMaterial` does (its `cull_mode`, `None` for a double-sided glTF
    /// material): bevy_pbr's prepass/mod.rs calls this for the shadow pass too, so the map draws
    /// the same faces as the camera.
    fn specialize(
        _pipeline: &MaterialPipeline<Self>,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        let data = key.bind_group_data;
        descriptor.primitive.cull_mode = (!data.double_sided).then_some(Face::Back);
        if let Some(fragment) = descriptor.fragment.as_mut() {
            if data.double_sided {
                fragment.shader_defs.push("SHADOW_ONLY_DOUBLE_SIDED".into());
            }
            if data.spot {
                fragment.shader_defs.push("SHADOW_ONLY_SPOT".into());
            }
        }
        Ok(())
    }
}

/// Registers the WGSL under the material's fixed handle.
pub fn add_shader(app: &mut App) {
    let shader = Shader::from_wgsl(include_str!("shadow_only.wgsl"), "shadow_only.wgsl");
    app.world_mut().resource_mut::<Assets<Shader>>().insert(&SHADER, shader);
}
