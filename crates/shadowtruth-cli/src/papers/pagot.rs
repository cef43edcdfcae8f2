//! Pagot, Comba & Oliveira, "Multiple-depth shadow maps" (SIBGRAPI 2004), Table 1 and Fig. 6, on
//! the plane of `scenes/papers/casters.json`.
//!
//! Fig. 6 shows a shadow on a plane at 512² and says the 3-SM with 3×3 PCF gives edges
//! comparable to the 1-SM with 4×4 PCF, and smoother; its other pair sets the 3-SM with 2×2 PCF
//! against the 1-SM with 3×3. The n-SM's extra depths are the min and
//! max over each texel's 3×3 neighbourhood, so on a plane tilted to the light they lie up to a
//! texel's depth step nearer than the receiver, and a tap reads them one texel further out: both
//! filters get the same constant bias, [`REACH_TEXELS`] depth steps of the plane, which covers
//! every depth either reads. Each pair is judged on the difference between its two filters
//! along the edges; their distinct levels (the smoothness, which Table 1's bounds decide) and
//! MAE against pixel coverage are reported beside.
//! Table 1: PCF(k, n) takes at most n·k + 1 values, checked on every cell of n = 1 to 4 depths
//! and box kernels 1×1 to 10×10.

use super::claims::{self, Claim, ClaimText, EdgeNumbers, SetupResult};
use super::measure::{LightMap, View, distinct_levels, interior_levels, light_of, shade, spec};
use super::names::{PAGOT, PLANE};
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
/// A set-up of Pagot et al.'s experiments: a light of the scene and a map resolution.
pub(super) struct PagotSetup {
    pub name: &'static str,
    pub light: &'static str,
    pub resolution: u32,
}

/// The paper's set-up (the directional light `sun` at 512²), the same light at 256² and 1024²,
/// and `other` (its name in the grid, and the light) at 512².
pub(super) fn setups_with(other: (&'static str, &'static str)) -> Vec<PagotSetup> {
    let s = |name, light, resolution| PagotSetup { name, light, resolution };
    vec![
        s("paper: directional light, 512²", "sun", RESOLUTION),
        s("256² map", "sun", 256),
        s("1024² map", "sun", 1024),
        s(other.0, other.1, RESOLUTION),
    ]
}

/// Fig. 6's pairs (an n-SM's kernel side and depths, then the single map's kernel side).
const PAIRS: [(u32, u32); 2] = [(3, 4), (2, 3)];

/// An n-SM (`depths`, min and max over 3×3 texels) filtered by a `side`² box, with a constant
/// bias of `reach_texels` depth steps of the plane in `map`.
fn mdsm(scene: &Scene, map: &LightMap, depths: u32, side: u32, reach_texels: f64) -> TechniqueSpec {
    let plane = scene.objects.iter().find(|o| o.name == PLANE).expect("casters.json has its plane");
    let tri = &scene.triangle(plane.first_triangle);
    let (z_u, z_v) = receiver_plane_slope(&map.view, tri).unwrap_or((0.0, 0.0));
    let bias = reach_texels * (z_u.abs() + z_v.abs()) / map.view.resolution as f64;
    spec(&format!(
        r#"{{ "technique": "mdsm", "depths": {depths}, "neighbourhood": 3, "select": "min_max",
             "kernel": "box", "size": {side}, "bias": "constant", "bias_depth": {bias:e} }}"#
    ))
}

/// The four filters of Fig. 6: each pair's 3-SM, then its 1-SM.
fn filters(scene: &Scene, map: &LightMap) -> [TechniqueSpec; 4] {
    let f = |depths, side| mdsm(scene, map, depths, side, REACH_TEXELS);
    [f(3, PAIRS[0].0), f(1, PAIRS[0].1), f(3, PAIRS[1].0), f(1, PAIRS[1].1)]
}

/// Table 1's cells as (kernel side, depths): n = 1 to 4 depths, box kernels 1×1 to 10×10 (40
/// cells); quick runs measure Fig. 6's four filters only.
fn table1_cells(quick: bool) -> Vec<(u32, u32)> {
    if quick {
        return vec![(PAIRS[0].0, 3), (PAIRS[0].1, 1), (PAIRS[1].0, 3), (PAIRS[1].1, 1)];
    }
    (1..=4).flat_map(|depths| (1..=10).map(move |side| (side, depths))).collect()
}

/// The bias of a Table 1 cell, in depth steps of the plane: the farthest tap (half the kernel,
/// rounded up) plus the neighbourhood's texel, and never less than Fig. 6's.
fn cell_reach_texels(side: u32) -> f64 {
    ((side.div_ceil(2) + 1) as f64).max(REACH_TEXELS)
}

fn edges(v_multi: &[f32], v_single: &[f32], on_plane: &[bool]) -> EdgeNumbers {
    let plane = |v: &[f32]| -> Vec<f32> { v.iter().zip(on_plane).filter(|p| *p.1).map(|p| *p.0).collect() };
    let (p3, p1) = (plane(v_multi), plane(v_single));
    let inside = |x: f32| x > 0.0 && x < 1.0;
    let edge: Vec<f64> = p3
        .iter()
        .zip(&p1)
        .filter(|(a, b)| inside(**a) || inside(**b))
        .map(|(a, b)| (a - b).abs() as f64)
        .collect();
    EdgeNumbers {
        levels_multi: interior_levels(p3.iter()),
        levels_single: interior_levels(p1.iter()),
        edge_pixels: edge.len() as u64,
        edge_mean_difference: edge.iter().sum::<f64>() / edge.len().max(1) as f64,
    }
}

/// Table 1's and Fig. 6's two pairs' results on one set-up.
fn measure(
    suite: &Suite,
    scene: &Scene,
    bvh: &SceneBvh,
    setup: &PagotSetup,
) -> Result<[SetupResult; 3], PlanError> {
    let view = View::trace(scene, bvh, "main", light_of(scene, setup.light)?)?;
    let map = LightMap::new(&view, setup.resolution);
    let techniques = filters(scene, &map);
    let v = techniques.each_ref().map(|t| shade(&view, &map, t, None, 1).visibility);
    let camera = scene.camera("main").expect("traced above");
    let coverage = suite
        .cache
        .coverage_reference(scene, bvh, &view.gbuffer, camera, &view.light, DEFAULT_COVERAGE_GRID)
        .map_err(|source| PlanError::Io { path: suite.cache.dir().to_path_buf(), source })?
        .0;
    let mae = |v: &[f32]| score_soft(&view.gbuffer, &coverage.visibility, v).mae;
    let cells: Vec<(TechniqueSpec, u32, u32)> = table1_cells(suite.options.quick)
        .into_iter()
        .map(|(side, n)| (mdsm(scene, &map, n, side, cell_reach_texels(side)), side * side, n))
        .collect();
    // A cell that is one of Fig. 6's filters reads its visibility, shaded above.
    let levels = |t: &TechniqueSpec| match techniques.iter().position(|f| f == t) {
        Some(f) => distinct_levels(v[f].iter()),
        None => distinct_levels(shade(&view, &map, t, None, 1).visibility.iter()),
    };
    let configs: Vec<(u32, u32, usize)> = cells.iter().map(|(t, k, n)| (*k, *n, levels(t))).collect();
    let about = json!({ "light": setup.light, "resolution": setup.resolution });
    let mut table1 = about.clone();
    table1["configurations"] = configs
        .iter()
        .zip(&cells)
        .map(|(&(k, n, d), (t, ..))| json!({ "technique": t.label(), "k": k, "n": n, "bound": n * k + 1, "distinct": d }))
        .collect();
    let on_plane = view.on_objects(|name| name == PLANE);
    let fig6 = |pair: usize| {
        let (multi, single) = (2 * pair, 2 * pair + 1);
        let e = edges(&v[multi], &v[single], &on_plane);
        let mut numbers = about.clone();
        numbers["techniques"] = json!([techniques[multi].label(), techniques[single].label()]);
        numbers["edges"] = serde_json::to_value(e).expect("plain numbers");
        numbers["mae_against_coverage"] = json!({ "multi": mae(&v[multi]), "single": mae(&v[single]) });
        SetupResult::new(setup.name, numbers, claims::pagot_fig6(&e, PAIRS[pair].1))
    };
    Ok([SetupResult::new(setup.name, table1, claims::pagot_table1(&configs)), fig6(0), fig6(1)])
}

/// Table 1 and Fig. 6.
pub(super) fn claims(suite: &mut Suite) -> Result<Vec<Claim>, PlanError> {
    let path = suite.scene("casters.json");
    let scene = load_scene(&path)?;
    let bvh = SceneBvh::build(&scene);
    let sun = View::trace(&scene, &bvh, "main", light_of(&scene, "sun")?)?;
    let techniques = filters(&scene, &LightMap::new(&sun, RESOLUTION)).to_vec();
    let runs = suite.report(&plan_of(&path, &["main"], "sun", techniques.clone(), &[RESOLUTION]))?;
    let error_maps = |pair: usize| {
        techniques[2 * pair..2 * pair + 2]
            .iter()
            .filter_map(|t| runs.error_map("main", t, RESOLUTION))
            .collect()
    };
    suite.stage("Pagot et al. set-ups")?;
    let (mut table1, mut fig6, mut fig6_small) = (Vec::new(), Vec::new(), Vec::new());
    for setup in suite.grid(setups_with(("spot light, 512²", "spot"))) {
        let [t, f, g] = measure(suite, &scene, &bvh, &setup)?;
        table1.push(t);
        fig6.push(f);
        fig6_small.push(g);
    }
    let setup = "scenes/papers/casters.json under the directional light at 512² (the paper shows a shadow on a \
                 plane), every filter with a constant bias of 3 depth steps of the plane, which covers the n-SM's \
                 extra depths (min and max over 3×3 texels) and every tap's reach.";
    let fig6_rule = "on the plane, over the pixels where either filter is strictly between 0 and 1: mean \
                     |v_multi − v_single| ≤ two steps of the single map's filter (2/16 for 4×4, 2/9 for 3×3): \
                     comparable. \"Smoother\" (more distinct levels) is Table 1's bound, n·k + 1 values against \
                     k + 1, which pagot2004-table1 judges: the levels are reported, not judged twice; MAE against \
                     pixel coverage reported.";
    Ok(vec![
        Claim::judged(
            ClaimText {
                id: "pagot2004-table1".into(),
                paper: PAGOT,
                statement: "PCF(k, n) over k taps of an n-depth map takes at most n·k + 1 distinct values.",
                setup,
                rule: "each configuration reaches n·k + 1 distinct values (it cannot exceed them by construction: \
                       the mean of k taps of n + 1 levels is one of n·k + 1 fractions); exceeding them would not \
                       hold. Every cell n = 1 to 4 depths × box kernels 1×1 to 10×10 (k = 1 to 100) is measured, \
                       each a part, with a constant bias of the farthest tap's reach plus one texel in depth steps of \
                       the plane (at least 3); quick runs measure Fig. 6's four filters only.",
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
                rule: fig6_rule,
            },
            fig6,
            error_maps(0),
        ),
        Claim::judged(
            ClaimText {
                id: "pagot2004-fig6-2x2".into(),
                paper: PAGOT,
                statement: "Fig. 6's other pair: a 3-SM with 2×2 PCF against a 1-SM with 3×3 PCF, comparable edges.",
                setup,
                rule: fig6_rule,
            },
            fig6_small,
            error_maps(1),
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
        assert_eq!((e.levels_multi, e.levels_single, e.edge_pixels), (2, 1, 2));
        assert_eq!(e.edge_mean_difference, 0.125);
    }
}
