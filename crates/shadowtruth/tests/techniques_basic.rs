//! The single-depth techniques against the reference: acne without bias, leaks with too much.
//! Every count comes from comparing with the ray-traced reference.

mod common;

use common::{contact_scene, tilted_plane, trace_first};
use shadowtruth::metrics::Counts;
use shadowtruth::raster::DepthFormat;
use shadowtruth::scene::Scene;
use shadowtruth::technique::{ConstantParams, CullSpec, NoneParams, SlopeScaledParams, TechniqueSpec};
use shadowtruth::trace::{GBuffer, HardReference};

fn score(
    scene: &Scene,
    g: &GBuffer,
    r: &HardReference,
    spec: &TechniqueSpec,
    resolution: u32,
) -> (Counts, Vec<f32>) {
    common::score_technique(scene, g, r, spec, resolution, DepthFormat::F32)
}

#[test]
fn no_bias_has_acne_on_a_plane_at_45_degrees() {
    let scene = tilted_plane();
    let (g, r) = trace_first(&scene);
    assert_eq!(
        g.evaluated.iter().filter(|&&i| r.lit[i as usize] == 0).count(),
        0,
        "the lone plane is lit in truth"
    );
    for resolution in [256, 1024] {
        let (none, _) = score(&scene, &g, &r, &TechniqueSpec::None(NoneParams {}), resolution);
        assert!(none.false_shadow > 0, "{resolution}: a plain depth test at 45° must show acne");
        assert_eq!(none.false_lit, 0, "nothing is shadowed in truth");
        // A slope-scaled bias removes it: the count above is the technique's, not the scene's.
        let slope =
            TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 1.5, units: 2.0, cull: CullSpec::None });
        let (biased, _) = score(&scene, &g, &r, &slope, resolution);
        assert!(biased.false_shadow * 100 < none.false_shadow, "{resolution}: {biased:?} vs {none:?}");
    }
}

#[test]
fn a_large_constant_bias_leaks_light_at_the_contact_shadow() {
    let scene = contact_scene();
    let (g, r) = trace_first(&scene);
    let small = TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.002) });
    let large = TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.4) });
    let (c_small, _) = score(&scene, &g, &r, &small, 2048);
    let (c_large, v) = score(&scene, &g, &r, &large, 2048);
    assert!(c_large.false_lit > 0, "a 0.4-unit bias must detach the shadow from the box: {c_large:?}");
    assert!(c_large.false_lit > 10 * c_small.false_lit.max(1), "{c_large:?} vs {c_small:?}");
    // The leak is at the contact: every false-lit ground pixel lies within the bias (as a
    // horizontal run along the light) of the box's footprint.
    for (k, &i) in g.evaluated.iter().enumerate() {
        let i = i as usize;
        if r.lit[i] == 0 && v[k] >= 0.5 {
            let p = g.position[i];
            assert!(p.y.abs() < 1e-6 || g.object(&scene, i) == 1, "leak away from the ground and box at {p}");
            assert!(p.x.abs() < 1.5 && p.z.abs() < 1.5, "false-lit pixel at {p} is far from the contact");
        }
    }
}
