//! The example command lines that end each command's `--help`. Each is parsed by the tests, so
//! none names an option that does not exist (arguments with spaces are single-quoted).

pub const RUN: &str = "\
Examples:
  shadowtruth run                                    # the bundled suite, default plan
  shadowtruth run scenes/rocks.json --plan plans/bias-sweep.json -o reports/sweep --timing
  shadowtruth run --resolutions 1024,2048 --table suite --shard 1/4";

pub const REFERENCE: &str = "\
Examples:
  shadowtruth reference scenes/rocks.json -o rocks-mask.png
  shadowtruth reference scenes/spot.json --light lamp --kind area --samples 8 -o lamp-soft.exr
  shadowtruth reference scenes/rocks.json -o mask.png --timing --threads 1";

pub const VERIFY: &str = "\
Examples:
  shadowtruth verify scenes/rocks.json
  shadowtruth verify scenes/papers/island.json --camera front --json verify.json";

pub const EXPORT_OBJ: &str = "\
Examples:
  shadowtruth export-obj scenes/rocks.json -o rocks-world.obj
  shadowtruth export-obj model.glb -o model-world.obj";

pub const GATE: &str = "\
Examples:
  shadowtruth gate reports/latest --rules gates/shadow-settings.toml
  shadowtruth gate reports/latest --rules gates/shadow-settings.toml --baseline reports/main --junit gate.xml";

pub const DEPTH_MAP: &str = "\
Examples:
  shadowtruth depth-map scenes/rocks.json --resolution 2048 -o rocks-depth.exr
  shadowtruth depth-map scenes/spot.json --light lamp --resolution 1024 --layer 2 --cull back -o second.exr";

pub const SCORE: &str = "\
Examples:
  shadowtruth score scenes/rocks.json --camera main --light sun --visibility shadows.exr -o scored
  shadowtruth score scenes/rocks.json --camera main --light sun --shadow-map depth.exr \
--technique '{\"technique\": \"constant\", \"bias_depth\": 0.001}' -o scored-map";

pub const TUNE: &str = "\
Examples:
  shadowtruth tune --technique slope_scaled --param factor=0.1:8 --param units=0.5:64 -o tuned
  shadowtruth tune scenes/rocks.json --technique constant --param bias_depth=1e-5:1e-2 --resolutions 2048";

pub const REPORT: &str = "\
Examples:
  shadowtruth report reports/latest";

pub const MERGE: &str = "\
Examples:
  shadowtruth merge shard1 shard2 shard3 shard4 -o reports/merged";

pub const PAPERS: &str = "\
Examples:
  shadowtruth papers                       # every claim, into reports/papers
  shadowtruth papers --quick -o reports/papers-quick";

pub const ISLAND: &str = "\
Examples:
  shadowtruth island                       # rewrites scenes/papers/island.json
  shadowtruth island --seed 7 -o my-island";

pub const VIEW_EXPORT: &str = "\
Examples:
  shadowtruth view-export scenes/rocks.json --camera main --light sun -o rocks-view
  shadowtruth view-export scenes/spot.json --light lamp --resolution 2048 -o spot-view";

pub const GENERATE: &str = "\
Examples:
  shadowtruth generate city --triangles 10M --image 4096,4096 -o city10m
  shadowtruth generate forest --instanced --triangles 100M -o forest100m";
