//! Whether a study's rerun reproduces its published file: the two CSV files compared cell by
//! cell, the columns this machine measures (times, memory) aside.

use std::path::Path;

use super::shard::StudyRef;

/// The verdict on a study's rerun.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reproduction {
    /// Nothing to compare: the run is not a study's, or its study names no results.
    Nothing,
    /// The study names results but has no such published file.
    NoPublished {
        /// The published file looked for.
        published: String,
        /// The study's results folder.
        results: String,
    },
    /// The run wrote the study's published results themselves.
    Wrote {
        /// The study's results folder.
        results: String,
    },
    /// The same, but for the measured columns.
    Same {
        /// The published file.
        published: String,
    },
    /// A difference.
    Differs {
        /// The file written.
        written: String,
        /// The published file.
        published: String,
        /// The first difference.
        difference: String,
    },
}

impl Reproduction {
    /// Whether the run reproduces (or there is nothing to compare).
    pub fn ok(&self) -> bool {
        !matches!(self, Reproduction::Differs { .. })
    }
}

impl std::fmt::Display for Reproduction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Reproduction::Nothing => Ok(()),
            Reproduction::NoPublished { published, results } => write!(
                f,
                "no published {published} to compare with (the study names {results})"
            ),
            Reproduction::Wrote { results } => {
                write!(f, "wrote the study's published results ({results})")
            }
            Reproduction::Same { published } => write!(
                f,
                "reproduces the published {published} exactly (but for what this machine measures: times, memory)"
            ),
            Reproduction::Differs {
                written,
                published,
                difference,
            } => write!(
                f,
                "{written} differs from the published {published}: {difference}"
            ),
        }
    }
}

/// After a run of `study` has written `file` into `out`, compares it with the study's
/// published one, the columns `measured` on this machine aside.
pub fn reproduction(
    study: Option<&StudyRef>,
    out: &Path,
    file: &str,
    measured: &dyn Fn(&str) -> bool,
) -> std::io::Result<Reproduction> {
    let Some(results) = study.and_then(|s| s.results.as_deref()) else {
        return Ok(Reproduction::Nothing);
    };
    let published = Path::new(results).join(file);
    let written = out.join(file);
    if !published.is_file() {
        return Ok(Reproduction::NoPublished {
            published: published.display().to_string(),
            results: results.to_owned(),
        });
    }
    if std::fs::canonicalize(&published)? == std::fs::canonicalize(&written)? {
        return Ok(Reproduction::Wrote {
            results: results.to_owned(),
        });
    }
    let read = |p: &Path| {
        std::fs::read_to_string(p)
            .map_err(|e| std::io::Error::new(e.kind(), format!("reading {}: {e}", p.display())))
    };
    Ok(
        match first_difference(&read(&published)?, &read(&written)?, measured) {
            None => Reproduction::Same {
                published: published.display().to_string(),
            },
            Some(difference) => Reproduction::Differs {
                written: written.display().to_string(),
                published: published.display().to_string(),
                difference,
            },
        },
    )
}

/// The first difference between two CSV texts with a header, the `measured` columns aside;
/// `None` when they are the same.
fn first_difference(
    published: &str,
    written: &str,
    measured: &dyn Fn(&str) -> bool,
) -> Option<String> {
    let table = |text: &str| -> Option<Vec<Vec<String>>> {
        csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(text.as_bytes())
            .records()
            .map(|r| Some(r.ok()?.iter().map(str::to_owned).collect()))
            .collect()
    };
    let (Some(a), Some(b)) = (table(published), table(written)) else {
        return Some("a file is not CSV".into());
    };
    let (Some(head_a), Some(head_b)) = (a.first(), b.first()) else {
        return Some("a file is empty".into());
    };
    if head_a != head_b {
        let only = |x: &[String], y: &[String]| {
            let names: Vec<&str> = x
                .iter()
                .filter(|c| !y.contains(c))
                .map(String::as_str)
                .collect();
            if names.is_empty() {
                "none".to_owned()
            } else {
                names.join(", ")
            }
        };
        return Some(format!(
            "the columns differ (only published: {}; only now: {})",
            only(head_a, head_b),
            only(head_b, head_a)
        ));
    }
    let keep: Vec<usize> = (0..head_a.len())
        .filter(|&i| !measured(&head_a[i]))
        .collect();
    if a.len() != b.len() {
        return Some(format!(
            "{} rows published, {} now",
            a.len() - 1,
            b.len() - 1
        ));
    }
    let differing: Vec<usize> = (1..a.len())
        .filter(|&r| keep.iter().any(|&i| a[r].get(i) != b[r].get(i)))
        .collect();
    let &first = differing.first()?;
    let col = keep
        .iter()
        .copied()
        .find(|&i| a[first].get(i) != b[first].get(i))
        .unwrap_or(0);
    Some(format!(
        "{} of {} rows differ; first at line {}, column {}: published {}, now {}",
        differing.len(),
        a.len() - 1,
        first + 1,
        head_a[col],
        a[first].get(col).map_or("", String::as_str),
        b[first].get(col).map_or("", String::as_str)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timed(name: &str) -> bool {
        name.starts_with("planner_ms")
    }

    #[test]
    fn published_results_are_compared_without_the_times() {
        let a = "variant,count,success,planner_ms_mean\nv,1,0.5,2.0\nv,2,0.4,3.0\n";
        assert_eq!(first_difference(a, a, &timed), None);
        let retimed = "variant,count,success,planner_ms_mean\nv,1,0.5,9.0\nv,2,0.4,1.0\n";
        assert_eq!(first_difference(a, retimed, &timed), None);
        let other = "variant,count,success,planner_ms_mean\nv,1,0.5,2.0\nv,2,0.3,3.0\n";
        assert_eq!(
            first_difference(a, other, &timed).unwrap(),
            "1 of 2 rows differ; first at line 3, column success: published 0.4, now 0.3"
        );
        let short = "variant,count,success,planner_ms_mean\nv,1,0.5,2.0\n";
        assert_eq!(
            first_difference(a, short, &timed).unwrap(),
            "2 rows published, 1 now"
        );
        let wider = "variant,count,success,planner_ms_mean,legs\nv,1,0.5,2.0,1\nv,2,0.4,3.0,1\n";
        assert_eq!(
            first_difference(a, wider, &timed).unwrap(),
            "the columns differ (only published: none; only now: legs)"
        );
        // A quoted name with a comma is one cell.
        let quoted = "variant,count\n\"zones A,B\",1\n";
        assert_eq!(first_difference(quoted, quoted, &timed), None);
        assert_eq!(first_difference("", a, &timed).unwrap(), "a file is empty");
    }

    #[test]
    fn a_rerun_is_checked_against_the_published_file() {
        let dir = std::env::temp_dir().join(format!("muse-sim-reproduce-{}", std::process::id()));
        let (published, out) = (dir.join("published"), dir.join("out"));
        std::fs::create_dir_all(&published).unwrap();
        std::fs::create_dir_all(&out).unwrap();
        let study = StudyRef {
            file: "s.toml".into(),
            title: "t".into(),
            results: Some(published.display().to_string()),
        };
        let text = "variant,count,planner_ms\nv,1,2.0\n";
        std::fs::write(out.join("f.csv"), text).unwrap();
        let verdict = |file: &str| reproduction(Some(&study), &out, file, &timed).unwrap();
        assert!(matches!(verdict("f.csv"), Reproduction::NoPublished { .. }));
        std::fs::write(published.join("f.csv"), text.replace("2.0", "7.5")).unwrap();
        assert!(matches!(verdict("f.csv"), Reproduction::Same { .. }));
        std::fs::write(published.join("f.csv"), text.replace("v,1", "v,2")).unwrap();
        let differs = verdict("f.csv");
        assert!(!differs.ok());
        assert!(
            differs
                .to_string()
                .ends_with("1 of 1 rows differ; first at line 2, column count: published 2, now 1"),
            "{differs}"
        );
        let same_folder = reproduction(Some(&study), &published, "f.csv", &timed).unwrap();
        assert!(matches!(same_folder, Reproduction::Wrote { .. }));
        assert_eq!(
            reproduction(None, &out, "f.csv", &timed).unwrap(),
            Reproduction::Nothing
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
