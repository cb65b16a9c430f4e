//! Retention without forgetting (`muse serve --archive-after-days N`): flights that landed more
//! than N whole days ago leave the hot tables for archive files, one per day, and their ids
//! stay, so that a retried id is answered as it first was.
//!
//! # The files
//!
//! In the archive folder, for each local day D (the service's UTC offset) on which archived
//! flights landed: `flights-D.csv.gz`, the `flights` table's columns (a header, then one row
//! per flight in answer order, `crc` included), and `events-D.csv.gz`, the `events` table's
//! columns for those flights' events. Gzip-compressed CSV: `pandas.read_csv` opens them as
//! they are. A file is written whole beside its final name, synced, then renamed: it is there
//! whole or not at all.
//!
//! # What stays in the store
//!
//! Each archived flight leaves a row in `archived` (its `seq`, `id`, the day of its file and a
//! checksum) and each archived event one in `archived_events` (its id and day): a few dozen
//! bytes each. A read by id that misses `flights` finds the flight there and reads it from its
//! day's file (its checksum checked); a new request under an archived id is a retry or a
//! conflict, as ever; and the start's check that keys run without a gap counts the archived
//! ones as present.
//!
//! # A pass
//!
//! For each day whose flights all landed more than N days ago (oldest first): the day's rows
//! still in the hot tables are read, merged with the day's files if they exist (rows already
//! moved by an earlier pass, or a pass a crash cut short), the files are written again if
//! anything is new, and only then are the rows moved, [`CHUNK`] flights per transaction: each
//! transaction records their ids in `archived` and deletes them and their events. A crash
//! between two transactions leaves every row either hot or archived in a file that holds it;
//! the next pass finishes the day. A flight answered late for an archived day (a departure
//! long past) is merged into the day's files by the next pass.

use std::collections::BTreeMap;
use std::io::{BufReader, BufWriter, Write as _};
use std::path::{Path, PathBuf};

use muse_model::{Instant, Millis, UtcOffset};

use super::rows::{EventRow, FlightRow, RowSum};
use super::{Archiver, StoreError};

/// Most flights moved per transaction.
pub const CHUNK: usize = 2_000;

/// Where and after how long flights are archived.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Retention {
    /// The archive folder (made if missing).
    pub dir: PathBuf,
    /// Whole days after which a day's flights are archived (at least 1).
    pub after_days: u32,
    /// The offset that makes days local.
    pub offset: UtcOffset,
}

/// What a pass archived.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Archived {
    /// Days whose files were written or completed.
    pub days: Vec<String>,
    /// Flights moved out of the hot tables.
    pub flights: u64,
    /// Events moved out of the hot tables.
    pub events: u64,
}

/// The checksum of an `archived` row.
pub(super) fn archived_sum(seq: i64, id: &str, day: &str) -> i64 {
    RowSum::new("archived").int(seq).text(id).text(day).finish()
}

/// An `archived` row read by id `id` (its `seq`, the `found` id, `day` and `crc`), checked:
/// its seq and day, or the damage of the store `label`.
pub(super) fn checked_archived(
    label: &str,
    id: &str,
    (seq, found, day, crc): (i64, String, String, i64),
) -> Result<(i64, String), StoreError> {
    if found != id || archived_sum(seq, &found, &day) != crc {
        return Err(StoreError::Damaged {
            path: label.to_owned(),
            what: format!(
                "archived row seq {seq} (id {found:?}): its checksum does not match its content"
            ),
        });
    }
    Ok((seq, day))
}

/// The file of `what` (`flights`, `events`) for `day` in `dir`.
pub(super) fn file(dir: &Path, what: &str, day: &str) -> PathBuf {
    dir.join(format!("{what}-{day}.csv.gz"))
}

fn io(what: String) -> impl FnOnce(std::io::Error) -> StoreError {
    move |error| StoreError::Io { what, error }
}

fn damaged(path: &Path, what: String) -> StoreError {
    StoreError::Damaged {
        path: path.display().to_string(),
        what,
    }
}

/// The flights table's columns, in the files' order.
const FLIGHT_HEADER: [&str; 18] = [
    "seq",
    "id",
    "operator",
    "origin",
    "destination",
    "departure_ms",
    "answered_ms",
    "plan",
    "reason",
    "free_flow_ms",
    "expanded",
    "status",
    "takeoff_ms",
    "landing_ms",
    "holds_until_ms",
    "cancelled_ms",
    "changes",
    "crc",
];

/// The events table's columns, in the files' order.
const EVENT_HEADER: [&str; 7] = [
    "id",
    "at_ms",
    "kind",
    "flight_seq",
    "zone",
    "changes",
    "crc",
];

fn opt<T: ToString>(v: Option<&T>) -> String {
    v.map_or_else(String::new, ToString::to_string)
}

fn flight_record(r: &FlightRow) -> [String; 18] {
    [
        r.seq.to_string(),
        r.id.clone(),
        r.operator.clone(),
        r.origin.clone(),
        r.destination.clone(),
        r.departure_ms.to_string(),
        r.answered_ms.to_string(),
        r.plan.clone().unwrap_or_default(),
        r.reason.clone().unwrap_or_default(),
        opt(r.free_flow_ms.as_ref()),
        r.expanded.to_string(),
        r.status.clone(),
        r.takeoff_ms.to_string(),
        r.landing_ms.to_string(),
        opt(r.holds_until_ms.as_ref()),
        opt(r.cancelled_ms.as_ref()),
        r.changes.clone().unwrap_or_default(),
        r.crc.to_string(),
    ]
}

fn event_record(r: &EventRow) -> [String; 7] {
    [
        r.id.to_string(),
        r.at_ms.to_string(),
        r.kind.clone(),
        r.flight_seq.to_string(),
        r.zone.clone().unwrap_or_default(),
        r.changes.to_string(),
        r.crc.to_string(),
    ]
}

/// A CSV record of a file, read by column.
struct Record<'a> {
    path: &'a Path,
    line: u64,
    fields: &'a csv::StringRecord,
}

impl Record<'_> {
    fn text(&self, at: usize) -> Result<String, StoreError> {
        self.fields.get(at).map(str::to_owned).ok_or_else(|| {
            damaged(
                self.path,
                format!("line {}: column {} is missing", self.line, at + 1),
            )
        })
    }

    fn opt_text(&self, at: usize) -> Result<Option<String>, StoreError> {
        Ok(Some(self.text(at)?).filter(|t| !t.is_empty()))
    }

    fn int(&self, at: usize) -> Result<i64, StoreError> {
        let t = self.text(at)?;
        t.parse().map_err(|_| {
            damaged(
                self.path,
                format!(
                    "line {}: column {} is {t:?}, not a whole number",
                    self.line,
                    at + 1
                ),
            )
        })
    }

    fn opt_int(&self, at: usize) -> Result<Option<i64>, StoreError> {
        match self.text(at)?.as_str() {
            "" => Ok(None),
            _ => self.int(at).map(Some),
        }
    }

    fn flight(&self) -> Result<FlightRow, StoreError> {
        Ok(FlightRow {
            seq: self.int(0)?,
            id: self.text(1)?,
            operator: self.text(2)?,
            origin: self.text(3)?,
            destination: self.text(4)?,
            departure_ms: self.int(5)?,
            answered_ms: self.int(6)?,
            plan: self.opt_text(7)?,
            reason: self.opt_text(8)?,
            free_flow_ms: self.opt_int(9)?,
            expanded: self.int(10)?,
            status: self.text(11)?,
            takeoff_ms: self.int(12)?,
            landing_ms: self.int(13)?,
            holds_until_ms: self.opt_int(14)?,
            cancelled_ms: self.opt_int(15)?,
            changes: self.opt_text(16)?,
            crc: self.int(17)?,
        })
    }

    fn event(&self) -> Result<EventRow, StoreError> {
        Ok(EventRow {
            id: self.int(0)?,
            at_ms: self.int(1)?,
            kind: self.text(2)?,
            flight_seq: self.int(3)?,
            zone: self.opt_text(4)?,
            changes: self.int(5)?,
            crc: self.int(6)?,
        })
    }
}

/// Reads every record of the file at `path` (none if it does not exist), checking its header,
/// and hands each to `each`.
fn read_file(
    path: &Path,
    header: &[&str],
    mut each: impl FnMut(&Record<'_>) -> Result<bool, StoreError>,
) -> Result<(), StoreError> {
    let f = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io(format!("opening {}", path.display()))(e)),
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(flate2::read::GzDecoder::new(BufReader::new(f)));
    let found = reader
        .headers()
        .map_err(|e| damaged(path, format!("its header cannot be read ({e})")))?
        .clone();
    if found.iter().ne(header.iter().copied()) {
        return Err(damaged(
            path,
            format!("its header is {found:?}, not the table's columns"),
        ));
    }
    let mut fields = csv::StringRecord::new();
    let mut line = 1;
    loop {
        line += 1;
        let more = reader
            .read_record(&mut fields)
            .map_err(|e| damaged(path, format!("line {line}: {e}")))?;
        if !more {
            return Ok(());
        }
        let record = Record {
            path,
            line,
            fields: &fields,
        };
        if !each(&record)? {
            return Ok(());
        }
    }
}

/// Writes `rows` (with `header`) to `path`, whole or not at all: beside it, synced, renamed.
fn write_file<const N: usize>(
    path: &Path,
    header: &[&str; N],
    rows: impl Iterator<Item = [String; N]>,
) -> Result<u64, StoreError> {
    let tmp = path.with_extension("gz.writing");
    let what = || format!("writing {}", tmp.display());
    let f = std::fs::File::create(&tmp).map_err(io(what()))?;
    let gz = flate2::write::GzEncoder::new(BufWriter::new(f), flate2::Compression::default());
    let mut w = csv::Writer::from_writer(gz);
    let mut n = 0;
    let csv_error = |e: csv::Error| StoreError::Io {
        what: what(),
        error: std::io::Error::other(e),
    };
    w.write_record(header).map_err(csv_error)?;
    for r in rows {
        w.write_record(&r).map_err(csv_error)?;
        n += 1;
    }
    let gz = w
        .into_inner()
        .map_err(|e| io(what())(std::io::Error::other(e.to_string())))?;
    let mut buffered = gz.finish().map_err(io(what()))?;
    buffered.flush().map_err(io(what()))?;
    let f = buffered
        .into_inner()
        .map_err(|e| io(what())(std::io::Error::other(e.to_string())))?;
    f.sync_all().map_err(io(what()))?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(io(format!("renaming {}", tmp.display())))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io(format!("syncing {}", dir.display())))?;
    Ok(n)
}

/// The archived flight `seq` from the file of `day` in `dir`, its checksum checked by the
/// caller; `None` if the file does not hold it.
pub(super) fn read_flight(
    dir: &Path,
    day: &str,
    seq: i64,
) -> Result<Option<FlightRow>, StoreError> {
    let path = file(dir, "flights", day);
    if !path.exists() {
        return Err(damaged(
            &path,
            format!("it is missing, but the store archived flight seq {seq} into it"),
        ));
    }
    let mut found = None;
    read_file(&path, &FLIGHT_HEADER, |r| {
        if r.int(0)? == seq {
            found = Some(r.flight()?);
            return Ok(false);
        }
        Ok(true)
    })?;
    Ok(found)
}

/// The archived flight `id` (`seq`, archived into the file of `day` in `dir`), read from its
/// file, its checksum checked.
pub(super) fn entry(
    dir: Option<&Path>,
    airspace: &muse_model::Airspace,
    id: &str,
    seq: i64,
    day: &str,
) -> Result<crate::flights::FlightEntry, StoreError> {
    let Some(dir) = dir else {
        return Err(StoreError::Io {
            what: format!(
                "reading flight {id:?}, archived into the files of {day}: this service was given \
                 no archive folder (--archive-dir)"
            ),
            error: std::io::Error::from(std::io::ErrorKind::NotFound),
        });
    };
    let path = file(dir, "flights", day);
    let row = read_flight(dir, day, seq)?.ok_or_else(|| {
        damaged(
            &path,
            format!(
                "it does not hold flight seq {seq} (id {id:?}), which the store archived into it"
            ),
        )
    })?;
    if row.id != id {
        return Err(damaged(
            &path,
            format!(
                "flight seq {seq} is archived as {id:?} but the file names it {:?}",
                row.id
            ),
        ));
    }
    row.entry(airspace, &path.display().to_string())
}

/// Runs one pass (see the module docs) at `now`.
pub fn pass(
    archiver: &mut dyn Archiver,
    retention: &Retention,
    now: Instant,
) -> Result<Archived, StoreError> {
    std::fs::create_dir_all(&retention.dir)
        .map_err(io(format!("creating {}", retention.dir.display())))?;
    let offset = retention.offset;
    let today = now.local_date(offset);
    let days_back = i64::from(retention.after_days);
    let cutoff_date = today
        .checked_sub(jiff::Span::new().days(days_back))
        .unwrap_or(today);
    // Every flight landing before the start of this local day is due.
    let cutoff = Instant::at_local(cutoff_date, Millis(0), offset);
    let mut out = Archived::default();
    while let Some(oldest) = archiver.oldest_landing(cutoff)? {
        let date = oldest.local_date(offset);
        if out.days.last() == Some(&date.to_string()) {
            return Err(StoreError::Damaged {
                path: archiver.label(),
                what: format!("the flights landing on {date} were archived but are still there"),
            });
        }
        let from = Instant::at_local(date, Millis(0), offset);
        let to = Instant::at_local(date, Millis::from_secs(86_400), offset).min(cutoff);
        let day = date.to_string();
        let (flights, events) = archiver.day_rows(from, to)?;
        if flights.is_empty() {
            // Rows of the day that hold a reservation (a flight still held) stay hot: no
            // flight landed before the cutoff holds one, so this is damage.
            return Err(StoreError::Damaged {
                path: archiver.label(),
                what: format!(
                    "flights landing on {day} read as due for the archive, but none could be \
                     read"
                ),
            });
        }
        merge(retention, &day, &flights, &events)?;
        for chunk in flights.chunks(CHUNK) {
            let seqs: Vec<i64> = chunk.iter().map(|f| f.seq).collect();
            let moved = events
                .iter()
                .filter(|e| seqs.binary_search(&e.flight_seq).is_ok())
                .map(|e| e.id)
                .collect::<Vec<_>>();
            archiver.move_rows(&day, chunk, &moved)?;
            out.flights += chunk.len() as u64;
            out.events += moved.len() as u64;
        }
        out.days.push(day);
    }
    if out.flights > 0 {
        archiver.reclaim()?;
    }
    Ok(out)
}

/// Writes the files of `day` to hold `flights` and `events` as well as what they held (rows
/// of the same key are the same row: the hot copy is taken).
fn merge(
    retention: &Retention,
    day: &str,
    flights: &[FlightRow],
    events: &[EventRow],
) -> Result<(), StoreError> {
    let path = file(&retention.dir, "flights", day);
    let mut all: BTreeMap<i64, FlightRow> = BTreeMap::new();
    read_file(&path, &FLIGHT_HEADER, |r| {
        let row = r.flight()?;
        if row.sum() != row.crc {
            return Err(damaged(
                &path,
                format!(
                    "line {}: flight seq {}: its checksum does not match",
                    r.line, row.seq
                ),
            ));
        }
        all.insert(row.seq, row);
        Ok(true)
    })?;
    let new = flights
        .iter()
        .any(|f| all.get(&f.seq).is_none_or(|old| old != f));
    if new {
        for f in flights {
            all.insert(f.seq, f.clone());
        }
        write_file(&path, &FLIGHT_HEADER, all.values().map(flight_record))?;
    }
    let path = file(&retention.dir, "events", day);
    let mut all: BTreeMap<i64, EventRow> = BTreeMap::new();
    read_file(&path, &EVENT_HEADER, |r| {
        let row = r.event()?;
        all.insert(row.id, row);
        Ok(true)
    })?;
    if new || events.iter().any(|e| !all.contains_key(&e.id)) {
        for e in events {
            all.insert(e.id, e.clone());
        }
        write_file(&path, &EVENT_HEADER, all.values().map(event_record))?;
    }
    Ok(())
}

/// Reads a whole file's bytes (for tests and checks): the decompressed CSV.
#[cfg(test)]
fn text_of(path: &Path) -> String {
    use std::io::Read as _;
    let mut s = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap())
        .read_to_string(&mut s)
        .unwrap();
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(seq: i64) -> FlightRow {
        let mut r = FlightRow {
            seq,
            id: format!("r{seq}, \"quoted\""),
            operator: "op".into(),
            origin: "A".into(),
            destination: "B".into(),
            departure_ms: 1_000,
            answered_ms: 900,
            plan: Some("[[\"A\",1000,1000],[\"B\",2000,2000]]".into()),
            reason: None,
            free_flow_ms: Some(1_000),
            expanded: 3,
            status: "planned".into(),
            takeoff_ms: 1_000,
            landing_ms: 2_000,
            holds_until_ms: None,
            cancelled_ms: None,
            changes: None,
            crc: 0,
        };
        r.crc = r.sum();
        r
    }

    #[test]
    fn a_day_file_is_merged_and_read_back_row_for_row() {
        let dir = std::env::temp_dir().join(format!("muse-archive-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let retention = Retention {
            dir: dir.clone(),
            after_days: 1,
            offset: UtcOffset::SINGAPORE,
        };
        merge(&retention, "2026-11-29", &[row(1), row(3)], &[]).unwrap();
        merge(&retention, "2026-11-29", &[row(2)], &[]).unwrap();
        for seq in 1..=3 {
            assert_eq!(
                read_flight(&dir, "2026-11-29", seq).unwrap(),
                Some(row(seq))
            );
        }
        assert_eq!(read_flight(&dir, "2026-11-29", 4).unwrap(), None);
        let text = text_of(&file(&dir, "flights", "2026-11-29"));
        assert!(text.starts_with("seq,id,operator,"), "{text}");
        assert_eq!(text.lines().count(), 4, "{text}");
        let e = read_flight(&dir, "2026-11-30", 1).unwrap_err().to_string();
        assert!(e.contains("is missing"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
