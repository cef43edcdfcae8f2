//! Reports assembled from parts: `merge` joins the folders of `run --shard K/N`, `run --resume`
//! reopens an interrupted run's folder.

mod merge;
mod resume;

pub use merge::merge_shards;
pub use resume::open_resumed;
