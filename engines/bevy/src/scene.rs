//! `scene.glb` as Bevy meshes. The export writes one world-space mesh per object with flat
//! per-face normals and one of two materials, `closed` (one-sided) and `open` (double-sided); the
//! meshes are read here rather than through Bevy's glTF loader so that each keeps exactly its
//! triangles, normals and sidedness, with no asset loading to wait for.

use bevy::asset::RenderAssetUsages;
use bevy::math::{Mat4, Vec3};
use bevy::render::mesh::{Indices, Mesh, PrimitiveTopology};
use std::path::Path;

/// One object: its mesh and whether both of its sides are drawn.
pub struct Object {
    pub mesh: Mesh,
    pub double_sided: bool,
}

pub fn read(path: &Path) -> Result<Vec<Object>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let glb =
        gltf::Gltf::from_slice(&bytes).map_err(|e| format!("{}: not a glTF binary: {e}", path.display()))?;
    let blob = glb.blob.as_deref();
    let mut objects = Vec::new();
    for scene in glb.document.scenes() {
        for node in scene.nodes() {
            collect(&node, Mat4::IDENTITY, blob, &mut objects)
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    if objects.is_empty() {
        return Err(format!("{}: no triangle meshes", path.display()));
    }
    Ok(objects)
}

fn collect(
    node: &gltf::Node,
    parent: Mat4,
    blob: Option<&[u8]>,
    out: &mut Vec<Object>,
) -> Result<(), String> {
    let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
    if let Some(mesh) = node.mesh() {
        for primitive in mesh.primitives() {
            out.push(object(&primitive, world, blob)?);
        }
    }
    for child in node.children() {
        collect(&child, world, blob, out)?;
    }
    Ok(())
}

fn object(primitive: &gltf::Primitive, world: Mat4, blob: Option<&[u8]>) -> Result<Object, String> {
    if primitive.mode() != gltf::mesh::Mode::Triangles {
        return Err("a primitive is not a triangle list".into());
    }
    let reader = primitive.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => blob,
        gltf::buffer::Source::Uri(_) => None,
    });
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or("a primitive has no POSITION")?
        .map(|p| world.transform_point3(Vec3::from(p)).to_array())
        .collect();
    let normal_from_object = world.inverse().transpose();
    let normals: Vec<[f32; 3]> = reader
        .read_normals()
        .ok_or("a primitive has no NORMAL (the normal bias needs the face normals)")?
        .map(|n| normal_from_object.transform_vector3(Vec3::from(n)).normalize_or_zero().to_array())
        .collect();
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, positions);
    mesh.insert_attribute(Mesh::ATTRIBUTE_NORMAL, normals);
    if let Some(indices) = reader.read_indices() {
        mesh.insert_indices(Indices::U32(indices.into_u32().collect()));
    }
    let double_sided = primitive.material().double_sided();
    Ok(Object { mesh, double_sided })
}
