//! A sweep cut into shards, for a cluster's array job, and the shards merged back exactly.
//!
//! The runs of an experiment are numbered in the order one machine runs and writes them
//! (case, then count, then repetition: see [`Kind`](super::Kind)); shard `K` of `N` runs those
//! whose number is `K` modulo `N`. The slices are disjoint and together whole, each run keeps
//! its seed, and since consecutive runs differ in size only by their count, every shard gets
//! the same mix of small and large days.
//!
//! A shard's result is a [`ShardFile`]: the sweep's [`fingerprint`], `K`, `N`, the number of
//! runs in the whole sweep and the shard's records, each with its run number.
//! [`merge`] checks that a set of shard files is one sweep cut once — same fingerprint, same
//! `N`, every shard once, every run once — and returns the records in the order one machine
//! would have written them.

use serde::{Deserialize, Serialize};

/// The format tag of a shard file.
pub const FORMAT: &str = "muse-sweep-shard/1";

/// Shard `index` of `of` (`0 <= index < of`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which slice, from 0.
    pub index: usize,
    /// How many slices.
    pub of: usize,
}

/// Why a shard spec or a set of shard files is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// `--shard` is not `K/N` with `0 <= K < N`.
    #[error("shard `{0}`: expected K/N with 0 <= K < N, e.g. 0/8 (Slurm: $SLURM_ARRAY_TASK_ID/N)")]
    Spec(String),
    /// No shard files were given.
    #[error("no shards to merge")]
    Empty,
    /// A file is not a shard file of this format.
    #[error("{file}: not a MUSE sweep shard ({message})")]
    Format {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// Two shards come from different sweeps (different parameters or cut).
    #[error(
        "{a} and {b} are shards of different sweeps ({what}): merge only the shards of one `muse sweep` command"
    )]
    Different {
        /// One shard file.
        a: String,
        /// The other.
        b: String,
        /// What differs.
        what: String,
    },
    /// The same shard was given twice.
    #[error("shard {index}/{of} is given twice: {a} and {b}")]
    Duplicate {
        /// The shard.
        index: usize,
        /// Of how many.
        of: usize,
        /// One file.
        a: String,
        /// The other.
        b: String,
    },
    /// Shards are missing.
    #[error(
        "missing shard(s) {missing} of {of}: run them (a killed shard is simply rerun) and merge again"
    )]
    Missing {
        /// The missing indices, e.g. `2/8, 5/8`.
        missing: String,
        /// Of how many.
        of: usize,
    },
    /// A shard's records are not exactly its runs.
    #[error("{file}: {message}")]
    Runs {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
}

impl Shard {
    /// The whole sweep as one shard.
    pub const WHOLE: Shard = Shard { index: 0, of: 1 };

    /// Reads `K/N`.
    ///
    /// ```
    /// use muse_sim::experiment::Shard;
    /// assert_eq!(Shard::parse("2/8").unwrap(), Shard { index: 2, of: 8 });
    /// assert!(Shard::parse("8/8").is_err() && Shard::parse("1").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let bad = || ShardError::Spec(text.to_owned());
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = k.trim().parse().map_err(|_| bad())?;
        let of: usize = n.trim().parse().map_err(|_| bad())?;
        if index >= of {
            return Err(bad());
        }
        Ok(Shard { index, of })
    }

    /// Whether run number `run` is in this shard.
    pub fn takes(self, run: usize) -> bool {
        run % self.of == self.index
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.of)
    }
}

/// An experiment's identity: a hash of everything that decides its runs — its grid (counts,
/// repetitions, seeds, demand window and rule, booking lead, flight parameters) and its
/// kind's cases (each variant's zones and parameters, or each lead's) — and of this
/// program's version.
///
/// ```
/// use muse_sim::experiment::fingerprint;
/// assert_eq!(fingerprint(&(1, "a")), fingerprint(&(1, "a")));
/// assert_ne!(fingerprint(&(1, "a")), fingerprint(&(2, "a")));
/// ```
pub fn fingerprint(spec: &impl std::fmt::Debug) -> String {
    // FNV-1a, 64 bits, over a canonical text of the spec: stable across runs and machines of
    // one build.
    let text = format!("{} {spec:?}", env!("CARGO_PKG_VERSION"));
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// One run in a shard file: its number in the whole sweep and its record (its kind's
/// [`Kind::Record`](super::Kind::Record)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardRun<R> {
    /// Its number in the whole sweep.
    pub run: usize,
    /// What it measured.
    #[serde(flatten)]
    pub record: R,
}

/// The study a sweep came from (`muse sweep --study FILE`), kept in its shards so that the
/// merge can name it and compare with its published results.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StudyRef {
    /// The study file, as given.
    pub file: String,
    /// Its title.
    pub title: String,
    /// The folder of its published results, if it names one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub results: Option<String>,
}

/// What a shard writes (as JSON, `shard.json`); `R` is the kind of record its sweep makes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound(serialize = "R: Serialize", deserialize = "R: Deserialize<'de>"))]
pub struct ShardFile<R> {
    /// [`FORMAT`].
    pub format: String,
    /// The sweep's [`fingerprint`].
    pub sweep: String,
    /// Which shard.
    pub shard: usize,
    /// Of how many.
    pub of: usize,
    /// Runs in the whole sweep.
    pub runs: usize,
    /// The command line that ran it, from the command's name on (what `merge` rebuilds the
    /// sweep from); a study's options written out.
    pub args: Vec<String>,
    /// The study it ran, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study: Option<StudyRef>,
    /// The shard's runs, by run number.
    pub records: Vec<ShardRun<R>>,
}

impl<R> ShardFile<R> {
    /// The file of shard `shard` of the sweep `sweep` (its [`fingerprint`]) of `runs` runs,
    /// run with the command line `args`, holding `records` (run number, record).
    pub fn new(
        sweep: String,
        shard: Shard,
        runs: usize,
        args: Vec<String>,
        study: Option<StudyRef>,
        records: Vec<(usize, R)>,
    ) -> ShardFile<R> {
        ShardFile {
            format: FORMAT.to_owned(),
            sweep,
            shard: shard.index,
            of: shard.of,
            runs,
            args,
            study,
            records: records
                .into_iter()
                .map(|(run, record)| ShardRun { run, record })
                .collect(),
        }
    }
}

impl<R: for<'de> Deserialize<'de>> ShardFile<R> {
    /// Reads a shard file's text; `file` names it in errors.
    pub fn read(text: &str, file: &str) -> Result<ShardFile<R>, ShardError> {
        let f: ShardFile<R> = serde_json::from_str(text).map_err(|e| ShardError::Format {
            file: file.to_owned(),
            message: e.to_string(),
        })?;
        if f.format != FORMAT {
            return Err(ShardError::Format {
                file: file.to_owned(),
                message: format!("format `{}`, expected `{FORMAT}`", f.format),
            });
        }
        Ok(f)
    }
}

/// Merges shard files `(name, file)` of one sweep into its records in the order of one
/// machine (see the module docs), or says why they are not one sweep cut once.
pub fn merge<R: Clone>(shards: &[(String, ShardFile<R>)]) -> Result<Vec<R>, ShardError> {
    let Some((first_name, first)) = shards.first() else {
        return Err(ShardError::Empty);
    };
    let mut by_index: Vec<Option<&str>> = vec![None; first.of];
    for (name, f) in shards {
        let differ = |what: String| ShardError::Different {
            a: first_name.clone(),
            b: name.clone(),
            what,
        };
        if f.sweep != first.sweep {
            return Err(differ(format!(
                "parameters {} and {}",
                first.sweep, f.sweep
            )));
        }
        if f.of != first.of || f.runs != first.runs {
            return Err(differ(format!("cut into {} and {} shards", first.of, f.of)));
        }
        let slot = by_index.get_mut(f.shard).ok_or_else(|| ShardError::Runs {
            file: name.clone(),
            message: format!("shard {} of {} does not exist", f.shard, f.of),
        })?;
        if let Some(a) = slot {
            return Err(ShardError::Duplicate {
                index: f.shard,
                of: f.of,
                a: (*a).to_owned(),
                b: name.clone(),
            });
        }
        *slot = Some(name);
    }
    let missing: Vec<String> = by_index
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(i, _)| format!("{i}/{}", first.of))
        .collect();
    if !missing.is_empty() {
        return Err(ShardError::Missing {
            missing: missing.join(", "),
            of: first.of,
        });
    }
    let mut runs: Vec<Option<R>> = vec![None; first.runs];
    for (name, f) in shards {
        let shard = Shard {
            index: f.shard,
            of: f.of,
        };
        let expected = (0..f.runs).filter(|&r| shard.takes(r)).count();
        if f.records.len() != expected {
            return Err(ShardError::Runs {
                file: name.clone(),
                message: format!(
                    "{} runs, expected {expected} for shard {shard} of a {}-run sweep (a shard that did not finish writes no file: rerun it)",
                    f.records.len(),
                    f.runs
                ),
            });
        }
        for r in &f.records {
            let bad = |message: String| ShardError::Runs {
                file: name.clone(),
                message,
            };
            if !shard.takes(r.run) || r.run >= f.runs {
                return Err(bad(format!("run {} is not in shard {shard}", r.run)));
            }
            if runs[r.run].replace(r.record.clone()).is_some() {
                return Err(bad(format!("run {} appears twice", r.run)));
            }
        }
    }
    // Every shard had exactly its runs, each once: all runs are there.
    Ok(runs.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record of a test.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    struct Record {
        planned: usize,
    }

    fn record(run: usize) -> Record {
        Record { planned: run }
    }

    fn shard_file(
        sweep: &str,
        index: usize,
        of: usize,
        runs: usize,
    ) -> (String, ShardFile<Record>) {
        let shard = Shard { index, of };
        (
            format!("out/{index}"),
            ShardFile {
                format: FORMAT.into(),
                sweep: sweep.into(),
                shard: index,
                of,
                runs,
                args: vec![],
                study: None,
                records: (0..runs)
                    .filter(|&r| shard.takes(r))
                    .map(|r| ShardRun {
                        run: r,
                        record: record(r),
                    })
                    .collect(),
            },
        )
    }

    #[test]
    fn shards_are_disjoint_and_whole() {
        for of in 1..7 {
            for runs in 0..20 {
                let mut seen = vec![0; runs];
                for index in 0..of {
                    for r in (0..runs).filter(|&r| Shard { index, of }.takes(r)) {
                        seen[r] += 1;
                    }
                }
                assert!(seen.iter().all(|&n| n == 1), "{of} shards of {runs} runs");
            }
        }
    }

    #[test]
    fn merge_restores_the_order_of_one_machine() {
        let shards: Vec<_> = [2, 0, 1].map(|i| shard_file("s", i, 3, 10)).into();
        let merged = merge(&shards).unwrap();
        assert_eq!(merged, (0..10).map(record).collect::<Vec<_>>());
        let text = serde_json::to_string(&shards[0].1).unwrap();
        assert_eq!(ShardFile::read(&text, "f").unwrap(), shards[0].1);
    }

    #[test]
    fn merge_refuses_other_sweeps_missing_and_duplicated_shards() {
        let e = merge(&[shard_file("s", 0, 2, 10), shard_file("t", 1, 2, 10)]).unwrap_err();
        assert!(e.to_string().contains("different sweeps"), "{e}");
        let e = merge(&[shard_file("s", 0, 2, 10), shard_file("s", 1, 3, 10)]).unwrap_err();
        assert!(e.to_string().contains("different sweeps"), "{e}");
        let e = merge(&[shard_file("s", 0, 3, 10), shard_file("s", 2, 3, 10)]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "missing shard(s) 1/3 of 3: run them (a killed shard is simply rerun) and merge again"
        );
        let e = merge(&[
            shard_file("s", 0, 2, 10),
            shard_file("s", 0, 2, 10),
            shard_file("s", 1, 2, 10),
        ])
        .unwrap_err();
        assert!(matches!(e, ShardError::Duplicate { index: 0, .. }), "{e}");
        let mut short = shard_file("s", 1, 2, 10);
        short.1.records.pop();
        let e = merge(&[shard_file("s", 0, 2, 10), short]).unwrap_err();
        assert!(e.to_string().contains("4 runs, expected 5"), "{e}");
        assert!(matches!(merge::<Record>(&[]), Err(ShardError::Empty)));
        assert!(
            ShardFile::<Record>::read("{}", "x.json")
                .unwrap_err()
                .to_string()
                .starts_with("x.json: not a MUSE sweep shard")
        );
    }
}
