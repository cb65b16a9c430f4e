//! CSV tables: what the readers (requests, pads, customers) share — the header, each record
//! with its line, and number cells, with errors naming the file, line and field — and the
//! writer every CSV output uses ([`CsvWriter`]).

use csv::StringRecord;

use crate::error::{InputError, Location};

/// A CSV file's text being read, cells trimmed.
pub(crate) struct Table<'a> {
    reader: csv::Reader<&'a [u8]>,
    headers: StringRecord,
    file: &'a str,
}

impl<'a> Table<'a> {
    /// The table of `text` (named `file` in errors), its header read.
    pub(crate) fn new(text: &'a str, file: &'a str) -> Result<Self, InputError> {
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let headers = reader
            .headers()
            .map_err(|e| {
                InputError::new(
                    file,
                    Location::Line(1),
                    None,
                    format!("cannot read the header: {e}"),
                )
            })?
            .clone();
        Ok(Table {
            reader,
            headers,
            file,
        })
    }

    /// The header's names.
    pub(crate) fn headers(&self) -> &StringRecord {
        &self.headers
    }

    /// The column named `name`, if the header has one.
    pub(crate) fn column(&self, name: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == name)
    }

    /// The columns `names`, each required; else an error naming the first missing one, with
    /// `columns` saying which a file of this kind has.
    pub(crate) fn required<const N: usize>(
        &self,
        names: [&str; N],
        columns: &str,
    ) -> Result<[usize; N], InputError> {
        let mut out = [0; N];
        for (slot, name) in out.iter_mut().zip(names) {
            *slot = self.column(name).ok_or_else(|| {
                InputError::new(
                    self.file,
                    Location::Line(1),
                    Some(name),
                    format!("the header has no `{name}` column: {columns}"),
                )
            })?;
        }
        Ok(out)
    }

    /// Each record with its line (the header is line 1), or the error of a malformed one.
    pub(crate) fn rows(
        &mut self,
    ) -> impl Iterator<Item = Result<(StringRecord, usize), InputError>> + '_ {
        let file = self.file;
        self.reader.records().map(move |record| {
            let record = record.map_err(|e| {
                let line = e.position().map_or(0, |p| p.line() as usize);
                InputError::new(
                    file,
                    Location::Line(line),
                    None,
                    format!("malformed CSV record: {e}"),
                )
            })?;
            let line = record.position().map_or(0, |p| p.line() as usize);
            Ok((record, line))
        })
    }
}

/// A finite number from a cell; else why not: `missing`, or `` `x` is not a number ``.
pub(crate) fn number(text: &str) -> Result<f64, String> {
    if text.is_empty() {
        return Err("missing".to_owned());
    }
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("`{text}` is not a number"))
}

/// A CSV table being written: RFC 4180 quoting (a cell with a comma, a quote or a line break
/// is quoted), `\n` line ends. The flights and stays tables are written with it.
///
/// ```
/// let mut t = muse_formats::CsvWriter::new(&["id", "name"]);
/// t.row(&["P1".into(), "Pad, one".into()]);
/// assert_eq!(t.finish(), "id,name\nP1,\"Pad, one\"\n");
/// ```
pub struct CsvWriter {
    out: String,
}

impl CsvWriter {
    /// A table with the header `columns`.
    pub fn new(columns: &[&str]) -> Self {
        let mut out = columns.join(",");
        out.push('\n');
        CsvWriter { out }
    }

    /// Appends one row.
    pub fn row(&mut self, cells: &[String]) {
        for (i, cell) in cells.iter().enumerate() {
            if i > 0 {
                self.out.push(',');
            }
            if cell.contains([',', '"', '\n', '\r']) {
                self.out.push('"');
                self.out.push_str(&cell.replace('"', "\"\""));
                self.out.push('"');
            } else {
                self.out.push_str(cell);
            }
        }
        self.out.push('\n');
    }

    /// The text written.
    pub fn finish(self) -> String {
        self.out
    }
}
