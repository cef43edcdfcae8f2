//! Value parsers of options that several commands share (`--threads`, `--depth-format`), each
//! checked by clap as it parses, so that a command's body receives valid values and a bad one is
//! named with its option. Below both `commands/` and `tune/`, which take them from here.

use clap::builder::{PossibleValuesParser, RangedU64ValueParser, TypedValueParser};
use shadowtruth::raster::DepthFormat;

/// Worker threads at most, on every command.
pub const MAX_THREADS: usize = 1024;

/// `--threads N`: 1 to [`MAX_THREADS`].
pub fn threads_parser() -> RangedU64ValueParser<usize> {
    RangedU64ValueParser::<usize>::new().range(1..=MAX_THREADS as u64)
}

/// A depth format by its name (`f32`, `unorm24`, `unorm16`, `f16`).
pub fn depth_format_parser() -> impl TypedValueParser<Value = DepthFormat> {
    let names = DepthFormat::ALL.map(DepthFormat::name);
    PossibleValuesParser::new(names).map(|name| DepthFormat::parse(&name).expect("one of the names above"))
}
