//! The node hierarchy of the scene to show: world transforms (parent × child, in f64) and what
//! each node carries: a mesh placement, a camera or a light.

use super::extras::Extras;
use super::names::UniqueNames;
use super::problem::GltfProblem;
use crate::json_input::as_bool;
use crate::scene::placement::Placement;
use glam::{DAffine3, DMat4, DQuat, DVec3, DVec4};
use std::collections::BTreeMap;

/// A camera or a light node.
pub(super) struct NodeItem {
    pub node: usize,
    pub world: DAffine3,
}

/// What the scene's nodes carry, in depth-first order of the hierarchy.
#[derive(Default)]
pub(super) struct NodeTree {
    /// Each referenced glTF mesh index with its placements, in mesh order.
    pub meshes: Vec<(usize, Vec<Placement>)>,
    pub cameras: Vec<NodeItem>,
    pub lights: Vec<NodeItem>,
}

/// Walks the default scene (else scene 0, else every node that is no node's child).
pub(super) fn walk(document: &gltf::Document, problems: &mut Vec<GltfProblem>) -> NodeTree {
    let (roots, roots_path) = roots(document);
    let mut visited = vec![false; document.nodes().len()];
    let mut stack: Vec<(gltf::Node, DAffine3, String)> =
        roots.into_iter().rev().map(|n| (n, DAffine3::IDENTITY, roots_path.clone())).collect();
    let (mut meshes, mut tree, mut names) = (BTreeMap::new(), NodeTree::default(), UniqueNames::default());
    while let Some((node, parent, from)) = stack.pop() {
        let at = format!("nodes[{}]", node.index());
        if std::mem::replace(&mut visited[node.index()], true) {
            problems
                .push(GltfProblem::new(from, format!("reaches {at} a second time: nodes must form trees")));
            continue;
        }
        let world = match local(&node, &at) {
            Ok(local) if (parent * local).is_finite() => parent * local,
            Ok(_) => {
                problems.push(GltfProblem::new(&at, "its world transform leaves the range of numbers"));
                continue;
            }
            Err(p) => {
                problems.push(p);
                continue;
            }
        };
        if let Some(mesh) = node.mesh() {
            let fallback = || mesh.name().map_or_else(|| format!("node{}", node.index()), str::to_string);
            let name = names.take(node.name(), fallback);
            let closed = Extras::read(node.extras(), &at).get("closed", as_bool, problems).unwrap_or(false);
            let mirrored = world.matrix3.determinant() < 0.0;
            let placement = Placement { world_from_mesh: world, mirrored, name, path: at.clone(), closed };
            meshes.entry(mesh.index()).or_insert_with(Vec::new).push(placement);
        }
        if node.camera().is_some() {
            tree.cameras.push(NodeItem { node: node.index(), world });
        }
        if node.light().is_some() {
            tree.lights.push(NodeItem { node: node.index(), world });
        }
        let children: Vec<gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world, format!("{at}.children"))));
    }
    tree.meshes = meshes.into_iter().collect();
    tree
}

/// The root nodes to walk and the JSON path that lists them.
fn roots(document: &gltf::Document) -> (Vec<gltf::Node<'_>>, String) {
    if let Some(scene) = document.default_scene().or_else(|| document.scenes().next()) {
        return (scene.nodes().collect(), format!("scenes[{}].nodes", scene.index()));
    }
    let mut is_child = vec![false; document.nodes().len()];
    for child in document.nodes().flat_map(|n| n.children()) {
        is_child[child.index()] = true;
    }
    (document.nodes().filter(|n| !is_child[n.index()]).collect(), "nodes".to_string())
}

/// The node's own transform: its matrix (which must be affine), or T · R · S with the rotation
/// normalized in f64.
fn local(node: &gltf::Node, at: &str) -> Result<DAffine3, GltfProblem> {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)));
            if m.row(3) != DVec4::W {
                return Err(GltfProblem::new(format!("{at}.matrix"), "its last row must be 0, 0, 0, 1"));
            }
            Ok(DAffine3::from_mat4(m))
        }
        gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
            let q = DQuat::from_array(rotation.map(f64::from));
            if !q.is_finite() || q.length() == 0.0 {
                return Err(GltfProblem::new(format!("{at}.rotation"), "must be a non-zero quaternion"));
            }
            let (s, t) = (DVec3::from(scale.map(f64::from)), DVec3::from(translation.map(f64::from)));
            Ok(DAffine3::from_scale_rotation_translation(s, q.normalize(), t))
        }
    }
}
