//! `reference --timing`: the tracer's primary and shadow rays per second on one view, and, given
//! the timing output of Embree on the same rays, the ratio to Embree's best. Two layouts are
//! read: the Embree reference tool's one line per thread count
//! (`embree N thread(s)  primary X Mrays/s (R rays)  occlusion Y Mrays/s (S rays)`), and a
//! native Embree benchmark's one line per mode
//! (`primary|shadow QUALITY MODE N thread(s) X Mrays/s (R rays, …`: single rays, packets,
//! streams, each build quality), of which the fastest mode of each kind counts.
//!
//! Primary rays are timed as that tool times them: the pixel-centre rays are prepared before
//! the clock starts, and the clock runs while they are traced and their closest hits written.
//! The G-buffer built from the same rays (their surface points, classes and certificates
//! besides) is timed beside them, with its time over theirs. Shadow rays likewise: prepared
//! from the G-buffer's points before the clock starts and traced in the batches the hard
//! reference traces them in; the whole hard reference (each ray built from its point, then
//! traced, and the mask written) is timed beside them, with its time over theirs.

use anyhow::{Result, bail};
use shadowtruth::metrics::timed_median;
use shadowtruth::scene::{Camera, Light, Scene};
use shadowtruth::trace::{
    GBuffer, SceneBvh, ShadowRay, hard_shadow_rays, primary_directions, primary_hits, trace_hard_reference,
    trace_shadow_rays,
};
use std::path::PathBuf;

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

/// Another tracer's timing at one thread count: its best rate of each kind, with the mode that
/// reached it where the file names modes (`p16c medium`).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct OtherTiming {
    pub timing: TraceTiming,
    pub primary_mode: Option<String>,
    pub occlusion_mode: Option<String>,
}

/// Our timing: the tracer's, and the G-buffer's and the hard reference's (pixels per second, in
/// millions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct OurTiming {
    pub tracer: TraceTiming,
    pub gbuffer: Rate,
    pub hard_reference: Rate,
}

/// Times the primary rays, the G-buffer, the shadow rays and the hard reference, each the median
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
    let (g, gbuffer_ms) = timed_median(repeats, || GBuffer::trace(bvh, camera, light));
    let shadow_ms = time_shadow_rays(scene, bvh, &g, light, repeats);
    let (_, reference_ms) =
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
        hard_reference: rate(rays.1, reference_ms),
    }
}

/// Shadow rays alone, in ms: prepared a group of bands at a time (`hard_shadow_rays`).
fn time_shadow_rays(scene: &Scene, bvh: &SceneBvh, g: &GBuffer, light: &Light, repeats: usize) -> f64 {
    time_prepared_rays(bvh, repeats, |each_group| {
        hard_shadow_rays(scene, g, light, SHADOW_RAYS_HELD, each_group)
    })
    .0
}

/// Prepared shadow rays alone: `prepare` hands each group of them over in turn (at most about
/// `SHADOW_RAYS_HELD` bytes), and each group is traced `repeats` times. Returns the median over
/// the repeats of each repeat's time summed over the groups (ms), and the count of rays.
pub(super) fn time_prepared_rays(
    bvh: &SceneBvh,
    repeats: usize,
    prepare: impl FnOnce(&mut dyn FnMut(&[Vec<ShadowRay>])),
) -> (f64, u64) {
    let (mut summed_ms, mut rays) = (vec![0.0; repeats.max(1)], 0);
    prepare(&mut |group| {
        rays += group.iter().map(Vec::len).sum::<usize>() as u64;
        for ms in summed_ms.iter_mut() {
            *ms += timed_median(1, || std::hint::black_box(trace_shadow_rays(bvh, group))).1;
        }
    });
    summed_ms.sort_by(f64::total_cmp);
    (summed_ms[summed_ms.len() / 2], rays)
}

/// The most bytes of prepared shadow rays the timing holds at once.
pub(super) const SHADOW_RAYS_HELD: usize = 64 << 20;

/// Our timing line, in the other tool's layout so that the two read side by side, and the
/// G-buffer's and the hard reference's rates on lines of their own.
pub(super) fn timing_line(t: &OurTiming, repeats: usize) -> String {
    let tracer = &t.tracer;
    format!(
        "shadowtruth {} threads  primary {:.3} Mrays/s ({} rays)   occlusion {:.3} Mrays/s ({} rays)   (median of {})\n\
         shadowtruth {} threads  G-buffer {:.3} Mpixels/s: the primary rays with their surface points, classes \
         and certificates, {:.2}× the time of the rays alone\n\
         shadowtruth {} threads  hard reference {:.3} Mpixels/s: the shadow rays built from the G-buffer's points \
         and traced, {:.2}× the time of the rays alone",
        tracer.threads,
        tracer.primary.mrays_per_s,
        tracer.primary.rays,
        tracer.occlusion.mrays_per_s,
        tracer.occlusion.rays,
        repeats.max(1),
        tracer.threads,
        t.gbuffer.mrays_per_s,
        tracer.primary.mrays_per_s / t.gbuffer.mrays_per_s,
        tracer.threads,
        t.hard_reference.mrays_per_s,
        tracer.occlusion.mrays_per_s / t.hard_reference.mrays_per_s,
    )
}

/// The ratio line against the other tracer's timing at our thread count; the G-buffer's rate
/// is set against the other tracer's primary rays too.
pub(super) fn ratio_line(ours_with_gbuffer: &OurTiming, other: &OtherTiming) -> String {
    let (ours, theirs) = (&ours_with_gbuffer.tracer, &other.timing);
    let ratio = |a: Rate, b: Rate| a.mrays_per_s / b.mrays_per_s;
    let mode = |m: &Option<String>| m.as_ref().map(|m| format!(" (its {m})")).unwrap_or_default();
    let best = if other.primary_mode.is_some() { "embree's best" } else { "embree" };
    let mut line = format!(
        "shadowtruth / {best}, {} threads: primary {:.2}×{}, occlusion {:.2}×{} (G-buffer {:.2}× its primary, \
         hard reference {:.2}× its occlusion)",
        ours.threads,
        ratio(ours.primary, theirs.primary),
        mode(&other.primary_mode),
        ratio(ours.occlusion, theirs.occlusion),
        mode(&other.occlusion_mode),
        ratio(ours_with_gbuffer.gbuffer, theirs.primary),
        ratio(ours_with_gbuffer.hard_reference, theirs.occlusion)
    );
    if ours.primary.rays != theirs.primary.rays {
        line += &format!(
            "  (not the same rays: {} primary rays here, {} there)",
            ours.primary.rays, theirs.primary.rays
        );
    }
    line
}

/// The timing at `threads` in the other tracers' output saved at `paths` (either layout,
/// mixed as they come): the best rate of each kind over every file, line and mode.
pub(super) fn read_other_timing(paths: &[PathBuf], threads: usize) -> Result<OtherTiming> {
    let mut lines = Vec::new();
    for path in paths {
        // A saved timing is some lines; a megabyte is far more than any tracer prints.
        let text = shadowtruth::input_file::read_named_text(path, 1 << 20)
            .map_err(|e| anyhow::anyhow!("--embree-timing: {e}"))?;
        let found: Vec<TimingLine> = text.lines().filter_map(parse_line).collect();
        if found.is_empty() {
            bail!(
                "{}: no timing line (expected `embree N threads  primary X Mrays/s (R rays)  occlusion Y Mrays/s \
                 (S rays)`, or `primary|shadow QUALITY MODE N threads X Mrays/s (R rays, …`)",
                path.display()
            );
        }
        lines.extend(found);
    }
    let at: Vec<&TimingLine> = lines.iter().filter(|l| l.threads == threads).collect();
    let best = |kind: Kind| {
        at.iter()
            .filter(|l| l.kind == kind || l.kind == Kind::Both)
            .map(|l| (if kind == Kind::Occlusion { l.occlusion } else { l.primary }, &l.mode))
            .filter_map(|(rate, mode)| Some((rate?, mode.clone())))
            .max_by(|a, b| a.0.mrays_per_s.total_cmp(&b.0.mrays_per_s))
    };
    match (best(Kind::Primary), best(Kind::Occlusion)) {
        (Some((primary, primary_mode)), Some((occlusion, occlusion_mode))) => Ok(OtherTiming {
            timing: TraceTiming { threads, primary, occlusion },
            primary_mode,
            occlusion_mode,
        }),
        _ => {
            let mut present: Vec<usize> = lines.iter().map(|l| l.threads).collect();
            present.sort_unstable();
            present.dedup();
            let present: Vec<String> = present.iter().map(usize::to_string).collect();
            bail!(
                "--embree-timing: no primary and shadow timing at {threads} threads (the files have {}); \
                 run with --threads set to one of those",
                present.join(", ")
            )
        }
    }
}

/// A rate as written: finite and above zero, or nothing (a ratio to it would mean nothing).
fn positive(word: &str) -> Option<f64> {
    word.parse().ok().filter(|r: &f64| r.is_finite() && *r > 0.0)
}

/// What a timing line times.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Primary,
    Occlusion,
    Both,
}

/// One line of another tracer's timing output.
#[derive(Clone, Debug, PartialEq)]
struct TimingLine {
    kind: Kind,
    threads: usize,
    primary: Option<Rate>,
    occlusion: Option<Rate>,
    mode: Option<String>,
}

fn parse_line(line: &str) -> Option<TimingLine> {
    parse_reference_tool_line(line).or_else(|| parse_native_line(line))
}

/// `embree 2 threads  primary 9.985 Mrays/s (786432 rays)   occlusion 10.127 Mrays/s (520624 rays)`.
fn parse_reference_tool_line(line: &str) -> Option<TimingLine> {
    let words: Vec<&str> = line.split_whitespace().collect();
    if words.first() != Some(&"embree") {
        return None;
    }
    let threads = words.get(1)?.parse().ok()?;
    let rate = |kind: &str| -> Option<Rate> {
        let at = words.iter().position(|w| *w == kind)?;
        let mrays_per_s = positive(words.get(at + 1)?)?;
        let rays = words.get(at + 3)?.trim_start_matches('(').parse().ok()?;
        Some(Rate { mrays_per_s, rays })
    };
    Some(TimingLine {
        kind: Kind::Both,
        threads,
        primary: Some(rate("primary")?),
        occlusion: Some(rate("occlusion")?),
        mode: None,
    })
}

/// `shadow  medium    p16c   2 threads    26.860 Mrays/s  (1115292 rays, median 0.0415 s, …`.
fn parse_native_line(line: &str) -> Option<TimingLine> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let [kind, quality, mode, threads, unit, rate, "Mrays/s", rays, ..] = words[..] else {
        return None;
    };
    let kind = match kind {
        "primary" => Kind::Primary,
        "shadow" => Kind::Occlusion,
        _ => return None,
    };
    if !unit.starts_with("thread") {
        return None;
    }
    let rate = Rate { mrays_per_s: positive(rate)?, rays: rays.strip_prefix('(')?.parse().ok()? };
    let (primary, occlusion) = if kind == Kind::Primary { (Some(rate), None) } else { (None, Some(rate)) };
    Some(TimingLine {
        kind,
        threads: threads.parse().ok()?,
        primary,
        occlusion,
        mode: Some(format!("{mode} {quality}")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const EMBREE: &str = "{\"mask\": \"m.png\"}\n\
        embree 1 thread   primary 5.732 Mrays/s (786432 rays)   occlusion 5.737 Mrays/s (520624 rays)\n\
        embree 2 threads  primary 9.985 Mrays/s (786432 rays)   occlusion 10.127 Mrays/s (520624 rays)\n";

    /// Lines of a native Embree benchmark, as it prints them (two libraries' headers, modes at
    /// two qualities and thread counts).
    const NATIVE: &str = "== 2026-12-03T16:53:04Z load 1.50 3.35 3.15  embree_native4 --threads 1,2\n\
        embree 4.4.0 (API 4)  device \"\"  triangles 199952  image 1920x1080  primary 2073600 rays  shadow 1115292 rays\n\
        build quality high: 0.169 s (rtcCommitScene with Embree's own TBB threads)\n\
        primary high      1ray   1 thread      7.325 Mrays/s  (2073600 rays, median 0.2831 s, min 0.2676, max 0.2989)  hits 1154436\n\
        primary high      p16    1 thread     15.681 Mrays/s  (2073600 rays, median 0.1322 s, min 0.1279, max 0.1391)  hits 1154436\n\
        shadow  high      p16c   1 thread     14.092 Mrays/s  (1115292 rays, median 0.0791 s, min 0.0739, max 0.0810)  occluded 204416\n\
        shadow  high      p16    2 threads    24.453 Mrays/s  (1115292 rays, median 0.0456 s, min 0.0413, max 0.0473)  occluded 204416\n\
        primary medium    p16    1 thread     16.377 Mrays/s  (2073600 rays, median 0.1266 s, min 0.1221, max 0.1340)  hits 1154436\n\
        shadow  medium    p8c    1 thread     12.728 Mrays/s  (1115292 rays, median 0.0876 s, min 0.0817, max 0.0951)  occluded 204416\n\
        primary medium    p16    2 threads    25.002 Mrays/s  (2073600 rays, median 0.0829 s, min 0.0805, max 0.0839)  hits 1154436\n";

    fn saved(name: &str, text: &str) -> PathBuf {
        let path =
            std::env::temp_dir().join(format!("shadowtruth-embree-timing-{}-{name}", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn reads_each_thread_count_of_the_embree_tool_output() {
        let timings: Vec<TimingLine> = EMBREE.lines().filter_map(parse_line).collect();
        let rate = |mrays_per_s, rays| Some(Rate { mrays_per_s, rays });
        assert_eq!(
            timings,
            [
                TimingLine {
                    kind: Kind::Both,
                    threads: 1,
                    primary: rate(5.732, 786432),
                    occlusion: rate(5.737, 520624),
                    mode: None
                },
                TimingLine {
                    kind: Kind::Both,
                    threads: 2,
                    primary: rate(9.985, 786432),
                    occlusion: rate(10.127, 520624),
                    mode: None
                },
            ]
        );
    }

    /// Of a native benchmark's modes the fastest of each kind counts, over both qualities, and
    /// only at the thread count asked for; the header lines are not timings.
    #[test]
    fn the_best_native_mode_of_each_kind_counts() {
        let path = saved("native.txt", NATIVE);
        let one = read_other_timing(std::slice::from_ref(&path), 1).unwrap();
        assert_eq!(one.timing.primary, Rate { mrays_per_s: 16.377, rays: 2073600 });
        assert_eq!(one.timing.occlusion, Rate { mrays_per_s: 14.092, rays: 1115292 });
        assert_eq!(one.primary_mode.as_deref(), Some("p16 medium"));
        assert_eq!(one.occlusion_mode.as_deref(), Some("p16c high"));
        let two = read_other_timing(std::slice::from_ref(&path), 2).unwrap();
        assert_eq!((two.timing.primary.mrays_per_s, two.timing.occlusion.mrays_per_s), (25.002, 24.453));
        // Two files: the best of both, whichever layout each has.
        let tool = saved("tool.txt", EMBREE);
        let both = read_other_timing(&[tool.clone(), path.clone()], 1).unwrap();
        assert_eq!(both.timing.primary.mrays_per_s, 16.377);
        let err = read_other_timing(std::slice::from_ref(&path), 4).unwrap_err().to_string();
        assert!(err.contains("no primary and shadow timing at 4 threads (the files have 1, 2)"), "{err}");
        for p in [path, tool] {
            std::fs::remove_file(p).unwrap();
        }
        assert_eq!(parse_line("shadow  high  p16  1 thread  NaN Mrays/s  (10 rays, median"), None);
        assert_eq!(parse_line("primary high  p16  1 thread  -3 Mrays/s  (10 rays, median"), None);
    }

    #[test]
    fn the_ratio_divides_our_rate_by_theirs_and_flags_other_rays() {
        let mut theirs = OtherTiming {
            timing: TraceTiming {
                threads: 2,
                primary: Rate { mrays_per_s: 10.0, rays: 100 },
                occlusion: Rate { mrays_per_s: 8.0, rays: 60 },
            },
            primary_mode: None,
            occlusion_mode: None,
        };
        let mut ours = OurTiming {
            tracer: TraceTiming {
                threads: 2,
                primary: Rate { mrays_per_s: 5.0, rays: 100 },
                occlusion: Rate { mrays_per_s: 10.0, rays: 59 },
            },
            gbuffer: Rate { mrays_per_s: 4.0, rays: 100 },
            hard_reference: Rate { mrays_per_s: 6.0, rays: 59 },
        };
        assert_eq!(
            ratio_line(&ours, &theirs),
            "shadowtruth / embree, 2 threads: primary 0.50×, occlusion 1.25× (G-buffer 0.40× its primary, \
             hard reference 0.75× its occlusion)"
        );
        (theirs.primary_mode, theirs.occlusion_mode) = (Some("p16 high".into()), Some("p8c medium".into()));
        assert_eq!(
            ratio_line(&ours, &theirs),
            "shadowtruth / embree's best, 2 threads: primary 0.50× (its p16 high), occlusion 1.25× \
             (its p8c medium) (G-buffer 0.40× its primary, hard reference 0.75× its occlusion)"
        );
        ours.tracer.primary.rays = 99;
        assert!(ratio_line(&ours, &theirs).ends_with("(not the same rays: 99 primary rays here, 100 there)"));
    }

    #[test]
    fn a_file_without_the_thread_count_names_the_counts_it_has() {
        let path = saved("tool-only.txt", EMBREE);
        let err = read_other_timing(std::slice::from_ref(&path), 4).unwrap_err().to_string();
        assert!(err.contains("no primary and shadow timing at 4 threads (the files have 1, 2)"), "{err}");
        assert_eq!(
            read_other_timing(std::slice::from_ref(&path), 2).unwrap().timing.primary.mrays_per_s,
            9.985
        );
        std::fs::write(&path, "nothing here\n").unwrap();
        let err = read_other_timing(std::slice::from_ref(&path), 1).unwrap_err().to_string();
        assert!(err.contains("no timing line"), "{err}");
        std::fs::remove_file(&path).unwrap();
    }
}
