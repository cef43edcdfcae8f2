//! `reference --timing`: the tracer's primary and shadow rays per second on one view, and, given
//! the `--timing` output of another tracer on the same rays (the Embree reference tool's lines
//! `embree N thread(s)  primary X Mrays/s (R rays)  occlusion Y Mrays/s (S rays)`), the ratio.
//!
//! Primary rays are timed as that tool times them: the pixel-centre rays are prepared before
//! the clock starts, and the clock runs while they are traced and their closest hits written.
//! The G-buffer built from the same rays (their surface points and classes besides) is timed
//! beside them. Shadow rays are timed as the whole hard reference: building each shadow ray
//! from its G-buffer point (which the other tool does before its clock) included.

use anyhow::{Result, bail};
use shadowtruth::metrics::timed_median;
use shadowtruth::scene::{Camera, Light, Scene};
use shadowtruth::trace::{GBuffer, SceneBvh, primary_directions, primary_hits, trace_hard_reference};
use std::path::Path;

/// Rays per second (in millions) of one kind, over how many rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rate {
    pub mrays_per_s: f64,
    pub rays: u64,
}

/// One tracer's timing on one view at one thread count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TraceTiming {
    pub threads: usize,
    pub primary: Rate,
    pub occlusion: Rate,
}

/// Our timing: the tracer's, and the G-buffer's (pixels per second, in millions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct OurTiming {
    pub tracer: TraceTiming,
    pub gbuffer: Rate,
}

/// Times the primary rays, the G-buffer and the hard reference (shadow rays), each the median
/// of `repeats` (each measurement's repeats in a row).
pub(super) fn time_tracer(
    scene: &Scene,
    bvh: &SceneBvh,
    camera: &Camera,
    light: &Light,
    repeats: usize,
) -> OurTiming {
    let directions = primary_directions(camera);
    let (_, primary_ms) =
        timed_median(repeats, || std::hint::black_box(primary_hits(bvh, camera, &directions)));
    let (g, gbuffer_ms) = timed_median(repeats, || GBuffer::trace(scene, bvh, camera, light));
    let (_, shadow_ms) =
        timed_median(repeats, || std::hint::black_box(trace_hard_reference(scene, bvh, &g, light)));
    let rays = (g.pixel_count() as u64, g.evaluated.len() as u64);
    let rate = |rays: u64, ms: f64| Rate { mrays_per_s: rays as f64 / ms / 1e3, rays };
    OurTiming {
        tracer: TraceTiming {
            threads: rayon::current_num_threads(),
            primary: rate(rays.0, primary_ms),
            occlusion: rate(rays.1, shadow_ms),
        },
        gbuffer: rate(rays.0, gbuffer_ms),
    }
}

/// Our timing line, in the other tool's layout so that the two read side by side, and the
/// G-buffer's rate on a line of its own.
pub(super) fn timing_line(t: &OurTiming, repeats: usize) -> String {
    let tracer = &t.tracer;
    format!(
        "shadowtruth {} threads  primary {:.3} Mrays/s ({} rays)   occlusion {:.3} Mrays/s ({} rays)   (median of {})\n\
         shadowtruth {} threads  G-buffer {:.3} Mpixels/s: the primary rays with their surface points and classes",
        tracer.threads,
        tracer.primary.mrays_per_s,
        tracer.primary.rays,
        tracer.occlusion.mrays_per_s,
        tracer.occlusion.rays,
        repeats.max(1),
        tracer.threads,
        t.gbuffer.mrays_per_s,
    )
}

/// The ratio line against the other tracer's timing at our thread count; the G-buffer's rate
/// is set against the other tracer's primary rays too.
pub(super) fn ratio_line(ours_with_gbuffer: &OurTiming, theirs: &TraceTiming) -> String {
    let ours = &ours_with_gbuffer.tracer;
    let ratio = |a: Rate, b: Rate| a.mrays_per_s / b.mrays_per_s;
    let mut line = format!(
        "shadowtruth / embree, {} threads: primary {:.2}×, occlusion {:.2}× (G-buffer {:.2}× its primary)",
        ours.threads,
        ratio(ours.primary, theirs.primary),
        ratio(ours.occlusion, theirs.occlusion),
        ratio(ours_with_gbuffer.gbuffer, theirs.primary)
    );
    if ours.primary.rays != theirs.primary.rays {
        line += &format!(
            "  (not the same rays: {} primary rays here, {} there)",
            ours.primary.rays, theirs.primary.rays
        );
    }
    line
}

/// The timing at `threads` in the other tracer's `--timing` output saved at `path`.
pub(super) fn read_other_timing(path: &Path, threads: usize) -> Result<TraceTiming> {
    // A saved timing is a few lines; a megabyte is far more than any tracer prints.
    let text = shadowtruth::input_file::read_named_text(path, 1 << 20)
        .map_err(|e| anyhow::anyhow!("--embree-timing: {e}"))?;
    let timings: Vec<TraceTiming> = text.lines().filter_map(parse_timing_line).collect();
    if timings.is_empty() {
        bail!(
            "{}: no timing line (expected `embree N threads  primary X Mrays/s (R rays)  occlusion Y Mrays/s (S rays)`)",
            path.display()
        );
    }
    match timings.iter().find(|t| t.threads == threads) {
        Some(t) => Ok(*t),
        None => {
            let present: Vec<String> = timings.iter().map(|t| t.threads.to_string()).collect();
            bail!(
                "{}: no timing at {threads} threads (it has {}); run with --threads set to one of those",
                path.display(),
                present.join(", ")
            )
        }
    }
}

/// `embree 2 threads  primary 9.985 Mrays/s (786432 rays)   occlusion 10.127 Mrays/s (520624 rays)`.
fn parse_timing_line(line: &str) -> Option<TraceTiming> {
    let words: Vec<&str> = line.split_whitespace().collect();
    if words.first() != Some(&"embree") {
        return None;
    }
    let threads = words.get(1)?.parse().ok()?;
    let rate = |kind: &str| -> Option<Rate> {
        let at = words.iter().position(|w| *w == kind)?;
        let mrays_per_s = words.get(at + 1)?.parse().ok()?;
        let rays = words.get(at + 3)?.trim_start_matches('(').parse().ok()?;
        Some(Rate { mrays_per_s, rays })
    };
    Some(TraceTiming { threads, primary: rate("primary")?, occlusion: rate("occlusion")? })
}

#[cfg(test)]
mod tests {
    use super::*;

    const EMBREE: &str = "{\"mask\": \"m.png\"}\n\
        embree 1 thread   primary 5.732 Mrays/s (786432 rays)   occlusion 5.737 Mrays/s (520624 rays)\n\
        embree 2 threads  primary 9.985 Mrays/s (786432 rays)   occlusion 10.127 Mrays/s (520624 rays)\n";

    #[test]
    fn reads_each_thread_count_of_the_embree_tool_output() {
        let timings: Vec<TraceTiming> = EMBREE.lines().filter_map(parse_timing_line).collect();
        assert_eq!(
            timings,
            [
                TraceTiming {
                    threads: 1,
                    primary: Rate { mrays_per_s: 5.732, rays: 786432 },
                    occlusion: Rate { mrays_per_s: 5.737, rays: 520624 },
                },
                TraceTiming {
                    threads: 2,
                    primary: Rate { mrays_per_s: 9.985, rays: 786432 },
                    occlusion: Rate { mrays_per_s: 10.127, rays: 520624 },
                },
            ]
        );
    }

    #[test]
    fn the_ratio_divides_our_rate_by_theirs_and_flags_other_rays() {
        let theirs = TraceTiming {
            threads: 2,
            primary: Rate { mrays_per_s: 10.0, rays: 100 },
            occlusion: Rate { mrays_per_s: 8.0, rays: 60 },
        };
        let mut ours = OurTiming {
            tracer: TraceTiming {
                threads: 2,
                primary: Rate { mrays_per_s: 5.0, rays: 100 },
                occlusion: Rate { mrays_per_s: 10.0, rays: 59 },
            },
            gbuffer: Rate { mrays_per_s: 4.0, rays: 100 },
        };
        assert_eq!(
            ratio_line(&ours, &theirs),
            "shadowtruth / embree, 2 threads: primary 0.50×, occlusion 1.25× (G-buffer 0.40× its primary)"
        );
        ours.tracer.primary.rays = 99;
        assert!(ratio_line(&ours, &theirs).ends_with("(not the same rays: 99 primary rays here, 100 there)"));
    }

    #[test]
    fn a_file_without_the_thread_count_names_the_counts_it_has() {
        let path = std::env::temp_dir().join(format!("shadowtruth-embree-timing-{}.txt", std::process::id()));
        std::fs::write(&path, EMBREE).unwrap();
        let err = read_other_timing(&path, 4).unwrap_err().to_string();
        assert!(err.contains("no timing at 4 threads (it has 1, 2)"), "{err}");
        assert_eq!(read_other_timing(&path, 2).unwrap().primary.mrays_per_s, 9.985);
        std::fs::write(&path, "nothing here\n").unwrap();
        assert!(read_other_timing(&path, 1).unwrap_err().to_string().contains("no timing line"));
        std::fs::remove_file(&path).unwrap();
    }
}
