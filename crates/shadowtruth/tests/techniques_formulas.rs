//! Worked examples of the technique formulas, computed by hand.

mod common;

use common::scene_from_json;
use glam::{Vec3, Vec4};
use serde_json::json;
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::{PixelFootprint, Scene};
use shadowtruth::technique::{
    AdaptiveBias, EpsilonScale, LayerNeeds, Sample, ShadeContext, receiver_plane_slope,
};

/// A 10×10 ground square lit straight from above: the orthographic view's bounds and depth
/// range are known exactly.
fn lit_from_above() -> Scene {
    scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "flat",
        "objects": [{ "name": "g", "shape": { "type": "box", "size": [10, 2, 10] }, "closed": true }],
        "cameras": [{ "name": "c", "position": [0, 5, 5], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 8, "height": 8 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }))
}

#[test]
fn receiver_plane_slope_of_a_known_triangle() {
    let scene = lit_from_above();
    let view = LightView::new(&scene.lights[0], scene.bounds(), 256);
    let world_from_clip = view.clip_from_world.inverse();
    // Vertices placed at chosen (u, v, d): the plane d = 0.3 + 0.5(u − 0.2) + 0.3(v − 0.2).
    let at = |u: f32, v: f32, d: f32| {
        let h = world_from_clip * Vec4::new(2.0 * u - 1.0, 2.0 * v - 1.0, d, 1.0);
        h.truncate() / h.w
    };
    let tri = [at(0.2, 0.2, 0.3), at(0.6, 0.2, 0.5), at(0.2, 0.7, 0.45)];
    let (z_u, z_v) = receiver_plane_slope(&view, &tri).expect("a triangle facing the light");
    assert!((z_u - 0.5).abs() < 1e-5 && (z_v - 0.3).abs() < 1e-5, "({z_u}, {z_v})");
}

#[test]
fn adaptive_bias_of_a_tilted_plane_under_an_orthographic_light() {
    let scene = lit_from_above();
    let view = LightView::new(&scene.lights[0], scene.bounds(), 64);
    let layers =
        shadowtruth::technique::BuiltLayers::build(&scene, &view, DepthFormat::F32, &LayerNeeds::default());
    let ctx = ShadeContext::new(&scene, PixelFootprint::of(&scene.cameras[0]), &view, layers.as_layers());
    let (n, f) = (view.near as f64, view.far as f64);
    let scene_scale = (Vec3::new(10.0, 2.0, 10.0)).length() as f64;
    for theta_deg in [30.0f64, 60.0] {
        let theta = theta_deg.to_radians();
        // A receiver on a plane tilted by θ about z, at a point off its texel centre.
        let normal = Vec3::new(theta.sin() as f32, theta.cos() as f32, 0.0);
        // Deep enough below the near plane that the tangent plane meets the texel ray inside
        // the frustum (otherwise the receiver depth is used, as the guard says).
        let position = Vec3::new(1.234, -0.5, -2.345);
        let s = Sample { position, normal, triangle: 0 };
        for (k, scale) in [(1e-4f32, EpsilonScale::Original), (1e-4, EpsilonScale::Ehm)] {
            let t = AdaptiveBias { k, epsilon: scale }.test(&s, &ctx).expect("in front of the light");
            // The light ray through the texel centre meets the tangent plane at height
            // y = p.y − tanθ·(x_c − p.x); depth grows downwards, linearly over [n, f].
            let uvd = view.project(position).unwrap();
            let texel_world = 10.0 / 64.0;
            let (x_c, z_c) = {
                let world_from_clip = view.clip_from_world.inverse();
                let (u_c, v_c) = ((t.texel.0 as f32 + 0.5) / 64.0, 1.0 - (t.texel.1 as f32 + 0.5) / 64.0);
                let h = world_from_clip * Vec4::new(2.0 * u_c - 1.0, 2.0 * v_c - 1.0, 0.5, 1.0);
                ((h.x / h.w) as f64, (h.z / h.w) as f64)
            };
            assert!(
                (x_c - position.x as f64).abs() <= texel_world
                    && (z_c - position.z as f64).abs() <= texel_world
            );
            let d_receiver = uvd.z as f64;
            let d_occluder = d_receiver + theta.tan() * (x_c - position.x as f64) / (f - n);
            assert!(
                (t.occluder_depth.unwrap() as f64 - d_occluder).abs() < 2e-6,
                "θ = {theta_deg}: occluder depth {:?} vs {d_occluder}",
                t.occluder_depth
            );
            assert!((t.compared_depth as f64 - d_occluder.min(d_receiver)).abs() < 2e-6);
            let mut epsilon = k as f64 * scene_scale / (f - n);
            if scale == EpsilonScale::Ehm {
                epsilon *= (1.0 / theta.cos().powi(2)).min(100.0);
            }
            assert!((t.epsilon as f64 - epsilon).abs() < 1e-6 * epsilon, "{} vs {epsilon}", t.epsilon);
        }
    }
}
