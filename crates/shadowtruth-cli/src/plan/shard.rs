//! `run --shard K/N`: which views of the schedule shard K of N runs. Views are dealt out
//! round-robin in schedule order (view i, counted from 0, goes to shard i mod N + 1), so that
//! every view — its G-buffer, references and shadow maps — stays within one shard, and shards of
//! a suite whose scenes differ in view count still get views of every scene.

use shadowtruth::record::ShardRecord;
use std::fmt;

/// Shard `index` of `count`, 1 ≤ index ≤ count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    index: u32,
    count: u32,
}

impl Shard {
    pub fn new(index: u32, count: u32) -> Result<Self, String> {
        if count == 0 {
            return Err(format!("{index}/{count}: N must be at least 1"));
        }
        if !(1..=count).contains(&index) {
            return Err(format!("{index}/{count}: K must be between 1 and N ({count})"));
        }
        Ok(Shard { index, count })
    }

    /// Parses `K/N`, the form `--shard` takes.
    pub fn parse(text: &str) -> Result<Self, String> {
        let wrong = || format!("'{text}' is not K/N (shard K of N, 1 ≤ K ≤ N, e.g. 2/4)");
        let (k, n) = text.split_once('/').ok_or_else(wrong)?;
        let (k, n) =
            (k.trim().parse::<u32>().map_err(|_| wrong())?, n.trim().parse::<u32>().map_err(|_| wrong())?);
        Shard::new(k, n)
    }

    /// The shard that runs the view at `position` (from 0) of the schedule, round-robin.
    pub fn owner_of(position: usize, count: u32) -> u32 {
        (position % count as usize) as u32 + 1
    }

    /// Whether this shard runs the view at `position` of the schedule.
    pub fn owns(&self, position: usize) -> bool {
        Shard::owner_of(position, self.count) == self.index
    }

    pub fn record(&self) -> ShardRecord {
        ShardRecord { index: self.index, count: self.count }
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}
