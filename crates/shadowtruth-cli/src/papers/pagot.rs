//! Pagot, Comba & Oliveira, "Multiple-depth shadow maps" (SIBGRAPI 2004), Table 1 and Fig. 6, on
//! the plane of `scenes/papers/casters.json`.
//!
//! Fig. 6 shows a shadow on a plane at 512² and says the 3-SM with 3×3 PCF gives edges
//! comparable to the 1-SM with 4×4 PCF, and smoother. The n-SM's extra depths are the min and
//! max over each texel's 3×3 neighbourhood, so on a plane tilted to the light they lie up to a
//! texel's depth step nearer than the receiver, and a tap reads them one texel further out: both
//! filters get the same constant bias, [`REACH_TEXELS`] depth steps of the plane, which covers
//! every depth either reads. Judged on edge smoothness (distinct levels along the edges) and on
//! the difference between the two filters; MAE against pixel coverage is reported beside.
//! Table 1: PCF(k, n) takes at most n·k + 1 values.

use super::claims::{self, Claim, ClaimText, EdgeNumbers, SetupResult};
use super::measure::{LightMap, View, distinct_levels, interior_levels, light_of, shade, spec};
use super::names::PLANE;
use super::suite::{Suite, plan_of};
use crate::plan::{DEFAULT_COVERAGE_GRID, PlanError};
use serde_json::json;
use shadowtruth::metrics::score_soft;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::technique::{TechniqueSpec, receiver_plane_slope};
use shadowtruth::trace::SceneBvh;

const RESOLUTION: u32 = 512;
/// Depth steps (texels of the plane's slope, in u plus v) the bias covers: a 3×3 tap one texel
/// out reads a neighbourhood one more texel out, plus the receiver's offset within its texel;
/// the 4×4 taps reach no further.
const REACH_TEXELS: f64 = 3.0;
const PAGOT: &str = "Pagot, Comba & Oliveira, Multiple-depth shadow maps (SIBGRAPI 2004)";

struct PagotSetup {
    name: &'static str,
    light: &'static str,
    resolution: u32,
}

fn setups() -> Vec<PagotSetup> {
    let s = |name, light, resolution| PagotSetup { name, light, resolution };
    vec![
        s("paper: directional light, 512²", "sun", RESOLUTION),
        s("256² map", "sun", 256),
        s("1024² map", "sun", 1024),
        s("spot light, 512²", "spot", RESOLUTION),
    ]
}

/// The two filters with the bias that covers the extra depths of the plane in `map`.
fn filters(scene: &Scene, map: &LightMap) -> [TechniqueSpec; 2] {
    let plane = scene.objects.iter().find(|o| o.name == PLANE).expect("casters.json has its plane");
    let tri = &scene.triangle(plane.first_triangle);
    let (z_u, z_v) = receiver_plane_slope(&map.view, tri).unwrap_or((0.0, 0.0));
    let bias = REACH_TEXELS * (z_u.abs() + z_v.abs()) / map.view.resolution as f64;
    let mdsm = |depths, size| {
        spec(&format!(
            r#"{{ "technique": "mdsm", "depths": {depths}, "neighbourhood": 3, "select": "min_max",
                 "kernel": "box", "size": {size}, "bias": "constant", "bias_depth": {bias:e} }}"#
        ))
    };
    [mdsm(3, 3), mdsm(1, 4)]
}

fn edges(v3: &[f32], v1: &[f32], on_plane: &[bool]) -> EdgeNumbers {
    let plane = |v: &[f32]| -> Vec<f32> { v.iter().zip(on_plane).filter(|p| *p.1).map(|p| *p.0).collect() };
    let (p3, p1) = (plane(v3), plane(v1));
    let inside = |x: f32| x > 0.0 && x < 1.0;
    let edge: Vec<f64> = p3
        .iter()
        .zip(&p1)
        .filter(|(a, b)| inside(**a) || inside(**b))
        .map(|(a, b)| (a - b).abs() as f64)
        .collect();
    EdgeNumbers {
        levels_3sm_3x3: interior_levels(p3.iter()),
        levels_1sm_4x4: interior_levels(p1.iter()),
        edge_pixels: edge.len() as u64,
        edge_mean_difference: edge.iter().sum::<f64>() / edge.len().max(1) as f64,
    }
}

/// Table 1's and Fig. 6's results on one set-up.
fn measure(
    suite: &Suite,
    scene: &Scene,
    bvh: &SceneBvh,
    setup: &PagotSetup,
) -> Result<[SetupResult; 2], PlanError> {
    let view = View::trace(scene, bvh, "main", light_of(scene, setup.light)?)?;
    let map = LightMap::new(&view, setup.resolution);
    let [f3, f1] = filters(scene, &map);
    let (v3, v1) = (shade(&view, &map, &f3, None, 1).visibility, shade(&view, &map, &f1, None, 1).visibility);
    let camera = scene.camera("main").expect("traced above");
    let coverage = suite
        .cache
        .coverage_reference(scene, bvh, &view.gbuffer, camera, &view.light, DEFAULT_COVERAGE_GRID)
        .map_err(|source| PlanError::Io { path: suite.cache.dir().to_path_buf(), source })?
        .0;
    let mae = |v: &[f32]| score_soft(&view.gbuffer, &coverage.visibility, v).mae;
    let all = |v: &[f32]| distinct_levels(v.iter());
    let configs = [(9u32, 3u32, all(&v3)), (16, 1, all(&v1))];
    let about = json!({ "light": setup.light, "resolution": setup.resolution, "techniques": [f3.label(), f1.label()] });
    let mut table1 = about.clone();
    table1["configurations"] = configs
        .iter()
        .map(|&(k, n, d)| json!({ "k": k, "n": n, "bound": n * k + 1, "distinct": d }))
        .collect();
    let e = edges(&v3, &v1, &view.on_objects(|name| name == PLANE));
    let mut fig6 = about;
    fig6["edges"] = serde_json::to_value(e).expect("plain numbers");
    fig6["mae_against_coverage"] = json!({ "3sm_pcf3x3": mae(&v3), "1sm_pcf4x4": mae(&v1) });
    Ok([
        SetupResult::new(setup.name, table1, claims::pagot_table1(&configs)),
        SetupResult::new(setup.name, fig6, claims::pagot_fig6(&e)),
    ])
}

/// Table 1 and Fig. 6.
pub(super) fn claims(suite: &mut Suite) -> Result<Vec<Claim>, PlanError> {
    let path = suite.scene("casters.json");
    let scene = load_scene(&path)?;
    let bvh = SceneBvh::build(&scene);
    let sun = View::trace(&scene, &bvh, "main", light_of(&scene, "sun")?)?;
    let techniques = filters(&scene, &LightMap::new(&sun, RESOLUTION)).to_vec();
    let runs = suite.report(&plan_of(&path, &["main"], "sun", techniques.clone(), &[RESOLUTION]))?;
    let error_maps = techniques.iter().filter_map(|t| runs.error_map("main", t, RESOLUTION)).collect();
    suite.stage("Pagot et al. set-ups")?;
    let (mut table1, mut fig6) = (Vec::new(), Vec::new());
    for setup in suite.grid(setups()) {
        let [t, f] = measure(suite, &scene, &bvh, &setup)?;
        table1.push(t);
        fig6.push(f);
    }
    let setup = "scenes/papers/casters.json under the directional light at 512² (the paper shows a shadow on a \
                 plane), both \
                 filters with a constant bias of 3 depth steps of the plane, which covers the n-SM's extra depths \
                 (min and max over 3×3 texels) and every tap's reach.";
    Ok(vec![
        Claim::judged(
            ClaimText {
                id: "pagot2004-table1".into(),
                paper: PAGOT,
                statement: "PCF(k, n) over k taps of an n-depth map takes at most n·k + 1 distinct values.",
                setup,
                rule: "each configuration reaches n·k + 1 distinct values (it cannot exceed them by construction: \
                       the mean of k taps of n + 1 levels is one of n·k + 1 fractions); exceeding them would not \
                       hold. Two configurations are measured (3-SM 3×3, 1-SM 4×4), not the table's every cell.",
            },
            table1,
            vec![],
        ),
        Claim::judged(
            ClaimText {
                id: "pagot2004-fig6".into(),
                paper: PAGOT,
                statement: "A 3-SM with 3×3 PCF gives shadow edges comparable to, and smoother than, a 1-SM with 4×4 \
                            PCF.",
                setup,
                rule: "on the plane: more distinct levels strictly between 0 and 1 with the 3-SM (smoother); mean \
                       |v₃ − v₁| over the pixels where either is strictly between 0 and 1 ≤ 0.125 (comparable); \
                       MAE against pixel coverage reported, not judged",
            },
            fig6,
            error_maps,
        ),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_count_levels_and_differences_on_the_plane_only() {
        let v3 = [0.0, 0.25, 0.5, 1.0, 0.5];
        let v1 = [0.0, 0.25, 0.25, 1.0, 0.75];
        let e = edges(&v3, &v1, &[true, true, true, true, false]);
        assert_eq!((e.levels_3sm_3x3, e.levels_1sm_4x4, e.edge_pixels), (2, 1, 2));
        assert_eq!(e.edge_mean_difference, 0.125);
    }
}
