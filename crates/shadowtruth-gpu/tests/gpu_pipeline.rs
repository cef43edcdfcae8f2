//! The GPU pipeline (this crate) against the CPU: the depth map of the device's rasterizer against
//! `rasterize_nearest`, and the fragment shader's shadow tests against the CPU techniques, on the
//! bundled scenes. A machine without a Vulkan adapter fails here with the message saying how to
//! get one (`bash scripts/test.sh` installs Mesa's lavapipe): the cross-check never passes by not
//! running.
//! docs/conventions.md ("GPU pipeline") holds the measurements these bounds come from.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use shadowtruth::raster::{Culling, DepthLayer, LightView, RasterSettings, rasterize_nearest};
use shadowtruth::technique::TechniqueSpec;
use shadowtruth::{BuiltLayers, DepthFormat, GBuffer, Scene};
use shadowtruth_gpu::{GpuDepthMap, GpuDevice, GpuTechnique, shade_visibility};

const SCENES: [&str; 5] = ["plane_box", "rocks", "spot", "grazing_wall", "l_shape"];

fn gpu() -> GpuDevice {
    GpuDevice::new().unwrap_or_else(|e| panic!("{e}; `bash scripts/test.sh` installs lavapipe"))
}

fn gpu_layer(gpu: &GpuDevice, scene: &Scene, view: &LightView, settings: &RasterSettings) -> DepthLayer {
    let map = GpuDepthMap::render(gpu, scene, view, settings).unwrap_or_else(|e| panic!("{e}"));
    map.read_back(gpu).unwrap_or_else(|e| panic!("{e}"))
}

/// The largest depth step from texel i to one of its four neighbours in `layer`: the local slope
/// that scales the depth error of vertex snapping (and is large across silhouettes).
fn local_step(layer: &DepthLayer, x: usize, row: usize) -> f32 {
    let n = layer.resolution as usize;
    let z = layer.depth[row * n + x];
    let mut step = 0.0f32;
    for (dx, dy) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
        let (xx, yy) = (x as i64 + dx, row as i64 + dy);
        if xx >= 0 && yy >= 0 && xx < n as i64 && yy < n as i64 {
            step = step.max((layer.depth[yy as usize * n + xx as usize] - z).abs());
        }
    }
    step
}

/// Where the device's map departs from the CPU's.
struct MapDifferences {
    /// Texels covered by one side only.
    coverage: u32,
    /// Texels both cover whose depths differ by more than 1/64 of the CPU's local depth step
    /// plus 4·10⁻⁶.
    outside: u32,
    /// The largest depth difference over texels both cover.
    max_diff: f32,
}

fn differences(cpu: &DepthLayer, gpu: &DepthLayer) -> MapDifferences {
    let n = cpu.resolution as usize;
    let mut d = MapDifferences { coverage: 0, outside: 0, max_diff: 0.0 };
    for row in 0..n {
        for x in 0..n {
            let (c, g) = (cpu.depth[row * n + x], gpu.depth[row * n + x]);
            if (c < 1.0) != (g < 1.0) {
                d.coverage += 1;
                continue;
            }
            let diff = (c - g).abs();
            d.max_diff = d.max_diff.max(diff);
            d.outside += (diff > local_step(cpu, x, row) / 64.0 + 4e-6) as u32;
        }
    }
    d
}

/// Without depth bias the device's map covers the CPU's texels, and its depths differ from the
/// CPU's by at most 1/64 of the local depth step plus 4·10⁻⁶: the CPU evaluates the depth plane
/// through vertices snapped to 1/256 texel, the device through the unsnapped ones, and the
/// difference grows with the slope. At most one texel per map may break either bound (a triangle
/// edge through a texel centre within the rounding of the two setups; one texel of `spot` was
/// measured).
#[test]
fn depth_map_matches_the_cpu_rasterizer() {
    let gpu = gpu();
    println!("adapter: {:?}", gpu.adapter());
    println!(
        "{:14} {:>5} {:>20} {:>9} {:>9} {:>12}",
        "scene", "N", "culling", "coverage", "outside", "max |Δd|"
    );
    for name in SCENES {
        let scene = common::bundled(name);
        for resolution in [256u32, 1024, 2048] {
            let view = LightView::new(&scene.lights[0], scene.bounds(), resolution);
            for culling in [Culling::None, Culling::BackFacesOfClosed, Culling::FrontFacesOfClosed] {
                let settings = RasterSettings { culling, ..Default::default() };
                let cpu = rasterize_nearest(&scene, &view, &settings);
                let gpu_map = gpu_layer(&gpu, &scene, &view, &settings);
                let MapDifferences { coverage, outside, max_diff } = differences(&cpu, &gpu_map);
                println!(
                    "{name:14} {resolution:>5} {:>20} {coverage:>9} {outside:>9} {max_diff:>12.3e}",
                    format!("{culling:?}")
                );
                assert!(
                    coverage <= 1,
                    "{name} {resolution} {culling:?}: {coverage} texels covered by one side only"
                );
                assert!(
                    outside <= 1,
                    "{name} {resolution} {culling:?}: {outside} texels beyond the depth bound"
                );
            }
        }
    }
}

/// The device's polygon offset: `units` as the CPU's (r of an f32 map), and the slope m as the
/// max-norm max(|∂z/∂x|, |∂z/∂y|) that Vulkan allows instead of the CPU's |∇z|, so that the
/// device's slope offset is between 1/√2 and 1 times the CPU's. Measured as the offset a
/// factor of 1 adds to each map, on texels whose offset is at least 10⁻⁵; at least 95 % of them
/// fall in that range (the rest are texels where the offset changes which surface is nearest).
#[test]
fn depth_bias_slope_is_the_max_norm() {
    let gpu = gpu();
    let plain = RasterSettings::default();
    let offset = RasterSettings { slope_factor: 1.0, ..Default::default() };
    let units = RasterSettings { slope_units: 8.0, ..Default::default() };
    for name in SCENES {
        let scene = common::bundled(name);
        let view = LightView::new(&scene.lights[0], scene.bounds(), 1024);
        let (cp, cs) = (rasterize_nearest(&scene, &view, &plain), rasterize_nearest(&scene, &view, &offset));
        let (gp, gs) = (gpu_layer(&gpu, &scene, &view, &plain), gpu_layer(&gpu, &scene, &view, &offset));
        let (mut inside, mut total) = (0usize, 0usize);
        for i in 0..cp.depth.len() {
            let (oc, og) = (cs.depth[i] - cp.depth[i], gs.depth[i] - gp.depth[i]);
            if cs.depth[i] < 1.0 && oc >= 1e-5 {
                total += 1;
                inside += (0.70..=1.01).contains(&(og / oc)) as usize;
            }
        }
        let share = inside as f64 / total.max(1) as f64;
        println!("{name:14} slope offset ratio in [0.70, 1.01] on {share:.4} of {total} texels");
        assert!(total > 0 && share >= 0.95, "{name}: {share}");
        // `units` alone: the same r on both sides, up to the depth-plane difference above.
        let (cu, gu) = (rasterize_nearest(&scene, &view, &units), gpu_layer(&gpu, &scene, &view, &units));
        for i in 0..cu.depth.len() {
            if cu.depth[i] < 0.999 && cp.depth[i] < 1.0 {
                let (oc, og) = (cu.depth[i] - cp.depth[i], gu.depth[i] - gp.depth[i]);
                assert!((oc - og).abs() <= 1e-6 + 0.01 * oc, "{name} texel {i}: offsets {oc} and {og}");
            }
        }
    }
}

const TECHNIQUES: [&str; 9] = [
    r#"{"technique": "none"}"#,
    r#"{"technique": "constant", "bias_depth": 0.0005}"#,
    r#"{"technique": "constant", "bias_world": 0.02}"#,
    r#"{"technique": "slope_scaled", "factor": 1.5, "units": 2}"#,
    r#"{"technique": "normal_offset", "scale_texels": 1.0}"#,
    r#"{"technique": "pcf", "kernel": "box", "size": 3, "bias_depth": 0.0005}"#,
    r#"{"technique": "pcf", "kernel": "box", "size": 4, "bias": "slope_scaled", "factor": 1.5, "units": 2}"#,
    r#"{"technique": "pcf", "kernel": "bilinear", "bias_depth": 0.0005}"#,
    r#"{"technique": "pcf", "kernel": "bilinear", "bias": "slope_scaled", "factor": 1.5, "units": 2}"#,
];

/// A tap coordinate closer than this (in texels) to a texel boundary may read either texel.
const EDGE_TEXELS: f32 = 1e-3;

/// Whether every tap of `spec` at the receiver of pixel i lies at least `EDGE_TEXELS` from a
/// texel boundary: the taps of a receiver at texel-space (x, y) = (u·N, (1 − v)·N) sit at x + a
/// for whole a (point tests, odd boxes), x + ½ + a (even boxes) or x − ½ + a (bilinear), and
/// likewise in y; normal offset projects the moved receiver.
fn away_from_texel_edges(spec: &TechniqueSpec, view: &LightView, g: &GBuffer, i: usize) -> bool {
    let (mut p, normal) = (g.position[i], g.normal[i]);
    let shift = match GpuTechnique::from_spec(spec).unwrap() {
        GpuTechnique::PcfBox { size, .. } => (size as f32 - 1.0) * 0.5,
        GpuTechnique::PcfBilinear { .. } => 0.5,
        GpuTechnique::NormalOffset { scale_texels, one_minus_n_dot_l } => {
            let l = view.to_light.unwrap_or_else(|| (view.position.unwrap() - p).normalize());
            let n_dot_l = normal.dot(l).clamp(0.0, 1.0);
            let g = if one_minus_n_dot_l { 1.0 - n_dot_l } else { (1.0 - n_dot_l * n_dot_l).max(0.0).sqrt() };
            p += normal * (scale_texels * view.texel_world_size(p) * g);
            0.0
        }
        _ => 0.0,
    };
    let Some(uvd) = view.project(p) else { return true };
    let n = view.resolution as f32;
    let clear = |t: f32| {
        let f = (t - shift).rem_euclid(1.0);
        f.min(1.0 - f) >= EDGE_TEXELS
    };
    clear(uvd.x * n) && clear((1.0 - uvd.y) * n)
}

/// Share of the evaluated pixels away from texel edges whose visibility agrees (within 10⁻⁶: the
/// hardware's bilinear weights round differently), and the share of pixels so counted.
fn agreement(spec: &TechniqueSpec, view: &LightView, g: &GBuffer, cpu: &[f32], gpu: &[f32]) -> (f64, f64) {
    let (mut counted, mut agree) = (0usize, 0usize);
    for &i in &g.evaluated {
        let i = i as usize;
        if away_from_texel_edges(spec, view, g, i) {
            counted += 1;
            agree += ((cpu[i] - gpu[i]).abs() <= 1e-6) as usize;
        }
    }
    (agree as f64 / counted.max(1) as f64, counted as f64 / g.evaluated.len().max(1) as f64)
}

/// The fragment shader's shadow tests against the CPU techniques, on the G-buffer's surface
/// points at 1024². `shared`: the GPU shades the CPU's own depth layer (uploaded), so only the
/// shading differs: ≥ 99.9 % of the pixels away from texel edges agree. `full`: the GPU shades
/// its own map; printed, and ≥ 99 % for the maps without a slope offset (whose depths differ
/// as `depth_map_matches_the_cpu_rasterizer` bounds; with one, the slopes differ as
/// `depth_bias_slope_is_the_max_norm` shows).
#[test]
fn gpu_shading_agrees_with_the_cpu_techniques() {
    let gpu = gpu();
    println!("{:14} {:72} {:>8} {:>8} {:>8}", "scene", "technique", "counted", "shared", "full");
    for name in SCENES {
        let scene = common::bundled(name);
        let (g, _) = common::trace_first(&scene);
        let view = LightView::new(&scene.lights[0], scene.bounds(), 1024);
        for json in TECHNIQUES {
            let spec: TechniqueSpec = serde_json::from_str(json).unwrap();
            let technique = GpuTechnique::from_spec(&spec).unwrap();
            let layers = shadowtruth::rasterize_layers(&scene, &view, DepthFormat::F32, &spec).unwrap();
            let cpu = shadowtruth::shade_technique(&spec, &scene, &g, &view, &layers).unwrap();
            let BuiltLayers::Nearest(layer) = &layers else { panic!("{json} reads one layer") };
            let shared = GpuDepthMap::upload(&gpu, layer).unwrap();
            let shared = shade_visibility(&gpu, &g, &view, &shared, technique).unwrap();
            let own =
                GpuDepthMap::render(&gpu, &scene, &view, &GpuTechnique::raster_settings(&spec)).unwrap();
            let full = shade_visibility(&gpu, &g, &view, &own, technique).unwrap();
            let (shared_agree, counted) = agreement(&spec, &view, &g, &cpu, &shared);
            let (full_agree, _) = agreement(&spec, &view, &g, &cpu, &full);
            println!("{name:14} {:72} {counted:>8.4} {shared_agree:>8.5} {full_agree:>8.5}", spec.label());
            assert!(shared_agree >= 0.999, "{name} {}: {shared_agree}", spec.label());
            let slope = GpuTechnique::raster_settings(&spec).slope_factor != 0.0;
            assert!(slope || full_agree >= 0.99, "{name} {}: {full_agree}", spec.label());
        }
    }
}

/// The GPU's visibility scores through the same path as the CPU's: identical buffers give
/// identical counts, and an unsupported technique is refused by name.
#[test]
fn gpu_visibility_scores_like_the_cpu_and_refuses_other_techniques() {
    let gpu = gpu();
    let scene = common::bundled("plane_box");
    let (g, r) = common::trace_first(&scene);
    let view = LightView::new(&scene.lights[0], scene.bounds(), 2048);
    let spec: TechniqueSpec =
        serde_json::from_str(r#"{"technique": "constant", "bias_depth": 0.0005}"#).unwrap();
    let layers = shadowtruth::rasterize_layers(&scene, &view, DepthFormat::F32, &spec).unwrap();
    let cpu = shadowtruth::shade_technique(&spec, &scene, &g, &view, &layers).unwrap();
    let BuiltLayers::Nearest(layer) = &layers else { panic!() };
    let map = GpuDepthMap::upload(&gpu, layer).unwrap();
    let visibility =
        shade_visibility(&gpu, &g, &view, &map, GpuTechnique::from_spec(&spec).unwrap()).unwrap();
    assert_eq!(visibility.len(), g.pixel_count());
    let uploaded = map.read_back(&gpu).unwrap();
    assert_eq!(&uploaded, layer, "the upload keeps every depth bit");
    let (c, v) = (
        shadowtruth::score_visibility(&g, &r, &cpu).unwrap(),
        shadowtruth::score_visibility(&g, &r, &visibility).unwrap(),
    );
    assert_eq!((c.evaluated, c.false_shadow, c.false_lit), (v.evaluated, v.false_shadow, v.false_lit));
    for json in [
        r#"{"technique": "receiver_plane"}"#,
        r#"{"technique": "pcf", "kernel": "poisson"}"#,
        r#"{"technique": "pcf", "layers": "midpoint"}"#,
    ] {
        let spec: TechniqueSpec = serde_json::from_str(json).unwrap();
        let e = GpuTechnique::from_spec(&spec).unwrap_err().to_string();
        assert!(e.contains(&spec.label()) && e.contains("no GPU implementation"), "{e}");
    }
}

/// The CPU rasterizer's `DepthPlane::Exact` (the plane through the unsnapped vertices) against
/// the device's map: the largest depth difference over texels both cover, per depth-plane mode.
/// Exact is within 10⁻⁵ everywhere and at least ten times closer than snapped (measured: 10 to
/// 140 times; docs/conventions.md, "Rasterizer", holds the table).
#[test]
fn exact_depth_plane_matches_the_gpu_more_closely() {
    use shadowtruth::raster::DepthPlane;
    let gpu = gpu();
    println!("{:14} {:>5} {:>12} {:>12}", "scene", "N", "snapped", "exact");
    for name in SCENES {
        let scene = common::bundled(name);
        for resolution in [256u32, 1024, 2048] {
            let view = LightView::new(&scene.lights[0], scene.bounds(), resolution);
            let device = gpu_layer(&gpu, &scene, &view, &RasterSettings::default());
            let max_diff = |depth_plane| {
                let cpu =
                    rasterize_nearest(&scene, &view, &RasterSettings { depth_plane, ..Default::default() });
                let both = cpu.depth.iter().zip(&device.depth).filter(|(c, g)| **c < 1.0 && **g < 1.0);
                both.map(|(c, g)| (c - g).abs()).fold(0.0f32, f32::max)
            };
            let (snapped, exact) = (max_diff(DepthPlane::Snapped), max_diff(DepthPlane::Exact));
            println!("{name:14} {resolution:>5} {snapped:>12.3e} {exact:>12.3e}");
            assert!(
                exact <= 1e-5 && exact * 10.0 <= snapped,
                "{name} {resolution}: exact {exact:e}, snapped {snapped:e}"
            );
        }
    }
}

/// A point light's cube (scenes/point/room.json, faces of 512² plus a guard band of 8 texels):
/// each face drawn by the device against the CPU rasterizer under the bounds of
/// `depth_map_matches_the_cpu_rasterizer`, and each face's pixels shaded through its own map (the
/// GPU's and the CPU's) agreeing as `gpu_shading_agrees_with_the_cpu_techniques` requires.
#[test]
fn cube_faces_match_the_cpu() {
    let gpu = gpu();
    let scene = shadowtruth::load_scene(common::repo().join("scenes/point/room.json")).unwrap();
    let light = &scene.lights[0];
    let cube = shadowtruth::cube_map(light, 512).unwrap();
    assert_eq!(cube.guard_texels, 8);
    let g = GBuffer::trace(&shadowtruth::SceneBvh::build(&scene), &scene.cameras[0], light);
    println!(
        "{:4} {:>8} {:>9} {:>9} {:72} {:>8} {:>8}",
        "face", "pixels", "coverage", "outside", "technique", "counted", "full"
    );
    for (f, view) in cube.faces.iter().enumerate() {
        let settings = RasterSettings::default();
        let cpu = rasterize_nearest(&scene, view, &settings);
        let gpu_map = gpu_layer(&gpu, &scene, view, &settings);
        let n = view.resolution as usize;
        let (mut coverage, mut outside) = (0, 0);
        for row in 0..n {
            for x in 0..n {
                let (c, d) = (cpu.depth[row * n + x], gpu_map.depth[row * n + x]);
                if (c < 1.0) != (d < 1.0) {
                    coverage += 1;
                } else {
                    outside += ((c - d).abs() > local_step(&cpu, x, row) / 64.0 + 4e-6) as u32;
                }
            }
        }
        assert!(coverage <= 1 && outside <= 1, "face {f}: {coverage} coverage, {outside} depth differences");
        // The face's own pixels: those whose direction from the light it is chosen for.
        let mut on_face = g.clone();
        on_face.evaluated.retain(|&i| cube.face_of(g.position[i as usize]) == f);
        for json in TECHNIQUES {
            let spec: TechniqueSpec = serde_json::from_str(json).unwrap();
            let technique = GpuTechnique::from_spec(&spec).unwrap();
            let layers = shadowtruth::rasterize_layers(&scene, view, DepthFormat::F32, &spec).unwrap();
            let cpu_visibility =
                shadowtruth::shade_technique(&spec, &scene, &on_face, view, &layers).unwrap();
            let own = GpuDepthMap::render(&gpu, &scene, view, &GpuTechnique::raster_settings(&spec)).unwrap();
            let full = shade_visibility(&gpu, &on_face, view, &own, technique).unwrap();
            let (full_agree, counted) = agreement(&spec, view, &on_face, &cpu_visibility, &full);
            let pixels = on_face.evaluated.len();
            println!(
                "{f:4} {pixels:>8} {coverage:>9} {outside:>9} {:72} {counted:>8.4} {full_agree:>8.5}",
                spec.label()
            );
            let slope = GpuTechnique::raster_settings(&spec).slope_factor != 0.0;
            assert!(slope || full_agree >= 0.99, "face {f} {}: {full_agree}", spec.label());
        }
    }
}

/// The casters are streamed to the device in chunks of bounded size, so that a scene past the
/// adapter's buffer limit is drawn (chunk by chunk) instead of refused: the map is the same bits
/// whatever the chunk size, down to one triangle per draw, closed objects' chunks before open
/// ones' as one draw of each would order them.
#[test]
fn a_map_drawn_in_chunks_is_the_map_drawn_at_once() {
    let gpu = gpu();
    for name in ["plane_box", "rocks"] {
        let scene = common::bundled(name);
        let view = LightView::new(&scene.lights[0], scene.bounds(), 512);
        for culling in [Culling::None, Culling::BackFacesOfClosed] {
            let settings = RasterSettings { culling, ..RasterSettings::default() };
            let whole = gpu_layer(&gpu, &scene, &view, &settings);
            let triangles = scene.triangle_count();
            for chunk in [1, 7, triangles / 3 + 1, triangles] {
                let map = GpuDepthMap::render_in_chunks(&gpu, &scene, &view, &settings, chunk).unwrap();
                let layer = map.read_back(&gpu).unwrap();
                let bits = |l: &DepthLayer| l.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
                assert!(bits(&layer) == bits(&whole), "{name} {culling:?}: chunks of {chunk} triangles");
            }
        }
    }
}

/// Placed meshes are drawn by instanced draws (the mesh once, one f32 transform per placement,
/// as an engine draws them), where the CPU places each vertex in f64 and rounds once: the maps
/// differ only where a texel centre lies within that rounding of an edge. Checked on instanced
/// spheres (rotated, non-uniformly scaled and mirrored, so that culling must follow the swapped
/// winding) and boxes over a flat ground, under a sun and a spot, with each culling: the same
/// bounds as the flat scenes' maps, and the same bits whatever the draws' chunk size.
#[test]
fn instanced_meshes_drawn_instanced_match_the_cpu_rasterizer() {
    use serde_json::json;
    let placements: Vec<_> = (0..12)
        .map(|i| {
            let scale = match i % 3 {
                0 => json!([1.0, 1.3, 1.0]),
                1 => json!([0.7, 1.9, 0.9]),
                _ => json!([-0.8, 1.1, 0.8]),
            };
            json!({ "scale": scale, "rotate_deg": [7.0 * i as f64, 33.0 * i as f64 + 11.0, -5.0 * i as f64],
                    "translate": [(i % 4) as f64 * 2.6 - 4.0, 0.4 + 0.1 * i as f64, (i / 4) as f64 * 2.9 - 3.0] })
        })
        .collect();
    let scene = common::scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "placed",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [14, 14], "subdivisions": 4 } },
            { "name": "tree", "shape": { "type": "sphere", "radius": 0.6, "segments": 24, "rings": 12 },
              "closed": true, "instances": placements },
            { "name": "rock", "shape": { "type": "box", "size": [0.5, 0.3, 0.4] }, "closed": true,
              "instances": [{ "translate": [1.1, 0.15, 1.2] }, { "rotate_deg": [0, 45, 0], "translate": [-1.5, 0.15, 0.5] }] }
        ],
        "cameras": [{ "name": "cam", "position": [-7, 6, 8], "look_at": [0, 0.5, 0], "fov_y_deg": 50, "width": 64, "height": 48 }],
        "lights": [
            { "name": "sun", "type": "directional", "direction": [-0.35, -1, -0.25] },
            { "name": "lamp", "type": "spot", "position": [2, 7, 3], "direction": [-0.3, -1, -0.4], "cone_deg": 80, "near": 0.5, "far": 30 }
        ]
    }));
    assert_eq!(scene.instances.len(), 14, "the spheres and boxes are placed, not flattened");
    assert!(scene.instances.iter().any(|i| i.mirrored), "some placements mirror");
    let mut ground_only = scene.clone();
    ground_only.instances.clear();
    let gpu = gpu();
    for light in &scene.lights {
        for resolution in [512u32, 1024] {
            let view = LightView::new(light, scene.bounds(), resolution);
            let ground = rasterize_nearest(&ground_only, &view, &RasterSettings::default());
            for culling in [Culling::None, Culling::BackFacesOfClosed, Culling::FrontFacesOfClosed] {
                let settings = RasterSettings { culling, ..Default::default() };
                let cpu = rasterize_nearest(&scene, &view, &settings);
                let whole = gpu_layer(&gpu, &scene, &view, &settings);
                let n = resolution as usize;
                let placed = cpu.depth.iter().zip(&ground.depth).filter(|(c, g)| c < g).count();
                let MapDifferences { coverage, outside, .. } = differences(&cpu, &whole);
                let case = format!("{} {resolution} {culling:?}", light.name);
                println!(
                    "{case}: {placed} texels of placements, {coverage} covered by one side only, {outside} beyond the depth bound"
                );
                assert!(placed > n * n / 100, "{case}: the placements are in the map");
                assert!(coverage <= 1, "{case}: {coverage} texels covered by one side only");
                assert!(outside <= 1, "{case}: {outside} texels beyond the depth bound");
                for chunk in [1, 5] {
                    let map = GpuDepthMap::render_in_chunks(&gpu, &scene, &view, &settings, chunk).unwrap();
                    let bits = |l: &DepthLayer| l.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
                    let layer = map.read_back(&gpu).unwrap();
                    assert!(bits(&layer) == bits(&whole), "{case}: chunks of {chunk}");
                }
            }
        }
    }
}
