//! Error attribution on traced scenes: acne where no shadow boundary exists, aliasing at the
//! boundary of a well-biased technique, leaks under a huge bias, and the counts adding up to
//! the false pixels for every technique, resolution and thread count.

mod common;

use common::{bundled, contact_scene, tilted_plane, trace_first};
use shadowtruth::metrics::{Attribution, Counts, LightUv, attribute};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{
    ConstantParams, CullSpec, FalloffSpec, NoneParams, NormalOffsetParams, SlopeScaledParams, TechniqueSpec,
};
use shadowtruth::trace::{GBuffer, HardReference};

/// Shades `spec` at `resolution` and returns its counts with the attribution filled in.
fn run(
    scene: &Scene,
    g: &GBuffer,
    r: &HardReference,
    spec: &TechniqueSpec,
    resolution: u32,
) -> (Counts, Attribution) {
    let (counts, v) = common::score_technique(scene, g, r, spec, resolution, DepthFormat::F32);
    let view = LightView::new(&scene.lights[0], scene.bounds(), resolution);
    let a = attribute(scene, g, r, &v, &LightUv::new(g, &view), None);
    (counts.with_attribution(a), a)
}

fn sum_holds(c: &Counts, a: &Attribution) -> bool {
    a.aliasing + a.acne + a.leak == c.false_shadow + c.false_lit
        && a.acne <= c.false_shadow
        && a.leak <= c.false_lit
}

#[test]
fn without_a_shadow_boundary_every_error_is_acne() {
    let scene = tilted_plane();
    let (g, r) = trace_first(&scene);
    assert!(g.evaluated.iter().all(|&i| r.lit[i as usize] != 0), "the lone plane is lit in truth");
    let (c, a) = run(&scene, &g, &r, &TechniqueSpec::None(NoneParams {}), 512);
    assert!(c.false_shadow > 0, "a plain depth test at 45° shows acne");
    assert_eq!(a.aliasing, 0, "{a:?}");
    assert_eq!(a.leak, 0, "{a:?}");
    assert_eq!(a.acne, c.false_shadow, "{a:?} vs {c:?}");
    assert_eq!((c.aliasing, c.acne, c.leak), (a.aliasing, a.acne, a.leak));
}

#[test]
fn a_well_biased_map_errs_at_the_shadow_boundary_only() {
    let scene = bundled("plane_box");
    let (g, r) = trace_first(&scene);
    let slope =
        TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 2.0, units: 4.0, cull: CullSpec::None });
    let (c, a) = run(&scene, &g, &r, &slope, 512);
    let wrong = c.false_shadow + c.false_lit;
    assert!(sum_holds(&c, &a), "{a:?} vs {c:?}");
    assert!(a.aliasing > 0, "a 512² map cannot follow the box's shadow edge: {a:?}");
    assert!(a.aliasing * 10 >= wrong * 9, "the remaining errors lie at the boundary: {a:?} of {wrong}");
}

#[test]
fn a_huge_constant_bias_is_attributed_to_leaks() {
    let scene = contact_scene();
    let (g, r) = trace_first(&scene);
    let huge = TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.5) });
    let (c, a) = run(&scene, &g, &r, &huge, 2048);
    assert!(sum_holds(&c, &a), "{a:?} vs {c:?}");
    assert!(a.leak > 0, "the detached contact shadow leaks: {a:?}");
    // Most of the leak is far from the boundary: the bias is ~70 texels at 2048².
    assert!(a.leak * 2 > c.false_lit, "{a:?} vs {c:?}");
}

#[test]
fn the_classes_add_up_to_the_false_pixels() {
    let techniques = [
        TechniqueSpec::None(NoneParams {}),
        TechniqueSpec::Constant(ConstantParams { bias_depth: Some(0.002), bias_world: None }),
        TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.3) }),
        TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 1.5, units: 2.0, cull: CullSpec::None }),
        TechniqueSpec::NormalOffset(NormalOffsetParams {
            scale_texels: 1.0,
            falloff: FalloffSpec::default(),
            ..Default::default()
        }),
    ];
    let mut classes_seen = Attribution::default();
    for name in ["plane_box", "spot"] {
        let scene = bundled(name);
        let (g, r) = trace_first(&scene);
        for spec in &techniques {
            for resolution in [64, 256, 1024] {
                let (c, a) = run(&scene, &g, &r, spec, resolution);
                assert!(sum_holds(&c, &a), "{name} {} {resolution}: {a:?} vs {c:?}", spec.label());
                classes_seen.aliasing += a.aliasing;
                classes_seen.acne += a.acne;
                classes_seen.leak += a.leak;
            }
        }
    }
    assert!(
        classes_seen.aliasing > 0 && classes_seen.acne > 0 && classes_seen.leak > 0,
        "the sweep exercises every class: {classes_seen:?}"
    );
}

#[test]
fn the_attribution_is_the_same_on_one_and_two_threads() {
    let scene = bundled("plane_box");
    let (g, r) = trace_first(&scene);
    let specs = [
        TechniqueSpec::None(NoneParams {}),
        TechniqueSpec::Constant(ConstantParams { bias_depth: None, bias_world: Some(0.3) }),
    ];
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| specs.iter().map(|s| run(&scene, &g, &r, s, 256).1).collect::<Vec<_>>())
    };
    let one = on(1);
    assert!(one.iter().all(|a| a.aliasing + a.acne + a.leak > 0), "{one:?}");
    assert_eq!(one, on(2));
}
