//! The durable store: one interface ([`Store`] for the planner task's writes and the start's
//! reads, [`Reads`] for the handlers'), two implementations:
//!
//! - `sqlite`, the default: `muse.db` under `--data` (bundled SQLite, WAL, `synchronous=FULL`),
//!   one process per folder, no server to run;
//! - `pg`, for operators who outgrow one machine: the same tables in a PostgreSQL database
//!   (`--store postgres://…`), its durability and replication PostgreSQL's own.
//!
//! # What it holds
//!
//! `meta` (the airspace and parameters the store was written for, in words), `flights` (every
//! request ever answered, its id the key for the life of the store, with its current state and
//! plan), `zones` (zones announced during the day), `events` (every change of every flight,
//! the stream of `GET /v1/events`), and two views, `cancellations` and `zone_outcomes`. The
//! columns are the same in both stores (see each one's `schema`).
//!
//! # The promises, in both
//!
//! - **Acknowledged means committed.** Only the planner task writes: the rows of a group of
//!   decisions go into one transaction, and [`Store::commit`] returns once it is durable; only
//!   then are the group's answers sent. A crash keeps every committed transaction and discards
//!   the one it tore.
//! - **Ids forever.** A flight's row stays for the life of the store; a retried id is answered
//!   from it.
//! - **Damage is never silent.** Every row carries the CRC-32 of its content (see `rows`),
//!   checked whenever it is read: a flipped byte is found and named ([`StoreError::Damaged`]),
//!   never reinterpreted.
//! - **A bounded start.** The start reads the `meta` rows, every zone and every flight still
//!   holding a reservation, and checks the last flights and events written whole; older
//!   flights are read by index when asked for, and checked then.

pub mod archive;
mod keys;
mod meta;
mod pg;
mod pool;
mod rows;
mod sqlite;

use std::path::PathBuf;

use muse_model::{Airspace, Instant};

pub use sqlite::{DB_FILE, ImportReport, LOG_FILE};

use crate::events::Event;
use crate::flights::{FlightEntry, ListQuery};

/// How many of the last flights, and of the last events, the start checks whole by default.
pub const RECENT: u64 = 16_384;

/// Where the service keeps its store.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StoreAt {
    /// The embedded SQLite store in a data folder (made if missing; one service per folder).
    Folder(PathBuf),
    /// A PostgreSQL database, by its connection URL (`postgres://user@host:port/database`):
    /// its tables are made at the first start, and several services may share it.
    Postgres(String),
}

impl StoreAt {
    /// The store in words for messages: the folder's database file, or the URL without its
    /// password.
    pub fn label(&self) -> String {
        match self {
            StoreAt::Folder(dir) => dir.join(DB_FILE).display().to_string(),
            StoreAt::Postgres(url) => pg::without_password(url),
        }
    }
}

impl From<PathBuf> for StoreAt {
    fn from(dir: PathBuf) -> Self {
        StoreAt::Folder(dir)
    }
}

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
    /// An error of the SQLite database (part of the message, as for [`StoreError::Io`]).
    #[error("{what}: {error}")]
    Sql {
        /// What was being done.
        what: String,
        /// The error.
        error: rusqlite::Error,
    },
    /// An error of the PostgreSQL database or of the connection to it (part of the message,
    /// with the server's detail when it gave one).
    #[error("{what}: {}", pg::describe(.error))]
    Postgres {
        /// What was being done (names the database).
        what: String,
        /// The error.
        error: postgres::Error,
    },
    /// Another process holds the folder.
    #[error(
        "{0} is in use by another process (the lock on its LOCK file is held); stop that \
         `muse serve` or choose another --data folder"
    )]
    Locked(PathBuf),
    /// Another service took the lead: this one may write no more.
    #[error(
        "{path}: another service took the lead (term {now}, this service's was {mine}); this \
         one stops writing"
    )]
    Deposed {
        /// The database's URL.
        path: String,
        /// This service's term.
        mine: i64,
        /// The term in the store.
        now: i64,
    },
    /// Stored data failed an integrity check.
    #[error(
        "{path} is damaged: {what}; refusing to use it (restore the store from a backup, or \
         move it away to start empty)"
    )]
    Damaged {
        /// The database (or log) file, or the database's URL.
        path: String,
        /// What is damaged.
        what: String,
    },
    /// The file or database is not a MUSE store, or one of a newer format.
    #[error("{path} is not a MUSE store this version can read: {why}")]
    NotAStore {
        /// The file or the database's URL.
        path: String,
        /// Why.
        why: String,
    },
    /// The database server is set up so that it could lose what it acknowledges.
    #[error("{path} cannot keep the store's promises: {why}")]
    Unsafe {
        /// The database's URL.
        path: String,
        /// Which setting, and what to do.
        why: String,
    },
    /// The store was written for another airspace or other parameters.
    #[error(
        "{path} was written by a service planning with {stored}; this service plans with \
         {wanted}: its flights cannot be restored here (start with the same airspace, zones \
         and parameters, or use another store)"
    )]
    Mismatch {
        /// The store.
        path: String,
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

/// What a full check of the store read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Checked {
    /// Flight rows read and checked.
    pub flights: u64,
    /// Event rows read and checked.
    pub events: u64,
    /// Zone rows read and checked.
    pub zones: u64,
}

/// What the start checked whole of the last flights and events written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Recent {
    /// Flights checked.
    pub flights: u64,
    /// Events checked.
    pub events: u64,
}

/// The open store, written by the planner task only (see the module docs). Both stores
/// implement it; the engine knows no other.
pub(crate) trait Store: Send {
    /// The store in words, for messages (a file, or a URL without its password).
    fn label(&self) -> String;

    /// Writes a flight as it now stands: a new one (`new`) or a change of a stored one.
    fn put_flight(
        &mut self,
        airspace: &Airspace,
        entry: &FlightEntry,
        new: bool,
    ) -> Result<(), StoreError>;

    /// Writes an event.
    fn put_event(&mut self, event: &Event) -> Result<(), StoreError>;

    /// Writes an announced zone: a new one, or a stored one's new state.
    fn put_zone(&mut self, zone: &StoredZone) -> Result<(), StoreError>;

    /// Writes the withdrawal of the stored zone `id` at `at`.
    fn put_zone_withdrawn(&mut self, id: &str, at: Instant) -> Result<(), StoreError> {
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

    /// Makes everything written since the last commit durable (one transaction). Only after
    /// this returns may the answers it holds be sent. Returns the rows committed.
    fn commit(&mut self) -> Result<usize, StoreError>;

    /// Housekeeping between groups, once their answers are sent (SQLite: lets its WAL start
    /// again now and then). Nothing by default.
    fn tidy(&mut self) {}

    /// Every announced zone, in announcement order.
    fn zones(&mut self) -> Result<Vec<StoredZone>, StoreError>;

    /// How many flights hold a reservation that ends at or after `now`.
    fn count_holding(&mut self, now: Instant) -> Result<u64, StoreError>;

    /// The flights holding a reservation that ends at or after `now` (checked), in answer
    /// order; `progress` is told how many were read so far.
    fn holding(
        &mut self,
        airspace: &Airspace,
        now: Instant,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Vec<FlightEntry>, StoreError>;

    /// Checks the last flights and events written, whole (as many as the opening said);
    /// `held` are the flights read as still holding at `now`.
    fn check_recent(
        &mut self,
        airspace: &Airspace,
        now: Instant,
        held: &std::collections::HashSet<u64>,
    ) -> Result<Recent, StoreError>;

    /// Reads every row and checks it: the whole store, in time that grows with it (`muse
    /// serve --check-store`); `progress` is told the flights checked.
    fn check_all(
        &mut self,
        airspace: &Airspace,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Checked, StoreError>;

    /// The last sequence number and the last event id stored (0: none).
    fn last_keys(&mut self) -> Result<(u64, u64), StoreError>;

    /// Bytes the store takes (SQLite: the database and its WAL; PostgreSQL: its tables with
    /// their indexes).
    fn bytes(&mut self) -> u64;

    /// From here to [`Store::end_snapshot`], reads see one state of the store, whatever
    /// another service commits meanwhile (a standby loads while the leader writes). A store
    /// in a data folder has one writer, this service: nothing to do.
    fn begin_snapshot(&mut self) -> Result<(), StoreError> {
        Ok(())
    }

    /// Ends [`Store::begin_snapshot`].
    fn end_snapshot(&mut self) -> Result<(), StoreError> {
        Ok(())
    }

    /// Takes the lead if no other service holds it, advertising `address` (the URL other
    /// services forward writes to) and recording `now` as its start: from then on this service
    /// alone writes, and a write of a service the lead was taken from fails. `Ok(false)`:
    /// another service leads. A store in a data folder is led by the one process that holds
    /// its folder.
    fn try_lead(&mut self, address: &str, now: Instant) -> Result<bool, StoreError> {
        let _ = (address, now);
        Ok(true)
    }

    /// The service that leads, as it advertised itself, if one does.
    fn leader(&mut self) -> Result<Option<Leader>, StoreError> {
        Ok(None)
    }

    /// Waits up to `timeout` for a commit of the service that leads, returning early when one
    /// is announced (a standby following the leader).
    fn wait_for_commits(&mut self, timeout: std::time::Duration) -> Result<(), StoreError> {
        std::thread::sleep(timeout);
        Ok(())
    }

    /// A connection of its own for archiving (see [`archive`]), beside this one: for the
    /// leader only (its transactions are fenced as this store's are).
    fn archiver(&mut self) -> Result<Box<dyn Archiver>, StoreError>;

    /// Closes the store at a clean stop.
    fn close(self: Box<Self>) -> Result<(), StoreError>;
}

/// What [`archive::pass`] needs of a store: the flights due, a day's rows, and moving them
/// out, on a connection of its own.
pub(crate) trait Archiver: Send {
    /// The store in words, for messages.
    fn label(&self) -> String;

    /// The earliest landing before `before` of a flight still in the hot tables.
    fn oldest_landing(&mut self, before: Instant) -> Result<Option<Instant>, StoreError>;

    /// The flights landing in `[from, to)` still in the hot tables, in answer order, and their
    /// events, in order.
    fn day_rows(
        &mut self,
        from: Instant,
        to: Instant,
    ) -> Result<(Vec<rows::FlightRow>, Vec<rows::EventRow>), StoreError>;

    /// In one transaction: records `flights` and `events` as archived in the file of `day`,
    /// and deletes them from the hot tables.
    fn move_rows(
        &mut self,
        day: &str,
        flights: &[rows::FlightRow],
        events: &[i64],
    ) -> Result<(), StoreError>;

    /// After a pass that moved rows: lets the space they took be used again (PostgreSQL:
    /// `VACUUM` of the hot tables; SQLite reuses freed pages by itself).
    fn reclaim(&mut self) -> Result<(), StoreError> {
        Ok(())
    }
}

/// The service that leads a shared store.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Leader {
    /// Its address, as it advertised it (`http://host:port`).
    pub address: String,
    /// Its term: raised by one at every change of leader.
    pub term: i64,
}

/// The handlers' reads, beside the planner task's writes: they see what is committed, which
/// is everything acknowledged (answers go out after their commit). Blocking: call them off the
/// async workers (`spawn_blocking`).
pub(crate) trait Reads: Send + Sync + std::fmt::Debug {
    /// The flight with client id `id`: from the hot tables, else from its archive file (see
    /// [`archive`]).
    fn flight(&self, airspace: &Airspace, id: &str) -> Result<Option<FlightEntry>, StoreError> {
        if let Some(e) = self.hot_flight(airspace, id)? {
            return Ok(Some(e));
        }
        self.archived_id(id)?
            .map(|(seq, day)| archive::entry(self.archive_dir(), airspace, id, seq, &day))
            .transpose()
    }

    /// The flight with client id `id` in the hot tables.
    fn hot_flight(&self, airspace: &Airspace, id: &str) -> Result<Option<FlightEntry>, StoreError>;

    /// The archived flight with client id `id`: its sequence number and the day of its file
    /// (its `archived` row's checksum checked).
    fn archived_id(&self, id: &str) -> Result<Option<(i64, String)>, StoreError>;

    /// The archive folder archived flights are read from, if this service was given one.
    fn archive_dir(&self) -> Option<&std::path::Path>;

    /// The flights a listing asks for, in answer order, and whether more follow the page.
    fn list(
        &self,
        airspace: &Airspace,
        query: &ListQuery,
    ) -> Result<(Vec<FlightEntry>, bool), StoreError>;

    /// Up to `limit` events with an id above `after` (of `operator`'s flights only, when
    /// given), each with its flight as it stood then.
    fn events_after(
        &self,
        airspace: &Airspace,
        after: u64,
        operator: Option<&str>,
        limit: usize,
    ) -> Result<Vec<Event>, StoreError>;

    /// The largest id of an event archived (with its flight; see [`archive`]), 0 if none.
    fn archived_events_through(&self) -> Result<u64, StoreError>;
}

/// A store opened and checked against the world it will serve, not yet loaded.
#[derive(Debug)]
pub enum Opening {
    /// A data folder, locked.
    Folder(sqlite::Opening),
    /// A PostgreSQL database, its tables made if it had none.
    Postgres(Box<pg::Opening>),
}

impl Opening {
    /// Opens the store `at` and checks what it holds against `world`: a store written for the
    /// same world, (in a folder) a log of an earlier version written for it, or nothing yet.
    /// Quick: reads no flight.
    pub fn open(at: &StoreAt, world: &WorldMeta, legacy_world: &str) -> Result<Self, StoreError> {
        Ok(match at {
            StoreAt::Folder(dir) => {
                Opening::Folder(sqlite::Opening::open(dir, world, legacy_world)?)
            }
            StoreAt::Postgres(url) => Opening::Postgres(Box::new(pg::Opening::open(url, world)?)),
        })
    }

    /// Has the start check the last `n` flights and events whole (default [`RECENT`]).
    #[must_use]
    pub fn checking_recent(self, n: u64) -> Self {
        match self {
            Opening::Folder(o) => Opening::Folder(o.checking_recent(n)),
            Opening::Postgres(o) => Opening::Postgres(Box::new(o.checking_recent(n))),
        }
    }

    /// The log of an earlier version that will be converted, if there is one.
    pub fn imports(&self) -> Option<&std::path::Path> {
        match self {
            Opening::Folder(o) => o.imports(),
            Opening::Postgres(_) => None,
        }
    }

    /// The store in words, for messages.
    pub fn label(&self) -> String {
        match self {
            Opening::Folder(o) => o.label(),
            Opening::Postgres(o) => o.label(),
        }
    }

    /// The handlers' reads of this store; archived flights are read from `archive`.
    pub(crate) fn reads(&self, archive: Option<PathBuf>) -> Box<dyn Reads> {
        match self {
            Opening::Folder(o) => Box::new(o.reader(archive)),
            Opening::Postgres(o) => Box::new(o.reader(archive)),
        }
    }

    /// Converts a log of an earlier version if there is one (calling `progress` with the
    /// records read so far), creates the store's tables if there are none, and opens it for
    /// writing.
    pub(crate) fn finish(
        self,
        airspace: &Airspace,
        world: &WorldMeta,
        progress: &mut dyn FnMut(u64),
    ) -> Result<(Box<dyn Store>, Option<ImportReport>), StoreError> {
        match self {
            Opening::Folder(o) => {
                let (store, report) = o.finish(airspace, world, progress)?;
                Ok((Box::new(store), report))
            }
            Opening::Postgres(o) => Ok((Box::new(o.finish()), None)),
        }
    }

    /// Converts a log of an earlier version, makes the store if there is none, and closes it
    /// cleanly, without serving (`muse serve --import-log`):
    /// what was converted, if anything.
    pub fn import_only(
        self,
        airspace: &Airspace,
        world: &WorldMeta,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Option<ImportReport>, StoreError> {
        let (store, report) = self.finish(airspace, world, progress)?;
        store.close()?;
        Ok(report)
    }

    /// Reads and checks every row of the store, then closes it, without serving (`muse serve
    /// --check-store`); `progress` is told the flights checked.
    pub fn check_all(
        self,
        airspace: &Airspace,
        world: &WorldMeta,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Checked, StoreError> {
        let (mut store, _) = self.finish(airspace, world, &mut |_| {})?;
        let checked = store.check_all(airspace, progress)?;
        store.close()?;
        Ok(checked)
    }
}
