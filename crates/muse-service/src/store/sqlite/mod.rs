//! The embedded store: an SQLite database, `muse.db` under `--data` (bundled SQLite, WAL,
//! `synchronous=FULL`), that operators can inspect, back up and query with their own tools.
//!
//! # Writing
//!
//! [`SqliteStore::commit`] returns once the transaction is durable (SQLite syncs the WAL on
//! every commit with `synchronous=FULL`) and counted in `ACKED` (see `acked`). A background
//! thread checkpoints the WAL into the database file, so commits never wait for it.
//!
//! # Reading and damage
//!
//! At start the service checks that the database holds every transaction acknowledged (see
//! `acked`) and every page its header counts (a file cut short is refused, see `file`), and
//! checks the last flights and events written whole, with the indexes that lead to them (see
//! `recent`). SQLite's own "malformed" is named as damage too.
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
mod archive;
mod checkpoint;
mod file;
mod legacy;
mod open;
mod queries;
mod reader;
mod recent;
mod schema;
mod writes;

use std::fs::File;
use std::path::PathBuf;

use muse_model::{Airspace, Instant};
use rusqlite::Connection;

pub use legacy::{ImportReport, LOG_FILE};
pub use open::Opening;
pub(crate) use open::{connect, sync_dir, write_schema};
pub use reader::Reader;
use writes::{write_event, write_flight, write_zone};

use super::{
    Archiver, Checked, RECENT, Reads, Recent, Store, StoreError, StoredZone, WorldMeta, meta, rows,
};
use crate::events::Event;
use crate::flights::FlightEntry;

/// The database's file name inside the data folder.
pub const DB_FILE: &str = "muse.db";
/// How often the writer lets the WAL start again (see [`SqliteStore::tidy`]): as often as the
/// checkpointer passes, so that the writer's own copy is of the frames since its last pass.
pub const WAL_RESTART: std::time::Duration = std::time::Duration::from_millis(500);

/// The lock file's name inside the data folder.
pub const LOCK_FILE: &str = "LOCK";

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

/// The open SQLite store, written by the planner task only (see the module docs).
#[derive(Debug)]
pub struct SqliteStore {
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

impl SqliteStore {
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
}

impl Store for SqliteStore {
    fn label(&self) -> String {
        self.path.display().to_string()
    }

    fn put_flight(
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

    fn put_event(&mut self, event: &Event) -> Result<(), StoreError> {
        self.begin()?;
        write_event(&self.conn, event)?;
        self.written += 1;
        Ok(())
    }

    fn put_zone(&mut self, zone: &StoredZone) -> Result<(), StoreError> {
        self.begin()?;
        write_zone(&self.conn, zone)?;
        self.written += 1;
        Ok(())
    }

    /// Commits the transaction (SQLite syncs the WAL with `synchronous=FULL`) and records it
    /// in `ACKED` before returning.
    fn commit(&mut self) -> Result<usize, StoreError> {
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

    /// Lets the WAL start again from its beginning, at most every [`WAL_RESTART`]. The
    /// checkpoint thread copies committed pages into the database all the time, but under
    /// steady writes it never catches up with the last commit, and SQLite restarts the WAL
    /// only when a write begins with every frame copied: so now and then the writer finishes
    /// the copy itself (the frames since the thread's last pass, and one sync of the database
    /// file), and the next write starts the WAL afresh. Without this the WAL grows for as long
    /// as writes keep coming.
    fn tidy(&mut self) {
        if self.in_transaction || self.last_wal_restart.elapsed() < WAL_RESTART {
            return;
        }
        // A failed checkpoint loses nothing (the WAL keeps the pages); the next one tries.
        let _ = self.conn.execute_batch("PRAGMA wal_checkpoint(PASSIVE);");
        self.last_wal_restart = std::time::Instant::now();
    }

    fn zones(&mut self) -> Result<Vec<StoredZone>, StoreError> {
        queries::zones(&self.conn, &self.label()).map_err(|e| e.in_store(&self.label()))
    }

    fn count_holding(&mut self, now: Instant) -> Result<u64, StoreError> {
        queries::count_holding(&self.conn, now).map_err(|e| e.in_store(&self.label()))
    }

    fn holding(
        &mut self,
        airspace: &Airspace,
        now: Instant,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Vec<FlightEntry>, StoreError> {
        queries::holding(&self.conn, airspace, &self.label(), now, progress)
            .map_err(|e| e.in_store(&self.label()))
    }

    /// SQLite's check of the database's structure first, then every row.
    fn check_all(
        &mut self,
        airspace: &Airspace,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Checked, StoreError> {
        queries::check_all(&self.conn, airspace, &self.label(), progress)
    }

    fn check_recent(
        &mut self,
        airspace: &Airspace,
        now: Instant,
        held: &std::collections::HashSet<u64>,
    ) -> Result<Recent, StoreError> {
        recent::check(&self.conn, airspace, &self.label(), now, held, self.recent)
            .map_err(|e| e.in_store(&self.label()))
    }

    /// The archived keys count: a number once given is never given again.
    fn last_keys(&mut self) -> Result<(u64, u64), StoreError> {
        let keys = || {
            Ok((
                queries::max_key(&self.conn, "flights", "seq")?
                    .max(queries::max_key(&self.conn, "archived", "seq")?),
                queries::max_key(&self.conn, "events", "id")?.max(queries::max_key(
                    &self.conn,
                    "archived_events",
                    "id",
                )?),
            ))
        };
        keys().map_err(|e: StoreError| e.in_store(&self.label()))
    }

    fn bytes(&mut self) -> u64 {
        let size = |p: PathBuf| std::fs::metadata(p).map_or(0, |m| m.len());
        size(self.path.clone()) + size(self.path.with_extension("db-wal"))
    }

    fn archiver(&mut self) -> Result<Box<dyn Archiver>, StoreError> {
        Ok(Box::new(archive::SqliteArchiver::open(&self.path)?))
    }

    /// Checkpoints the WAL into the database and empties it.
    fn close(self: Box<Self>) -> Result<(), StoreError> {
        let SqliteStore {
            conn,
            _checkpoints: checkpoints,
            ..
        } = *self;
        drop(checkpoints);
        conn.execute_batch("PRAGMA wal_checkpoint(TRUNCATE);")
            .map_err(sql("checkpointing"))?;
        conn.close().map_err(|(_, e)| StoreError::Sql {
            what: "closing the store".into(),
            error: e,
        })
    }
}
