//! `shadowtruth verify`: the hard reference checked against exact predicates, view by view
//! (docs/reference.md); exit 1 when a disagreement lies outside the documented error band.

use super::args::set_threads;
use crate::option_values::threads_parser;
use anyhow::{Context, Result, bail};
use clap::Args;
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::trace::SceneBvh;
use shadowtruth::verify::{Adjudicator, PixelSelection, ViewVerification, verify_view};
use std::path::{Path, PathBuf};

#[derive(Args)]
pub(super) struct VerifyArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Camera name (default: every camera of the scene).
    #[arg(long)]
    camera: Option<String>,
    /// Light name (default: every light of the scene).
    #[arg(long)]
    light: Option<String>,
    /// Pixels to check per view: `all`, or N for about N evaluated pixels spread uniformly plus
    /// every pixel next to a shadow boundary.
    #[arg(long, default_value_t = PixelSelection::default())]
    pixels: PixelSelection,
    /// Also write the results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
}

pub(super) fn verify(a: VerifyArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let scene: Scene = load_scene(&a.scene)?;
    let select = |name: &Option<String>, names: Vec<&str>, what: &str| -> Result<Vec<String>> {
        match name {
            Some(n) if names.contains(&n.as_str()) => Ok(vec![n.clone()]),
            Some(n) => bail!("{}: no {what} named '{n}' (have: {})", a.scene.display(), names.join(", ")),
            None if names.is_empty() => bail!("{}: the scene has no {what}", a.scene.display()),
            None => Ok(names.iter().map(|s| s.to_string()).collect()),
        }
    };
    let cameras = select(&a.camera, scene.cameras.iter().map(|c| c.name.as_str()).collect(), "camera")?;
    let lights = select(&a.light, scene.lights.iter().map(|l| l.name.as_str()).collect(), "light")?;
    let bvh = SceneBvh::build(&scene);
    let adjudicator = Adjudicator::new(&scene);
    let mut views = Vec::new();
    for camera in &cameras {
        for light in &lights {
            let (c, l) = (scene.camera(camera).expect("selected"), scene.light(light).expect("selected"));
            let v = verify_view(&scene, &bvh, &adjudicator, c, l, a.pixels);
            print_verification(&a.scene, &v);
            views.push(v);
        }
    }
    if let Some(path) = &a.json {
        let text = serde_json::to_string_pretty(&serde_json::json!({ "scene": a.scene, "views": views }))?;
        write_atomic(path, text.as_bytes()).with_context(|| format!("writing {}", path.display()))?;
    }
    let failed = views.iter().filter(|v| !v.passed()).count();
    if failed == 0 {
        println!("verify: {} views, no disagreement outside the error band", views.len());
        Ok(0)
    } else {
        println!("verify: {failed} of {} views have disagreements outside the error band", views.len());
        Ok(1)
    }
}

fn print_verification(scene: &Path, v: &ViewVerification) {
    let pct = |n: usize| 100.0 * n as f64 / v.checked.max(1) as f64;
    println!(
        "{}  camera {}  light {}: {} evaluated pixels, {} checked ({} next to a shadow boundary) in {:.1} s",
        scene.display(),
        v.camera,
        v.light,
        v.evaluated,
        v.checked,
        v.checked_at_boundary,
        v.seconds
    );
    println!("  agree with the exact answer   {:>9} ({:.4} %)", v.agree, pct(v.agree));
    println!(
        "  disagree                      {:>9} ({} at a shadow boundary, {} away)",
        v.disagree_at_boundary + v.disagree_away_from_boundary,
        v.disagree_at_boundary,
        v.disagree_away_from_boundary
    );
    println!("    inside the error band       {:>9}", v.disagree_in_band);
    println!("    outside the error band      {:>9}", v.disagree_outside_band);
    println!("  exact answer inside the band  {:>9} ({:.4} %)", v.in_band, pct(v.in_band));
    if v.inconsistent > 0 {
        println!(
            "  ADJUDICATOR INCONSISTENT on {} pixels: the exact test and the band disagree",
            v.inconsistent
        );
    }
    for c in &v.cases {
        let verdict = |shadowed: bool| if shadowed { "shadowed" } else { "lit" };
        println!(
            "    pixel ({}, {}) on triangle {}: traced {}, exact {}{}{}{}",
            c.x,
            c.y,
            c.surface_triangle,
            verdict(c.traced_shadowed),
            verdict(c.exact_shadowed),
            c.triangle.map(|t| format!(", triangle {t}")).unwrap_or_default(),
            if c.outside_band() { "  OUTSIDE THE BAND" } else { "  (inside the band)" },
            if c.at_boundary { ", at a shadow boundary" } else { "" },
        );
    }
}
