//! Cascaded shadow maps through the library: texel snapping keeps a stabilised cascade's depth
//! map bit-identical under a camera translation of less than a texel; unsnapped, it changes.

mod common;

use glam::Vec3;
use shadowtruth::raster::{Cascades, DepthLayer, RasterSettings, rasterize_nearest};
use shadowtruth::scene::{Camera, CascadeFit, CascadeSettings, SplitScheme};

fn settings(fit: CascadeFit, stabilize: bool) -> CascadeSettings {
    CascadeSettings {
        count: 1,
        split: SplitScheme::Practical { lambda: 0.5 },
        fit,
        stabilize,
        blend_band: 0.0,
        near_distance: None,
        max_distance: Some(12.0),
    }
}

/// The one cascade's light view and depth map for `camera`.
fn cascade_map(settings: &CascadeSettings, camera: &Camera) -> (Cascades, DepthLayer) {
    let scene = common::bundled("plane_box");
    let cascades = Cascades::new(settings, &scene.lights[0], camera, scene.bounds(), 512, 12.0);
    let map = rasterize_nearest(&scene, &cascades.views[0], &RasterSettings::default());
    (cascades, map)
}

/// `camera` moved by `distance` along the light's x axis (across the map, not along the light).
fn moved(camera: &Camera, across: Vec3, distance: f32) -> Camera {
    let offset = across * distance;
    Camera { position: camera.position + offset, look_at: camera.look_at + offset, ..camera.clone() }
}

#[test]
fn a_sub_texel_camera_move_keeps_a_stabilised_cascade_bit_identical_and_an_unsnapped_one_not() {
    let camera = common::bundled("plane_box").cameras[0].clone();
    let stable = settings(CascadeFit::Sphere, true);
    let (cascades, base) = cascade_map(&stable, &camera);
    let m = cascades.views[0].light_from_world;
    let across = Vec3::new(m.x_axis.x, m.y_axis.x, m.z_axis.x).normalize();
    // 0.3 texel: of the two directions, at least one stays within the snapped texel.
    let step = 0.3 * cascades.texel_world(0) as f32;
    let kept: Vec<f32> = [step, -step]
        .into_iter()
        .filter(|&d| {
            let (c, map) = cascade_map(&stable, &moved(&camera, across, d));
            c.views == cascades.views
                && map.depth.iter().zip(&base.depth).all(|(a, b)| a.to_bits() == b.to_bits())
        })
        .collect();
    assert!(!kept.is_empty(), "a stabilised cascade moved under a camera move of 0.3 texel both ways");
    for fit in [CascadeFit::Sphere, CascadeFit::Frustum] {
        let loose = settings(fit, false);
        let (_, before) = cascade_map(&loose, &camera);
        let (_, after) = cascade_map(&loose, &moved(&camera, across, kept[0]));
        assert_ne!(before.depth, after.depth, "{fit:?}: an unsnapped cascade follows the camera");
    }
}

#[test]
fn a_stabilised_sphere_cascade_keeps_its_texel_size_as_the_camera_turns() {
    let camera = common::bundled("plane_box").cameras[0].clone();
    let stable = settings(CascadeFit::Sphere, true);
    let turned = Camera { look_at: camera.look_at + Vec3::new(2.0, -0.3, 1.0), ..camera.clone() };
    let (a, _) = cascade_map(&stable, &camera);
    let (b, _) = cascade_map(&stable, &turned);
    assert_eq!(a.texel_world(0), b.texel_world(0));
    let tight = settings(CascadeFit::Frustum, false);
    let (c, _) = cascade_map(&tight, &camera);
    let (d, _) = cascade_map(&tight, &turned);
    assert_ne!(c.texel_world(0), d.texel_world(0));
}
