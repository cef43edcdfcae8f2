//! `shadowtruth verify`: the G-buffer and hard reference checked against exact predicates,
//! view by view (docs/reference.md); exit 1 when a disagreement lies on a pixel the tracer did
//! not flag as uncertain (outside the error band).

use super::args::set_threads;
use crate::option_values::threads_parser;
use anyhow::{Context, Result, bail};
use clap::Args;
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::trace::SceneBvh;
use shadowtruth::verify::{Adjudicator, Disagreement, PixelSelection, ViewVerification, verify_view};
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
            None if names.is_empty() => {
                bail!("{}: {}", a.scene.display(), shadowtruth::scene::missing_view_item(&a.scene, what))
            }
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
        println!("verify: {failed} of {} views failed: disagreements outside the error band", views.len());
        Ok(1)
    }
}

fn print_verification(scene: &Path, v: &ViewVerification) {
    let pct = |n: usize| 100.0 * n as f64 / v.checked.max(1) as f64;
    println!(
        "{}  camera {}  light {}: {} evaluated pixels ({} flagged uncertain by the tracer), {} checked \
         ({} next to a shadow boundary), {} primary rays checked, in {:.1} s",
        scene.display(),
        v.camera,
        v.light,
        v.evaluated,
        v.uncertain,
        v.checked,
        v.checked_at_boundary,
        v.primary_checked,
        v.seconds
    );
    println!("  shadow agrees with the exact answer  {:>9} ({:.4} %)", v.agree, pct(v.agree));
    println!(
        "  shadow disagrees                     {:>9} ({} at a shadow boundary, {} away)",
        v.disagree_at_boundary + v.disagree_away_from_boundary,
        v.disagree_at_boundary,
        v.disagree_away_from_boundary
    );
    println!("    on pixels the tracer flagged       {:>9} (inside the error band)", v.disagree_in_band);
    println!(
        "    on pixels it did not flag          {:>9} (outside the error band)",
        v.disagree_outside_band
    );
    println!(
        "  primary hit or facing disagrees      {:>9} inside the band, {} outside",
        v.primary_disagree_in_band, v.primary_disagree_outside_band
    );
    println!("  checked pixels the tracer flagged    {:>9} (the error band)", v.in_band);
    println!("  largest point error / its precision  {:>9.4}", v.max_point_error_ratio);
    for c in &v.cases {
        let band = if c.outside_band() { "  OUTSIDE THE BAND" } else { "  (inside the band)" };
        match &c.disagreement {
            Disagreement::Shadow {
                surface_triangle,
                traced_shadowed,
                exact_shadowed,
                triangle,
                at_boundary,
            } => {
                let verdict = |shadowed: bool| if shadowed { "shadowed" } else { "lit" };
                println!(
                    "    pixel ({}, {}) on triangle {surface_triangle}: traced {}, exact {}{}{band}{}",
                    c.x,
                    c.y,
                    verdict(*traced_shadowed),
                    verdict(*exact_shadowed),
                    triangle.map(|t| format!(", triangle {t}")).unwrap_or_default(),
                    if *at_boundary { ", at a shadow boundary" } else { "" },
                );
            }
            Disagreement::Primary { traced_triangle, exact_triangle, point_error_ratio } => {
                let seen = |t: &Option<u32>| t.map_or("nothing".to_string(), |t| format!("triangle {t}"));
                println!(
                    "    pixel ({}, {}) primary hit: traced {}, exact {}{}{band}",
                    c.x,
                    c.y,
                    seen(traced_triangle),
                    seen(exact_triangle),
                    point_error_ratio
                        .map(|r| format!(", point error {r:.3} of its precision"))
                        .unwrap_or_default(),
                );
            }
            Disagreement::Facing { triangle, traced_facing, exact_facing } => {
                let side = |facing: bool| if facing { "faces the light" } else { "facing away" };
                println!(
                    "    pixel ({}, {}) on triangle {triangle}: traced {}, exact {}{band}",
                    c.x,
                    c.y,
                    side(*traced_facing),
                    side(*exact_facing),
                );
            }
        }
    }
    if v.passed() {
        println!("  passed");
    } else {
        println!(
            "  FAILED: {} shadow and {} primary disagreements outside the error band",
            v.disagree_outside_band, v.primary_disagree_outside_band
        );
    }
}
