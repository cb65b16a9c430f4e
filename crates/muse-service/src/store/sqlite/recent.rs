//! The start's check of what was written last: the rows a crash can have damaged, read whole
//! in time that does not grow with the days served.
//!
//! The start reads the zones and the flights still ahead (by the index of flights still
//! ahead). That alone leaves out the flights answered last that hold nothing (rejected,
//! cancelled, ended) and every index entry, and a damaged index entry hides a flight without a
//! word: a key changed in the index of ids makes its flight a `404`. So the start also reads
//! the last flights and the last events ([`RECENT`] of each unless told otherwise) in key
//! order (the numbers run without a gap: a missing or misplaced row is damage), checks each row's checksum, and for
//! each flight that the index of ids and the index of operators lead to it, and that the index
//! of flights still ahead lists it if it holds anything from now on. Older rows are checked
//! when they are read, and all of them by `muse serve --check-store`.

use std::collections::{HashMap, HashSet};

use muse_model::{Airspace, Instant};
use rusqlite::Connection;

use super::archive::archived_between;
use super::queries::{flight_by_seq, indexed, max_key};
use super::rows::{EVENT_COLUMNS, EventRow, FLIGHT_COLUMNS, FlightRow};
use super::{Recent, StoreError, sql};

/// Checks the last `window` flights and events (see the module docs); `held` are the flights
/// the start read as still holding at `now`.
pub(super) fn check(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    now: Instant,
    held: &HashSet<u64>,
    window: u64,
) -> Result<Recent, StoreError> {
    if window == 0 {
        return Ok(Recent::default());
    }
    let mut keys = Keys::last(conn, path, "flights", "seq", window)?;
    let mut changes = HashMap::new();
    {
        let mut stmt = conn
            .prepare(&format!(
                "SELECT {FLIGHT_COLUMNS} FROM flights WHERE seq >= ?1 ORDER BY seq"
            ))
            .map_err(sql("checking the last flights"))?;
        let rows = stmt
            .query_map([keys.first as i64], |r| FlightRow::read(r, 0))
            .map_err(sql("checking the last flights"))?;
        for row in rows {
            let row = row.map_err(sql("checking the last flights"))?;
            keys.next(conn, row.seq)?;
            let entry = row.entry(airspace, path)?;
            indexed(conn, path, &row)?;
            if row.holds_until_ms.is_some_and(|h| h >= now.0) && !held.contains(&entry.seq) {
                return Err(StoreError::Damaged {
                    path: path.to_owned(),
                    what: format!(
                        "flights row seq {} (id {:?}) holds a reservation ahead, but the index \
                         of flights still ahead does not list it",
                        row.seq, row.id
                    ),
                });
            }
            changes.insert(entry.seq, entry.changes.len());
        }
    }
    let flights = keys.finish()?;
    let mut keys = Keys::last(conn, path, "events", "id", window)?;
    let mut stmt = conn
        .prepare(&format!(
            "SELECT {EVENT_COLUMNS} FROM events WHERE id >= ?1 ORDER BY id"
        ))
        .map_err(sql("checking the last events"))?;
    let rows = stmt
        .query_map([keys.first as i64], |r| EventRow::read(r, 0))
        .map_err(sql("checking the last events"))?;
    for row in rows {
        let row = row.map_err(sql("checking the last events"))?;
        keys.next(conn, row.id)?;
        let seq = u64::try_from(row.flight_seq).unwrap_or(0);
        let flight_changes = match changes.get(&seq) {
            Some(&c) => Some(c),
            None => flight_by_seq(conn, airspace, path, seq)?.map(|f| f.changes.len()),
        };
        row.check(path, flight_changes)?;
    }
    Ok(Recent {
        flights,
        events: keys.finish()?,
    })
}

/// The keys of a table's last rows, read in order: they run without a gap from `first` to the
/// largest stored.
struct Keys<'a> {
    path: &'a str,
    table: &'static str,
    key: &'static str,
    first: u64,
    /// The key the next row must have.
    want: u64,
    last: u64,
}

impl<'a> Keys<'a> {
    /// The last `window` keys of `table` (column `key`).
    fn last(
        conn: &Connection,
        path: &'a str,
        table: &'static str,
        key: &'static str,
        window: u64,
    ) -> Result<Keys<'a>, StoreError> {
        let last = max_key(conn, table, key)?;
        let first = last.saturating_sub(window) + 1;
        Ok(Keys {
            path,
            table,
            key,
            first,
            want: first,
            last,
        })
    }

    /// The next row read has key `got`: the one expected (or the next after keys archived;
    /// see `store::archive`), or damage.
    fn next(&mut self, conn: &Connection, got: i64) -> Result<(), StoreError> {
        if got > self.want as i64 {
            let (table, key) = if self.table == "flights" {
                ("archived", "seq")
            } else {
                ("archived_events", "id")
            };
            let gap = got as u64 - self.want;
            if archived_between(conn, table, key, self.want, got as u64)? == gap {
                self.first += gap;
                self.want = got as u64;
            }
        }
        if got != self.want as i64 {
            return Err(self.damaged(format!(
                "{} row {} {} is missing (the rows go on with {} {got})",
                self.table, self.key, self.want, self.key
            )));
        }
        self.want += 1;
        Ok(())
    }

    /// Every key up to the largest was read; returns how many rows were.
    fn finish(self) -> Result<u64, StoreError> {
        if self.last > 0 && self.want != self.last + 1 {
            return Err(self.damaged(format!(
                "{} rows {} {} to {} are missing",
                self.table, self.key, self.want, self.last
            )));
        }
        Ok(self.want - self.first)
    }

    fn damaged(&self, what: String) -> StoreError {
        StoreError::Damaged {
            path: self.path.to_owned(),
            what,
        }
    }
}
