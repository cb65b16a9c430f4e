//! The SQLite store's side of archiving (see `store::archive`): a write connection of its
//! own, whose transactions are short (one chunk of flights each) so that the planner task's
//! commits wait at most one of them.

use std::path::{Path, PathBuf};

use muse_model::Instant;
use rusqlite::{Connection, OptionalExtension as _, params};

use super::super::archive::{archived_sum, checked_archived};
use super::super::rows::{EVENT_COLUMNS, EventRow, FLIGHT_COLUMNS, FlightRow};
use super::{Archiver, StoreError, connect, sql};

/// The tables that keep what was archived, made in a store that lacks them.
pub(super) const CREATE: &str = "
CREATE TABLE IF NOT EXISTS archived (
    seq INTEGER PRIMARY KEY,             -- the flight's sequence number
    id  TEXT NOT NULL UNIQUE,            -- its client id: still names it
    day TEXT NOT NULL,                   -- the day of its archive file
    crc INTEGER NOT NULL
);
CREATE TABLE IF NOT EXISTS archived_events (
    id  INTEGER PRIMARY KEY,             -- the event's id
    day TEXT NOT NULL                    -- the day of its archive file
);
";

/// The archiving connection of the store at `path`.
pub(super) struct SqliteArchiver {
    path: PathBuf,
    conn: Connection,
}

impl SqliteArchiver {
    pub(super) fn open(path: &Path) -> Result<Self, StoreError> {
        Ok(SqliteArchiver {
            path: path.to_path_buf(),
            conn: connect(path, true)?,
        })
    }
}

impl Archiver for SqliteArchiver {
    fn label(&self) -> String {
        self.path.display().to_string()
    }

    fn oldest_landing(&mut self, before: Instant) -> Result<Option<Instant>, StoreError> {
        self.conn
            .query_row(
                "SELECT min(landing_ms) FROM flights WHERE landing_ms < ?1",
                [before.0],
                |r| r.get::<_, Option<i64>>(0),
            )
            .map(|t| t.map(Instant))
            .map_err(sql("finding the flights due for the archive"))
    }

    fn day_rows(
        &mut self,
        from: Instant,
        to: Instant,
    ) -> Result<(Vec<FlightRow>, Vec<EventRow>), StoreError> {
        let what = "reading the flights due for the archive";
        let mut stmt = self
            .conn
            .prepare(&format!(
                "SELECT {FLIGHT_COLUMNS} FROM flights WHERE landing_ms >= ?1 AND landing_ms < ?2 \
                 ORDER BY seq"
            ))
            .map_err(sql(what))?;
        let flights = stmt
            .query_map([from.0, to.0], |r| FlightRow::read(r, 0))
            .map_err(sql(what))?
            .collect::<Result<Vec<_>, _>>()
            .map_err(sql(what))?;
        let mut stmt = self
            .conn
            .prepare(&format!(
                "SELECT {EVENT_COLUMNS} FROM events WHERE flight_seq IN \
                 (SELECT seq FROM flights WHERE landing_ms >= ?1 AND landing_ms < ?2) ORDER BY id"
            ))
            .map_err(sql(what))?;
        let events = stmt
            .query_map([from.0, to.0], |r| EventRow::read(r, 0))
            .map_err(sql(what))?
            .collect::<Result<Vec<_>, _>>()
            .map_err(sql(what))?;
        Ok((flights, events))
    }

    fn move_rows(
        &mut self,
        day: &str,
        flights: &[FlightRow],
        events: &[i64],
    ) -> Result<(), StoreError> {
        let what = "moving flights to the archive";
        let tx = self
            .conn
            .transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)
            .map_err(sql(what))?;
        {
            let mut archived = tx
                .prepare_cached("INSERT INTO archived (seq, id, day, crc) VALUES (?1, ?2, ?3, ?4)")
                .map_err(sql(what))?;
            let mut flight = tx
                .prepare_cached("DELETE FROM flights WHERE seq = ?1")
                .map_err(sql(what))?;
            let mut event = tx
                .prepare_cached("DELETE FROM events WHERE id = ?1")
                .map_err(sql(what))?;
            let mut archived_event = tx
                .prepare_cached("INSERT INTO archived_events (id, day) VALUES (?1, ?2)")
                .map_err(sql(what))?;
            for e in events {
                event.execute([e]).map_err(sql(what))?;
                archived_event.execute(params![e, day]).map_err(sql(what))?;
            }
            for f in flights {
                archived
                    .execute(params![f.seq, f.id, day, archived_sum(f.seq, &f.id, day)])
                    .map_err(sql(what))?;
                flight.execute([f.seq]).map_err(sql(what))?;
            }
        }
        tx.commit().map_err(sql(what))
    }
}

/// The archived flight with client id `id`: its `seq` and day, its row's checksum checked.
pub(super) fn archived_id(
    conn: &Connection,
    path: &str,
    id: &str,
) -> Result<Option<(i64, String)>, StoreError> {
    let row: Option<(i64, String, String, i64)> = conn
        .prepare_cached("SELECT seq, id, day, crc FROM archived WHERE id = ?1")
        .and_then(|mut s| {
            s.query_row([id], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?)))
                .optional()
        })
        .map_err(sql("reading the archived ids"))?;
    row.map(|r| checked_archived(path, id, r)).transpose()
}

/// How many of the keys in `[from, to)` of `table` (`archived` by `seq`, `archived_events` by
/// `id`) were archived.
pub(super) fn archived_between(
    conn: &Connection,
    table: &str,
    key: &str,
    from: u64,
    to: u64,
) -> Result<u64, StoreError> {
    conn.query_row(
        &format!("SELECT count(*) FROM {table} WHERE {key} >= ?1 AND {key} < ?2"),
        [from as i64, to as i64],
        |r| r.get::<_, i64>(0),
    )
    .map(|n| n as u64)
    .map_err(sql("reading the archived keys"))
}
