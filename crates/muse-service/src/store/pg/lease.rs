//! Which service leads a PostgreSQL store: one writer, any number of standbys, and a leader
//! that was deposed can never commit.
//!
//! - **The lock.** A service leads while its writing connection holds a session-level
//!   advisory lock ([`WRITER_LOCK`]). PostgreSQL releases it when that session ends: at once
//!   when the process dies (its socket is closed), or when the server finds the connection
//!   dead. A standby takes it with `pg_try_advisory_lock`, which never waits.
//! - **The term.** Taking the lead raises `lease.term` and records the leader's address, in one
//!   transaction. Every write transaction of the leader first reads the term `FOR SHARE` and
//!   goes on only if it is still its own: a new leader's raise waits for that transaction to
//!   end, and every later one of the old leader finds the new term and fails
//!   ([`StoreError::Deposed`]). The lock alone already keeps two sessions from leading at
//!   once; the term also fences a leader whose session outlived its lock (a connection pooler
//!   that shares sessions, an operator's `pg_advisory_unlock_all`).
//! - **Following.** The leader's commits notify [`CHANNEL`]; a standby listens on it and reads
//!   what was committed as soon as it is told (or every time its wait ends).

use muse_model::Instant;
use postgres::{Client, SimpleQueryMessage};

use super::{PostgresStore, pg};
use crate::store::{Leader, StoreError};

/// The key of the session-level advisory lock the leader holds.
pub(super) const WRITER_LOCK: i64 = 0x4d55_5345_0002;

/// The channel the leader's commits notify.
pub(super) const CHANNEL: &str = "muse_commits";

/// The text of a statement that begins a leader's write transaction and reads the term.
const BEGIN: &str = "BEGIN; SELECT term FROM lease WHERE one = 1 FOR SHARE";

/// The statement that ends a leader's write transaction, telling the standbys.
pub(super) const COMMIT: &str = "NOTIFY muse_commits; COMMIT";

impl PostgresStore {
    /// Takes the lead if no service holds it (see the module docs): `Ok(true)` if this
    /// service leads now.
    pub(super) fn take_lead(&mut self, address: &str, now: Instant) -> Result<bool, StoreError> {
        if self.term.is_some() {
            return Ok(true);
        }
        let mine: bool = self
            .client
            .query_one("SELECT pg_try_advisory_lock($1)", &[&WRITER_LOCK])
            .and_then(|r| r.try_get(0))
            .map_err(pg("taking the lead"))?;
        if !mine {
            return Ok(false);
        }
        let term: i64 = self
            .client
            .query_one(
                "INSERT INTO lease (one, term, holder, since_ms) VALUES (1, 1, $1, $2) \
                 ON CONFLICT (one) DO UPDATE SET term = lease.term + 1, holder = $1, \
                 since_ms = $2 RETURNING term",
                &[&address, &now.0],
            )
            .and_then(|r| r.try_get(0))
            .map_err(pg("taking the lead"))?;
        if self.listening {
            self.client
                .batch_execute(&format!("UNLISTEN {CHANNEL}"))
                .map_err(pg("leaving the standbys' channel"))?;
            self.listening = false;
        }
        self.term = Some(term);
        Ok(true)
    }

    /// Begins a write transaction of the leader, after checking that it still leads.
    pub(super) fn begin_fenced(&mut self) -> Result<(), StoreError> {
        match self.term {
            Some(mine) => begin_fenced(&mut self.client, &self.label, mine),
            None => Err(StoreError::Deposed {
                path: self.label.clone(),
                mine: 0,
                now: self.read_leader()?.map_or(0, |l| l.term),
            }),
        }
    }

    /// The leader, as the lease records it.
    pub(super) fn read_leader(&mut self) -> Result<Option<Leader>, StoreError> {
        let row = self
            .client
            .query_opt("SELECT holder, term FROM lease WHERE one = 1", &[])
            .map_err(pg("reading the lease"))?;
        row.map(|r| {
            Ok(Leader {
                address: r.try_get(0)?,
                term: r.try_get(1)?,
            })
        })
        .transpose()
        .map_err(pg("reading the lease"))
    }

    /// Waits up to `timeout` for the leader's next commit (see the module docs).
    pub(super) fn wait(&mut self, timeout: std::time::Duration) -> Result<(), StoreError> {
        use postgres::fallible_iterator::FallibleIterator as _;
        if !self.listening {
            self.client
                .batch_execute(&format!("LISTEN {CHANNEL}"))
                .map_err(pg("listening for the leader's commits"))?;
            self.listening = true;
        }
        let mut notifications = self.client.notifications();
        let told = notifications
            .timeout_iter(timeout)
            .next()
            .map_err(pg("waiting for the leader's commits"))?
            .is_some();
        if told {
            // Every notification already received counts as one: the reads that follow see
            // everything committed.
            let mut pending = notifications.iter();
            while pending
                .next()
                .map_err(pg("waiting for the leader's commits"))?
                .is_some()
            {}
        }
        Ok(())
    }
}

/// Begins a write transaction on `client` after checking, in it, that the term is still
/// `mine` (see the module docs); rolls back and says so if it is not. `label` names the
/// store in errors.
pub(super) fn begin_fenced(client: &mut Client, label: &str, mine: i64) -> Result<(), StoreError> {
    let messages = client
        .simple_query(BEGIN)
        .map_err(pg("starting a transaction"))?;
    let now = messages.iter().find_map(|m| match m {
        SimpleQueryMessage::Row(row) => row.get(0).and_then(|t| t.parse::<i64>().ok()),
        _ => None,
    });
    if now != Some(mine) {
        let _ = client.batch_execute("ROLLBACK");
        return Err(StoreError::Deposed {
            path: label.to_owned(),
            mine,
            now: now.unwrap_or(0),
        });
    }
    Ok(())
}
