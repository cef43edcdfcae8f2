//! The plan's shaded techniques grouped by the depth layers they read (in plan order): each
//! group's layers are built once per (view, resolution, depth format) and read by every member.

use shadowtruth::technique::{LayerNeeds, TechniqueSpec};

/// Each group's layer needs and its members (indices into the plan's techniques).
pub(crate) type LayerGroups = Vec<(LayerNeeds, Vec<usize>)>;

/// Imported techniques (`external`) build no technique and read no layers: they are in no group.
pub(super) fn layer_groups(techniques: &[TechniqueSpec]) -> LayerGroups {
    let mut groups: LayerGroups = Vec::new();
    for (ti, t) in techniques.iter().enumerate() {
        let Some(technique) = t.build() else { continue };
        let needs = technique.layer_needs();
        match groups.iter_mut().find(|(n, _)| *n == needs) {
            Some((_, members)) => members.push(ti),
            None => groups.push((needs, vec![ti])),
        }
    }
    groups
}
