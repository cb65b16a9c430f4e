//! Converting a data folder written by an earlier version: the append-only log `muse.log`
//! becomes the store, once, with every flight, cancellation, zone and event kept (event ids
//! unchanged, so a client resumes across the upgrade).
//!
//! # The log's format
//!
//! The file starts with the 16-byte magic `MUSE-LOG-V1\n\0\0\0\0`, then records, each
//! `len: u32 LE | crc: u32 LE | payload`, `payload` being `len` bytes of JSON (one
//! record) and `crc` its CRC-32. The first record is a header naming the airspace and
//! parameters the log was written for. The log is read as a stream, one record at a time.
//!
//! # What the conversion keeps and what it says
//!
//! Records are applied in log order, as the earlier version replayed them: a flight's answer,
//! an operator's cancellation, a zone announcement with each flight's stored outcome, a
//! withdrawal. A record cut short or failing its checksum at the end of the log is the torn
//! tail of a write that was never acknowledged (at most one group of that version, 4 MiB, or
//! the larger record a `large` marker announced): it is left out and reported. Damage
//! followed by more data than that stops the conversion with an error naming the offset.
//!
//! The earlier version could store an id twice (a request re-sent after its retention): both
//! flights were acknowledged and both are kept, the first under the id (which names it from
//! then on), each later one under `ID#2`, `ID#3`, … (`#` is never in a client's id), and the
//! report lists them. A cancellation names the latest flight of its id, as it did then.
//!
//! The store is written beside the log as `muse.db.importing` and renamed `muse.db` once
//! complete; the log is then renamed `muse.log.imported` (never deleted). A conversion
//! interrupted by a crash starts again from the log.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufReader, Read as _};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use muse_model::plan::{Fate, FateKind};
use muse_model::{Airspace, Instant, Millis, Plan, RejectReason, Request};
use rusqlite::Connection;
use serde::Deserialize;

use super::{
    StoreError, StoredZone, WorldMeta, sql, sync_dir, write_event, write_flight, write_schema,
    write_zone,
};
use crate::events::{Event, EventKind};
use crate::flights::FlightEntry;

/// The log's file name inside the data folder.
pub const LOG_FILE: &str = "muse.log";
/// What a converted log is renamed to.
pub const IMPORTED_FILE: &str = "muse.log.imported";

/// The first bytes of every log.
const MAGIC: &[u8; 16] = b"MUSE-LOG-V1\n\0\0\0\0";
/// Largest record the earlier version wrote.
const MAX_RECORD: u32 = 256 << 20;
/// Largest group the earlier version wrote with one `write`: the bound on a torn tail.
const MAX_GROUP_BYTES: u64 = 4 << 20;

/// One record of the log.
#[derive(Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum Record {
    Header { world: String },
    Flight(FlightRecord),
    Cancel { id: String, at: i64 },
    Zone(ZoneRecord),
    Large { bytes: u64 },
    Withdraw { id: String, at: i64 },
}

#[derive(Debug, Deserialize)]
struct ZoneRecord {
    id: String,
    feature: String,
    announced: i64,
    outcomes: Vec<OutcomeRecord>,
}

#[derive(Debug, Deserialize)]
struct OutcomeRecord {
    seq: u64,
    airborne: bool,
    outcome: String,
    #[serde(default)]
    path: Option<Vec<(String, i64, i64)>>,
}

#[derive(Debug, Deserialize)]
struct FlightRecord {
    seq: u64,
    id: String,
    operator: String,
    origin: String,
    destination: String,
    departure: i64,
    answered: i64,
    path: Option<Vec<(String, i64, i64)>>,
    reason: Option<String>,
    free_flow: Option<i64>,
    expanded: u64,
}

/// What a conversion did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ImportReport {
    /// Whole records read (the header included).
    pub records: u64,
    /// Flights kept.
    pub flights: u64,
    /// Cancellations by operators.
    pub cancellations: u64,
    /// Zones announced, and of those withdrawn.
    pub zones: u64,
    /// Zones withdrawn.
    pub withdrawn: u64,
    /// Events numbered.
    pub events: u64,
    /// Bytes of torn tail left out (never acknowledged).
    pub torn_bytes: u64,
    /// Flights stored under another id because theirs was taken: `(id, stored as)`.
    pub renamed: Vec<(String, String)>,
    /// Where the log now is.
    pub log: PathBuf,
}

/// The log, read one record at a time.
struct LogReader {
    path: PathBuf,
    file: BufReader<File>,
    len: u64,
    at: u64,
    /// How long a torn tail may be from here.
    allowance: u64,
}

/// What the next read found.
enum Next {
    Record(Record, u64),
    /// The end, after `torn` bytes of torn tail (0: a clean end).
    End {
        torn: u64,
    },
}

impl LogReader {
    fn open(path: &Path) -> Result<LogReader, StoreError> {
        let label = path.display().to_string();
        let file = File::open(path).map_err(|error| StoreError::Io {
            what: format!("opening {label}"),
            error,
        })?;
        let len = file
            .metadata()
            .map_err(|error| StoreError::Io {
                what: format!("reading {label}"),
                error,
            })?
            .len();
        let mut file = BufReader::with_capacity(1 << 20, file);
        let mut magic = [0u8; 16];
        if len < 16 || file.read_exact(&mut magic).is_err() || &magic != MAGIC {
            return Err(StoreError::NotAStore {
                path: path.display().to_string(),
                why: "it is not a MUSE log (bad magic bytes)".into(),
            });
        }
        Ok(LogReader {
            path: path.to_path_buf(),
            file,
            len,
            at: 16,
            allowance: MAX_GROUP_BYTES,
        })
    }

    fn next(&mut self) -> Result<Next, StoreError> {
        let rest = self.len - self.at;
        if rest == 0 {
            return Ok(Next::End { torn: 0 });
        }
        let torn = |r: &LogReader| {
            if rest > r.allowance {
                Err(StoreError::Damaged {
                    path: r.path.display().to_string(),
                    what: format!(
                        "the record at byte {} is damaged and {rest} bytes follow it: not a torn \
                         write from a crash but corruption of acknowledged data",
                        r.at
                    ),
                })
            } else {
                Ok(Next::End { torn: rest })
            }
        };
        let mut head = [0u8; 8];
        if rest < 8 || self.file.read_exact(&mut head).is_err() {
            return torn(self);
        }
        let len = u32::from_le_bytes(head[..4].try_into().expect("4 bytes"));
        let crc = u32::from_le_bytes(head[4..].try_into().expect("4 bytes"));
        if len == 0 || len > MAX_RECORD || u64::from(len) + 8 > rest {
            return torn(self);
        }
        let mut payload = vec![0u8; len as usize];
        if self.file.read_exact(&mut payload).is_err() || crc32fast::hash(&payload) != crc {
            return torn(self);
        }
        let record: Record = serde_json::from_slice(&payload).map_err(|e| StoreError::Damaged {
            path: self.path.display().to_string(),
            what: format!("the record at byte {} does not decode: {e}", self.at),
        })?;
        let offset = self.at;
        self.at += 8 + u64::from(len);
        self.allowance = match &record {
            Record::Large { bytes } => MAX_GROUP_BYTES.max(*bytes),
            _ => MAX_GROUP_BYTES,
        };
        Ok(Next::Record(record, offset))
    }
}

/// Checks that the log at `path` was written for `world` (the earlier version's description
/// of the airspace and parameters).
pub(super) fn check_header(path: &Path, world: &str) -> Result<(), StoreError> {
    let mut log = LogReader::open(path)?;
    match log.next()? {
        Next::Record(Record::Header { world: stored }, _) if stored == world => Ok(()),
        Next::Record(Record::Header { world: stored }, _) => Err(StoreError::Mismatch {
            path: path.display().to_string(),
            stored,
            wanted: world.to_owned(),
        }),
        Next::Record(..) => Err(StoreError::NotAStore {
            path: path.display().to_string(),
            why: "its first record is not a header".into(),
        }),
        // Torn before its header was whole: nothing was ever acknowledged.
        Next::End { .. } => Ok(()),
    }
}

/// Renames a converted log to [`IMPORTED_FILE`] beside it (never over an earlier one).
pub(super) fn retire(log: &Path) -> Result<PathBuf, StoreError> {
    let dir = log.parent().unwrap_or(Path::new("."));
    let mut to = dir.join(IMPORTED_FILE);
    let mut k = 2;
    while to.exists() {
        to = dir.join(format!("{IMPORTED_FILE}.{k}"));
        k += 1;
    }
    std::fs::rename(log, &to).map_err(|error| StoreError::Io {
        what: format!("renaming {} to {}", log.display(), to.display()),
        error,
    })?;
    sync_dir(dir)?;
    Ok(to)
}

/// Converts the log at `log` into a new store at `db` (see the module docs); `progress` is
/// told the records read so far.
pub(super) fn import(
    log: &Path,
    db: &Path,
    airspace: &Airspace,
    world: &WorldMeta,
    progress: &mut dyn FnMut(u64),
) -> Result<ImportReport, StoreError> {
    let tmp = db.with_extension("db.importing");
    let _ = std::fs::remove_file(&tmp);
    let conn = Connection::open(&tmp).map_err(|error| StoreError::Sql {
        what: format!("creating {}", tmp.display()),
        error,
    })?;
    // A conversion that does not finish is started again from the log: no journal needed.
    conn.execute_batch(
        "PRAGMA journal_mode = OFF; PRAGMA synchronous = OFF; PRAGMA cache_size = -262144;",
    )
    .map_err(sql("setting up the conversion"))?;
    write_schema(&conn, world)?;
    conn.execute_batch("BEGIN").map_err(sql("converting"))?;
    let mut import = Import {
        conn: &conn,
        label: tmp.display().to_string(),
        airspace,
        report: ImportReport::default(),
        latest: HashMap::new(),
        zones: HashMap::new(),
    };
    let mut reader = LogReader::open(log)?;
    loop {
        match reader.next()? {
            Next::Record(record, offset) => {
                import.report.records += 1;
                match import.apply(record) {
                    Ok(()) => {}
                    Err(Bad::Store(e)) => return Err(e),
                    Err(Bad::Record(what)) => {
                        return Err(StoreError::Damaged {
                            path: log.display().to_string(),
                            what: format!("the record at byte {offset}: {what}"),
                        });
                    }
                }
                if import.report.records.is_multiple_of(4_096) {
                    progress(import.report.records);
                }
            }
            Next::End { torn } => {
                import.report.torn_bytes = torn;
                break;
            }
        }
    }
    progress(import.report.records);
    let mut report = import.report;
    conn.execute_batch("COMMIT; PRAGMA journal_mode = WAL;")
        .map_err(sql("finishing the conversion"))?;
    conn.close().map_err(|(_, error)| StoreError::Sql {
        what: format!("closing {}", tmp.display()),
        error,
    })?;
    File::open(&tmp)
        .and_then(|f| f.sync_all())
        .map_err(|error| StoreError::Io {
            what: format!("syncing {}", tmp.display()),
            error,
        })?;
    std::fs::rename(&tmp, db).map_err(|error| StoreError::Io {
        what: format!("renaming {} to {}", tmp.display(), db.display()),
        error,
    })?;
    sync_dir(db.parent().unwrap_or(Path::new(".")))?;
    report.log = retire(log)?;
    Ok(report)
}

/// Why a record could not be applied: what is wrong with it, or a failure of the store.
enum Bad {
    Record(String),
    Store(StoreError),
}

impl From<String> for Bad {
    fn from(e: String) -> Self {
        Bad::Record(e)
    }
}

impl From<StoreError> for Bad {
    fn from(e: StoreError) -> Self {
        Bad::Store(e)
    }
}

/// The conversion's working state.
struct Import<'c> {
    conn: &'c Connection,
    label: String,
    airspace: &'c Airspace,
    report: ImportReport,
    /// For ids stored twice: the latest flight's sequence number.
    latest: HashMap<String, u64>,
    /// Zones by id.
    zones: HashMap<String, StoredZone>,
}

impl Import<'_> {
    fn find(&self, id: &str) -> Result<Option<FlightEntry>, StoreError> {
        super::queries::flight_by_id(self.conn, self.airspace, &self.label, id)
    }

    /// Applies one record.
    fn apply(&mut self, record: Record) -> Result<(), Bad> {
        match record {
            Record::Header { .. } | Record::Large { .. } => {}
            Record::Flight(f) => {
                let mut entry = self.flight(&f)?;
                if self.find(&entry.request.id)?.is_some() {
                    let id = entry.request.id.clone();
                    let mut k = 2;
                    while self.find(&format!("{id}#{k}"))?.is_some() {
                        k += 1;
                    }
                    let renamed = format!("{id}#{k}");
                    self.latest.insert(id.clone(), entry.seq);
                    self.report.renamed.push((id, renamed.clone()));
                    entry.request.id = renamed;
                }
                self.report.flights += 1;
                let entry = Arc::new(entry);
                write_flight(self.conn, &self.label, self.airspace, &entry, true)?;
                if entry.result.is_ok() {
                    let at = entry.answered;
                    self.event(EventKind::Planned, at, None, entry)?;
                }
            }
            Record::Cancel { id, at } => {
                let seq = match self.latest.get(&id) {
                    Some(&seq) => Some(seq),
                    None => self.find(&id)?.map(|f| f.seq),
                };
                let seq = seq.ok_or_else(|| format!("a cancellation of unknown flight `{id}`"))?;
                let mut entry = self.by_seq(seq)?;
                entry.cancelled_at = Some(Instant(at));
                self.report.cancellations += 1;
                self.change(EventKind::Cancelled, Instant(at), None, entry)?;
            }
            Record::Zone(z) => {
                let n = Instant(z.announced);
                for o in &z.outcomes {
                    let entry = self.by_seq(o.seq)?;
                    let fate = self.fate(&entry.request.id, o)?;
                    let kind = EventKind::of_fate(fate.kind());
                    let entry = entry.changed(&z.id, n, o.airborne, fate);
                    self.change(kind, n, Some(&z.id), entry)?;
                }
                let zone = StoredZone {
                    id: z.id.clone(),
                    feature: z.feature,
                    announced: n,
                    withdrawn: None,
                    affected: z.outcomes.len(),
                };
                self.report.zones += 1;
                write_zone(self.conn, &zone)?;
                self.zones.insert(z.id, zone);
            }
            Record::Withdraw { id, at } => {
                let zone = self
                    .zones
                    .get_mut(&id)
                    .ok_or_else(|| format!("a withdrawal of unknown zone `{id}`"))?;
                zone.withdrawn = Some(Instant(at));
                self.report.withdrawn += 1;
                write_zone(self.conn, zone)?;
            }
        }
        Ok(())
    }

    fn by_seq(&self, seq: u64) -> Result<FlightEntry, Bad> {
        super::queries::flight_by_seq(self.conn, self.airspace, &self.label, seq)?
            .ok_or_else(|| Bad::Record(format!("flight #{seq} is unknown")))
    }

    /// Writes a changed flight and its event.
    fn change(
        &mut self,
        kind: EventKind,
        at: Instant,
        zone: Option<&str>,
        entry: FlightEntry,
    ) -> Result<(), StoreError> {
        let entry = Arc::new(entry);
        write_flight(self.conn, &self.label, self.airspace, &entry, false)?;
        self.event(kind, at, zone, entry)
    }

    fn event(
        &mut self,
        kind: EventKind,
        at: Instant,
        zone: Option<&str>,
        entry: Arc<FlightEntry>,
    ) -> Result<(), StoreError> {
        self.report.events += 1;
        write_event(
            self.conn,
            &Event {
                id: self.report.events,
                kind,
                at,
                zone: zone.map(str::to_owned),
                entry,
            },
        )
    }

    fn plan(&self, flight: &str, stays: &[(String, i64, i64)]) -> Result<Plan, String> {
        super::rows::plan_of(self.airspace, stays).map_err(|e| format!("flight `{flight}`: {e}"))
    }

    fn flight(&self, r: &FlightRecord) -> Result<FlightEntry, String> {
        let node = |id: &str| {
            self.airspace
                .node_id(id)
                .ok_or_else(|| format!("flight `{}`: unknown node `{id}`", r.id))
        };
        let result = match (&r.path, &r.reason) {
            (Some(path), None) => Ok(self.plan(&r.id, path)?),
            (None, Some(reason)) => Err(RejectReason::parse(reason)
                .ok_or_else(|| format!("flight `{}`: unknown reason `{reason}`", r.id))?),
            _ => return Err(format!("flight `{}`: neither a plan nor a reason", r.id)),
        };
        Ok(FlightEntry {
            seq: r.seq,
            operator: r.operator.clone(),
            request: Request {
                id: r.id.clone(),
                origin: node(&r.origin)?,
                destination: node(&r.destination)?,
                departure: Instant(r.departure),
                submitted: Instant(r.departure),
            },
            result,
            free_flow: r.free_flow.map(Millis),
            expanded: r.expanded,
            answered: Instant(r.answered),
            cancelled_at: None,
            changes: Vec::new(),
            fates: Vec::new(),
        })
    }

    fn fate(&self, flight: &str, o: &OutcomeRecord) -> Result<Fate, String> {
        let kind = FateKind::parse(&o.outcome)
            .ok_or_else(|| format!("flight `{flight}`: unknown outcome `{}`", o.outcome))?;
        let plan = || match &o.path {
            Some(path) => self.plan(flight, path),
            None => Err(format!(
                "flight `{flight}`: a {} outcome without a path",
                o.outcome
            )),
        };
        Ok(match kind {
            FateKind::Replanned => Fate::Replanned(plan()?),
            FateKind::Diverted => Fate::Diverted(plan()?),
            FateKind::Contingency => Fate::Contingency(plan()?),
            FateKind::Cancelled => Fate::Cancelled,
        })
    }
}
