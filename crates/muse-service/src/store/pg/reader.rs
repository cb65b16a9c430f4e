//! Reads for the HTTP handlers: a small pool of connections to the database, beside the
//! planner task's. A reader sees what is committed, which is everything acknowledged.

use muse_model::Airspace;
use postgres::Client;

use super::super::pool::Pool;
use super::connect::connect;
use super::queries;
use crate::events::Event;
use crate::flights::{FlightEntry, ListQuery};
use crate::store::{Reads, StoreError};

/// The handlers' reads (see the module docs).
pub struct Reader {
    url: String,
    label: String,
    /// The archive folder (see `store::archive`).
    archive: Option<std::path::PathBuf>,
    idle: Pool<Client>,
}

impl std::fmt::Debug for Reader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reader")
            .field("label", &self.label)
            .finish_non_exhaustive()
    }
}

impl Reader {
    /// Reads the database at `url`; connects on first use.
    pub(super) fn new(url: String, label: String, archive: Option<std::path::PathBuf>) -> Self {
        Reader {
            url,
            label,
            archive,
            idle: Pool::default(),
        }
    }

    fn with<T>(
        &self,
        f: impl FnOnce(&mut Client, &str) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        self.idle.with(
            || connect(&self.url, &self.label),
            |c| !c.is_closed(),
            |client| f(client, &self.label),
        )
    }
}

impl Drop for Reader {
    /// The connections are closed on a thread of their own: each holds a small runtime of its
    /// own, which may not be dropped on an async worker.
    fn drop(&mut self) {
        let idle = self.idle.take_all();
        if !idle.is_empty() {
            let _ = std::thread::Builder::new()
                .name("muse-pg-close".into())
                .spawn(move || drop(idle));
        }
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
