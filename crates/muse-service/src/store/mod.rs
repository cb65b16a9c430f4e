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
//! every commit with `synchronous=FULL`) and counted in `ACKED` (see `acked`); only then are
//! the group's answers sent. A crash
//! leaves every committed transaction and discards the one it tore: nothing acknowledged is
//! lost, nothing unacknowledged survives half-written. A background thread checkpoints the
//! WAL into the database file, so commits never wait for it.
//!
//! # Reading and damage
//!
//! Every row carries the CRC-32 of its content (see `rows`), checked whenever it is read:
//! a flipped byte is found and named ([`StoreError::Damaged`]), never reinterpreted. At start
//! the service checks that the database holds every transaction acknowledged (see `acked`)
//! and every page its header counts (a file cut short is refused), reads the `meta` rows, every
//! zone and every flight still holding a reservation, and checks the last flights and events
//! written whole, with the indexes that lead to them (see `recent`); reads of older flights go
//! to the database by index, and are checked then. Damage makes the start fail, or the read
//! that meets it fail, naming it; SQLite's own "malformed" is named as damage too.
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

mod acked;
mod checkpoint;
mod file;
mod legacy;
mod open;
mod queries;
mod reader;
mod recent;
mod rows;
mod schema;
mod writes;

use std::fs::File;
use std::path::{Path, PathBuf};

use muse_model::{Airspace, Instant};
use rusqlite::Connection;

pub use legacy::{ImportReport, LOG_FILE};
pub use open::Opening;
pub(crate) use open::{connect, sync_dir, write_schema};
pub use queries::Checked;
pub use reader::Reader;
pub use recent::{RECENT, Recent};
use writes::{write_event, write_flight, write_zone};

use crate::events::Event;
use crate::flights::FlightEntry;

/// The database's file name inside the data folder.
pub const DB_FILE: &str = "muse.db";
/// How often the writer lets the WAL start again (see [`Store::tidy`]): as often as the
/// checkpointer passes, so that the writer's own copy is of the frames since its last pass.
pub const WAL_RESTART: std::time::Duration = std::time::Duration::from_millis(500);

/// The lock file's name inside the data folder.
pub const LOCK_FILE: &str = "LOCK";

/// Errors of the store.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// An I/O error, with what was being done. (The error is part of the message, not a
    /// `source`: a chain would print it twice.)
    #[error("{what}: {error}")]
    Io {
        /// What was being done (names the file).
        what: String,
        /// The error.
        error: std::io::Error,
    },
    /// An error of the database (part of the message, as for [`StoreError::Io`]).
    #[error("{what}: {error}")]
    Sql {
        /// What was being done.
        what: String,
        /// The error.
        error: rusqlite::Error,
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

impl StoreError {
    /// This error, as damage of the store at `path` when SQLite found the file malformed (a
    /// page whose structure a flipped byte broke), so that it is named as damage.
    pub(crate) fn in_store(self, path: &str) -> StoreError {
        match self {
            StoreError::Sql { what, error }
                if matches!(
                    error.sqlite_error_code(),
                    Some(rusqlite::ErrorCode::DatabaseCorrupt | rusqlite::ErrorCode::NotADatabase)
                ) =>
            {
                StoreError::Damaged {
                    path: path.to_owned(),
                    what: format!("{what}: SQLite finds it malformed ({error})"),
                }
            }
            other => other,
        }
    }
}

/// An error of the database while doing `what`.
pub(crate) fn sql(what: &str) -> impl FnOnce(rusqlite::Error) -> StoreError + '_ {
    move |error| StoreError::Sql {
        what: what.to_owned(),
        error,
    }
}

fn io(what: impl Into<String>) -> impl FnOnce(std::io::Error) -> StoreError {
    let what = what.into();
    move |error| StoreError::Io { what, error }
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

/// The open store, written by the planner task only (see the module docs).
#[derive(Debug)]
pub struct Store {
    path: PathBuf,
    conn: Connection,
    /// Held for the life of the store.
    _lock: File,
    in_transaction: bool,
    /// Write transactions committed (see `acked`).
    count: acked::Count,
    /// The record of the transactions acknowledged.
    acked: acked::Acked,
    /// How many of the last flights and events the start checks whole.
    recent: u64,
    /// Rows written in the open transaction.
    written: usize,
    /// When the writer last finished a checkpoint itself (see [`Store::tidy`]).
    last_wal_restart: std::time::Instant,
    _checkpoints: checkpoint::Checkpointer,
}

impl Store {
    /// The database's path.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    fn label(&self) -> String {
        self.path.display().to_string()
    }

    fn begin(&mut self) -> Result<(), StoreError> {
        if !self.in_transaction {
            self.conn
                .prepare_cached("BEGIN IMMEDIATE")
                .and_then(|mut s| s.execute([]))
                .map_err(sql("starting a transaction"))?;
            self.in_transaction = true;
        }
        Ok(())
    }

    /// Writes a flight as it now stands: a new one (`new`) or a change of a stored one.
    pub(crate) fn put_flight(
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
    pub(crate) fn put_event(&mut self, event: &Event) -> Result<(), StoreError> {
        self.begin()?;
        write_event(&self.conn, event)?;
        self.written += 1;
        Ok(())
    }

    /// Writes an announced zone: a new one, or the withdrawal of a stored one.
    pub(crate) fn put_zone(&mut self, zone: &StoredZone) -> Result<(), StoreError> {
        self.begin()?;
        write_zone(&self.conn, zone)?;
        self.written += 1;
        Ok(())
    }

    /// Writes the withdrawal of the stored zone `id` at `at`.
    pub(crate) fn put_zone_withdrawn(&mut self, id: &str, at: Instant) -> Result<(), StoreError> {
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
    pub(crate) fn commit(&mut self) -> Result<usize, StoreError> {
        if !self.in_transaction {
            return Ok(0);
        }
        let next = acked::Count {
            n: self.count.n + 1,
            ..self.count
        };
        acked::write_row(&self.conn, next)?;
        self.conn
            .prepare_cached("COMMIT")
            .and_then(|mut s| s.execute([]))
            .map_err(sql("committing"))?;
        self.in_transaction = false;
        self.count = next;
        self.acked.record(next)?;
        Ok(std::mem::take(&mut self.written))
    }

    /// Lets the WAL start again from its beginning, at most every [`WAL_RESTART`]: call it
    /// between groups, once their answers are sent. The checkpoint thread copies committed
    /// pages into the database all the time, but under steady writes it never catches up
    /// with the last commit, and SQLite restarts the WAL only when a write begins with every
    /// frame copied: so now and then the writer finishes the copy itself (the frames since
    /// the thread's last pass, and one sync of the database file), and the next write starts
    /// the WAL afresh. Without this the WAL grows for as long as writes keep coming.
    pub(crate) fn tidy(&mut self) {
        if self.in_transaction || self.last_wal_restart.elapsed() < WAL_RESTART {
            return;
        }
        // A failed checkpoint loses nothing (the WAL keeps the pages); the next one tries.
        let _ = self.conn.execute_batch("PRAGMA wal_checkpoint(PASSIVE);");
        self.last_wal_restart = std::time::Instant::now();
    }

    /// Every announced zone, in announcement order.
    pub(crate) fn zones(&self) -> Result<Vec<StoredZone>, StoreError> {
        queries::zones(&self.conn, &self.label()).map_err(|e| e.in_store(&self.label()))
    }

    /// How many flights hold a reservation that ends at or after `now`.
    pub(crate) fn count_holding(&self, now: Instant) -> Result<u64, StoreError> {
        queries::count_holding(&self.conn, now).map_err(|e| e.in_store(&self.label()))
    }

    /// The flights holding a reservation that ends at or after `now` (checked), in answer
    /// order; `progress` is told how many were read so far.
    pub(crate) fn holding(
        &self,
        airspace: &Airspace,
        now: Instant,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Vec<FlightEntry>, StoreError> {
        queries::holding(&self.conn, airspace, &self.label(), now, progress)
            .map_err(|e| e.in_store(&self.label()))
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

    /// Checks the last flights and events written (as many as the opening said; see `recent`);
    /// `held` are the flights read as still holding at `now`.
    pub(crate) fn check_recent(
        &self,
        airspace: &Airspace,
        now: Instant,
        held: &std::collections::HashSet<u64>,
    ) -> Result<Recent, StoreError> {
        recent::check(&self.conn, airspace, &self.label(), now, held, self.recent)
            .map_err(|e| e.in_store(&self.label()))
    }

    /// The last sequence number and the last event id stored (0: none).
    pub(crate) fn last_keys(&self) -> Result<(u64, u64), StoreError> {
        let keys = || {
            Ok((
                queries::max_key(&self.conn, "flights", "seq")?,
                queries::max_key(&self.conn, "events", "id")?,
            ))
        };
        keys().map_err(|e: StoreError| e.in_store(&self.label()))
    }

    /// Bytes on disk: the database and its WAL.
    pub(crate) fn bytes(&self) -> u64 {
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
            error: e,
        })
    }
}
