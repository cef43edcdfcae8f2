//! `--fit export`: a directional light's cascade with the exported map's box instead of the box
//! Bevy fits to the camera, so that Bevy draws and samples its map on the export's texel grid.

use crate::view::OrthoBox;
use bevy::math::{Mat4, Vec4};
use bevy::pbr::Cascades;
use bevy::reflect::{PartialReflect, ReflectMut, Struct};

/// The four fields of bevy_pbr's `Cascade` (light/mod.rs, `calculate_cascade`).
pub struct ExportCascade {
    world_from_cascade: Mat4,
    clip_from_cascade: Mat4,
    clip_from_world: Mat4,
    texel_size_world: f32,
}

impl ExportCascade {
    pub fn new(view_from_world: Mat4, ortho: OrthoBox, map_size_texels: u32) -> Self {
        let clip_from_cascade = reverse_z_orthographic(ortho);
        let width = ortho.right - ortho.left;
        let height = ortho.top - ortho.bottom;
        ExportCascade {
            world_from_cascade: view_from_world.inverse(),
            clip_from_cascade,
            clip_from_world: clip_from_cascade * view_from_world,
            // The normal bias's unit (render/shadows.wgsl, sample_directional_cascade): the
            // texel's larger side, as shadowtruth's emulation measures a texel.
            texel_size_world: width.max(height) / map_size_texels as f32,
        }
    }
}

/// Bevy's cascade projection (`calculate_cascade`): reverse Z, the near plane at depth 1 and
/// the far plane at 0, x and y over the box.
fn reverse_z_orthographic(b: OrthoBox) -> Mat4 {
    let (w, h, d) = (b.right - b.left, b.top - b.bottom, b.far - b.near);
    Mat4::from_cols(
        Vec4::new(2.0 / w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0 / h, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0 / d, 0.0),
        Vec4::new(-(b.right + b.left) / w, -(b.top + b.bottom) / h, b.far / d, 1.0),
    )
}

/// Writes `fitted` into every cascade of every view in `cascades`; returns how many it wrote
/// (0 if `Cascades` no longer has the layout of bevy_pbr 0.16).
pub fn overwrite(cascades: &mut Cascades, fitted: &ExportCascade) -> usize {
    let mut written = 0;
    for_each_cascade(cascades, |cascade| written += usize::from(write_fields(cascade, fitted)));
    written
}

/// The texel size of the first cascade, world units (what Bevy fitted, or the export's).
pub fn texel_size_world(cascades: &mut Cascades) -> Option<f32> {
    let mut size = None;
    for_each_cascade(cascades, |cascade| {
        let field = cascade.field("texel_size").and_then(|f| f.try_downcast_ref::<f32>());
        size = size.or(field.copied());
    });
    size
}

/// Calls `f` on every cascade of every view, through `Reflect` (the fields are crate-private).
fn for_each_cascade(cascades: &mut Cascades, mut f: impl FnMut(&mut dyn Struct)) {
    let ReflectMut::Struct(light) = cascades.reflect_mut() else {
        return;
    };
    let Some(per_view) = light.field_mut("cascades") else {
        return;
    };
    // `EntityHashMap` is a newtype over a `HashMap` (bevy_ecs entity/hash_map.rs).
    let ReflectMut::TupleStruct(newtype) = per_view.reflect_mut() else {
        return;
    };
    let Some(ReflectMut::Map(per_view)) = newtype.field_mut(0).map(|m| m.reflect_mut()) else {
        return;
    };
    for i in 0..per_view.len() {
        let Some(ReflectMut::List(list)) = per_view.get_at_mut(i).map(|(_, l)| l.reflect_mut()) else {
            continue;
        };
        for j in 0..list.len() {
            if let Some(ReflectMut::Struct(cascade)) = list.get_mut(j).map(|c| c.reflect_mut()) {
                f(cascade);
            }
        }
    }
}

/// True when all four fields were found and written.
fn write_fields(cascade: &mut dyn Struct, fitted: &ExportCascade) -> bool {
    let mut set = |name: &str, value: &dyn PartialReflect| {
        cascade.field_mut(name).and_then(|field| field.try_apply(value).ok()).is_some()
    };
    set("world_from_cascade", &fitted.world_from_cascade)
        & set("clip_from_cascade", &fitted.clip_from_cascade)
        & set("clip_from_world", &fitted.clip_from_world)
        & set("texel_size", &fitted.texel_size_world)
}
