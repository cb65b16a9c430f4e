//! The durable store: one append-only log of checksummed records under `--data`.
//!
//! # Why a log and not `SQLite`
//!
//! The service's state is a sequence of events (a flight answered, a flight cancelled, a zone
//! announced with what it did to each flight it hit, a zone withdrawn) that is only ever
//! appended to and, at start, read back whole to rebuild the schedule. An append-only log is
//! exactly that, in one file, with no query engine, no C dependency and
//! one system call per durable group: every group of records is written with one `write`
//! and made durable with one `fdatasync` before any of its answers is sent (group commit).
//! What it costs — no ad-hoc queries — the service does not need: the in-memory index
//! answers reads.
//!
//! # Format
//!
//! The file `muse.log` starts with the 16-byte magic `MUSE-LOG-V1\n\0\0\0\0`, then records,
//! each `len: u32 LE | crc: u32 LE | payload` where `payload` is `len` bytes of JSON (one
//! [`Record`]) and `crc` is the CRC-32 (IEEE) of the payload. The first record is always a
//! [`Record::Header`] naming the airspace and parameters the log was written with.
//!
//! # Recovery
//!
//! On open the log is read from the start. A record that is cut short by the end of the
//! file, or whose checksum does not match, begins the *torn tail*: what a crash in the
//! middle of a group write leaves behind. Nothing in the torn tail was acknowledged (answers
//! go out only after the `fdatasync` of their whole group), so it is dropped: its bytes are
//! saved beside the log as `torn-<offset>.bin` for inspection and the log is truncated to the
//! last whole record. A torn tail longer than the largest group the service writes cannot
//! come from a crash: that is corruption of acknowledged data, and opening fails with an
//! error naming the offset rather than silently losing flights. The one record that may be
//! larger than a group — a zone announcement that hit many flights — is committed alone,
//! after a [`Record::Large`] marker that tells recovery how long its torn tail may be.
//!
//! # One process per folder
//!
//! `LOCK` in the folder is held with an exclusive advisory lock for the life of the store;
//! a second process on the same folder is refused with a clear error.

use std::fs::{File, OpenOptions};
use std::io::{Read as _, Write as _};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// The first bytes of every log.
const MAGIC: &[u8; 16] = b"MUSE-LOG-V1\n\0\0\0\0";
/// Largest record accepted. A flight is far below this; a zone announcement holds the new
/// plan of every flight it hit (a few hundred bytes each), so it can be larger than a group:
/// see [`Store::commit_alone`].
pub const MAX_RECORD: u32 = 256 << 20;
/// Largest group written with one `write` (the commit flushes earlier if a group would grow
/// beyond it): the bound on a torn tail after a crash.
pub const MAX_GROUP_BYTES: usize = 4 << 20;

/// The log's file name inside the data folder.
pub const LOG_FILE: &str = "muse.log";
/// The lock file's name inside the data folder.
pub const LOCK_FILE: &str = "LOCK";

/// Errors of the store.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// An I/O error, with what was being done.
    #[error("{what}: {source}")]
    Io {
        /// What was being done (names the file).
        what: String,
        /// The error.
        source: std::io::Error,
    },
    /// Another process holds the folder.
    #[error(
        "{0} is in use by another process (the lock on its LOCK file is held); stop that \
         `muse serve` or choose another --data folder"
    )]
    Locked(PathBuf),
    /// The file is not a MUSE log.
    #[error("{0} is not a MUSE log (bad magic bytes)")]
    NotALog(PathBuf),
    /// A damaged record followed by more data than a crash can leave.
    #[error(
        "{path}: the record at byte {offset} is damaged and {after} bytes follow it: this is not \
         a torn write from a crash but corruption of stored data; refusing to start (move the \
         file away to start empty, or restore it from a backup)"
    )]
    Corrupt {
        /// The log.
        path: PathBuf,
        /// Where the damaged record starts.
        offset: u64,
        /// Bytes from there to the end of the file.
        after: u64,
    },
    /// A whole record that does not decode (written by another version?).
    #[error("{path}: the record at byte {offset} does not decode: {reason}")]
    Undecodable {
        /// The log.
        path: PathBuf,
        /// Where the record starts.
        offset: u64,
        /// Why.
        reason: String,
    },
    /// The log was written for another airspace or other parameters.
    #[error(
        "{path} was written by a service planning on {stored}, not on {wanted}: its flights \
         cannot be restored here; use another --data folder"
    )]
    Mismatch {
        /// The log.
        path: PathBuf,
        /// What the log says.
        stored: String,
        /// What this service plans on.
        wanted: String,
    },
}

fn io(what: impl Into<String>) -> impl FnOnce(std::io::Error) -> StoreError {
    let what = what.into();
    move |source| StoreError::Io { what, source }
}

/// One record of the log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Record {
    /// What the log was written for: restored flights are only valid on the same airspace and
    /// parameters.
    Header {
        /// A description of the airspace and parameters (see `World::fingerprint`).
        world: String,
    },
    /// A request and the answer given to it (planned or rejected).
    Flight(FlightRecord),
    /// A planned flight cancelled by its operator.
    Cancel {
        /// The flight's id.
        id: String,
        /// When (service clock, ms since the epoch).
        at: i64,
    },
    /// A zone announced during the day (SPEC §11) and what it did to every flight it hit.
    Zone(ZoneRecord),
    /// A marker committed just before a record larger than [`MAX_GROUP_BYTES`] (see
    /// [`Store::commit_alone`]): a crash while that record is written may leave a torn tail
    /// of up to `bytes` bytes after the marker, which recovery then drops rather than
    /// calling it corruption.
    Large {
        /// The size of the record that follows, header included.
        bytes: u64,
    },
    /// An announced zone withdrawn (nothing was replanned).
    Withdraw {
        /// The zone's id.
        id: String,
        /// When (service clock, ms since the epoch).
        at: i64,
    },
}

/// A zone announcement, as stored: the zone as sent and the outcome of every flight it hit,
/// so that a restart puts the announcement back *without replanning* (replanning again
/// against a schedule restored in another order could give other answers than the ones
/// acknowledged).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ZoneRecord {
    /// The zone's id.
    pub id: String,
    /// The ED-318 feature as received (compact JSON, without `announced`).
    pub feature: String,
    /// The announcement instant (service clock, ms since the epoch).
    pub announced: i64,
    /// The flights it hit, in the order they were replanned.
    pub outcomes: Vec<OutcomeRecord>,
}

/// What an announcement made of one flight, as stored.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct OutcomeRecord {
    /// The flight's sequence number.
    pub seq: u64,
    /// Whether it had taken off at the announcement.
    pub airborne: bool,
    /// `replanned`, `diverted`, `cancelled` or `contingency`.
    pub outcome: String,
    /// The new plan (replanned, diverted) or the committed part (contingency) as
    /// `(node id, arrive, depart)` stays; absent when cancelled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<Vec<(String, i64, i64)>>,
}

/// A request and its answer, as stored.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FlightRecord {
    /// The service's sequence number of the flight (its id in the schedule).
    pub seq: u64,
    /// The client's id.
    pub id: String,
    /// The operator that sent it.
    pub operator: String,
    /// Origin station id.
    pub origin: String,
    /// Destination station id.
    pub destination: String,
    /// Requested departure, ms since the epoch.
    pub departure: i64,
    /// When it was answered (service clock, ms since the epoch).
    pub answered: i64,
    /// The plan as `(node id, arrive, depart)` stays, or `None` when rejected.
    pub path: Option<Vec<(String, i64, i64)>>,
    /// The rejection reason (file spelling), when rejected.
    pub reason: Option<String>,
    /// Free-flow time, ms, where defined.
    pub free_flow: Option<i64>,
    /// Search labels expanded.
    pub expanded: u64,
}

/// What opening found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Recovery {
    /// Whole records read (the header included).
    pub records: usize,
    /// Bytes of torn tail dropped (0 after a clean stop or most crashes).
    pub torn_bytes: u64,
    /// Where the torn tail was saved, if there was one.
    pub torn_saved: Option<PathBuf>,
}

/// The open log (see the module docs).
#[derive(Debug)]
pub struct Store {
    path: PathBuf,
    file: File,
    /// Held for the life of the store.
    _lock: File,
    /// Records appended but not yet committed.
    pending: Vec<u8>,
    pending_records: usize,
    bytes: u64,
}

impl Store {
    /// Opens (or creates) the log in `dir`, takes the folder's lock, recovers from a torn tail
    /// and returns the store with every record in the log. A new log starts with a header
    /// for `world`; an existing one must have been written for the same `world`.
    pub fn open(dir: &Path, world: &str) -> Result<(Store, Vec<Record>, Recovery), StoreError> {
        std::fs::create_dir_all(dir).map_err(io(format!("creating {}", dir.display())))?;
        let lock_path = dir.join(LOCK_FILE);
        let lock = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(io(format!("opening {}", lock_path.display())))?;
        match lock.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(StoreError::Locked(dir.to_path_buf()));
            }
            Err(std::fs::TryLockError::Error(e)) => {
                return Err(io(format!("locking {}", lock_path.display()))(e));
            }
        }
        let path = dir.join(LOG_FILE);
        let existed = path.exists();
        let mut file = OpenOptions::new()
            .create(true)
            .read(true)
            .append(true)
            .open(&path)
            .map_err(io(format!("opening {}", path.display())))?;
        let mut store = Store {
            path: path.clone(),
            file: file.try_clone().map_err(io("cloning the log handle"))?,
            _lock: lock,
            pending: Vec::new(),
            pending_records: 0,
            bytes: 0,
        };
        let mut data = Vec::new();
        file.read_to_end(&mut data)
            .map_err(io(format!("reading {}", path.display())))?;
        // A crash while the log was being created leaves a prefix of the magic, or the magic
        // and a torn header: nothing was acknowledged yet, so start afresh.
        let fresh = data.len() <= MAGIC.len() && MAGIC.starts_with(&data);
        if !fresh && (data.len() < MAGIC.len() || &data[..MAGIC.len()] != MAGIC) {
            return Err(StoreError::NotALog(path));
        }
        let (records, good_end) = if fresh {
            (Vec::new(), 0)
        } else {
            scan(&data, &path)?
        };
        let mut recovery = Recovery {
            records: records.len(),
            ..Recovery::default()
        };
        let good_end = if records.is_empty() { 0 } else { good_end };
        if good_end < data.len() {
            let torn = &data[good_end..];
            let saved = dir.join(format!("torn-{good_end}.bin"));
            std::fs::write(&saved, torn).map_err(io(format!("writing {}", saved.display())))?;
            file.set_len(good_end as u64)
                .map_err(io(format!("truncating {}", path.display())))?;
            file.sync_all()
                .map_err(io(format!("syncing {}", path.display())))?;
            recovery.torn_bytes = torn.len() as u64;
            recovery.torn_saved = Some(saved);
        }
        if records.is_empty() {
            store.pending.extend_from_slice(MAGIC);
            let header = Record::Header {
                world: world.to_owned(),
            };
            store.append(&header);
            store.commit()?;
            if !existed {
                sync_dir(dir)?;
            }
            recovery.records = 1;
            return Ok((store, vec![header], recovery));
        }
        match records.first() {
            Some(Record::Header { world: stored }) if stored == world => {}
            Some(Record::Header { world: stored }) => {
                return Err(StoreError::Mismatch {
                    path,
                    stored: stored.clone(),
                    wanted: world.to_owned(),
                });
            }
            _ => {
                return Err(StoreError::Undecodable {
                    path,
                    offset: MAGIC.len() as u64,
                    reason: "the first record is not a header".into(),
                });
            }
        }
        // Appends go to the end of the file (opened in append mode), which is now `good_end`.
        store.bytes = good_end as u64;
        Ok((store, records, recovery))
    }

    /// The log's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Bytes in the log, committed.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Records appended and not yet committed.
    pub fn pending_records(&self) -> usize {
        self.pending_records
    }

    /// Bytes appended and not yet committed.
    pub fn pending_bytes(&self) -> usize {
        self.pending.len()
    }

    /// Appends a record to the current group (not yet durable: see [`Store::commit`]).
    pub fn append(&mut self, record: &Record) {
        let start = self.pending.len();
        self.pending.extend_from_slice(&[0; 8]);
        // Serialising plain strings and numbers cannot fail.
        serde_json::to_writer(&mut self.pending, record).expect("records serialise");
        let payload = &self.pending[start + 8..];
        let len = payload.len() as u32;
        let crc = crc32fast::hash(payload);
        self.pending[start..start + 4].copy_from_slice(&len.to_le_bytes());
        self.pending[start + 4..start + 8].copy_from_slice(&crc.to_le_bytes());
        self.pending_records += 1;
    }

    /// Commits what is pending, then `record` as a group of its own, however large (a zone
    /// announcement): a record larger than [`MAX_GROUP_BYTES`] is preceded by a committed
    /// [`Record::Large`] marker, so that a crash while it is written leaves a torn tail that
    /// recovery recognises. A record larger than [`MAX_RECORD`] is refused (nothing of it is
    /// written).
    pub fn commit_alone(&mut self, record: &Record) -> Result<(), StoreError> {
        self.commit()?;
        // Serialising plain strings and numbers cannot fail.
        let payload = serde_json::to_vec(record).expect("records serialise");
        if payload.len() > MAX_RECORD as usize {
            return Err(StoreError::Io {
                what: format!("writing {}", self.path.display()),
                source: std::io::Error::other(format!(
                    "a record of {} bytes is larger than the {MAX_RECORD} bytes a log record may hold",
                    payload.len()
                )),
            });
        }
        let bytes = payload.len() + 8;
        if bytes > MAX_GROUP_BYTES {
            self.append(&Record::Large {
                bytes: bytes as u64,
            });
            self.commit()?;
        }
        self.pending
            .extend_from_slice(&(payload.len() as u32).to_le_bytes());
        self.pending
            .extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
        self.pending.extend_from_slice(&payload);
        self.pending_records += 1;
        self.commit()
    }

    /// Writes the current group with one `write` and makes it durable with `fdatasync`.
    /// Only after this returns may the group's answers be sent.
    pub fn commit(&mut self) -> Result<(), StoreError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        self.file
            .write_all(&self.pending)
            .map_err(io(format!("writing {}", self.path.display())))?;
        self.file
            .sync_data()
            .map_err(io(format!("syncing {}", self.path.display())))?;
        self.bytes += self.pending.len() as u64;
        self.pending.clear();
        self.pending_records = 0;
        Ok(())
    }
}

/// Reads every whole record of `data` (which starts with the magic); returns them and where
/// the whole records end. A damaged record with more than [`MAX_GROUP_BYTES`] after it is
/// corruption, not a torn tail, unless it follows a [`Record::Large`] marker announcing a
/// larger record: then up to that many bytes may be torn.
fn scan(data: &[u8], path: &Path) -> Result<(Vec<Record>, usize), StoreError> {
    let mut records = Vec::new();
    let mut at = MAGIC.len();
    let mut allowance = MAX_GROUP_BYTES;
    loop {
        let rest = &data[at..];
        if rest.is_empty() {
            return Ok((records, at));
        }
        let whole = rest.len() >= 8 && {
            let len = u32::from_le_bytes(rest[..4].try_into().expect("4 bytes"));
            let crc = u32::from_le_bytes(rest[4..8].try_into().expect("4 bytes"));
            len > 0
                && len <= MAX_RECORD
                && rest.len() >= 8 + len as usize
                && crc32fast::hash(&rest[8..8 + len as usize]) == crc
        };
        if !whole {
            if rest.len() > allowance {
                return Err(StoreError::Corrupt {
                    path: path.to_path_buf(),
                    offset: at as u64,
                    after: rest.len() as u64,
                });
            }
            return Ok((records, at));
        }
        let len = u32::from_le_bytes(rest[..4].try_into().expect("4 bytes")) as usize;
        let record: Record =
            serde_json::from_slice(&rest[8..8 + len]).map_err(|e| StoreError::Undecodable {
                path: path.to_path_buf(),
                offset: at as u64,
                reason: e.to_string(),
            })?;
        allowance = match &record {
            Record::Large { bytes } => MAX_GROUP_BYTES.max(usize::try_from(*bytes).unwrap_or(0)),
            _ => MAX_GROUP_BYTES,
        };
        records.push(record);
        at += 8 + len;
    }
}

/// Makes a new file's directory entry durable.
fn sync_dir(dir: &Path) -> Result<(), StoreError> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io(format!("syncing the folder {}", dir.display())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flight(seq: u64) -> Record {
        Record::Flight(FlightRecord {
            seq,
            id: format!("f{seq}"),
            operator: "op".into(),
            origin: "S001".into(),
            destination: "S002".into(),
            departure: 1_000,
            answered: 500,
            path: Some(vec![
                ("S001".into(), 1_000, 1_000),
                ("S002".into(), 2_000, 2_000),
            ]),
            reason: None,
            free_flow: Some(1_000),
            expanded: 2,
        })
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("muse-store-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn round_trip_and_lock() {
        let d = dir("round");
        {
            let (mut s, recs, rec) = Store::open(&d, "w").unwrap();
            assert_eq!(recs.len(), 1);
            assert_eq!(rec.torn_bytes, 0);
            s.append(&flight(1));
            s.append(&Record::Cancel {
                id: "f1".into(),
                at: 700,
            });
            s.commit().unwrap();
            // A second opener is refused while the first holds the folder.
            assert!(matches!(Store::open(&d, "w"), Err(StoreError::Locked(_))));
        }
        let (s, recs, _) = Store::open(&d, "w").unwrap();
        assert_eq!(recs.len(), 3);
        assert_eq!(recs[1], flight(1));
        drop(s);
        let e = Store::open(&d, "other").unwrap_err().to_string();
        assert!(e.contains("not on other"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn every_torn_tail_is_dropped_never_misread() {
        let d = dir("torn");
        let full = {
            let (mut s, _, _) = Store::open(&d, "w").unwrap();
            s.append(&flight(1));
            s.commit().unwrap();
            s.append(&flight(2));
            s.append(&flight(3));
            s.commit().unwrap();
            std::fs::read(s.path()).unwrap()
        };
        let log = d.join(LOG_FILE);
        let (_, end) = scan(&full, &log).unwrap();
        assert_eq!(end, full.len());
        // Record ends: header, flight 1 (the end of the first group), flight 2.
        let mut ends = Vec::new();
        let mut at = MAGIC.len();
        for _ in 0..3 {
            let len = u32::from_le_bytes(full[at..at + 4].try_into().unwrap()) as usize;
            at += 8 + len;
            ends.push(at);
        }
        let (first_group_end, second_record_end) = (ends[1], ends[2]);
        // Cut anywhere inside the second group, or zero its bytes: flights 2 and 3 vanish
        // together or 3 alone, flight 1 always stays, nothing is misread.
        for cut in first_group_end..full.len() {
            for zeroed in [false, true] {
                let mut bytes = full.clone();
                if zeroed {
                    bytes[cut..].fill(0);
                } else {
                    bytes.truncate(cut);
                }
                std::fs::write(&log, &bytes).unwrap();
                let (_s, recs, rec) = Store::open(&d, "w").unwrap();
                assert!((2..=3).contains(&recs.len()), "cut {cut}: {}", recs.len());
                assert_eq!(recs[1], flight(1));
                if recs.len() == 3 {
                    assert_eq!(recs[2], flight(2));
                }
                // A cut between two records tears nothing.
                let boundary = cut == first_group_end || cut == second_record_end;
                assert_eq!(
                    rec.torn_bytes > 0,
                    !boundary || (zeroed && cut < full.len()),
                    "cut {cut} zeroed {zeroed}"
                );
                assert_eq!(
                    std::fs::metadata(&log).unwrap().len(),
                    bytes.len() as u64 - rec.torn_bytes
                );
            }
        }
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn damage_far_from_the_end_is_an_error() {
        let d = dir("corrupt");
        {
            let (mut s, _, _) = Store::open(&d, "w").unwrap();
            s.append(&flight(1));
            s.commit().unwrap();
            let big = "x".repeat(1 << 16);
            for i in 0..80 {
                let mut r = flight(2 + i);
                if let Record::Flight(f) = &mut r {
                    f.operator.clone_from(&big);
                }
                s.append(&r);
                s.commit().unwrap();
            }
        }
        let log = d.join(LOG_FILE);
        let mut bytes = std::fs::read(&log).unwrap();
        bytes[MAGIC.len() + 10] ^= 0xff; // inside the header record
        std::fs::write(&log, &bytes).unwrap();
        let e = Store::open(&d, "w").unwrap_err();
        assert!(matches!(e, StoreError::Corrupt { offset: 16, .. }), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    fn zone(feature_bytes: usize) -> Record {
        Record::Zone(ZoneRecord {
            id: "Z".into(),
            feature: "x".repeat(feature_bytes),
            announced: 900,
            outcomes: vec![
                OutcomeRecord {
                    seq: 1,
                    airborne: false,
                    outcome: "replanned".into(),
                    path: Some(vec![
                        ("S001".into(), 1_000, 1_000),
                        ("S003".into(), 3_000, 3_000),
                    ]),
                },
                OutcomeRecord {
                    seq: 2,
                    airborne: false,
                    outcome: "cancelled".into(),
                    path: None,
                },
            ],
        })
    }

    #[test]
    fn a_record_larger_than_a_group_is_marked_and_its_torn_tail_dropped() {
        let d = dir("large");
        let big = zone(MAX_GROUP_BYTES + 100_000);
        let small = zone(10);
        {
            let (mut s, _, _) = Store::open(&d, "w").unwrap();
            s.append(&flight(1));
            s.commit_alone(&small).unwrap();
            s.commit_alone(&big).unwrap();
            s.append(&Record::Withdraw {
                id: "Z".into(),
                at: 950,
            });
            s.commit().unwrap();
        }
        let (s, recs, _) = Store::open(&d, "w").unwrap();
        drop(s);
        let bytes =
            (MAX_GROUP_BYTES + 100_000 + 8 + serde_json::to_vec(&small).unwrap().len() - 10) as u64;
        assert_eq!(
            recs[1..],
            [
                flight(1),
                small.clone(),
                Record::Large { bytes },
                big.clone(),
                Record::Withdraw {
                    id: "Z".into(),
                    at: 950
                }
            ]
        );
        // A crash in the middle of the large record: its torn tail, longer than any group,
        // is dropped, and everything before it stays.
        let log = d.join(LOG_FILE);
        let full = std::fs::read(&log).unwrap();
        let cut = full.len() - 100 - 50_000;
        std::fs::write(&log, &full[..cut]).unwrap();
        let (s, recs, rec) = Store::open(&d, "w").unwrap();
        drop(s);
        assert!(rec.torn_bytes > MAX_GROUP_BYTES as u64);
        assert_eq!(recs[1..], [flight(1), small, Record::Large { bytes }]);
        // Without the marker the same tail is taken for corruption.
        let marker_end = std::fs::metadata(&log).unwrap().len() as usize;
        let mut unmarked = full[..cut].to_vec();
        let marker_len = {
            let mut at = MAGIC.len();
            let mut last = 0;
            while at < marker_end {
                last = u32::from_le_bytes(unmarked[at..at + 4].try_into().unwrap()) as usize + 8;
                at += last;
            }
            last
        };
        unmarked.drain(marker_end - marker_len..marker_end);
        std::fs::write(&log, &unmarked).unwrap();
        assert!(matches!(
            Store::open(&d, "w"),
            Err(StoreError::Corrupt { .. })
        ));
        std::fs::remove_dir_all(&d).unwrap();
    }
}
