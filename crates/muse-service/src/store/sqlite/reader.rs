//! Reads for the HTTP handlers: a small pool of read-only connections to the store, used
//! beside the planner task's (WAL lets readers and the writer work at once). A reader sees
//! what is committed, which is everything acknowledged: answers go out after their commit.

use std::path::PathBuf;

use muse_model::Airspace;
use rusqlite::Connection;

use super::super::pool::Pool;
use super::{Reads, StoreError, connect, queries};
use crate::events::Event;
use crate::flights::{FlightEntry, ListQuery};

/// The handlers' reads (see the module docs).
#[derive(Debug)]
pub struct Reader {
    path: PathBuf,
    label: String,
    /// The archive folder (see `store::archive`).
    archive: Option<PathBuf>,
    idle: Pool<Connection>,
}

impl Reader {
    /// Reads the store at `path` (the database file), and archived flights from `archive`;
    /// connects on first use.
    pub fn new(path: PathBuf, archive: Option<PathBuf>) -> Self {
        Reader {
            label: path.display().to_string(),
            path,
            archive,
            idle: Pool::default(),
        }
    }

    fn with<T>(
        &self,
        f: impl FnOnce(&Connection, &str) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        self.idle.with(
            || connect(&self.path, false),
            |_| true,
            |conn| f(conn, &self.label).map_err(|e| e.in_store(&self.label)),
        )
    }
}

impl Reads for Reader {
    fn hot_flight(&self, airspace: &Airspace, id: &str) -> Result<Option<FlightEntry>, StoreError> {
        self.with(|c, label| queries::flight_by_id(c, airspace, label, id))
    }

    fn archived_id(&self, id: &str) -> Result<Option<(i64, String)>, StoreError> {
        self.with(|c, label| super::archive::archived_id(c, label, id))
    }

    fn archive_dir(&self) -> Option<&std::path::Path> {
        self.archive.as_deref()
    }

    fn list(
        &self,
        airspace: &Airspace,
        query: &ListQuery,
    ) -> Result<(Vec<FlightEntry>, bool), StoreError> {
        self.with(|c, label| queries::list(c, airspace, label, query))
    }

    /// Up to `limit` events with an id above `after` (of `operator`'s flights only, when
    /// given), each with its flight as it stood then.
    fn events_after(
        &self,
        airspace: &Airspace,
        after: u64,
        operator: Option<&str>,
        limit: usize,
    ) -> Result<Vec<Event>, StoreError> {
        self.with(|c, label| queries::events_after(c, airspace, label, after, operator, limit))
    }

    fn archived_events_through(&self) -> Result<u64, StoreError> {
        self.with(|c, _| queries::max_key(c, "archived_events", "id"))
    }
}
