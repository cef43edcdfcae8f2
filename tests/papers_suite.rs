//! `shadowtruth papers` end to end: the report, claims.json with one verdict per claim, the page
//! and the Figure 12 grid.

mod common;

use std::collections::BTreeSet;
use std::process::Command;

#[test]
fn papers_writes_every_claim_with_a_verdict_its_page_and_figure_12() {
    let out = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["papers", "--no-cache", "--quiet", "--scenes"])
        .arg(common::repo().join("scenes"))
        .arg("-o")
        .arg(out.path())
        .status()
        .unwrap();
    assert!(status.success());
    let claims: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("claims.json")).unwrap()).unwrap();
    assert_eq!(claims["format"], "shadowtruth/claims/v1");
    let claims = claims["claims"].as_array().unwrap();
    let ids: BTreeSet<&str> = claims.iter().map(|c| c["id"].as_str().unwrap()).collect();
    assert_eq!(ids.len(), claims.len(), "ids are unique");
    for id in [
        "ehm2015-fig12-a",
        "ehm2015-fig12-d",
        "ehm2015-fig12-g",
        "ehm2015-fig4",
        "ehm2015-table1",
        "pagot2004-table1",
        "pagot2004-fig6",
        "weiskopf2003-fig5-r64",
        "weiskopf2003-fig5-r128",
    ] {
        assert!(ids.contains(id), "{id} is missing");
    }
    for c in claims {
        assert!(["holds", "partly", "does_not_hold"].contains(&c["verdict"].as_str().unwrap()), "{c}");
        for key in ["paper", "statement", "rule"] {
            assert!(!c[key].as_str().unwrap().is_empty(), "{key} of {c}");
        }
        assert!(!c["numbers"].as_object().unwrap().is_empty());
        for f in c["figures"].as_array().unwrap() {
            assert!(out.path().join(f.as_str().unwrap()).is_file(), "{f}");
        }
    }
    let page = std::fs::read_to_string(out.path().join("claims.html")).unwrap();
    assert!(claims.iter().all(|c| page.contains(c["id"].as_str().unwrap())));
    let grid = image::open(out.path().join("figures/papers.figure12.png")).unwrap();
    assert!(grid.width() > 1000 && grid.height() > 1000);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("report.json")).unwrap()).unwrap();
    // Island: 8 techniques × 2 cameras; L-shape: 6 techniques × 2 resolutions.
    assert_eq!(report["runs"].as_array().unwrap().len(), 8 * 2 + 6 * 2);
}
