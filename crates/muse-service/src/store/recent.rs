//! The start's check of what was written last: the rows a crash can have damaged, read whole
//! in time that does not grow with the days served.
//!
//! The start reads the zones and the flights still ahead (by the index of flights still
//! ahead). That alone leaves out the flights answered last that hold nothing (rejected,
//! cancelled, ended) and every index entry, and a damaged index entry hides a flight without a
//! word: a key changed in the index of ids makes its flight a `404`. So the start also reads
//! the last flights and the last events ([`RECENT`] of each unless told otherwise) in key order (the numbers run
//! without a gap: a missing or misplaced row is damage), checks each row's checksum, and for
//! each flight that the index of ids and the index of operators lead to it, and that the index
//! of flights still ahead lists it if it holds anything from now on. Older rows are checked
//! when they are read, and all of them by `muse serve --check-store`.

use std::collections::{HashMap, HashSet};

use muse_model::{Airspace, Instant};
use rusqlite::{Connection, OptionalExtension as _, params};

use super::queries::{flight_by_seq, max_key};
use super::rows::{EVENT_COLUMNS, EventRow, FLIGHT_COLUMNS, FlightRow};
use super::{StoreError, sql};

/// How many of the last flights, and of the last events, the start checks whole by default.
pub const RECENT: u64 = 16_384;

/// What the start checked whole of the last flights and events written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Recent {
    /// Flights checked.
    pub flights: u64,
    /// Events checked.
    pub events: u64,
}

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
    let damaged = |what: String| StoreError::Damaged {
        path: path.to_owned(),
        what,
    };
    let mut recent = Recent::default();
    let last = max_key(conn, "flights", "seq")?;
    let first = last.saturating_sub(window) + 1;
    let mut changes = HashMap::new();
    {
        let mut stmt = conn
            .prepare(&format!(
                "SELECT {FLIGHT_COLUMNS} FROM flights WHERE seq >= ?1 ORDER BY seq"
            ))
            .map_err(sql("checking the last flights"))?;
        let rows = stmt
            .query_map([first as i64], |r| FlightRow::read(r, 0))
            .map_err(sql("checking the last flights"))?;
        let mut want = first;
        for row in rows {
            let row = row.map_err(sql("checking the last flights"))?;
            if row.seq != want as i64 {
                return Err(damaged(format!(
                    "flights row seq {want} is missing (the rows go on with seq {})",
                    row.seq
                )));
            }
            let entry = row.entry(airspace, path)?;
            indexed(conn, path, &row)?;
            if row.holds_until_ms.is_some_and(|h| h >= now.0) && !held.contains(&entry.seq) {
                return Err(damaged(format!(
                    "flights row seq {} (id {:?}) holds a reservation ahead, but the index of \
                     flights still ahead does not list it",
                    row.seq, row.id
                )));
            }
            changes.insert(entry.seq, entry.changes.len());
            want += 1;
            recent.flights += 1;
        }
        if want != last + 1 && last > 0 {
            return Err(damaged(format!(
                "flights rows seq {want} to {last} are missing"
            )));
        }
    }
    let last = max_key(conn, "events", "id")?;
    let first = last.saturating_sub(window) + 1;
    let mut stmt = conn
        .prepare(&format!(
            "SELECT {EVENT_COLUMNS} FROM events WHERE id >= ?1 ORDER BY id"
        ))
        .map_err(sql("checking the last events"))?;
    let rows = stmt
        .query_map([first as i64], |r| EventRow::read(r, 0))
        .map_err(sql("checking the last events"))?;
    let mut want = first;
    for row in rows {
        let row = row.map_err(sql("checking the last events"))?;
        if row.id != want as i64 {
            return Err(damaged(format!(
                "events row id {want} is missing (the rows go on with id {})",
                row.id
            )));
        }
        let seq = u64::try_from(row.flight_seq).unwrap_or(0);
        let flight_changes = match changes.get(&seq) {
            Some(&c) => Some(c),
            None => flight_by_seq(conn, airspace, path, seq)?.map(|f| f.changes.len()),
        };
        row.check(path, flight_changes)?;
        want += 1;
        recent.events += 1;
    }
    if want != last + 1 && last > 0 {
        return Err(damaged(format!(
            "events rows id {want} to {last} are missing"
        )));
    }
    Ok(recent)
}

/// Checks that the index of ids and the index of operators lead to the flight `row` (its
/// checksum checked by the caller).
fn indexed(conn: &Connection, path: &str, row: &FlightRow) -> Result<(), StoreError> {
    let damaged = |what: String| StoreError::Damaged {
        path: path.to_owned(),
        what: format!("flights row seq {} (id {:?}): {what}", row.seq, row.id),
    };
    let by_id: Option<i64> = conn
        .prepare_cached(
            "SELECT seq FROM flights INDEXED BY sqlite_autoindex_flights_1 WHERE id = ?1",
        )
        .and_then(|mut s| s.query_row([&row.id], |r| r.get(0)).optional())
        .map_err(sql("reading the index of ids"))?;
    if by_id != Some(row.seq) {
        return Err(damaged(format!(
            "the index of ids leads to {}",
            by_id.map_or("no flight".to_owned(), |s| format!("seq {s}"))
        )));
    }
    let by_operator: Option<i64> = conn
        .prepare_cached(
            "SELECT seq FROM flights INDEXED BY flights_by_operator \
             WHERE operator = ?1 AND seq = ?2",
        )
        .and_then(|mut s| {
            s.query_row(params![row.operator, row.seq], |r| r.get(0))
                .optional()
        })
        .map_err(sql("reading the index of operators"))?;
    if by_operator.is_none() {
        return Err(damaged(format!(
            "the index of operators has no entry for it under {:?}",
            row.operator
        )));
    }
    Ok(())
}

/// Checks a flight the start read by the index of flights still ahead (its checksum checked by
/// the caller): that it does hold something from `now` on, and that the other indexes lead to
/// it.
pub(super) fn held_and_indexed(
    conn: &Connection,
    path: &str,
    row: &FlightRow,
    now: Instant,
) -> Result<(), StoreError> {
    if row.holds_until_ms.is_none_or(|h| h < now.0) {
        return Err(StoreError::Damaged {
            path: path.to_owned(),
            what: format!(
                "flights row seq {} (id {:?}): the index of flights still ahead lists it, but \
                 it holds nothing from now on",
                row.seq, row.id
            ),
        });
    }
    indexed(conn, path, row)
}
