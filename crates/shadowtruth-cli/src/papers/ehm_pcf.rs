//! Ehm et al. (WSCG 2015), Fig. 4, on `scenes/papers/casters.json`: a sphere, a box
//! and a cylinder floating over a plane, 11×11 PCF with receiver-plane depth bias, with the
//! adaptive bias per tap and with the Δbias optimisation (Algorithm 1).
//!
//! Fig. 4's two difference images set receiver-plane bias against the adaptive bias, and
//! against Δbias; the paper sees "small differences in the self shadow, however no differences
//! in the shadows cast on the plane". Each pair is a claim, judged on the plane's pixels (every
//! shadow on it is cast by another object) and on the casters' (their self shadows). Adaptive
//! against Δbias is the same function here (both extrapolate the post-projective depth, which
//! is exactly affine on a triangle, where the paper's Δbias approximates), so their difference
//! is 0 by construction: it is reported beside, never judged. (What they cost is `ehm_cost.rs`.)
//! The sensitivity grid moves the resolution, K and the light (spot or directional).

use super::claims::{self, Agreement, Claim, ClaimText, DIFFERENT_VISIBILITY, SetupResult};
use super::measure::{LightMap, View, light_of, shade, spec};
use super::names::{EHM, PLANE};
use super::suite::{Suite, plan_of};
use crate::plan::PlanError;
use serde_json::json;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::trace::SceneBvh;

/// The paper's filter: 11×11 PCF; its K; the map resolution.
const RESOLUTION: u32 = 2048;
const K: f32 = 0.0001;
/// The paper's 11×11 PCF.
const SIDE: u32 = 11;

struct PcfSetup {
    name: &'static str,
    light: &'static str,
    resolution: u32,
    k: f32,
}

fn setups() -> Vec<PcfSetup> {
    let s = |name, light, resolution, k| PcfSetup { name, light, resolution, k };
    vec![
        s("paper: spot light, 2048², K = 0.0001", "spot", RESOLUTION, K),
        s("1024² map", "spot", 1024, K),
        s("K = 0.001", "spot", RESOLUTION, 0.001),
        s("directional light", "sun", RESOLUTION, K),
    ]
}

/// Box PCF of `side`² taps with the per-tap `bias` (`receiver_plane` with the set-up's depth bias
/// of 1e-5, or `adaptive` / `adaptive_delta` with `k`), as JSON. Fig. 4 filters 11×11; the cost
/// claims (`ehm_cost.rs`) every odd side up to it.
pub(super) fn pcf(bias: &str, side: u32, k: f32) -> String {
    match bias {
        "receiver_plane" => format!(
            r#"{{ "technique": "pcf", "kernel": "box", "size": {side}, "bias": "receiver_plane", "bias_depth": 0.00001 }}"#
        ),
        _ => format!(
            r#"{{ "technique": "pcf", "kernel": "box", "size": {side}, "bias": "{bias}", "k": {k} }}"#
        ),
    }
}

/// The per-pixel agreement of `a` and `b` on the plane (`on_plane`) and elsewhere.
fn agreement(a: &[f32], b: &[f32], on_plane: &[bool]) -> Agreement {
    let mut n = Agreement::default();
    for ((x, y), &plane) in a.iter().zip(b).zip(on_plane) {
        let d = (x - y).abs();
        let differs = (d > DIFFERENT_VISIBILITY) as u64;
        if plane {
            (n.cast_pixels, n.cast_differing) = (n.cast_pixels + 1, n.cast_differing + differs);
        } else {
            (n.self_pixels, n.self_differing) = (n.self_pixels + 1, n.self_differing + differs);
        }
        n.largest_difference = n.largest_difference.max(d);
    }
    n
}

/// Fig. 4's two pairs' results on one set-up.
fn measure(scene: &Scene, bvh: &SceneBvh, setup: &PcfSetup) -> Result<[SetupResult; 2], PlanError> {
    let view = View::trace(scene, bvh, "main", light_of(scene, setup.light)?)?;
    let map = LightMap::new(&view, setup.resolution);
    let run = |bias| shade(&view, &map, &spec(&pcf(bias, SIDE, setup.k)), None, 1);
    let (rp, adaptive, delta) = (run("receiver_plane"), run("adaptive"), run("adaptive_delta"));
    let on_plane = view.on_objects(|name| name == PLANE);
    let against_rp = |other: &[f32]| agreement(&rp.visibility, other, &on_plane);
    let (with_adaptive, with_delta) = (against_rp(&adaptive.visibility), against_rp(&delta.visibility));
    let same_by_construction = agreement(&adaptive.visibility, &delta.visibility, &on_plane);
    let about = json!({ "light": setup.light, "resolution": setup.resolution, "k": setup.k });
    let fig4 = |pair: &Agreement| {
        let mut numbers = about.clone();
        numbers["agreement"] = serde_json::to_value(pair).expect("plain numbers");
        numbers["adaptive_against_delta"] =
            serde_json::to_value(same_by_construction).expect("plain numbers");
        numbers
    };
    Ok([
        SetupResult::new(setup.name, fig4(&with_adaptive), claims::ehm_fig4(&with_adaptive)),
        SetupResult::new(setup.name, fig4(&with_delta), claims::ehm_fig4(&with_delta)),
    ])
}

/// Fig. 4.
pub(super) fn claims(suite: &mut Suite) -> Result<Vec<Claim>, PlanError> {
    let path = suite.scene("casters.json");
    let techniques =
        ["receiver_plane", "adaptive", "adaptive_delta"].map(|b| spec(&pcf(b, SIDE, K))).to_vec();
    let runs = suite.report(&plan_of(&path, &["main"], "spot", techniques.clone(), &[RESOLUTION]))?;
    let error_maps = |k: [usize; 2]| {
        k.iter().filter_map(|&k| runs.error_map("main", &techniques[k], RESOLUTION)).collect()
    };
    suite.stage("Ehm et al. Fig. 4 set-ups")?;
    let scene = load_scene(&path)?;
    let bvh = SceneBvh::build(&scene);
    let (mut fig4_adaptive, mut fig4_delta) = (Vec::new(), Vec::new());
    for setup in suite.grid(setups()) {
        let [a, d] = measure(&scene, &bvh, &setup)?;
        fig4_adaptive.push(a);
        fig4_delta.push(d);
    }
    let setup = "scenes/papers/casters.json: a sphere, a box and a cylinder floating over a plane under a spot \
                 light, 2048² perspective map, 11×11 box PCF, K = 0.0001, receiver-plane bias with a depth bias of \
                 1e-5 (the paper gives none); judged on the plane, where every shadow is cast, and on the casters, \
                 where they shadow themselves. Adaptive and Δbias are the same function here (exact \
                 extrapolation of the affine post-projective depth), so their difference, 0 by construction, is \
                 reported as adaptive_against_delta and not judged.";
    let fig4_rule = "plane pixels whose visibilities differ by more than 1e-6: ≤ 0.01 % (\"no differences in the \
                     shadows cast on the plane\"); casters' pixels that differ: at least one, and ≤ 1 % of them \
                     (\"small differences in the self shadow\")";
    let fig4 = |id: &str, statement, results, figures| {
        Claim::judged(
            ClaimText { id: id.into(), paper: EHM, statement, setup, rule: fig4_rule },
            results,
            figures,
        )
    };
    Ok(vec![
        fig4(
            "ehm2015-fig4-adaptive",
            "Receiver-plane depth bias against the adaptive bias per tap, 11×11 PCF: \"small differences in the self \
             shadow, however no differences in the shadows cast on the plane\".",
            fig4_adaptive,
            error_maps([0, 1]),
        ),
        fig4(
            "ehm2015-fig4-delta",
            "Receiver-plane depth bias against the adaptive bias with the Δbias optimisation, 11×11 PCF: small \
             differences in the self shadow, no differences in the shadows cast on the plane.",
            fig4_delta,
            error_maps([0, 2]),
        ),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agreement_counts_differences_past_the_threshold_by_region() {
        let a = [0.5, 0.5, 0.5, 0.25];
        let b = [0.5, 0.5 + 2e-6, 0.5 + 0.5e-6, 0.75];
        let n = agreement(&a, &b, &[true, true, true, false]);
        assert_eq!((n.cast_pixels, n.cast_differing, n.self_pixels, n.self_differing), (3, 1, 1, 1));
        assert_eq!(n.largest_difference, 0.5);
    }
}
