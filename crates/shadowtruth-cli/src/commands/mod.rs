//! The `shadowtruth` command: the clap definitions of its commands (each command's options and
//! body in a file of its own), the dispatch and the exit codes: 0 success, 1 a gate failed, 2 a
//! usage or input error.

use anyhow::Result;
use clap::{Parser, Subcommand};

mod args;
mod depth_map;
mod examples;
mod export_obj;
mod folder_lock;
mod gate;
mod generate;
mod island;
mod merge;
mod named_item;
mod papers;
mod plan_report;
mod progress;
mod reference;
mod report;
mod run;
mod scene_paths;
mod score;
mod table;
mod trace_timing;
mod tune;
mod verify;
mod view_export;

/// shadowtruth measures how wrong shadow maps are: an exact ray-traced reference decides, pixel
/// by pixel, what is lit; every shadow-map technique is scored against it (false shadow: acne,
/// self-shadowing; false lit: leaks, peter-panning) per resolution and bias setting.
#[derive(Parser)]
#[command(name = "shadowtruth", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// One value per process, parsed once: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Run techniques over scenes and write OUT_DIR/report.json.
    ///
    /// With no arguments: every scene of `scenes/` with the default plan (plans/default.json:
    /// every technique at a few settings; shadow maps 512² to 4096² in f32 depth).
    #[command(after_help = examples::RUN)]
    Run(run::RunArgs),
    /// Write the exact hard shadow mask of one camera and light as a PNG, or a soft reference
    /// (pixel coverage, area light) as an EXR.
    ///
    /// Hard mask grey levels: 255 lit, 0 shadowed, 128 background, 64 facing away from the
    /// light, 192 outside the light, 96 uncertain (the tracer cannot decide it beyond doubt).
    /// Soft references: channels V (visibility in [0, 1], 0 where not evaluated) and E (its
    /// standard error), f32, row 0 at the top.
    #[command(after_help = examples::REFERENCE)]
    Reference(reference::ReferenceArgs),
    /// Check the hard reference against exact predicates: the same visibility decided exactly
    /// on the f32 inputs, independent of the tracer (docs/reference.md).
    ///
    /// Checks every camera with every light unless --camera / --light name one. Prints, per
    /// view, the agreement with the exact answer, the disagreements at and away from shadow
    /// boundaries, and the worst cases with their pixel and triangles. Exit 1 when a
    /// disagreement lies outside the documented error band.
    #[command(after_help = examples::VERIFY)]
    Verify(verify::VerifyArgs),
    /// Write the scene's world-space triangles as OBJ (one `o` group per object), with
    /// coordinates that read back as the same f32 values.
    #[command(after_help = examples::EXPORT_OBJ)]
    ExportObj(export_obj::ExportObjArgs),
    /// Check a report against rules: exit 0 when every rule holds, 1 on violations, 2 on bad input.
    ///
    /// Rules (TOML, `[[rule]]` tables) select runs by glob patterns and bound a metric absolutely
    /// (`max`) and/or against a baseline report (`max_increase`, `max_increase_ratio`). With
    /// --baseline every baseline run must pair with a run of the report (same view, resolution,
    /// depth format, reference and technique parameters); one that does not is a violation.
    #[command(after_help = examples::GATE)]
    Gate(gate::GateArgs),
    /// Write one depth layer of a light as a one-channel f32 EXR, with a JSON sidecar holding
    /// clip_from_world and the near and far planes, to check the rasterizer against another.
    #[command(after_help = examples::DEPTH_MAP)]
    DepthMap(depth_map::DepthMapArgs),
    /// Score another renderer's shadows: its visibility buffer of one view (and optionally its
    /// camera depth) against the exact reference, into a report folder like `run`'s.
    ///
    /// The buffer is one technique, `external`, with the same metrics, attribution (at
    /// --resolution), figures, CSV, plots and page as the built-in ones. Pixels where the
    /// renderer shows another surface (background where the reference has a surface, or a depth
    /// beyond the tolerance) are counted as surface_mismatch and left out of the rates. In a plan
    /// the same is a technique entry {"technique": "external", "name": ..., "visibility":
    /// "renders/{scene}.{camera}.{light}.exr"}.
    ///
    /// With --shadow-map and --technique instead of --visibility: the renderer's shadow map (as
    /// `depth-map` writes it) read by a built-in technique, to tell a wrong map from a wrong test.
    #[command(after_help = examples::SCORE)]
    Score(score::ScoreArgs),
    /// Find the setting of one technique to ship: the values of one to three of its parameters
    /// that minimise an objective (total error by default) per scene and for the whole suite,
    /// each with its safe range (where the objective stays within 10 % of the optimum).
    ///
    /// One parameter is searched by a log grid and golden-section refinement, two or three by a
    /// coarse grid and coordinate refinement. The views are traced and the maps set up once;
    /// each evaluation is one shading pass per view and resolution. OUT gets tune.json
    /// (shadowtruth/tune/v1), plots/tune_<param>.png, the tuned settings run as a report
    /// (report.json, figures, page) and tune-gate.toml, gate rules that lock the suite setting's
    /// error on every view. docs/tune.md explains the search.
    #[command(after_help = examples::TUNE)]
    Tune(tune::TuneArgs),
    /// Re-render report.csv, the plots and index.html of a report folder from its report.json,
    /// without running anything.
    #[command(after_help = examples::REPORT)]
    Report(report::ReportArgs),
    /// Join the report folders of `run --shard K/N` (K = 1..N, any order) into one report
    /// folder, as the whole run would have written it apart from timings.
    ///
    /// OUT gets report.json (the runs in the whole run's order), the shards' figures, and
    /// report.csv, plots and index.html rendered from the merged report. Refused, naming the
    /// folder: a folder that is no shard, shards of different plans, scenes or options, a
    /// missing or repeated shard, a run in a view of another shard, an unfinished shard.
    /// docs/cluster.md runs shards as a Slurm job array or a CI matrix.
    #[command(after_help = examples::MERGE)]
    Merge(merge::MergeArgs),
    /// Reproduce the papers' results and judge each claim: Ehm et al.'s Figure 12 on the island
    /// (scenes/papers/island.json); their Fig. 4, Table 1, §3.3 and Table 2 and Pagot et al.'s
    /// Table 1 and Fig. 6 on scenes/papers/casters.json; Pagot et al.'s Fig. 7 on
    /// scenes/papers/curved.json; Weiskopf & Ertl's Fig. 5 to 7 on scenes/papers/l_above.json.
    ///
    /// Writes the usual report (the papers' set-ups) into OUT_DIR, plus claims.json (per claim:
    /// id, paper, statement, set-up, rule, our numbers, verdict holds / fragile / partly /
    /// does_not_hold, the margin of the test nearest to changing it, and the same rule over
    /// other set-ups: sensitivity, sensitivity_summary) and claims.html.
    #[command(after_help = examples::PAPERS)]
    Papers(papers::PapersArgs),
    /// Generate the island of Ehm et al. (WSCG 2015, Figure 12) from a seed: DIR/island.json
    /// and DIR/meshes/island_terrain.obj.
    ///
    /// Noisy terrain rising from a sea plane, thin-trunked trees, a spot light `sun_spot`,
    /// a `front` camera on the lit side (the featured tree's trunk `tree00_trunk` in view) and
    /// a `back` camera where the light grazes the slopes. The same seed gives the same bytes;
    /// the default seed gives the committed scenes/papers/island.json.
    #[command(after_help = examples::ISLAND)]
    Island(island::IslandArgs),
    /// Write everything an engine needs to render the same pixels under the same light into
    /// DIR: view.json, the G-buffer as EXRs and the scene as glTF binary.
    ///
    /// view.json (format shadowtruth/view/v1): the camera's view and projection matrices and
    /// the light's shadow-map view (the CPU rasterizer's, at --resolution) in OpenGL, Vulkan and
    /// D3D form, each row-major and column-major, with the image size, near/far, the pixel-centre
    /// convention and the light's parameters. position.exr and normal.exr (f32 R, G, B = x, y,
    /// z) and ids.exr (u32 triangle, object, class: 0 background, 1 facing away, 2 outside the
    /// light, 3 evaluated), row 0 at the top. scene.glb: one mesh per object in world space,
    /// every camera and every light (KHR_lights_punctual).
    #[command(after_help = examples::VIEW_EXPORT)]
    ViewExport(view_export::ViewExportArgs),
    /// Generate a procedural scene of a given size into DIR: DIR/scene.json and one mesh file
    /// per object, the same bytes for the same arguments.
    ///
    /// `city`: a gentle terrain and closed buildings of varied heights (low houses to towers),
    /// one per lot of a square grid, their walls tessellated to reach the size. `forest`: a
    /// hilly terrain and closed trees (trunk and ellipsoid crown) on a jittered grid. About 40 %
    /// of the triangles are terrain. The count is met within 2 % from 20K triangles up. Each
    /// scene has a camera `main` over the ground from one corner, a low directional `sun` and a
    /// spot light `lamp` above the centre, both casting long shadows into the view.
    #[command(after_help = examples::GENERATE)]
    Generate(generate::GenerateArgs),
}

/// Parses the arguments and runs the command: 0 success, 1 a gate failed, 2 a usage or input
/// error.
pub fn main() -> std::process::ExitCode {
    use clap::{CommandFactory, FromArgMatches};
    use std::process::ExitCode;
    let parsed = Cli::command().try_get_matches().and_then(|m| Ok((Cli::from_arg_matches(&m)?, m)));
    let (args, matches) = match parsed {
        Ok(parsed) => parsed,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = folder_lock::lock_output_folder(&matches).and_then(|()| dispatch(args.command));
    shadowtruth::output_lock::release_output_folders();
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Runs one command; its exit code (0, or 1 for a failed gate or verification).
fn dispatch(command: Command) -> Result<u8> {
    match command {
        Command::Run(a) => run::run(a),
        Command::Reference(a) => reference::reference(a),
        Command::Verify(a) => verify::verify(a),
        Command::ExportObj(a) => export_obj::export_obj(a),
        Command::Gate(a) => gate::gate(a),
        Command::DepthMap(a) => depth_map::depth_map(a),
        Command::Score(a) => score::score(a),
        Command::Tune(a) => tune::run_tune(a),
        Command::Report(a) => report::report(a),
        Command::Merge(a) => merge::merge(a),
        Command::Papers(a) => papers::papers(a),
        Command::Island(a) => island::island(a),
        Command::ViewExport(a) => view_export::view_export(a),
        Command::Generate(a) => generate::generate(a),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_folder_writing_command_names_its_folder_argument() {
        let cli = <Cli as clap::CommandFactory>::command();
        for (name, arg) in folder_lock::FOLDER_WRITING_COMMANDS {
            let command = cli.find_subcommand(name).unwrap_or_else(|| panic!("no command {name}"));
            assert!(command.get_arguments().any(|a| a.get_id() == arg), "{name} has no argument {arg}");
        }
    }

    /// `a 'b c' d  # note` → ["a", "b c", "d"]: the shell's words of an example line.
    fn words(line: &str) -> Vec<String> {
        let line = line.split(" #").next().unwrap_or_default();
        let (mut out, mut word, mut quoted) = (Vec::new(), String::new(), false);
        for c in line.chars() {
            match c {
                '\'' => quoted = !quoted,
                ' ' if !quoted => out.extend((!word.is_empty()).then(|| std::mem::take(&mut word))),
                c => word.push(c),
            }
        }
        out.extend((!word.is_empty()).then_some(word));
        out
    }

    #[test]
    fn every_command_ends_its_help_with_examples_that_parse() {
        let cli = <Cli as clap::CommandFactory>::command();
        for command in cli.get_subcommands() {
            let name = command.get_name();
            let help = command.get_after_help().map(|h| h.to_string()).unwrap_or_default();
            let lines: Vec<&str> =
                help.lines().filter_map(|l| l.trim().strip_prefix("shadowtruth ")).collect();
            assert!(help.starts_with("Examples:") && !lines.is_empty(), "{name} has no examples");
            for line in lines {
                let argv = std::iter::once("shadowtruth".to_string()).chain(words(line));
                let parsed = Cli::try_parse_from(argv);
                assert!(parsed.is_ok(), "{name}: `{line}` does not parse: {}", parsed.err().unwrap());
                assert!(words(line)[0] == name, "{name}: `{line}` is another command's");
            }
        }
    }

    #[test]
    fn every_option_and_argument_says_what_it_is() {
        let cli = <Cli as clap::CommandFactory>::command();
        let mut silent = Vec::new();
        for command in cli.get_subcommands() {
            for arg in command.get_arguments().filter(|a| a.get_id() != "help") {
                let help = arg.get_help().or(arg.get_long_help()).map(|h| h.to_string()).unwrap_or_default();
                if help.trim().is_empty() {
                    silent.push(format!("{} {}", command.get_name(), arg.get_id()));
                }
            }
        }
        assert!(silent.is_empty(), "without help: {silent:?}");
    }
}
