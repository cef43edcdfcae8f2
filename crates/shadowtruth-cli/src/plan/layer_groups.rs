//! The plan's shaded techniques grouped by the depth layers they read (in plan order): each
//! group's layers are built once per (view, resolution, depth format) and read by every member.

use shadowtruth::raster::{Culling, MomentWarp};
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

/// A group's layers in words, for `--timing` and progress: what is drawn and how.
pub(super) fn group_label(needs: &LayerNeeds) -> String {
    let mut label = match (needs.moments, needs.multi_depth, needs.second_layer) {
        (Some(m), _, _) => {
            let warp = match m.warp {
                MomentWarp::Depth2 => "VSM",
                MomentWarp::Exponential { .. } => "ESM",
                MomentWarp::Evsm2 { .. } => "EVSM2",
                MomentWarp::Evsm4 { .. } => "EVSM4",
                MomentWarp::Power4 => "MSM",
            };
            format!("{warp} moments{}", if m.mipmaps { " with mipmaps" } else { "" })
        }
        (None, Some(m), _) => format!("{} depths per texel", m.depths),
        (None, None, true) => "two nearest".to_string(),
        (None, None, false) => "nearest".to_string(),
    };
    match needs.culling {
        Culling::None => {}
        Culling::BackFacesOfClosed => label.push_str(", back faces culled"),
        Culling::FrontFacesOfClosed => label.push_str(", front faces culled"),
    }
    if needs.slope_factor != 0.0 || needs.slope_units != 0.0 {
        label.push_str(&format!(", offset ({}, {})", needs.slope_factor, needs.slope_units));
    }
    label
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_group_is_named_by_its_layers_culling_and_offset() {
        let spec = |json: &str| serde_json::from_str::<TechniqueSpec>(json).unwrap();
        let label = |json: &str| group_label(&spec(json).build().unwrap().layer_needs());
        assert_eq!(label(r#"{"technique": "none"}"#), "nearest");
        assert_eq!(
            label(r#"{"technique": "slope_scaled", "factor": 2, "units": 4, "cull": "back"}"#),
            "nearest, back faces culled, offset (2, 4)"
        );
        assert_eq!(label(r#"{"technique": "midpoint"}"#), "two nearest");
        assert_eq!(label(r#"{"technique": "vsm", "mipmaps": true}"#), "VSM moments with mipmaps");
    }
}
