//! `shadowtruth papers --quick` end to end: the report, claims.json with one verdict per claim
//! and a sensitivity list that agrees with its summary, the page and the Figure 12 grid.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use serde_json::Value;
use std::collections::BTreeSet;
use std::process::Command;

const IDS: [&str; 29] = [
    "ehm2015-fig12-a-front",
    "ehm2015-fig12-c-back",
    "ehm2015-fig12-e-trunks",
    "ehm2015-fig12-f-back",
    "ehm2015-fig12-g-front",
    "ehm2015-fig12-h-trunks",
    "ehm2015-fig12-i-back",
    "ehm2015-fig12-enhanced-light-points",
    "ehm2015-fig4-adaptive",
    "ehm2015-fig4-delta",
    "ehm2015-table1",
    "ehm2015-s3.3-polygon-offset",
    "ehm2015-table2-pcss",
    "pagot2004-table1",
    "pagot2004-fig6",
    "pagot2004-fig6-2x2",
    "pagot2004-fig7-curved",
    "weiskopf2003-fig5-dual-r64",
    "weiskopf2003-fig5-b-midpoint-r64",
    "weiskopf2003-fig5-d-constant-r64",
    "weiskopf2003-fig6-bilinear-r64",
    "weiskopf2003-fig7-jittered-r64",
    "weiskopf2003-offset-dependence-r64",
    "weiskopf2003-fig5-dual-r128",
    "weiskopf2003-fig5-b-midpoint-r128",
    "weiskopf2003-fig5-d-constant-r128",
    "weiskopf2003-fig6-bilinear-r128",
    "weiskopf2003-fig7-jittered-r128",
    "weiskopf2003-offset-dependence-r128",
];
const VERDICTS: [&str; 3] = ["holds", "partly", "does_not_hold"];

/// The verdict of the paper's set-up.
fn setups_verdict(c: &Value) -> &str {
    c["sensitivity"][0]["verdict"].as_str().unwrap()
}

/// The summary as the three counts and the total: "holds in X of Y set-ups; partly in P; does
/// not hold in N".
fn parse_summary(s: &str) -> [usize; 4] {
    let numbers: Vec<usize> = s
        .split(|c: char| !c.is_ascii_digit())
        .filter(|w| !w.is_empty())
        .map(|w| w.parse().unwrap())
        .collect();
    assert!(s.starts_with("holds in ") && numbers.len() == 4, "summary {s:?}");
    [numbers[0], numbers[2], numbers[3], numbers[1]]
}

fn check_claim(c: &Value, out: &std::path::Path) {
    let verdict = c["verdict"].as_str().unwrap();
    assert!(VERDICTS.contains(&verdict) || verdict == "fragile", "{c}");
    // Every rule has tests: the margin names the one nearest to changing the verdict, and a
    // fragile verdict is one that holds on the paper's set-up by less than it moves.
    let (margin, spread) = (c["margin_fraction"].as_f64().unwrap(), c["margin_spread"].as_f64().unwrap());
    assert!(c["margin"].as_str().unwrap().contains('%'), "{}", c["margin"]);
    if verdict == "fragile" {
        assert!(setups_verdict(c) == "holds" && margin < spread, "{c}");
    } else if verdict == "holds" {
        assert!(margin >= spread, "{c}");
    }
    for key in ["paper", "statement", "setup", "rule", "sensitivity_summary"] {
        assert!(!c[key].as_str().unwrap().is_empty(), "{key} of {}", c["id"]);
    }
    assert!(!c["numbers"].as_object().unwrap().is_empty());
    let setups = c["sensitivity"].as_array().unwrap();
    // Quick: the paper's set-up and one other.
    assert_eq!(setups.len(), 2, "{}", c["id"]);
    if verdict != "fragile" {
        assert_eq!(setups[0]["verdict"], c["verdict"], "the claim's verdict is its paper set-up's");
    }
    assert!(!setups[0]["tests"].as_array().unwrap().is_empty(), "{}", c["id"]);
    assert_eq!(setups[0]["numbers"], c["numbers"]);
    assert!(setups[0]["setup"].as_str().unwrap().starts_with("paper"));
    let count = |v: &str| setups.iter().filter(|s| s["verdict"] == v).count();
    let [holds, partly, not, total] = parse_summary(c["sensitivity_summary"].as_str().unwrap());
    assert_eq!(
        [holds, partly, not, total],
        [count("holds"), count("partly"), count("does_not_hold"), setups.len()]
    );
    for s in setups {
        assert!(
            VERDICTS.contains(&s["verdict"].as_str().unwrap()) && !s["setup"].as_str().unwrap().is_empty()
        );
    }
    // A figure's claim shows its own set-up: the error maps of the runs it judges.
    let figures = c["figures"].as_array().unwrap();
    assert!(!c["id"].as_str().unwrap().contains("-fig") || !figures.is_empty(), "{}", c["id"]);
    for f in figures {
        assert!(out.join(f.as_str().unwrap()).is_file(), "{f}");
    }
}

/// The paper set-up's numbers come from the claims' own shading; the report's runs from the plan
/// executor: both must count the same. The papers' leaks are every false lit away from a
/// boundary: the report's leaks and light bleeding together.
fn check_against_report(claims: &[Value], report: &Value) {
    let fig12a = claims.iter().find(|c| c["id"] == "ehm2015-fig12-a-front").unwrap();
    for camera in ["front", "back"] {
        let run = report["runs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["camera"] == camera && r["label"] == "adaptive(epsilon=original,k=0.0001)")
            .unwrap_or_else(|| panic!("the report lacks the {camera} run"));
        let ours = &fig12a["numbers"]["original_k_0.0001"][camera];
        for key in ["acne", "aliasing", "evaluated"] {
            assert_eq!(ours[key], run["counts"][key], "{camera} {key}");
        }
        let counted = |key: &str| run["counts"][key].as_u64().unwrap();
        assert_eq!(ours["leak"].as_u64(), Some(counted("leak") + counted("light_bleeding")), "{camera} leak");
    }
}

#[test]
fn papers_writes_every_claim_with_its_sensitivity_its_page_and_figure_12() {
    let out = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["papers", "--no-cache", "--quiet", "--quick", "--scenes"])
        .arg(common::repo().join("scenes"))
        .arg("-o")
        .arg(out.path())
        .status()
        .unwrap();
    assert!(status.success());
    let claims: Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("claims.json")).unwrap()).unwrap();
    assert_eq!(claims["format"], "shadowtruth/claims/v1");
    let claims = claims["claims"].as_array().unwrap();
    let ids: BTreeSet<&str> = claims.iter().map(|c| c["id"].as_str().unwrap()).collect();
    assert_eq!(ids.len(), claims.len(), "ids are unique");
    assert_eq!(ids, IDS.into_iter().collect());
    for c in claims {
        check_claim(c, out.path());
    }
    let page = std::fs::read_to_string(out.path().join("claims.html")).unwrap();
    for c in claims {
        assert!(
            page.contains(c["id"].as_str().unwrap())
                && page.contains(c["sensitivity_summary"].as_str().unwrap())
        );
    }
    let grid = image::open(out.path().join("figures/papers.figure12.png")).unwrap();
    assert!(grid.width() > 1000 && grid.height() > 1000);
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("report.json")).unwrap()).unwrap();
    // Island: 3 settings × 2 cameras; casters: 3 PCF under the spot, 4 n-SM under the sun;
    // curved: 2 n-SM; L above the ground: 8 techniques × 2 resolutions.
    assert_eq!(report["runs"].as_array().unwrap().len(), 3 * 2 + 3 + 4 + 2 + 8 * 2);
    check_against_report(claims, &report);
}
