//! What an experiment's records become, written once for every kind: CSV files (through the
//! `csv` crate), summaries of means with 95% confidence intervals, text tables and plots.

use muse_render::{PlotOptions, Series};

use crate::stats::MeanCi;

/// A column of a CSV file: its name and how a row writes its cell.
pub struct Column<'a, T> {
    /// The header.
    pub name: &'static str,
    cell: Box<dyn Fn(&T) -> String + 'a>,
}

impl<'a, T> Column<'a, T> {
    /// The column `name` whose cell of a row is `cell(row)`.
    pub fn new(name: &'static str, cell: impl Fn(&T) -> String + 'a) -> Self {
        Column {
            name,
            cell: Box::new(cell),
        }
    }

    /// The cell of `row`.
    pub fn cell(&self, row: &T) -> String {
        (self.cell)(row)
    }
}

/// Why an experiment's files could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A CSV file could not be written.
    #[error("writing {file}: {source}")]
    Csv {
        /// The file.
        file: String,
        /// Cause.
        source: csv::Error,
    },
    /// A plot could not be drawn.
    #[error("drawing {file}: {source}")]
    Plot {
        /// The file.
        file: String,
        /// Cause.
        source: muse_render::RenderError,
    },
}

/// The CSV text of `rows` under `columns` (named `file` in errors): a header line, then one
/// line per row, `\n`-terminated; a cell is quoted only when it holds a comma, a quote or a
/// line break, quotes doubled.
///
/// ```
/// use muse_sim::experiment::{Column, csv_text};
/// let columns = [
///     Column::new("name", |r: &(&str, f64)| r.0.to_owned()),
///     Column::new("x", |r: &(&str, f64)| format!("{:.3}", r.1)),
/// ];
/// let text = csv_text("t.csv", &columns, &[("a", 1.0), ("b, \"c\"", 0.5)]).unwrap();
/// assert_eq!(text, "name,x\na,1.000\n\"b, \"\"c\"\"\",0.500\n");
/// ```
pub fn csv_text<T>(
    file: &str,
    columns: &[Column<'_, T>],
    rows: &[T],
) -> Result<String, ReportError> {
    let err = |source| ReportError::Csv {
        file: file.to_owned(),
        source,
    };
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    w.write_record(columns.iter().map(|c| c.name))
        .map_err(err)?;
    for row in rows {
        w.write_record(columns.iter().map(|c| c.cell(row)))
            .map_err(err)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| err(csv::Error::from(e.into_error())))?;
    // Every cell is a `String`: the bytes are UTF-8.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// A metric of the summary: its name (the columns `NAME_mean`, `NAME_ci95_low`,
/// `NAME_ci95_high`) and its value in one run, `None` when the run has none (it is then left
/// out of that metric's mean).
pub struct Metric<R> {
    /// Its name.
    pub name: &'static str,
    /// Its value in a run.
    pub value: fn(&R) -> Option<f64>,
}

/// How a kind's records are summarized: grouped by case and count, in the order they first
/// appear, with the mean and 95% confidence interval of each metric over a group's runs.
pub struct SummarySpec<R> {
    /// The summary file, e.g. `sweep_summary.csv`.
    pub file: &'static str,
    /// A run's case (a text naming it) and count: the runs of a group share both.
    pub group: fn(&R) -> (String, usize),
    /// The first columns of the file, before the metrics (case, count, runs, …).
    pub head: Vec<Column<'static, Group<R>>>,
    /// The metrics, in column order.
    pub metrics: Vec<Metric<R>>,
}

/// The runs of one case and count, summarized.
#[derive(Clone, Debug, PartialEq)]
pub struct Group<R> {
    /// The group's first run, standing for its case.
    pub first: R,
    /// Requests per run.
    pub count: usize,
    /// Runs in the group.
    pub runs: usize,
    metrics: Vec<(&'static str, MeanCi)>,
}

impl<R> Group<R> {
    /// The mean and 95% CI of the metric `name` over the group's runs.
    ///
    /// # Panics
    /// If the summary has no such metric: the kinds ask only for their own.
    pub fn metric(&self, name: &str) -> MeanCi {
        self.metrics
            .iter()
            .find(|(n, _)| *n == name)
            .map_or_else(|| panic!("no metric `{name}` in this summary"), |(_, m)| *m)
    }
}

/// Groups `records` by case and count (first appearance order) and summarizes each metric.
pub fn summarize<R: Clone>(records: &[R], spec: &SummarySpec<R>) -> Vec<Group<R>> {
    let mut keys: Vec<(String, usize)> = Vec::new();
    for r in records {
        let k = (spec.group)(r);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .filter_map(|key| {
            let runs: Vec<&R> = records.iter().filter(|r| (spec.group)(r) == key).collect();
            let metrics = spec
                .metrics
                .iter()
                .map(|m| {
                    let xs: Vec<f64> = runs.iter().filter_map(|r| (m.value)(r)).collect();
                    (m.name, MeanCi::of(&xs))
                })
                .collect();
            Some(Group {
                first: (*runs.first()?).clone(),
                count: key.1,
                runs: runs.len(),
                metrics,
            })
        })
        .collect()
}

/// The summary CSV of `groups`: the spec's first columns, then each metric's mean and 95% CI
/// bounds, six decimals.
pub fn summary_csv<R>(spec: &SummarySpec<R>, groups: &[Group<R>]) -> Result<String, ReportError> {
    let names: Vec<[String; 3]> = spec
        .metrics
        .iter()
        .map(|m| {
            let n = m.name;
            [
                format!("{n}_mean"),
                format!("{n}_ci95_low"),
                format!("{n}_ci95_high"),
            ]
        })
        .collect();
    let mut header: Vec<&str> = spec.head.iter().map(|c| c.name).collect();
    header.extend(names.iter().flatten().map(String::as_str));
    let err = |source| ReportError::Csv {
        file: spec.file.to_owned(),
        source,
    };
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    w.write_record(&header).map_err(err)?;
    for g in groups {
        let mut cells: Vec<String> = spec.head.iter().map(|c| c.cell(g)).collect();
        for m in &spec.metrics {
            let ci = g.metric(m.name);
            cells.extend([ci.mean, ci.low(), ci.high()].map(|x| format!("{x:.6}")));
        }
        w.write_record(&cells).map_err(err)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| err(csv::Error::from(e.into_error())))?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// A plot: its file, its options and its series.
pub struct Plot {
    /// The file, e.g. `sweep_success.svg`.
    pub file: &'static str,
    /// Title, labels, axes and footnote.
    pub options: PlotOptions,
    /// The lines.
    pub series: Vec<Series>,
}

/// How a column of a [`TextTable`] is aligned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Align {
    /// Padded on the right.
    Left,
    /// Padded on the left.
    Right,
}

/// A table of text for the terminal: each column padded to its width (wider cells are not
/// cut), columns separated by one space.
#[derive(Clone, Debug)]
pub(crate) struct TextTable {
    columns: Vec<(String, usize, Align)>,
    rows: Vec<Vec<String>>,
}

impl TextTable {
    /// A table of these columns: (header, width, alignment).
    pub(crate) fn new(columns: &[(&str, usize, Align)]) -> Self {
        TextTable {
            columns: columns
                .iter()
                .map(|&(h, w, a)| (h.to_owned(), w, a))
                .collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row, one cell per column.
    pub(crate) fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    fn line(&self, cells: &[String], f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, (cell, (_, width, align))) in cells.iter().zip(&self.columns).enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            match align {
                Align::Left => write!(f, "{cell:<width$}")?,
                Align::Right => write!(f, "{cell:>width$}")?,
            }
        }
        writeln!(f)
    }
}

impl std::fmt::Display for TextTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let header: Vec<String> = self.columns.iter().map(|c| c.0.clone()).collect();
        self.line(&header, f)?;
        for row in &self.rows {
            self.line(row, f)?;
        }
        Ok(())
    }
}

/// `mean ± half-width` of `m` scaled by `scale`, with `prec` decimals.
pub(crate) fn plus_minus(m: MeanCi, scale: f64, prec: usize) -> String {
    format!(
        "{:.prec$} ± {:.prec$}",
        m.mean * scale,
        m.half_width * scale
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_tables_pad_each_column() {
        let mut t = TextTable::new(&[("name", 6, Align::Left), ("n", 3, Align::Right)]);
        t.row(vec!["a".into(), "12".into()]);
        t.row(vec!["longer name".into(), "1234".into()]);
        assert_eq!(t.to_string(), "name     n\na       12\nlonger name 1234\n");
        let m = MeanCi {
            n: 2,
            mean: 0.5,
            half_width: 0.01,
        };
        assert_eq!(plus_minus(m, 100.0, 1), "50.0 ± 1.0");
    }

    #[test]
    fn a_carriage_return_is_quoted_too() {
        let columns = [Column::new("name", |r: &&str| (*r).to_owned())];
        let text = csv_text("t.csv", &columns, &["a\rb", "c\nd", "e"]).unwrap();
        assert_eq!(text, "name\n\"a\rb\"\n\"c\nd\"\ne\n");
    }
}
