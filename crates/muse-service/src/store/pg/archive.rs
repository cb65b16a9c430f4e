//! The PostgreSQL store's side of archiving (see `store::archive`): a connection of its own,
//! whose transactions are fenced as the leader's writes are (a deposed leader archives
//! nothing) and short (one chunk of flights each).

use muse_model::Instant;
use postgres::Client;

use super::super::archive::{archived_sum, checked_archived};
use super::super::rows::{EVENT_COLUMNS, EventRow, FLIGHT_COLUMNS, FlightRow};
use super::pg;
use crate::store::{Archiver, StoreError};

/// The tables that keep what was archived.
pub(super) const CREATE: &str = "
CREATE TABLE IF NOT EXISTS archived (
    seq bigint PRIMARY KEY,              -- the flight's sequence number
    id  text NOT NULL UNIQUE,            -- its client id: still names it
    day text NOT NULL,                   -- the day of its archive file
    crc bigint NOT NULL
);
CREATE TABLE IF NOT EXISTS archived_events (
    id  bigint PRIMARY KEY,              -- the event's id
    day text NOT NULL                    -- the day of its archive file
);
";

/// The archiving connection of a leader in term `term`.
pub(super) struct PgArchiver {
    pub(super) label: String,
    pub(super) client: Client,
    pub(super) term: i64,
}

impl Archiver for PgArchiver {
    fn label(&self) -> String {
        self.label.clone()
    }

    fn oldest_landing(&mut self, before: Instant) -> Result<Option<Instant>, StoreError> {
        let row = self
            .client
            .query_one(
                "SELECT min(landing_ms) FROM flights WHERE landing_ms < $1",
                &[&before.0],
            )
            .map_err(pg("finding the flights due for the archive"))?;
        let t: Option<i64> = row
            .try_get(0)
            .map_err(pg("finding the flights due for the archive"))?;
        Ok(t.map(Instant))
    }

    fn day_rows(
        &mut self,
        from: Instant,
        to: Instant,
    ) -> Result<(Vec<FlightRow>, Vec<EventRow>), StoreError> {
        let what = "reading the flights due for the archive";
        let flights = self
            .client
            .query(
                &format!(
                    "SELECT {FLIGHT_COLUMNS} FROM flights WHERE landing_ms >= $1 \
                     AND landing_ms < $2 ORDER BY seq"
                ),
                &[&from.0, &to.0],
            )
            .map_err(pg(what))?
            .iter()
            .map(|r| FlightRow::read(r, 0))
            .collect::<Result<Vec<_>, _>>()
            .map_err(pg(what))?;
        let events = self
            .client
            .query(
                &format!(
                    "SELECT {EVENT_COLUMNS} FROM events WHERE flight_seq IN \
                     (SELECT seq FROM flights WHERE landing_ms >= $1 AND landing_ms < $2) \
                     ORDER BY id"
                ),
                &[&from.0, &to.0],
            )
            .map_err(pg(what))?
            .iter()
            .map(|r| EventRow::read(r, 0))
            .collect::<Result<Vec<_>, _>>()
            .map_err(pg(what))?;
        Ok((flights, events))
    }

    fn move_rows(
        &mut self,
        day: &str,
        flights: &[FlightRow],
        events: &[i64],
    ) -> Result<(), StoreError> {
        let what = "moving flights to the archive";
        super::lease::begin_fenced(&mut self.client, &self.label, self.term)?;
        let seqs: Vec<i64> = flights.iter().map(|f| f.seq).collect();
        let ids: Vec<&str> = flights.iter().map(|f| f.id.as_str()).collect();
        let sums: Vec<i64> = flights
            .iter()
            .map(|f| archived_sum(f.seq, &f.id, day))
            .collect();
        let moved = (|| {
            self.client.execute(
                "INSERT INTO archived_events (id, day) SELECT unnest($1::bigint[]), $2",
                &[&events, &day],
            )?;
            self.client
                .execute("DELETE FROM events WHERE id = ANY($1)", &[&events])?;
            self.client.execute(
                "INSERT INTO archived (seq, id, day, crc) \
                 SELECT s, i, $3, c FROM unnest($1::bigint[], $2::text[], $4::bigint[]) AS t (s, i, c)",
                &[&seqs, &ids, &day, &sums],
            )?;
            self.client
                .execute("DELETE FROM flights WHERE seq = ANY($1)", &[&seqs])?;
            self.client.batch_execute("COMMIT")
        })();
        if moved.is_err() {
            let _ = self.client.batch_execute("ROLLBACK");
        }
        moved.map_err(pg(what))
    }

    fn reclaim(&mut self) -> Result<(), StoreError> {
        self.vacuum()
    }
}

/// (The rest of [`Archiver`] for PostgreSQL.)
impl PgArchiver {
    /// `VACUUM` of the hot tables, so that the next day's rows take the space the archived
    /// ones left (autovacuum would, later; this is at once, and only after a pass).
    fn vacuum(&mut self) -> Result<(), StoreError> {
        self.client
            .batch_execute("VACUUM flights, events")
            .map_err(pg("vacuuming the hot tables after archiving"))
    }
}

/// The archived flight with client id `id`: its `seq` and day, its row's checksum checked.
pub(super) fn archived_id(
    client: &mut Client,
    label: &str,
    id: &str,
) -> Result<Option<(i64, String)>, StoreError> {
    let row = client
        .query_opt(
            "SELECT seq, id, day, crc FROM archived WHERE id = $1",
            &[&id],
        )
        .map_err(pg("reading the archived ids"))?;
    let Some(row) = row else { return Ok(None) };
    let read = || -> Result<(i64, String, String, i64), postgres::Error> {
        Ok((
            row.try_get(0)?,
            row.try_get(1)?,
            row.try_get(2)?,
            row.try_get(3)?,
        ))
    };
    let row = read().map_err(pg("reading the archived ids"))?;
    checked_archived(label, id, row).map(Some)
}

/// How many of the keys in `[from, to)` of `table` (`archived` by `seq`, `archived_events` by
/// `id`) were archived.
pub(super) fn archived_between(
    client: &mut Client,
    table: &str,
    key: &str,
    from: u64,
    to: u64,
) -> Result<u64, StoreError> {
    client
        .query_one(
            &format!("SELECT count(*) FROM {table} WHERE {key} >= $1 AND {key} < $2"),
            &[&(from as i64), &(to as i64)],
        )
        .and_then(|r| r.try_get::<_, i64>(0))
        .map(|n| n as u64)
        .map_err(pg("reading the archived keys"))
}
