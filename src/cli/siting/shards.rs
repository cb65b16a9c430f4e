//! `muse siting --shard K/N` and `--from-shards`: the greedy's first round — every candidate
//! evaluated with the existing pads, nine tenths of the work — split over machines, each
//! shard's evaluations in a `shard.json`, merged to finish the greedy in one place.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use muse_sim::experiment::Shard;
use muse_siting::greedy::FirstRound;
use muse_siting::{Evaluation, Siting};
use serde_json::{Value, json};

/// The `format` of a siting shard file.
const FORMAT: &str = "muse-siting-shard/1";

/// The shard file in a shard's output folder.
pub const FILE: &str = "shard.json";

fn evaluation_json(e: &Evaluation) -> Value {
    json!({
        "delivered": e.delivered,
        "served": e.served,
        "expanded": e.expanded,
        "corridors": e.corridors,
    })
}

fn evaluation_of(v: &Value, at: &str) -> anyhow::Result<Evaluation> {
    let numbers = |field: &str| -> anyhow::Result<Vec<u32>> {
        v[field]
            .as_array()
            .with_context(|| format!("{at}: `{field}` is not a list"))?
            .iter()
            .map(|x| {
                x.as_u64()
                    .and_then(|x| u32::try_from(x).ok())
                    .with_context(|| format!("{at}: `{field}` holds {x}, not a count"))
            })
            .collect()
    };
    let count = |field: &str| {
        v[field]
            .as_u64()
            .with_context(|| format!("{at}: `{field}` is not a count"))
    };
    Ok(Evaluation {
        delivered: numbers("delivered")?,
        served: numbers("served")?,
        expanded: count("expanded")?,
        corridors: usize::try_from(count("corridors")?)?,
    })
}

/// The text of a shard's `shard.json`: the problem it belongs to (`problem`), the shard, and
/// its evaluations by candidate id.
pub fn shard_json(problem: &str, shard: Shard, siting: &Siting, first: &FirstRound) -> String {
    let evaluations: Vec<Value> = first
        .evaluations
        .iter()
        .map(|(c, e)| {
            let mut v = evaluation_json(e);
            v["candidate"] = json!(siting.candidates()[*c].id);
            v
        })
        .collect();
    let doc = json!({
        "format": FORMAT,
        "problem": problem,
        "shard": format!("{}/{}", shard.index, shard.of),
        "candidates": siting.candidates().len(),
        "days": siting.day_count(),
        "base": evaluation_json(&first.base),
        "evaluations": evaluations,
    });
    serde_json::to_string_pretty(&doc).expect("JSON values serialize") + "\n"
}

/// Reads the shards in `dirs` (each a folder holding a `shard.json`, or the file itself) and
/// merges them into the whole first round. Refused: a file that is not a siting shard; shards
/// of another problem than `problem`; a shard missing or given twice; an unknown candidate.
pub fn merge(dirs: &[PathBuf], problem: &str, siting: &Siting) -> anyhow::Result<FirstRound> {
    let mut seen: Vec<Option<PathBuf>> = Vec::new();
    let mut base: Option<Evaluation> = None;
    let mut evaluations = Vec::new();
    for dir in dirs {
        let path = if dir.is_dir() {
            dir.join(FILE)
        } else {
            dir.clone()
        };
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(&path).with_context(|| format!("reading {shown}"))?;
        let doc: Value = serde_json::from_str(&text)
            .with_context(|| format!("{shown}: not a MUSE siting shard (not JSON)"))?;
        if doc["format"] != FORMAT {
            bail!("{shown}: not a MUSE siting shard (`format` is not `{FORMAT}`)");
        }
        if doc["problem"] != problem {
            bail!(
                "{shown} is a shard of another siting problem: its options or input files \
                 differ from this command's (the shard says {}, this command {problem})",
                doc["problem"]
            );
        }
        let shard = doc["shard"]
            .as_str()
            .map(Shard::parse)
            .with_context(|| format!("{shown}: `shard` is not K/N"))??;
        if seen.is_empty() {
            seen = vec![None; shard.of];
        }
        if seen.len() != shard.of {
            bail!(
                "{shown}: shard {}/{}, but another shard is of {}",
                shard.index,
                shard.of,
                seen.len()
            );
        }
        if let Some(first) = seen[shard.index].replace(path.clone()) {
            bail!(
                "{shown} and {} are both shard {}/{}",
                first.display(),
                shard.index,
                shard.of
            );
        }
        let b = evaluation_of(&doc["base"], &format!("{shown}: base"))?;
        match &base {
            Some(known) if *known != b => {
                bail!("{shown}: its base evaluation differs from the other shards'")
            }
            _ => base = Some(b),
        }
        for (i, v) in doc["evaluations"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            let at = format!("{shown}: evaluation {i}");
            let id = v["candidate"]
                .as_str()
                .with_context(|| format!("{at}: no `candidate`"))?;
            let c = siting
                .candidates()
                .iter()
                .position(|n| n.id == id)
                .with_context(|| format!("{at}: `{id}` is not a candidate"))?;
            evaluations.push((c, evaluation_of(v, &at)?));
        }
    }
    if let Some(missing) = seen.iter().position(Option::is_none) {
        bail!(
            "shard {missing}/{} is missing: give every shard's folder",
            seen.len()
        );
    }
    let base = base.context("no shards given")?;
    Ok(FirstRound { base, evaluations })
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
