//! The greedy's first round cut into shards (`muse siting --shard K/N`), each shard's
//! evaluations in a file ([`ShardFile`], `shard.json`), and the files merged back into the
//! whole first round ([`Merge`]).
//!
//! A shard file says which problem it belongs to (`problem`: a text the command makes of
//! everything the first round depends on), which shard it is (`K/N`), the problem's numbers
//! of candidates and days, the existing pads' evaluation and each of its candidates'. A merge
//! refuses a file that is not a siting shard, a shard of another problem, shards cut in
//! different numbers, a shard given twice or missing, base evaluations that differ and an
//! unknown candidate.

use muse_sim::experiment::Shard;
use serde::{Deserialize, Serialize};

use crate::greedy::FirstRound;
use crate::{Evaluation, Siting};

/// The `format` of a siting shard file.
pub const FORMAT: &str = "muse-siting-shard/1";

/// The shard file in a shard's output folder.
pub const FILE: &str = "shard.json";

/// What a shard writes (as JSON, `shard.json`). Its fields, and those of its evaluations, are
/// in the order written: alphabetical.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardFile {
    /// The existing pads alone.
    pub base: Counts,
    /// Candidates in the whole problem.
    pub candidates: usize,
    /// Days each evaluation plans.
    pub days: usize,
    /// The shard's candidates, each evaluated with the existing pads.
    pub evaluations: Vec<CandidateCounts>,
    /// [`FORMAT`].
    pub format: String,
    /// The problem the shard belongs to.
    pub problem: String,
    /// Which shard, `K/N`.
    pub shard: String,
}

/// An [`Evaluation`] as a shard file writes it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    /// Corridors of the rebuilt airspace.
    pub corridors: usize,
    /// Requests delivered, day by day.
    pub delivered: Vec<u32>,
    /// Labels expanded, over all days.
    pub expanded: u64,
    /// Requests served, day by day.
    pub served: Vec<u32>,
}

/// A candidate's [`Evaluation`] with the existing pads, as a shard file writes it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CandidateCounts {
    /// The candidate's id.
    pub candidate: String,
    /// Its evaluation.
    #[serde(flatten)]
    pub counts: Counts,
}

impl From<&Evaluation> for Counts {
    fn from(e: &Evaluation) -> Counts {
        Counts {
            corridors: e.corridors,
            delivered: e.delivered.clone(),
            expanded: e.expanded,
            served: e.served.clone(),
        }
    }
}

impl From<Counts> for Evaluation {
    fn from(c: Counts) -> Evaluation {
        Evaluation {
            delivered: c.delivered,
            served: c.served,
            expanded: c.expanded,
            corridors: c.corridors,
        }
    }
}

/// Why a shard file is refused.
#[derive(Debug, thiserror::Error)]
pub enum ShardFileError {
    /// The file is not JSON.
    #[error("{file}: not a MUSE siting shard (not JSON)")]
    NotJson {
        /// The file.
        file: String,
        /// What the JSON reader says.
        #[source]
        source: serde_json::Error,
    },
    /// The file's `format` is not [`FORMAT`].
    #[error("{file}: not a MUSE siting shard (`format` is not `{FORMAT}`)")]
    Format {
        /// The file.
        file: String,
    },
    /// The file's fields are not those of a shard file.
    #[error("{file}: not a MUSE siting shard ({message})")]
    Fields {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// The shard is of another problem.
    #[error(
        "{file} is a shard of another siting problem: its options or input files differ from \
         this command's (the shard says {theirs}, this command {ours})"
    )]
    OtherProblem {
        /// The file.
        file: String,
        /// Its `problem`, as written in JSON.
        theirs: String,
        /// This command's.
        ours: String,
    },
    /// The shard is not `K/N`.
    #[error(transparent)]
    Spec(#[from] muse_sim::experiment::ShardError),
    /// The shard is of another number of shards than an earlier one.
    #[error("{file}: shard {shard}, but another shard is of {of}")]
    Cut {
        /// The file.
        file: String,
        /// Its shard.
        shard: Shard,
        /// The earlier shards' number.
        of: usize,
    },
    /// The shard was given before.
    #[error("{file} and {first} are both shard {shard}")]
    Twice {
        /// The file.
        file: String,
        /// The file given before.
        first: String,
        /// The shard.
        shard: Shard,
    },
    /// The shard's base evaluation differs from an earlier shard's.
    #[error("{file}: its base evaluation differs from the other shards'")]
    Base {
        /// The file.
        file: String,
    },
    /// An evaluation names no candidate of the problem.
    #[error("{file}: evaluation {index}: `{id}` is not a candidate")]
    Candidate {
        /// The file.
        file: String,
        /// The evaluation's place in the file, from 0.
        index: usize,
        /// The id it names.
        id: String,
    },
    /// A shard was not given.
    #[error("shard {0} is missing: give every shard's folder")]
    Missing(Shard),
    /// No shard was given.
    #[error("no shards given")]
    Empty,
}

impl ShardFile {
    /// The file of shard `shard`'s first round `first` of the problem `problem` on `siting`.
    ///
    /// ```
    /// use muse_sim::experiment::Shard;
    /// use muse_siting::shard::ShardFile;
    /// # let siting = muse_siting::Siting::prepare(muse_siting::problem::example_input()).unwrap();
    /// let shard = Shard { index: 1, of: 2 };
    /// let first = muse_siting::greedy::first_round(&siting, shard, |_| {}).unwrap();
    /// let file = ShardFile::new("the problem", shard, &siting, &first);
    /// assert_eq!((file.shard.as_str(), file.evaluations.len()), ("1/2", 2));
    /// assert!(file.to_json().starts_with("{\n  \"base\": {\n    \"corridors\": "));
    /// ```
    pub fn new(problem: &str, shard: Shard, siting: &Siting, first: &FirstRound) -> ShardFile {
        ShardFile {
            base: Counts::from(&first.base),
            candidates: siting.candidates().len(),
            days: siting.day_count(),
            evaluations: first
                .evaluations
                .iter()
                .map(|(c, e)| CandidateCounts {
                    candidate: siting.candidates()[*c].id.clone(),
                    counts: Counts::from(e),
                })
                .collect(),
            format: FORMAT.to_owned(),
            problem: problem.to_owned(),
            shard: shard.to_string(),
        }
    }

    /// The file's text: indented JSON and a line end.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a shard file serializes") + "\n"
    }

    /// Reads the text of a shard file (named `file` in errors), refused unless it is a siting
    /// shard of the problem `problem`.
    ///
    /// ```
    /// use muse_siting::shard::ShardFile;
    /// let text = r#"{"format": "muse-siting-shard/1", "problem": "P", "shard": "0/1"}"#;
    /// let other = ShardFile::read(text, "shard.json", "Q").unwrap_err();
    /// assert!(other.to_string().contains("a shard of another siting problem"));
    /// let unfinished = ShardFile::read(text, "shard.json", "P").unwrap_err();
    /// assert!(unfinished.to_string().contains("missing field `base`"));
    /// ```
    pub fn read(text: &str, file: &str, problem: &str) -> Result<ShardFile, ShardFileError> {
        let doc: serde_json::Value =
            serde_json::from_str(text).map_err(|source| ShardFileError::NotJson {
                file: file.to_owned(),
                source,
            })?;
        if doc["format"] != FORMAT {
            return Err(ShardFileError::Format {
                file: file.to_owned(),
            });
        }
        if doc["problem"] != problem {
            return Err(ShardFileError::OtherProblem {
                file: file.to_owned(),
                theirs: doc["problem"].to_string(),
                ours: problem.to_owned(),
            });
        }
        serde_json::from_str(text).map_err(|e| ShardFileError::Fields {
            file: file.to_owned(),
            message: e.to_string(),
        })
    }
}

/// Shard files merged one by one ([`Merge::add`]) into the whole first round
/// ([`Merge::finish`]).
///
/// ```
/// use muse_sim::experiment::Shard;
/// use muse_siting::greedy::first_round;
/// use muse_siting::shard::{Merge, ShardFile};
/// # let siting = muse_siting::Siting::prepare(muse_siting::problem::example_input()).unwrap();
/// let mut merge = Merge::new(&siting);
/// for index in [1, 0] {
///     let shard = Shard { index, of: 2 };
///     let first = first_round(&siting, shard, |_| {}).unwrap();
///     merge.add(&format!("part{index}"), ShardFile::new("P", shard, &siting, &first)).unwrap();
/// }
/// let whole = merge.finish().unwrap();
/// assert_eq!(whole.evaluations.len(), siting.candidates().len());
/// ```
pub struct Merge<'s> {
    siting: &'s Siting,
    /// By shard index, the file given for it.
    seen: Vec<Option<String>>,
    base: Option<Evaluation>,
    evaluations: Vec<(usize, Evaluation)>,
}

impl<'s> Merge<'s> {
    /// No shards yet, of the problem on `siting`.
    pub fn new(siting: &'s Siting) -> Merge<'s> {
        Merge {
            siting,
            seen: Vec::new(),
            base: None,
            evaluations: Vec::new(),
        }
    }

    /// Adds the shard `shard` read from `file` (its name in errors).
    pub fn add(&mut self, file: &str, shard: ShardFile) -> Result<(), ShardFileError> {
        let which = Shard::parse(&shard.shard)?;
        if self.seen.is_empty() {
            self.seen = vec![None; which.of];
        }
        if self.seen.len() != which.of {
            return Err(ShardFileError::Cut {
                file: file.to_owned(),
                shard: which,
                of: self.seen.len(),
            });
        }
        if let Some(first) = self.seen[which.index].replace(file.to_owned()) {
            return Err(ShardFileError::Twice {
                file: file.to_owned(),
                first,
                shard: which,
            });
        }
        let base = Evaluation::from(shard.base);
        match &self.base {
            Some(known) if *known != base => {
                return Err(ShardFileError::Base {
                    file: file.to_owned(),
                });
            }
            _ => self.base = Some(base),
        }
        for (index, e) in shard.evaluations.into_iter().enumerate() {
            let c = self
                .siting
                .candidates()
                .iter()
                .position(|n| n.id == e.candidate)
                .ok_or_else(|| ShardFileError::Candidate {
                    file: file.to_owned(),
                    index,
                    id: e.candidate.clone(),
                })?;
            self.evaluations.push((c, e.counts.into()));
        }
        Ok(())
    }

    /// The whole first round, once every shard is given.
    pub fn finish(self) -> Result<FirstRound, ShardFileError> {
        if let Some(missing) = self.seen.iter().position(Option::is_none) {
            return Err(ShardFileError::Missing(Shard {
                index: missing,
                of: self.seen.len(),
            }));
        }
        Ok(FirstRound {
            base: self.base.ok_or(ShardFileError::Empty)?,
            evaluations: self.evaluations,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::greedy::first_round;
    use crate::problem::example_input;

    fn shards(siting: &Siting, of: usize) -> Vec<ShardFile> {
        (0..of)
            .map(|index| {
                let shard = Shard { index, of };
                let first = first_round(siting, shard, |_| {}).unwrap();
                ShardFile::new("P", shard, siting, &first)
            })
            .collect()
    }

    #[test]
    fn a_file_reads_back_as_written() {
        let siting = Siting::prepare(example_input()).unwrap();
        for file in shards(&siting, 2) {
            assert_eq!(ShardFile::read(&file.to_json(), "f", "P").unwrap(), file);
        }
    }

    #[test]
    fn shards_missing_twice_cut_otherwise_or_of_other_candidates_are_refused() {
        let siting = Siting::prepare(example_input()).unwrap();
        let files = shards(&siting, 2);
        let refused = |given: &[(&str, ShardFile)]| -> String {
            let mut merge = Merge::new(&siting);
            for (name, file) in given {
                if let Err(e) = merge.add(name, file.clone()) {
                    return e.to_string();
                }
            }
            merge.finish().unwrap_err().to_string()
        };
        assert_eq!(refused(&[]), "no shards given");
        assert_eq!(
            refused(&[("a", files[0].clone())]),
            "shard 1/2 is missing: give every shard's folder"
        );
        assert_eq!(
            refused(&[("a", files[1].clone()), ("b", files[1].clone())]),
            "b and a are both shard 1/2"
        );
        let third = shards(&siting, 3).swap_remove(2);
        assert_eq!(
            refused(&[("a", files[0].clone()), ("c", third)]),
            "c: shard 2/3, but another shard is of 2"
        );
        let mut unknown = files[1].clone();
        unknown.evaluations[0].candidate = "X".into();
        assert_eq!(
            refused(&[("a", files[0].clone()), ("u", unknown)]),
            "u: evaluation 0: `X` is not a candidate"
        );
        let mut other_base = files[1].clone();
        other_base.base.expanded += 1;
        assert_eq!(
            refused(&[("a", files[0].clone()), ("o", other_base)]),
            "o: its base evaluation differs from the other shards'"
        );
    }

    #[test]
    fn a_file_of_another_format_or_not_json_is_refused() {
        let format = ShardFile::read(r#"{"format": "muse-sweep-shard/1"}"#, "f", "P");
        assert_eq!(
            format.unwrap_err().to_string(),
            "f: not a MUSE siting shard (`format` is not `muse-siting-shard/1`)"
        );
        let text = ShardFile::read("not json", "f", "P").unwrap_err();
        assert_eq!(text.to_string(), "f: not a MUSE siting shard (not JSON)");
    }
}
