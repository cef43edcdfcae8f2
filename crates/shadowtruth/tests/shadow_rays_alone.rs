//! The shadow rays `reference --timing` traces alone (`hard_shadow_rays`, `trace_shadow_rays`)
//! are those of the hard reference: one per evaluated pixel, and as many occluded as the
//! reference leaves shadowed, on every view of the bundled scenes (a sun, spot lights).

mod common;

use common::bundled;
use shadowtruth::trace::{
    GBuffer, PixelClass, SceneBvh, hard_shadow_rays, trace_hard_reference, trace_shadow_rays,
};

#[test]
fn the_rays_alone_answer_as_the_hard_reference() {
    let mut shadowed_views = 0;
    for name in ["grazing_wall", "l_shape", "plane_box", "rocks", "spot"] {
        let scene = bundled(name);
        let bvh = SceneBvh::build(&scene);
        for camera in &scene.cameras {
            for light in &scene.lights {
                let g = GBuffer::trace(&scene, &bvh, camera, light);
                let reference = trace_hard_reference(&scene, &bvh, &g, light);
                let evaluated: Vec<usize> =
                    (0..g.pixel_count()).filter(|&i| g.class[i] == PixelClass::Evaluated).collect();
                let shadowed = evaluated.iter().filter(|&&i| reference.lit[i] == 0).count();
                let rays = hard_shadow_rays(&scene, &g, light);
                let view = format!("{name}/{}/{}", camera.name, light.name);
                assert_eq!(rays.iter().map(Vec::len).sum::<usize>(), evaluated.len(), "{view}");
                assert_eq!(trace_shadow_rays(&bvh, &rays), shadowed, "{view}");
                shadowed_views += (shadowed > 0 && shadowed < evaluated.len()) as usize;
            }
        }
    }
    assert!(shadowed_views >= 5, "the views must have both lit and shadowed pixels ({shadowed_views})");
}
