//! `tune`'s options as the command line gives them, and their checks: every number finite and
//! in its documented range (docs/tune.md, Options), every parameter known and given once,
//! before anything is traced. The fuzz entry `fuzzing::tune_options` parses with the same code.

use super::{LogRange, Objective, SuiteAggregate, TuneRequest};
use crate::option_values::{depth_format_parser, threads_parser};
use anyhow::{Result, anyhow, bail};
use clap::Args;
use serde_json::{Map, Value};
use shadowtruth::raster::{DepthFormat, MAX_SHADOW_MAP_RESOLUTION};
use std::path::PathBuf;

/// Parameters tuned together at most.
pub const MAX_PARAMS: usize = 3;
/// Each end of a searched range lies in [MIN_PARAM_VALUE, MAX_PARAM_VALUE]: far beyond any
/// bias, offset or radius a shadow map can use, well inside f32 (what the maps are shaded in).
pub const MIN_PARAM_VALUE: f64 = 1e-12;
pub const MAX_PARAM_VALUE: f64 = 1e12;
/// A range spans at most this many decades: the one-parameter grid then has a point every
/// 0.73 decades; a wider range leaves valleys between grid points unseen.
pub const MAX_SPAN_DECADES: f64 = 8.0;
/// A range spans at least this many decades (12 %): narrower, the three significant digits
/// every value is rounded to leave too few distinct settings to search.
pub const MIN_SPAN_DECADES: f64 = 0.05;
/// `--weight` lies in [MIN_WEIGHT, MAX_WEIGHT]: beyond, one rate is below a pixel in a million
/// of the other, and the objective is one rate alone.
pub const MIN_WEIGHT: f64 = 1e-6;
pub const MAX_WEIGHT: f64 = 1e6;
/// `--gate-slack` lies in [0, MAX_GATE_SLACK]: a rule ten times above the error is no gate.
pub const MAX_GATE_SLACK: f64 = 10.0;
/// Shadow-map resolutions an evaluation shades at most.
pub const MAX_RESOLUTIONS: usize = 8;

/// The options of `shadowtruth tune` (docs/tune.md).
#[derive(Args, Debug)]
pub struct TuneArgs {
    /// Scene files or folders of scene files (default: scenes/).
    pub scenes: Vec<PathBuf>,
    /// The technique: its name (`constant`), or a JSON object with its fixed parameters
    /// (`{"technique": "pcf", "kernel": "box", "size": 3}`).
    #[arg(long)]
    pub technique: String,
    /// A parameter to tune, with its range searched on a log scale: NAME or NAME=LO:HI
    /// (1e-12 ≤ LO < HI ≤ 1e12, HI/LO between 1.12 and 1e8; or both below zero, as an engine's
    /// bias towards the light, `bias=-0.01:-1e-5`, searched on its magnitude). One to three, each once. Known
    /// names have a default range (bias_depth 1e-6:0.1, bias_world 1e-5:1, scale_texels
    /// 0.01:10, factor 0.01:16, units 0.01:64, k 1e-6:0.1, z_offset 1e-5:0.1, radius_texels
    /// 0.25:8).
    #[arg(long = "param", required = true, value_name = "NAME[=LO:HI]", value_parser = param_arg)]
    pub params: Vec<ParamArg>,
    /// What to minimise: `total` (false shadow + false lit), `weighted` (false shadow + W·false
    /// lit, with --weight W) or `false-lit-under` (the least false lit with false shadow at most
    /// --max-false-shadow X). Rates are fractions of each scene's scored pixels.
    #[arg(long, value_enum, default_value_t = ObjectiveKind::Total)]
    pub objective: ObjectiveKind,
    /// The weight of false lit with `--objective weighted`, from 1e-6 to 1e6.
    #[arg(long, value_name = "W", required_if_eq("objective", "weighted"))]
    pub weight: Option<f64>,
    /// The bound on false shadow with `--objective false-lit-under`, a fraction from 0 to 1.
    #[arg(long, value_name = "X", required_if_eq("objective", "false-lit-under"))]
    pub max_false_shadow: Option<f64>,
    /// The suite's objective: the mean of the scenes' or the worst scene's.
    #[arg(long, value_enum, default_value_t = SuiteAggregate::Mean)]
    pub suite: SuiteAggregate,
    /// Shadow-map resolutions (at most 8, each once); every evaluation shades each of them.
    #[arg(long, value_delimiter = ',', default_value = "1024",
          value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    pub resolutions: Vec<u32>,
    /// Depth format of the shadow maps: f32, unorm24, unorm16 or f16.
    #[arg(long, default_value = "f32", value_parser = depth_format_parser())]
    pub depth_format: DepthFormat,
    /// Output folder: tune.json, tune-gate.toml, plots/tune.png and the tuned settings' report.
    #[arg(short, long, default_value = "reports/tune")]
    pub out: PathBuf,
    /// The slack of the gate rules written for the suite's setting (relative, from 0 to 10;
    /// one pixel more).
    #[arg(long, default_value_t = 0.1)]
    pub gate_slack: f64,
    /// Reference cache folder.
    #[arg(long, default_value = "references")]
    pub references: PathBuf,
    /// Trace every reference instead of reading or writing the cache.
    #[arg(long)]
    pub no_cache: bool,
    /// Write tune.json and the plot only, without running the tuned settings into a report.
    #[arg(long)]
    pub no_report: bool,
    /// Also run each scene's own best setting into the report, beside the suite's.
    #[arg(long, conflicts_with = "no_report")]
    pub report_scene_bests: bool,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    pub threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    pub quiet: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjectiveKind {
    Total,
    Weighted,
    FalseLitUnder,
}

/// `tune`'s options alone, for parsing them outside the command (`parse_tune_options`).
#[derive(clap::Parser)]
#[command(name = "tune")]
struct TuneCommand {
    #[command(flatten)]
    args: TuneArgs,
}

/// Parses `args` (without the command's name) as `shadowtruth tune` does.
pub fn parse_tune_options<I, T>(args: I) -> Result<TuneArgs, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    use clap::Parser;
    let named = std::iter::once(std::ffi::OsString::from("tune")).chain(args.into_iter().map(Into::into));
    TuneCommand::try_parse_from(named).map(|c| c.args)
}

/// Default search ranges of the parameters that have an obvious one.
const DEFAULT_RANGES: [(&str, f64, f64); 16] = [
    ("bias_depth", 1e-6, 0.1),
    ("bias_world", 1e-5, 1.0),
    ("scale_texels", 0.01, 10.0),
    ("factor", 0.01, 16.0),
    ("units", 0.01, 64.0),
    ("k", 1e-6, 0.1),
    ("z_offset", 1e-5, 0.1),
    ("radius_texels", 0.25, 8.0),
    // The filterable maps' (docs/formulas.md, "Filterable shadow maps").
    ("bleeding_reduction", 0.01, 0.95),
    ("min_variance", 1e-8, 1e-2),
    ("exponent", 5.0, 88.0),
    ("positive_exponent", 5.0, 44.0),
    ("negative_exponent", 1.0, 44.0),
    ("variance_bias", 1e-4, 0.1),
    ("moment_bias", 1e-6, 1e-2),
    ("depth_bias", 1e-6, 0.1),
];

impl TuneArgs {
    /// The request from the options, every problem named by its option and value; both ends
    /// of every range make a valid technique. Nothing is read or traced.
    pub fn request(&self) -> Result<TuneRequest> {
        self.check_counts()?;
        let base = technique_object(&self.technique)?;
        let params = self.param_ranges(&base)?;
        let request = TuneRequest { base, params, objective: self.objective()?, aggregate: self.suite };
        // The search evaluates values rounded to three significant digits: both the ends and
        // their rounded values must make a valid technique.
        for corner in [true, false] {
            let values: Vec<f64> =
                request.params.iter().map(|(_, r)| if corner { r.lo } else { r.hi }).collect();
            for values in [super::round_all(&values), values] {
                request.spec(&values).map_err(|e| {
                    let given: Vec<&str> = self.params.iter().map(|p| p.given.as_str()).collect();
                    anyhow!("--technique {} with --param {given:?}: {e}", self.technique)
                })?;
            }
        }
        check_gate_slack(self.gate_slack)?;
        Ok(request)
    }

    fn check_counts(&self) -> Result<()> {
        if self.params.len() > MAX_PARAMS {
            bail!(
                "--param: at most {MAX_PARAMS} parameters are tuned together ({} given)",
                self.params.len()
            );
        }
        if self.resolutions.len() > MAX_RESOLUTIONS {
            bail!("--resolutions: at most {MAX_RESOLUTIONS} resolutions ({} given)", self.resolutions.len());
        }
        let repeated = self.resolutions.iter().enumerate().find(|(i, r)| self.resolutions[..*i].contains(r));
        if let Some((_, r)) = repeated {
            bail!("--resolutions: {r} is given twice");
        }
        Ok(())
    }

    /// Every `--param`, each once, none already fixed by `--technique`.
    fn param_ranges(&self, base: &Map<String, Value>) -> Result<Vec<(String, LogRange)>> {
        let mut params: Vec<(String, LogRange)> = Vec::new();
        for ParamArg { given, name, range } in &self.params {
            if params.iter().any(|(n, _)| n == name) {
                bail!("--param {given}: {name} is given twice; tune each parameter once");
            }
            if base.contains_key(name) {
                bail!("--param {given}: {name} is fixed by --technique; tune it or fix it, not both");
            }
            params.push((name.clone(), *range));
        }
        Ok(params)
    }

    fn objective(&self) -> Result<Objective> {
        let weighted = self.objective == ObjectiveKind::Weighted;
        let under = self.objective == ObjectiveKind::FalseLitUnder;
        // An option the objective does not read would be a number silently ignored.
        if let (Some(w), false) = (self.weight, weighted) {
            bail!("--weight {w}: read only by --objective weighted");
        }
        if let (Some(x), false) = (self.max_false_shadow, under) {
            bail!("--max-false-shadow {x}: read only by --objective false-lit-under");
        }
        Ok(match self.objective {
            ObjectiveKind::Total => Objective::Total,
            ObjectiveKind::Weighted => {
                let weight =
                    self.weight.ok_or_else(|| anyhow!("--weight: required by --objective weighted"))?;
                if !(MIN_WEIGHT..=MAX_WEIGHT).contains(&weight) {
                    bail!("--weight {weight}: must be a number from {MIN_WEIGHT:e} to {MAX_WEIGHT:e}");
                }
                Objective::Weighted { weight }
            }
            ObjectiveKind::FalseLitUnder => {
                let max_false_shadow = self
                    .max_false_shadow
                    .ok_or_else(|| anyhow!("--max-false-shadow: required by --objective false-lit-under"))?;
                if !(0.0..=1.0).contains(&max_false_shadow) {
                    bail!("--max-false-shadow {max_false_shadow}: must be a fraction from 0 to 1");
                }
                Objective::FalseLitUnder { max_false_shadow }
            }
        })
    }
}

/// `--gate-slack`: finite and in [0, MAX_GATE_SLACK], so that every rule is a number the gate
/// reads and the tuned report itself meets.
fn check_gate_slack(slack: f64) -> Result<()> {
    if !(0.0..=MAX_GATE_SLACK).contains(&slack) {
        bail!("--gate-slack {slack}: must be a number from 0 to {MAX_GATE_SLACK}");
    }
    Ok(())
}

fn technique_object(text: &str) -> Result<Map<String, Value>> {
    if !text.trim_start().starts_with('{') {
        let mut m = Map::new();
        m.insert("technique".into(), Value::from(text));
        return Ok(m);
    }
    match serde_json::from_str(text) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => bail!("--technique: expected a technique name or a JSON object"),
        Err(e) => bail!("--technique: {e} (in {text})"),
    }
}

/// One `--param` as given (`NAME` or `NAME=LO:HI`), and the range it names.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamArg {
    pub given: String,
    pub name: String,
    pub range: LogRange,
}

/// `--param`'s value parser: the name, and its range given or by default, checked; clap names
/// the option and the value beside the message.
fn param_arg(text: &str) -> Result<ParamArg, String> {
    let (name, range) = match text.split_once('=') {
        Some((name, range)) => {
            let (lo, hi) = range.split_once(':').ok_or("expected NAME=LO:HI")?;
            let parse = |s: &str| s.trim().parse::<f64>().map_err(|e| format!("{s}: {e}"));
            (name.trim(), LogRange { lo: parse(lo)?, hi: parse(hi)? })
        }
        None => {
            let name = text.trim();
            let (_, lo, hi) = DEFAULT_RANGES
                .iter()
                .find(|(n, _, _)| *n == name)
                .ok_or_else(|| format!("{name} has no default range; give one as {name}=LO:HI"))?;
            (name, LogRange { lo: *lo, hi: *hi })
        }
    };
    check_range(range)?;
    Ok(ParamArg { given: text.to_string(), name: name.to_string(), range })
}

/// Both ends on one side of zero (a log scale of the magnitude), within the bounds.
fn check_range(range: LogRange) -> Result<(), String> {
    let ordered = range.lo < range.hi && range.lo.is_finite() && range.hi.is_finite();
    if !ordered || (range.lo <= 0.0 && range.hi >= 0.0) {
        return Err(
            "the range must satisfy 0 < LO < HI or LO < HI < 0 (it is searched on a log scale of the magnitude)"
                .into(),
        );
    }
    let LogRange { lo, hi } = range.magnitude();
    let within = |x: f64| (MIN_PARAM_VALUE..=MAX_PARAM_VALUE).contains(&x);
    if !within(lo) || !within(hi) {
        return Err(format!("LO and HI must lie from {MIN_PARAM_VALUE:e} to {MAX_PARAM_VALUE:e}"));
    }
    let decades = (hi / lo).log10();
    if !(MIN_SPAN_DECADES..=MAX_SPAN_DECADES).contains(&decades) {
        return Err(format!(
            "the range spans {decades:.3} decades; it must span {MIN_SPAN_DECADES} to {MAX_SPAN_DECADES} \
             (HI/LO from {:.3} to {:e}) for the search to resolve it",
            10f64.powf(MIN_SPAN_DECADES),
            10f64.powf(MAX_SPAN_DECADES)
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(args: &[&str]) -> Result<TuneRequest> {
        let base = ["--technique", "constant"];
        parse_tune_options(base.iter().chain(args)).map_err(|e| anyhow!("{e}"))?.request()
    }

    fn refused(args: &[&str], needle: &str) {
        let e = request(args).expect_err(&format!("{args:?} accepted"));
        assert!(e.to_string().contains(needle), "{args:?}: {e}");
    }

    #[test]
    fn the_readme_examples_are_accepted() {
        let r = request(&["--param", "bias_depth"]).unwrap();
        assert_eq!(r.params, vec![("bias_depth".to_string(), LogRange { lo: 1e-6, hi: 0.1 })]);
        let r = request(&["--param", "bias_depth=1e-4:1e-2", "--objective", "weighted", "--weight", "4"])
            .unwrap();
        assert_eq!(r.objective, Objective::Weighted { weight: 4.0 });
        let pcf = r#"{"technique": "pcf", "kernel": "poisson", "bias": "constant"}"#;
        let args = [
            "--technique",
            pcf,
            "--param",
            "bias_depth",
            "--param",
            "radius_texels=0.5:4",
            "--suite",
            "worst",
        ];
        assert_eq!(parse_tune_options(args).unwrap().request().unwrap().params.len(), 2);
    }

    #[test]
    fn every_number_outside_its_range_is_refused_naming_the_option_and_value() {
        // `--option=VALUE`: clap reads a lone `-1` as an option.
        let check = |objective: &[&str], option: &str, values: &[&str]| {
            for v in values {
                let given = format!("{option}={v}");
                let args: Vec<&str> = ["--param", "bias_depth"]
                    .iter()
                    .chain(objective)
                    .copied()
                    .chain([given.as_str()])
                    .collect();
                refused(&args, &format!("{option} {}", v.parse::<f64>().unwrap()));
            }
        };
        check(&["--objective", "weighted"], "--weight", &["NaN", "inf", "-1", "0", "1e7"]);
        check(&["--objective", "false-lit-under"], "--max-false-shadow", &["NaN", "-0.1", "1.5", "inf"]);
        check(&[], "--gate-slack", &["NaN", "-1", "inf", "11"]);
        assert!(request(&["--param", "bias_depth", "--gate-slack", "0"]).is_ok());
    }

    #[test]
    fn ranges_must_be_finite_positive_increasing_and_resolvable() {
        for (range, needle) in [
            ("bias_depth=NaN:1", "0 < LO < HI"),
            ("bias_depth=1e-3:inf", "0 < LO < HI"),
            ("bias_depth=0:1", "0 < LO < HI"),
            ("bias_depth=-1:1", "0 < LO < HI"),
            ("bias_depth=0.1:0.01", "0 < LO < HI"),
            ("bias_depth=1e-200:1e-190", "LO and HI"),
            ("bias_depth=1e-200:1e200", "LO and HI"),
            ("bias_depth=1e-9:1", "spans 9.000 decades"),
            ("bias_depth=0.01:0.0101", "spans 0.004 decades"),
        ] {
            refused(&["--param", range], &format!("invalid value '{range}' for '--param"));
            refused(&["--param", range], needle);
        }
        assert!(request(&["--param", "bias_depth=1e-9:0.1"]).is_ok(), "8 decades");
    }

    #[test]
    fn a_parameter_is_tuned_once_and_not_also_fixed() {
        refused(&["--param", "bias_depth", "--param", "bias_depth=1e-3:1e-2"], "bias_depth is given twice");
        let fixed =
            ["--technique", r#"{"technique": "constant", "bias_depth": 0.01}"#, "--param", "bias_depth"];
        let e = parse_tune_options(fixed).unwrap().request().unwrap_err();
        assert!(e.to_string().contains("fixed by --technique"), "{e}");
        refused(&["--param", "scale_texels"], "scale_texels");
    }

    #[test]
    fn counts_are_bounded() {
        let four = ["--param", "bias_depth", "--param", "a=1:2", "--param", "b=1:2", "--param", "c=1:2"];
        refused(&four, "at most 3");
        refused(&["--param", "bias_depth", "--resolutions", "1,2,3,4,5,6,7,8,9"], "--resolutions");
        refused(&["--param", "bias_depth", "--resolutions", "64,128,64"], "64 is given twice");
        for threads in ["0", "1025"] {
            let e = parse_tune_options([
                "--technique",
                "constant",
                "--param",
                "bias_depth",
                "--threads",
                threads,
            ]);
            assert!(e.is_err_and(|e| e.to_string().contains("--threads")), "--threads {threads}");
        }
    }

    #[test]
    fn an_option_the_objective_does_not_read_is_refused() {
        refused(&["--param", "bias_depth", "--weight", "2"], "--weight 2: read only by --objective weighted");
        refused(&["--param", "bias_depth", "--max-false-shadow", "0.1"], "--max-false-shadow 0.1");
    }
}
