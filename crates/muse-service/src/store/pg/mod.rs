//! The PostgreSQL store (`muse serve --store postgres://…`): the SQLite store's tables and
//! checksummed rows in a PostgreSQL database, for operators who run one already and want
//! their flights to outlive a machine. Replication, backups and point-in-time recovery are
//! PostgreSQL's own (docs/service.md).
//!
//! # Writing
//!
//! The planner task's connection opens a transaction at a group's first write and
//! [`PostgresStore::commit`] commits it: PostgreSQL returns once the commit is flushed to its
//! WAL (and, with synchronous standbys configured, to theirs). The start refuses a server that
//! would acknowledge commits it has not made durable (`fsync` off), and turns
//! `synchronous_commit` on for its own connection if the server has it off.
//!
//! # Reading and damage
//!
//! Every row's checksum is checked whenever it is read, as in the SQLite store. The start
//! reads the zones and the flights still holding a reservation, and checks the last flights
//! and events whole: their checksums, that their keys run without a gap, and that every flight
//! holding a reservation ahead was among those read. The structure of tables and indexes is
//! PostgreSQL's to keep (its page checksums, `initdb --data-checksums`, and `amcheck`).

mod archive;
mod connect;
mod lease;
mod open;
mod queries;
mod reader;
mod schema;

use std::collections::HashMap;
use std::fmt::Write as _;

use muse_model::{Airspace, Instant};
use postgres::{Client, Statement};

pub use open::Opening;

use super::rows::{EventRow, FlightRow, ZoneRow};
use super::{Archiver, Checked, Leader, Recent, Store, StoreError, StoredZone};
use crate::events::Event;
use crate::flights::FlightEntry;

/// `url` with its password, if it has one, replaced by `***` (for messages and logs).
pub(super) fn without_password(url: &str) -> String {
    let Some(scheme_end) = url.find("://").map(|i| i + 3) else {
        // A key=value connection string: hide the value of `password=`.
        return url
            .split_whitespace()
            .map(|kv| {
                if kv.starts_with("password=") {
                    "password=***"
                } else {
                    kv
                }
            })
            .collect::<Vec<_>>()
            .join(" ");
    };
    let rest = &url[scheme_end..];
    let authority_end = rest.find(['/', '?']).unwrap_or(rest.len());
    let authority = &rest[..authority_end];
    match authority.rfind('@') {
        Some(at) => match authority[..at].find(':') {
            Some(colon) => format!(
                "{}{}:***{}",
                &url[..scheme_end],
                &authority[..colon],
                &rest[at..]
            ),
            None => url.to_owned(),
        },
        None => url.to_owned(),
    }
}

/// The error in words: the server's message, detail and hint when it sent one.
pub(super) fn describe(error: &postgres::Error) -> String {
    match error.as_db_error() {
        Some(db) => {
            let mut s = format!("{}: {}", db.severity(), db.message());
            if let Some(d) = db.detail() {
                let _ = write!(s, " ({d})");
            }
            if let Some(h) = db.hint() {
                let _ = write!(s, "; hint: {h}");
            }
            s
        }
        None => error.to_string(),
    }
}

/// An error of the database while doing `what` (the caller names the database in `what` when
/// it is the first thing said).
pub(super) fn pg(what: &str) -> impl FnOnce(postgres::Error) -> StoreError + '_ {
    move |error| StoreError::Postgres {
        what: what.to_owned(),
        error,
    }
}

/// The open PostgreSQL store, written by the planner task only (see the module docs).
pub struct PostgresStore {
    url: String,
    label: String,
    client: Client,
    /// Prepared statements, by their text.
    prepared: HashMap<&'static str, Statement>,
    in_transaction: bool,
    /// How many of the last flights and events the start checks whole.
    recent: u64,
    /// Rows written in the open transaction.
    written: usize,
    /// The term this service leads in (`None`: a standby; see `lease`).
    term: Option<i64>,
    /// Whether the connection listens for the leader's commits (a standby's).
    listening: bool,
}

impl std::fmt::Debug for PostgresStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PostgresStore")
            .field("label", &self.label)
            .field("in_transaction", &self.in_transaction)
            .finish_non_exhaustive()
    }
}

impl PostgresStore {
    /// The statement of `text`, prepared once per connection.
    fn statement(&mut self, text: &'static str) -> Result<Statement, StoreError> {
        if let Some(s) = self.prepared.get(text) {
            return Ok(s.clone());
        }
        let s = self
            .client
            .prepare(text)
            .map_err(pg("preparing a statement"))?;
        self.prepared.insert(text, s.clone());
        Ok(s)
    }

    fn begin(&mut self) -> Result<(), StoreError> {
        if !self.in_transaction {
            self.begin_fenced()?;
            self.in_transaction = true;
        }
        Ok(())
    }

    /// Runs `text` with `params` inside the open transaction; the rows it changed.
    fn write(
        &mut self,
        text: &'static str,
        params: &[&(dyn postgres::types::ToSql + Sync)],
        what: &str,
    ) -> Result<u64, StoreError> {
        self.begin()?;
        let s = self.statement(text)?;
        let n = self.client.execute(&s, params).map_err(pg(what))?;
        self.written += 1;
        Ok(n)
    }
}

impl Store for PostgresStore {
    fn label(&self) -> String {
        self.label.clone()
    }

    fn put_flight(
        &mut self,
        airspace: &Airspace,
        entry: &FlightEntry,
        new: bool,
    ) -> Result<(), StoreError> {
        let r = FlightRow::of(airspace, entry);
        let text = if new {
            "INSERT INTO flights (seq, id, operator, origin, destination, departure_ms, \
             answered_ms, plan, reason, free_flow_ms, expanded, status, takeoff_ms, landing_ms, \
             holds_until_ms, cancelled_ms, changes, crc) \
             VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14, $15, $16, $17, $18)"
        } else {
            "UPDATE flights SET id = $2, operator = $3, origin = $4, destination = $5, \
             departure_ms = $6, answered_ms = $7, plan = $8, reason = $9, free_flow_ms = $10, \
             expanded = $11, status = $12, takeoff_ms = $13, landing_ms = $14, \
             holds_until_ms = $15, cancelled_ms = $16, changes = $17, crc = $18 WHERE seq = $1"
        };
        let changed = self.write(
            text,
            &[
                &r.seq,
                &r.id,
                &r.operator,
                &r.origin,
                &r.destination,
                &r.departure_ms,
                &r.answered_ms,
                &r.plan,
                &r.reason,
                &r.free_flow_ms,
                &r.expanded,
                &r.status,
                &r.takeoff_ms,
                &r.landing_ms,
                &r.holds_until_ms,
                &r.cancelled_ms,
                &r.changes,
                &r.crc,
            ],
            "writing a flight",
        )?;
        if changed != 1 {
            return Err(StoreError::Damaged {
                path: self.label.clone(),
                what: format!("flights row seq {} is missing", r.seq),
            });
        }
        Ok(())
    }

    fn put_event(&mut self, event: &Event) -> Result<(), StoreError> {
        let r = EventRow::of(event);
        self.write(
            "INSERT INTO events (id, at_ms, kind, flight_seq, zone, changes, crc) \
             VALUES ($1, $2, $3, $4, $5, $6, $7)",
            &[
                &r.id,
                &r.at_ms,
                &r.kind,
                &r.flight_seq,
                &r.zone,
                &r.changes,
                &r.crc,
            ],
            "writing an event",
        )?;
        Ok(())
    }

    fn put_zone(&mut self, zone: &StoredZone) -> Result<(), StoreError> {
        self.begin()?;
        let seq = queries::zone_seq(&mut self.client, &zone.id)?;
        let r = ZoneRow::new(seq, zone);
        self.write(
            "INSERT INTO zones (seq, id, feature, announced_ms, withdrawn_ms, affected, crc) \
             VALUES ($1, $2, $3, $4, $5, $6, $7) \
             ON CONFLICT (seq) DO UPDATE SET id = $2, feature = $3, announced_ms = $4, \
             withdrawn_ms = $5, affected = $6, crc = $7",
            &[
                &r.seq,
                &r.id,
                &r.feature,
                &r.announced_ms,
                &r.withdrawn_ms,
                &r.affected,
                &r.crc,
            ],
            "writing a zone",
        )?;
        Ok(())
    }

    fn commit(&mut self) -> Result<usize, StoreError> {
        if !self.in_transaction {
            return Ok(0);
        }
        // Whatever happens, the transaction is over: a failed commit is rolled back.
        self.in_transaction = false;
        self.client
            .batch_execute(lease::COMMIT)
            .map_err(pg("committing"))?;
        Ok(std::mem::take(&mut self.written))
    }

    fn zones(&mut self) -> Result<Vec<StoredZone>, StoreError> {
        queries::zones(&mut self.client, &self.label)
    }

    fn count_holding(&mut self, now: Instant) -> Result<u64, StoreError> {
        queries::count_holding(&mut self.client, now)
    }

    fn holding(
        &mut self,
        airspace: &Airspace,
        now: Instant,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Vec<FlightEntry>, StoreError> {
        queries::holding(&mut self.client, airspace, &self.label, now, progress)
    }

    fn check_recent(
        &mut self,
        airspace: &Airspace,
        now: Instant,
        held: &std::collections::HashSet<u64>,
    ) -> Result<Recent, StoreError> {
        queries::check_recent(
            &mut self.client,
            airspace,
            &self.label,
            now,
            held,
            self.recent,
        )
    }

    fn check_all(
        &mut self,
        airspace: &Airspace,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Checked, StoreError> {
        queries::check_all(&mut self.client, airspace, &self.label, progress)
    }

    /// The archived keys count: a number once given is never given again.
    fn last_keys(&mut self) -> Result<(u64, u64), StoreError> {
        let c = &mut self.client;
        Ok((
            queries::max_key(c, "flights", "seq")?.max(queries::max_key(c, "archived", "seq")?),
            queries::max_key(c, "events", "id")?.max(queries::max_key(c, "archived_events", "id")?),
        ))
    }

    fn bytes(&mut self) -> u64 {
        queries::bytes(&mut self.client).unwrap_or(0)
    }

    fn begin_snapshot(&mut self) -> Result<(), StoreError> {
        self.client
            .batch_execute("BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY")
            .map_err(pg("starting a snapshot"))
    }

    fn end_snapshot(&mut self) -> Result<(), StoreError> {
        self.client
            .batch_execute("COMMIT")
            .map_err(pg("ending a snapshot"))
    }

    fn try_lead(&mut self, address: &str, now: Instant) -> Result<bool, StoreError> {
        self.take_lead(address, now)
    }

    fn leader(&mut self) -> Result<Option<Leader>, StoreError> {
        self.read_leader()
    }

    fn wait_for_commits(&mut self, timeout: std::time::Duration) -> Result<(), StoreError> {
        self.wait(timeout)
    }

    fn archiver(&mut self) -> Result<Box<dyn Archiver>, StoreError> {
        let Some(term) = self.term else {
            return Err(StoreError::Deposed {
                path: self.label.clone(),
                mine: 0,
                now: self.read_leader()?.map_or(0, |l| l.term),
            });
        };
        Ok(Box::new(archive::PgArchiver {
            label: self.label.clone(),
            client: connect::connect(&self.url, &self.label)?,
            term,
        }))
    }

    fn close(self: Box<Self>) -> Result<(), StoreError> {
        let PostgresStore { client, .. } = *self;
        client.close().map_err(pg("closing the connection"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passwords_are_hidden() {
        assert_eq!(
            without_password("postgres://muse:secret@db.example:5432/muse"),
            "postgres://muse:***@db.example:5432/muse"
        );
        assert_eq!(
            without_password("postgresql://muse@127.0.0.1:5432/muse?sslmode=disable"),
            "postgresql://muse@127.0.0.1:5432/muse?sslmode=disable"
        );
        assert_eq!(
            without_password("host=db user=muse password=secret dbname=muse"),
            "host=db user=muse password=*** dbname=muse"
        );
    }
}
