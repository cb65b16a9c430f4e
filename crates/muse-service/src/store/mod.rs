//! The durable store: an SQLite database, `muse.db` under `--data` (bundled SQLite, WAL,
//! `synchronous=FULL`), that operators can inspect, back up and query with their own tools.
//!
//! # What it holds
//!
//! The tables are in [`schema`]: `meta` (the airspace and parameters the store was written
//! for, in words), `flights` (every request ever answered, its id the key for the life of the
//! store, with its current state and plan), `zones` (zones announced during the day), `events`
//! (every change of every flight, the stream of `GET /v1/events`), and two views,
//! `cancellations` and `zone_outcomes`.
//!
//! # Writing
//!
//! Only the planner task writes, through [`Store`]: the rows of a group of decisions go into
//! one transaction, and [`Store::commit`] returns once it is durable (SQLite syncs the WAL on
//! every commit with `synchronous=FULL`); only then are the group's answers sent. A crash
//! leaves every committed transaction and discards the one it tore: nothing acknowledged is
//! lost, nothing unacknowledged survives half-written. A background thread checkpoints the
//! WAL into the database file, so commits never wait for it.
//!
//! # Reading and damage
//!
//! Every row carries the CRC-32 of its content (see `rows`), checked whenever it is read:
//! a flipped byte is found and named ([`StoreError::Damaged`]), never reinterpreted. At start
//! the service reads the `meta` rows, every zone and every flight still holding a reservation,
//! and checks that the database file is as long as its header says (a file cut short is
//! refused); reads of older flights go to the database by index, and are checked then. A
//! damaged row makes the start fail, or the read that meets it fail, naming the row.
//!
//! # One process per folder
//!
//! `LOCK` in the folder is held with an exclusive advisory lock for the life of the store; a
//! second process on the same folder is refused with a clear error.
//!
//! # An older folder
//!
//! A folder written by an earlier version holds `muse.log`, an append-only log; it is
//! converted once (see [`legacy`]) and kept, renamed `muse.log.imported`.

mod checkpoint;
mod file;
pub mod legacy;
mod queries;
mod reader;
mod rows;
pub mod schema;

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use muse_model::{Airspace, Instant};
use rusqlite::{Connection, OpenFlags, OptionalExtension as _, params};

pub use legacy::ImportReport;
pub use queries::Checked;
pub use reader::Reader;

use crate::events::Event;
use crate::flights::FlightEntry;
use rows::{EventRow, FlightRow, ZoneRow, meta_sum};

/// The database's file name inside the data folder.
pub const DB_FILE: &str = "muse.db";
/// How often the writer lets the WAL start again (see [`Store::tidy`]).
pub const WAL_RESTART: std::time::Duration = std::time::Duration::from_millis(250);

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
    /// An error of the database.
    #[error("{what}: {source}")]
    Sql {
        /// What was being done.
        what: String,
        /// The error.
        source: rusqlite::Error,
    },
    /// Another process holds the folder.
    #[error(
        "{0} is in use by another process (the lock on its LOCK file is held); stop that \
         `muse serve` or choose another --data folder"
    )]
    Locked(PathBuf),
    /// Stored data failed an integrity check.
    #[error(
        "{path} is damaged: {what}; refusing to use it (restore the folder from a backup, or \
         move it away to start empty)"
    )]
    Damaged {
        /// The database (or log) file.
        path: String,
        /// What is damaged.
        what: String,
    },
    /// The file is not a MUSE store, or one of a newer format.
    #[error("{path} is not a MUSE store this version can read: {why}")]
    NotAStore {
        /// The file.
        path: PathBuf,
        /// Why.
        why: String,
    },
    /// The store was written for another airspace or other parameters.
    #[error(
        "{path} was written by a service planning with {stored}; this service plans with \
         {wanted}: its flights cannot be restored here (start with the same airspace, zones \
         and parameters, or use another --data folder)"
    )]
    Mismatch {
        /// The store.
        path: PathBuf,
        /// What the store says, where it differs.
        stored: String,
        /// What this service plans with, where it differs.
        wanted: String,
    },
}

/// An error of the database while doing `what`.
pub(crate) fn sql(what: &str) -> impl FnOnce(rusqlite::Error) -> StoreError + '_ {
    move |source| StoreError::Sql {
        what: what.to_owned(),
        source,
    }
}

fn io(what: impl Into<String>) -> impl FnOnce(std::io::Error) -> StoreError {
    let what = what.into();
    move |source| StoreError::Io { what, source }
}

/// What a store is written for: `(name, value)` pairs in words (`("speed", "30 km/h")`), the
/// airspace and zones by counts and checksums of their canonical files.
pub type WorldMeta = Vec<(String, String)>;

/// A zone announced during the day, as stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StoredZone {
    /// Its id.
    pub id: String,
    /// The ED-318 feature as received (compact JSON, without `announced`).
    pub feature: String,
    /// The announcement instant.
    pub announced: Instant,
    /// When it was withdrawn, if it was.
    pub withdrawn: Option<Instant>,
    /// How many flights it changed.
    pub affected: usize,
}

/// A data folder opened and locked, its store checked, not yet loaded.
#[derive(Debug)]
pub struct Opening {
    dir: PathBuf,
    lock: File,
    /// A log of an earlier version to convert first.
    import: Option<PathBuf>,
}

impl Opening {
    /// Locks `dir` (creating it if missing) and checks what it holds against `world`: a store
    /// written for the same world, a log of an earlier version written for it (to convert
    /// with [`Opening::finish`]), or nothing yet. Quick: reads no flight.
    pub fn open(dir: &Path, world: &WorldMeta, legacy_world: &str) -> Result<Opening, StoreError> {
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
        let db = dir.join(DB_FILE);
        let log = dir.join(legacy::LOG_FILE);
        let import = if db.exists() {
            file::check(&db)?;
            let conn = connect(&db, false)?;
            check_meta(&conn, &db, world)?;
            if log.exists() {
                // Converted, and the process stopped before the log was renamed.
                legacy::retire(&log)?;
            }
            None
        } else if log.exists() {
            legacy::check_header(&log, legacy_world)?;
            Some(log)
        } else {
            None
        };
        Ok(Opening {
            dir: dir.to_path_buf(),
            lock,
            import,
        })
    }

    /// Whether a log of an earlier version will be converted.
    pub fn imports(&self) -> Option<&Path> {
        self.import.as_deref()
    }

    /// Converts a log of an earlier version if there is one (calling `progress` with the
    /// records read so far), creates the store if there is none, and opens it for writing.
    pub fn finish(
        self,
        airspace: &Airspace,
        world: &WorldMeta,
        progress: &mut dyn FnMut(u64),
    ) -> Result<(Store, Option<ImportReport>), StoreError> {
        let db = self.dir.join(DB_FILE);
        let report = if let Some(log) = &self.import {
            Some(legacy::import(log, &db, airspace, world, progress)?)
        } else {
            if !db.exists() {
                create(&db, world)?;
            }
            None
        };
        let conn = connect(&db, true)?;
        let checkpoints = checkpoint::Checkpointer::start(&db)?;
        Ok((
            Store {
                path: db,
                conn,
                _lock: self.lock,
                in_transaction: false,
                written: 0,
                last_wal_restart: std::time::Instant::now(),
                _checkpoints: checkpoints,
            },
            report,
        ))
    }
}

/// Opens a connection to the database at `path` with the store's settings (`write`: the
/// planner task's, which syncs every commit; else a read-only one).
fn connect(path: &Path, write: bool) -> Result<Connection, StoreError> {
    let flags = if write {
        OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX
    } else {
        OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX
    };
    let conn = Connection::open_with_flags(path, flags).map_err(|source| StoreError::Sql {
        what: format!("opening {}", path.display()),
        source,
    })?;
    let settings = if write {
        "PRAGMA journal_mode = WAL; PRAGMA synchronous = FULL; PRAGMA wal_autocheckpoint = 0; \
         PRAGMA journal_size_limit = 16777216; PRAGMA cache_size = -65536; \
         PRAGMA busy_timeout = 10000;"
    } else {
        "PRAGMA busy_timeout = 10000; PRAGMA query_only = 1;"
    };
    conn.execute_batch(settings)
        .map_err(|source| StoreError::Sql {
            what: format!("setting up {}", path.display()),
            source,
        })?;
    Ok(conn)
}

/// Creates a new store at `path` for `world`, atomically: written beside it, then renamed.
fn create(path: &Path, world: &WorldMeta) -> Result<(), StoreError> {
    let tmp = path.with_extension("db.creating");
    let _ = std::fs::remove_file(&tmp);
    {
        let conn = Connection::open(&tmp).map_err(|source| StoreError::Sql {
            what: format!("creating {}", tmp.display()),
            source,
        })?;
        write_schema(&conn, world)?;
        conn.execute_batch("PRAGMA journal_mode = WAL;")
            .map_err(sql("setting WAL mode"))?;
        conn.close().map_err(|(_, e)| StoreError::Sql {
            what: format!("closing {}", tmp.display()),
            source: e,
        })?;
    }
    File::open(&tmp)
        .and_then(|f| f.sync_all())
        .map_err(io(format!("syncing {}", tmp.display())))?;
    std::fs::rename(&tmp, path).map_err(io(format!("renaming {}", tmp.display())))?;
    sync_dir(path.parent().unwrap_or(Path::new(".")))
}

/// Creates the tables of a new store in `conn` and records `world` in `meta`.
pub(crate) fn write_schema(conn: &Connection, world: &WorldMeta) -> Result<(), StoreError> {
    conn.execute_batch(&format!(
        "PRAGMA page_size = {}; BEGIN; {}",
        schema::PAGE_SIZE,
        schema::CREATE
    ))
    .map_err(sql("creating the tables"))?;
    let mut rows = vec![("format".to_owned(), schema::FORMAT.to_owned())];
    rows.extend(world.iter().cloned());
    for (key, value) in rows {
        conn.execute(
            "INSERT INTO meta (key, value, crc) VALUES (?1, ?2, ?3)",
            params![key, value, meta_sum(&key, &value)],
        )
        .map_err(sql("writing the meta table"))?;
    }
    conn.execute_batch("COMMIT")
        .map_err(sql("creating the tables"))
}

/// Checks the `meta` rows of an existing store: its format, then the world it was written for.
fn check_meta(conn: &Connection, path: &Path, world: &WorldMeta) -> Result<(), StoreError> {
    let not = |why: String| StoreError::NotAStore {
        path: path.to_path_buf(),
        why,
    };
    let mut stmt = conn
        .prepare("SELECT key, value, crc FROM meta")
        .map_err(|e| not(format!("it has no readable meta table ({e})")))?;
    let rows = stmt
        .query_map([], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })
        .map_err(|e| not(format!("its meta table cannot be read ({e})")))?;
    let mut stored = std::collections::BTreeMap::new();
    for row in rows {
        let (key, value, crc) = row.map_err(sql("reading the meta table"))?;
        if meta_sum(&key, &value) != crc {
            return Err(StoreError::Damaged {
                path: path.display().to_string(),
                what: format!(
                    "meta row {key:?}: its checksum does not match its content (a byte of it \
                     changed on disk)"
                ),
            });
        }
        stored.insert(key, value);
    }
    match stored.remove("format") {
        Some(f) if f == schema::FORMAT => {}
        Some(f) => {
            return Err(not(format!(
                "it is of format {f:?}, this version reads {:?}",
                schema::FORMAT
            )));
        }
        None => return Err(not("it has no format entry".into())),
    }
    let (mut was, mut now) = (Vec::new(), Vec::new());
    for (key, value) in world {
        let old = stored.remove(key);
        if old.as_deref() != Some(value.as_str()) {
            was.push(format!(
                "{key} {}",
                old.as_deref().unwrap_or("(not recorded)")
            ));
            now.push(format!("{key} {value}"));
        }
    }
    for (key, value) in stored {
        was.push(format!("{key} {value}"));
        now.push(format!("{key} (none)"));
    }
    if was.is_empty() {
        Ok(())
    } else {
        Err(StoreError::Mismatch {
            path: path.to_path_buf(),
            stored: was.join(", "),
            wanted: now.join(", "),
        })
    }
}

/// Makes a new file's directory entry durable.
pub(crate) fn sync_dir(dir: &Path) -> Result<(), StoreError> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io(format!("syncing the folder {}", dir.display())))
}

/// The open store, written by the planner task only (see the module docs).
#[derive(Debug)]
pub struct Store {
    path: PathBuf,
    conn: Connection,
    /// Held for the life of the store.
    _lock: File,
    in_transaction: bool,
    /// Rows written in the open transaction.
    written: usize,
    /// When the writer last finished a checkpoint itself (see [`Store::tidy`]).
    last_wal_restart: std::time::Instant,
    _checkpoints: checkpoint::Checkpointer,
}

impl Store {
    /// The database's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn label(&self) -> String {
        self.path.display().to_string()
    }

    fn begin(&mut self) -> Result<(), StoreError> {
        if !self.in_transaction {
            self.conn
                .execute_batch("BEGIN IMMEDIATE")
                .map_err(sql("starting a transaction"))?;
            self.in_transaction = true;
        }
        Ok(())
    }

    /// Rows written since the last commit.
    pub fn pending(&self) -> usize {
        self.written
    }

    /// Writes a flight as it now stands: a new one (`new`) or a change of a stored one.
    pub fn put_flight(
        &mut self,
        airspace: &Airspace,
        entry: &FlightEntry,
        new: bool,
    ) -> Result<(), StoreError> {
        self.begin()?;
        write_flight(&self.conn, &self.label(), airspace, entry, new)?;
        self.written += 1;
        Ok(())
    }

    /// Writes an event.
    pub fn put_event(&mut self, event: &Event) -> Result<(), StoreError> {
        self.begin()?;
        write_event(&self.conn, event)?;
        self.written += 1;
        Ok(())
    }

    /// Writes an announced zone: a new one, or the withdrawal of a stored one.
    pub fn put_zone(&mut self, zone: &StoredZone) -> Result<(), StoreError> {
        self.begin()?;
        write_zone(&self.conn, zone)?;
        self.written += 1;
        Ok(())
    }

    /// Writes the withdrawal of the stored zone `id` at `at`.
    pub fn put_zone_withdrawn(&mut self, id: &str, at: Instant) -> Result<(), StoreError> {
        let mut zone = self
            .zones()?
            .into_iter()
            .find(|z| z.id == id)
            .ok_or_else(|| StoreError::Damaged {
                path: self.label(),
                what: format!("zones row {id:?} is missing"),
            })?;
        zone.withdrawn = Some(at);
        self.put_zone(&zone)
    }

    /// Makes everything written since the last commit durable (one transaction, synced). Only
    /// after this returns may the answers it holds be sent. Returns the rows committed.
    pub fn commit(&mut self) -> Result<usize, StoreError> {
        if !self.in_transaction {
            return Ok(0);
        }
        self.conn
            .execute_batch("COMMIT")
            .map_err(sql("committing"))?;
        self.in_transaction = false;
        Ok(std::mem::take(&mut self.written))
    }

    /// Lets the WAL start again from its beginning, at most every [`WAL_RESTART`]: call it
    /// between groups, once their answers are sent. The checkpoint thread copies committed
    /// pages into the database all the time, but under steady writes it never catches up
    /// with the last commit, and SQLite restarts the WAL only when a write begins with every
    /// frame copied: so now and then the writer finishes the copy itself (the frames since
    /// the thread's last pass, and one sync of the database file), and the next write starts
    /// the WAL afresh. Without this the WAL grows for as long as writes keep coming.
    pub fn tidy(&mut self) {
        if self.in_transaction || self.last_wal_restart.elapsed() < WAL_RESTART {
            return;
        }
        // A failed checkpoint loses nothing (the WAL keeps the pages); the next one tries.
        let _ = self.conn.execute_batch("PRAGMA wal_checkpoint(PASSIVE);");
        self.last_wal_restart = std::time::Instant::now();
    }

    /// The flight with client id `id`, including those written in the open transaction.
    pub fn flight(&self, airspace: &Airspace, id: &str) -> Result<Option<FlightEntry>, StoreError> {
        queries::flight_by_id(&self.conn, airspace, &self.label(), id)
    }

    /// The flight with sequence number `seq`.
    pub fn flight_by_seq(
        &self,
        airspace: &Airspace,
        seq: u64,
    ) -> Result<Option<FlightEntry>, StoreError> {
        queries::flight_by_seq(&self.conn, airspace, &self.label(), seq)
    }

    /// Every announced zone, in announcement order.
    pub fn zones(&self) -> Result<Vec<StoredZone>, StoreError> {
        queries::zones(&self.conn, &self.label())
    }

    /// How many flights hold a reservation that ends at or after `now`.
    pub fn count_holding(&self, now: Instant) -> Result<u64, StoreError> {
        queries::count_holding(&self.conn, now)
    }

    /// The flights holding a reservation that ends at or after `now` (checked), in answer
    /// order; `progress` is told how many were read so far.
    pub fn holding(
        &self,
        airspace: &Airspace,
        now: Instant,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Vec<FlightEntry>, StoreError> {
        queries::holding(&self.conn, airspace, &self.label(), now, progress)
    }

    /// Reads every row and checks it (see the module docs): the whole store, in time that
    /// grows with it (`muse serve --check-store`); `progress` is told the flights checked.
    pub fn check_all(
        &self,
        airspace: &Airspace,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Checked, StoreError> {
        queries::check_all(&self.conn, airspace, &self.label(), progress)
    }

    /// The last sequence number and the last event id stored (0: none).
    pub fn last_keys(&self) -> Result<(u64, u64), StoreError> {
        Ok((
            queries::max_key(&self.conn, "flights", "seq")?,
            queries::max_key(&self.conn, "events", "id")?,
        ))
    }

    /// Bytes on disk: the database and its WAL.
    pub fn bytes(&self) -> u64 {
        let size = |p: PathBuf| std::fs::metadata(p).map_or(0, |m| m.len());
        size(self.path.clone()) + size(self.path.with_extension("db-wal"))
    }

    /// Checkpoints the WAL into the database and empties it (at a clean stop).
    pub fn close(self) -> Result<(), StoreError> {
        let Store {
            conn,
            _checkpoints: checkpoints,
            ..
        } = self;
        drop(checkpoints);
        conn.execute_batch("PRAGMA wal_checkpoint(TRUNCATE);")
            .map_err(sql("checkpointing"))?;
        conn.close().map_err(|(_, e)| StoreError::Sql {
            what: "closing the store".into(),
            source: e,
        })
    }
}

/// Writes a flight as it now stands: a new row (`new`) or the new state of a stored one.
fn write_flight(
    conn: &Connection,
    label: &str,
    airspace: &Airspace,
    entry: &FlightEntry,
    new: bool,
) -> Result<(), StoreError> {
    let r = FlightRow::of(airspace, entry);
    let sql_text = if new {
        "INSERT INTO flights (seq, id, operator, origin, destination, departure_ms, \
         answered_ms, plan, reason, free_flow_ms, expanded, status, takeoff_ms, landing_ms, \
         holds_until_ms, cancelled_ms, changes, crc) \
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18)"
    } else {
        "UPDATE flights SET id = ?2, operator = ?3, origin = ?4, destination = ?5, \
         departure_ms = ?6, answered_ms = ?7, plan = ?8, reason = ?9, free_flow_ms = ?10, \
         expanded = ?11, status = ?12, takeoff_ms = ?13, landing_ms = ?14, \
         holds_until_ms = ?15, cancelled_ms = ?16, changes = ?17, crc = ?18 WHERE seq = ?1"
    };
    let changed = conn
        .prepare_cached(sql_text)
        .and_then(|mut s| {
            s.execute(params![
                r.seq,
                r.id,
                r.operator,
                r.origin,
                r.destination,
                r.departure_ms,
                r.answered_ms,
                r.plan,
                r.reason,
                r.free_flow_ms,
                r.expanded,
                r.status,
                r.takeoff_ms,
                r.landing_ms,
                r.holds_until_ms,
                r.cancelled_ms,
                r.changes,
                r.crc
            ])
        })
        .map_err(sql("writing a flight"))?;
    if changed != 1 {
        return Err(StoreError::Damaged {
            path: label.to_owned(),
            what: format!("flights row seq {} is missing", r.seq),
        });
    }
    Ok(())
}

/// Writes an event row.
fn write_event(conn: &Connection, event: &Event) -> Result<(), StoreError> {
    let r = EventRow::of(event);
    conn.prepare_cached(
        "INSERT INTO events (id, at_ms, kind, flight_seq, zone, changes, crc) \
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
    )
    .and_then(|mut s| {
        s.execute(params![
            r.id,
            r.at_ms,
            r.kind,
            r.flight_seq,
            r.zone,
            r.changes,
            r.crc
        ])
    })
    .map_err(sql("writing an event"))?;
    Ok(())
}

/// Writes a zone row: a new zone (numbered after the last), or a stored one's new state.
fn write_zone(conn: &Connection, zone: &StoredZone) -> Result<(), StoreError> {
    let seq: Option<i64> = conn
        .prepare_cached("SELECT seq FROM zones WHERE id = ?1")
        .and_then(|mut s| s.query_row([&zone.id], |r| r.get(0)).optional())
        .map_err(sql("reading a zone"))?;
    let seq = match seq {
        Some(s) => s,
        None => queries::max_key(conn, "zones", "seq")? as i64 + 1,
    };
    let r = ZoneRow::new(seq, zone);
    conn.execute(
        "INSERT OR REPLACE INTO zones (seq, id, feature, announced_ms, withdrawn_ms, \
         affected, crc) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
        params![
            r.seq,
            r.id,
            r.feature,
            r.announced_ms,
            r.withdrawn_ms,
            r.affected,
            r.crc
        ],
    )
    .map_err(sql("writing a zone"))?;
    Ok(())
}
