//! Reads shared by the planner task's connection and the handlers' read connections: every
//! row read is checked against its checksum before it is used.

use muse_model::{Airspace, Instant};
use rusqlite::{Connection, OptionalExtension as _, params};

use super::rows::{EVENT_COLUMNS, EventRow, FLIGHT_COLUMNS, FlightRow, ZONE_COLUMNS, ZoneRow};
use super::{Checked, StoreError, StoredZone, sql};
use crate::events::Event;
use crate::flights::{FlightEntry, ListQuery};

/// The flight with client id `id`.
pub(super) fn flight_by_id(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    id: &str,
) -> Result<Option<FlightEntry>, StoreError> {
    let mut stmt = conn
        .prepare_cached(&format!(
            "SELECT {FLIGHT_COLUMNS} FROM flights WHERE id = ?1"
        ))
        .map_err(sql("reading a flight"))?;
    let row = stmt
        .query_row([id], |r| FlightRow::read(r, 0))
        .optional()
        .map_err(sql("reading a flight"))?;
    row.map(|r| {
        if r.id != id {
            return Err(StoreError::Damaged {
                path: path.to_owned(),
                what: format!(
                    "flights row seq {}: found under id {id:?} but names {:?}",
                    r.seq, r.id
                ),
            });
        }
        r.entry(airspace, path)
    })
    .transpose()
}

/// The flight with sequence number `seq`.
pub(super) fn flight_by_seq(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    seq: u64,
) -> Result<Option<FlightEntry>, StoreError> {
    let mut stmt = conn
        .prepare_cached(&format!(
            "SELECT {FLIGHT_COLUMNS} FROM flights WHERE seq = ?1"
        ))
        .map_err(sql("reading a flight"))?;
    let row = stmt
        .query_row([seq as i64], |r| FlightRow::read(r, 0))
        .optional()
        .map_err(sql("reading a flight"))?;
    row.map(|r| r.entry(airspace, path)).transpose()
}

/// The flights a listing asks for, in answer order, and whether more follow the page.
pub(super) fn list(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    q: &ListQuery,
) -> Result<(Vec<FlightEntry>, bool), StoreError> {
    let limit = q.limit.map_or(i64::MAX, |l| l as i64);
    // An operator's flights are read by the (operator, seq) index, everyone's by seq.
    let by = if q.operator.is_some() {
        "INDEXED BY flights_by_operator WHERE operator = ?2 AND seq > ?1"
    } else {
        "WHERE seq > ?1 AND ?2 IS NULL"
    };
    let mut stmt = conn
        .prepare_cached(&format!(
            "SELECT {FLIGHT_COLUMNS} FROM flights {by}
               AND (?3 IS NULL OR status = ?3)
               AND (?4 IS NULL OR landing_ms >= ?4)
               AND (?5 IS NULL OR takeoff_ms < ?5)
             ORDER BY seq LIMIT ?6"
        ))
        .map_err(sql("listing flights"))?;
    let rows = stmt
        .query_map(
            params![
                q.after.map_or(0, |a| a as i64),
                q.operator,
                q.status.map(crate::flights::Status::as_str),
                q.from.map(|t| t.0),
                q.to.map(|t| t.0),
                limit.saturating_add(1),
            ],
            |r| FlightRow::read(r, 0),
        )
        .map_err(sql("listing flights"))?;
    let mut out = Vec::new();
    for row in rows {
        let row = row.map_err(sql("listing flights"))?;
        if out.len() as i64 == limit {
            return Ok((out, true));
        }
        out.push(row.entry(airspace, path)?);
    }
    Ok((out, false))
}

/// Up to `limit` events with an id above `after`, each with its flight as it stood then,
/// keeping those of `operator` only when it is given.
pub(super) fn events_after(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    after: u64,
    operator: Option<&str>,
    limit: usize,
) -> Result<Vec<Event>, StoreError> {
    let columns: String = FLIGHT_COLUMNS
        .split(", ")
        .map(|c| format!("f.{}", c.trim()))
        .collect::<Vec<_>>()
        .join(", ");
    let event_columns: String = EVENT_COLUMNS
        .split(", ")
        .map(|c| format!("e.{}", c.trim()))
        .collect::<Vec<_>>()
        .join(", ");
    let mut stmt = conn
        .prepare_cached(&format!(
            "SELECT {event_columns}, {columns} FROM events e JOIN flights f ON f.seq = e.flight_seq
             WHERE e.id > ?1 AND (?2 IS NULL OR f.operator = ?2)
             ORDER BY e.id LIMIT ?3"
        ))
        .map_err(sql("reading events"))?;
    let rows = stmt
        .query_map(params![after as i64, operator, limit as i64], |r| {
            Ok((EventRow::read(r, 0)?, FlightRow::read(r, 7)?))
        })
        .map_err(sql("reading events"))?;
    let mut out = Vec::new();
    for row in rows {
        let (event, flight) = row.map_err(sql("reading events"))?;
        let flight = flight.entry(airspace, path)?;
        out.push(event.event(&flight, path)?);
    }
    Ok(out)
}

/// Every announced zone, in announcement order.
pub(super) fn zones(conn: &Connection, path: &str) -> Result<Vec<StoredZone>, StoreError> {
    let mut stmt = conn
        .prepare_cached(&format!("SELECT {ZONE_COLUMNS} FROM zones ORDER BY seq"))
        .map_err(sql("reading zones"))?;
    let rows = stmt
        .query_map([], |r| ZoneRow::read(r))
        .map_err(sql("reading zones"))?;
    let mut out = Vec::new();
    for row in rows {
        out.push(row.map_err(sql("reading zones"))?.zone(path)?);
    }
    Ok(out)
}

/// The flights holding a reservation that ends at or after `now`, in answer order; calls
/// `progress` with how many were read so far.
pub(super) fn holding(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    now: Instant,
    progress: &mut dyn FnMut(u64),
) -> Result<Vec<FlightEntry>, StoreError> {
    let mut stmt = conn
        .prepare_cached(&format!(
            "SELECT {FLIGHT_COLUMNS} FROM flights INDEXED BY flights_holding \
             WHERE holds_until_ms >= ?1"
        ))
        .map_err(sql("reading the flights still ahead"))?;
    let rows = stmt
        .query_map([now.0], |r| FlightRow::read(r, 0))
        .map_err(sql("reading the flights still ahead"))?;
    let mut out = Vec::new();
    for row in rows {
        let row = row.map_err(sql("reading the flights still ahead"))?;
        let entry = row.entry(airspace, path)?;
        held_and_indexed(conn, path, &row, now)?;
        out.push(entry);
        if out.len() % 1_024 == 0 {
            progress(out.len() as u64);
        }
    }
    progress(out.len() as u64);
    // Read by the index (the time it takes grows with the flights still ahead, never with
    // those that ended), then put in answer order.
    out.sort_unstable_by_key(|e| e.seq);
    Ok(out)
}

/// Checks that the index of ids and the index of operators lead to the flight `row` (its
/// checksum checked by the caller): a damaged index entry would otherwise hide the flight
/// from a read by id (a `404`) or from its operator's listing, or bring another in its place.
pub(super) fn indexed(conn: &Connection, path: &str, row: &FlightRow) -> Result<(), StoreError> {
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

/// How many flights hold a reservation that ends at or after `now`.
pub(super) fn count_holding(conn: &Connection, now: Instant) -> Result<u64, StoreError> {
    conn.query_row(
        "SELECT count(*) FROM flights INDEXED BY flights_holding WHERE holds_until_ms >= ?1",
        [now.0],
        |r| r.get::<_, i64>(0),
    )
    .map(|n| n as u64)
    .map_err(sql("counting the flights still ahead"))
}

/// The largest value of an integer key of `table` (0 for an empty table).
pub(super) fn max_key(conn: &Connection, table: &str, key: &str) -> Result<u64, StoreError> {
    conn.query_row(&format!("SELECT max({key}) FROM {table}"), [], |r| {
        r.get::<_, Option<i64>>(0)
    })
    .map(|n| n.map_or(0, |n| n as u64))
    .map_err(sql("reading the last key"))
}

/// Reads every row of the store and checks its checksum (and that it decodes), after SQLite's
/// own check of the database's structure; the first damage found is the error.
pub(super) fn check_all(
    conn: &Connection,
    airspace: &Airspace,
    path: &str,
    progress: &mut dyn FnMut(u64),
) -> Result<Checked, StoreError> {
    // Structure and indexes: every index entry matches its row (a damaged index entry would
    // hide a flight from a read by id, or from its operator's listing).
    let verdict: String = conn
        .query_row("PRAGMA integrity_check(1)", [], |r| r.get(0))
        .map_err(sql("checking the database's structure"))?;
    if verdict != "ok" {
        return Err(StoreError::Damaged {
            path: path.to_owned(),
            what: format!("SQLite's check of its structure says: {verdict}"),
        });
    }
    let mut checked = Checked::default();
    let mut stmt = conn
        .prepare(&format!(
            "SELECT {FLIGHT_COLUMNS} FROM flights ORDER BY seq"
        ))
        .map_err(sql("checking flights"))?;
    let mut flights = std::collections::HashMap::new();
    for row in stmt
        .query_map([], |r| FlightRow::read(r, 0))
        .map_err(sql("checking flights"))?
    {
        let entry = row
            .map_err(sql("checking flights"))?
            .entry(airspace, path)?;
        flights.insert(entry.seq, entry.changes.len());
        checked.flights += 1;
        if checked.flights.is_multiple_of(65_536) {
            progress(checked.flights);
        }
    }
    let mut stmt = conn
        .prepare(&format!("SELECT {EVENT_COLUMNS} FROM events ORDER BY id"))
        .map_err(sql("checking events"))?;
    for row in stmt
        .query_map([], |r| EventRow::read(r, 0))
        .map_err(sql("checking events"))?
    {
        let row = row.map_err(sql("checking events"))?;
        row.check(path, flights.get(&(row.flight_seq as u64)).copied())?;
        checked.events += 1;
    }
    checked.zones = zones(conn, path)?.len() as u64;
    progress(checked.flights);
    Ok(checked)
}
