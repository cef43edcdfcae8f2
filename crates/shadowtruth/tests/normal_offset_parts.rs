//! The optional parts of `normal_offset` that engines pair with the offset (docs/formulas.md,
//! "Normal offset") against the techniques they are made of: a move towards the light is
//! `constant`'s world bias, texels are world units times the texel's size, and the raster bias
//! is `slope_scaled`'s. Each part also changes the result, so none of these could pass by doing
//! nothing.

mod common;

use common::{contact_scene, shade_technique, trace_first};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::technique::TechniqueSpec;

const RESOLUTION: u32 = 512;

fn spec(json: serde_json::Value) -> TechniqueSpec {
    serde_json::from_value(json).unwrap()
}

fn differing(a: &[f32], b: &[f32]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

#[test]
fn each_part_equals_the_technique_it_is_taken_from() {
    let scene = contact_scene();
    let (g, _) = trace_first(&scene);
    let shade = |s: serde_json::Value| shade_technique(&scene, &g, &spec(s), RESOLUTION, DepthFormat::F32);
    let n = g.evaluated.len();
    let plain = shade(serde_json::json!({ "technique": "normal_offset", "scale_texels": 0.0 }));

    // Towards the light by 0.05 world units: the constant world bias, up to the rounding of a
    // moved point against a moved depth (a handful of pixels at texel borders).
    let moved =
        shade(serde_json::json!({ "technique": "normal_offset", "scale_texels": 0.0, "bias_world": 0.05 }));
    let constant = shade(serde_json::json!({ "technique": "constant", "bias_world": 0.05 }));
    assert!(differing(&plain, &moved) > n / 100, "the world bias changes the shadows");
    assert!(differing(&moved, &constant) <= n / 10_000, "{} of {n} differ", differing(&moved, &constant));

    // Texels: the same move, in texels of the orthographic map (one size everywhere).
    let view = LightView::new(&scene.lights[0], scene.bounds(), RESOLUTION);
    let texel = view.texel_world_size(glam::Vec3::ZERO);
    let in_texels =
        shade(serde_json::json!({ "technique": "normal_offset", "scale_texels": 0.0, "bias_texels": 3.0 }));
    let in_world = shade(
        serde_json::json!({ "technique": "normal_offset", "scale_texels": 0.0, "bias_world": (3.0 * texel) as f64 }),
    );
    assert!(differing(&plain, &in_texels) > n / 100);
    assert_eq!(in_texels, in_world);

    // The raster bias: slope_scaled's, bit for bit.
    let raster = shade(
        serde_json::json!({ "technique": "normal_offset", "scale_texels": 0.0, "factor": 2.0, "units": 4.0 }),
    );
    let slope = shade(serde_json::json!({ "technique": "slope_scaled", "factor": 2.0, "units": 4.0 }));
    assert!(differing(&plain, &raster) > n / 100);
    assert_eq!(raster, slope);
}

#[test]
fn falloff_none_offsets_surfaces_that_face_the_light() {
    // sin θ and 1 − N·L vanish where N·L = 1; g = 1 does not. The top of a box lit from
    // straight above, in a 16-bit map, has acne where its depth rounds below the stored one:
    // one texel towards the light clears it with `none` only.
    let scene = common::scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "top",
        "objects": [{ "name": "b", "shape": { "type": "box", "size": [4, 1, 4] }, "closed": true }],
        "cameras": [{ "name": "c", "position": [0.3, 6, 0.2], "look_at": [0, 0, 0], "fov_y_deg": 40, "width": 96, "height": 96 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }));
    let (g, _) = trace_first(&scene);
    let shade = |s: serde_json::Value| shade_technique(&scene, &g, &spec(s), 64, DepthFormat::Unorm16);
    let lit = |v: &[f32]| v.iter().filter(|&&x| x >= 0.5).count();
    let plain = shade(serde_json::json!({ "technique": "none" }));
    let sin = shade(serde_json::json!({ "technique": "normal_offset", "scale_texels": 1.0 }));
    let one_minus = shade(
        serde_json::json!({ "technique": "normal_offset", "scale_texels": 1.0, "falloff": "one_minus_n_dot_l" }),
    );
    let none =
        shade(serde_json::json!({ "technique": "normal_offset", "scale_texels": 1.0, "falloff": "none" }));
    assert_eq!(sin, plain, "sin θ = 0 on faces towards the light");
    assert_eq!(one_minus, plain, "1 − N·L = 0 there too");
    assert!(lit(&plain) < g.evaluated.len() * 9 / 10, "acne: {} of {} lit", lit(&plain), g.evaluated.len());
    assert_eq!(lit(&none), g.evaluated.len(), "one texel towards the light clears it");
    // There the normal is the direction to the light: the same move as a texel of depth bias.
    let towards =
        shade(serde_json::json!({ "technique": "normal_offset", "scale_texels": 0.0, "bias_texels": 1.0 }));
    assert_eq!(none, towards);
}
