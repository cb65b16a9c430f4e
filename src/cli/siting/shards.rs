//! `muse siting --shard K/N` and `--from-shards`: the greedy's first round — every candidate
//! evaluated with the existing pads, nine tenths of the work — split over machines, each
//! shard's evaluations in a `shard.json` ([`muse_siting::shard::ShardFile`]), merged to finish
//! the greedy in one place.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use muse_siting::Siting;
use muse_siting::greedy::FirstRound;
use muse_siting::shard::{FILE, Merge, ShardFile};

/// Reads the shards in `dirs` (each a folder holding a `shard.json`, or the file itself) and
/// merges them into the whole first round. Refused: a file that is not a siting shard; shards
/// of another problem than `problem`; a shard missing or given twice; an unknown candidate.
pub fn merge(dirs: &[PathBuf], problem: &str, siting: &Siting) -> anyhow::Result<FirstRound> {
    let mut merge = Merge::new(siting);
    for dir in dirs {
        let path = if dir.is_dir() {
            dir.join(FILE)
        } else {
            dir.clone()
        };
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(&path).with_context(|| format!("reading {shown}"))?;
        merge.add(&shown, ShardFile::read(&text, &shown, problem)?)?;
    }
    Ok(merge.finish()?)
}

/// FNV-1a (64 bits) of a file's bytes, in hex: which input a shard was made from.
pub fn file_digest(path: &Path) -> anyhow::Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    Ok(format!("{h:016x}"))
}
