//! The shadow rays `reference --timing` traces alone (`hard_shadow_rays`, `area_light_shadow_rays`,
//! `trace_shadow_rays`) are those of the references: for the hard reference one per evaluated
//! pixel, and as many occluded as it leaves shadowed; for the area-light reference as many
//! unoccluded as its visibilities count. On every view of the bundled scenes (a sun, spot
//! lights, each with a size).

mod common;

use common::bundled;
use shadowtruth::scene::{Light, Scene};
use shadowtruth::trace::{
    GBuffer, PixelClass, SceneBvh, ShadowRay, area_light_shadow_rays, hard_shadow_rays,
    trace_area_light_reference, trace_hard_reference, trace_shadow_rays,
};

/// Calls `check(scene, bvh, gbuffer, light, view)` for every view of the bundled scenes.
fn each_view(mut check: impl FnMut(&Scene, &SceneBvh, &GBuffer, &Light, &str)) {
    for name in ["grazing_wall", "l_shape", "plane_box", "rocks", "spot"] {
        let scene = bundled(name);
        let bvh = SceneBvh::build(&scene);
        for camera in &scene.cameras {
            for light in &scene.lights {
                let g = GBuffer::trace(&bvh, camera, light);
                check(&scene, &bvh, &g, light, &format!("{name}/{}/{}", camera.name, light.name));
            }
        }
    }
}

/// Traces the groups `prepare` hands over: (rays, occluded, groups).
fn trace_groups(
    bvh: &SceneBvh,
    prepare: impl FnOnce(&mut dyn FnMut(&[Vec<ShadowRay>])),
) -> (usize, usize, usize) {
    let (mut rays, mut occluded, mut groups) = (0, 0, 0);
    prepare(&mut |group| {
        rays += group.iter().map(Vec::len).sum::<usize>();
        occluded += trace_shadow_rays(bvh, group);
        groups += 1;
    });
    (rays, occluded, groups)
}

#[test]
fn the_rays_alone_answer_as_the_hard_reference() {
    let mut shadowed_views = 0;
    each_view(|scene, bvh, g, light, view| {
        let reference = trace_hard_reference(scene, bvh, g, light);
        let evaluated: Vec<usize> =
            (0..g.pixel_count()).filter(|&i| g.class[i] == PixelClass::Evaluated).collect();
        let shadowed = evaluated.iter().filter(|&&i| reference.lit[i] == 0).count();
        // Groups of about 64 KB of rays, so that a view comes in several.
        let (rays, occluded, groups) =
            trace_groups(bvh, |each| hard_shadow_rays(scene, g, light, 1 << 16, each));
        assert_eq!(rays, evaluated.len(), "{view}");
        assert_eq!(occluded, shadowed, "{view}");
        assert!(groups > 1, "{view}: the rays come in groups ({groups})");
        shadowed_views += (shadowed > 0 && shadowed < evaluated.len()) as usize;
    });
    assert!(shadowed_views >= 5, "the views must have both lit and shadowed pixels ({shadowed_views})");
}

#[test]
fn the_area_light_rays_alone_answer_as_its_reference() {
    let grid = 3;
    let mut views = 0;
    each_view(|scene, bvh, g, light, view| {
        let reference = trace_area_light_reference(scene, bvh, g, light, grid).expect("a light with a size");
        // Each visibility is the count of unoccluded rays over the n×n samples.
        let samples = (grid * grid) as f32;
        let unoccluded: usize = reference.visibility.iter().map(|&v| (v * samples).round() as usize).sum();
        let mut prepared = Ok(());
        let (rays, occluded, groups) = trace_groups(bvh, |each| {
            prepared = area_light_shadow_rays(scene, g, light, grid, 1 << 16, each);
        });
        prepared.expect("a light with a size");
        assert_eq!(rays - occluded, unoccluded, "{view}");
        assert!(groups > 1 && occluded > 0 && unoccluded > 0, "{view}: {groups} groups, {occluded} occluded");
        views += 1;
    });
    assert!(views >= 5);
}
