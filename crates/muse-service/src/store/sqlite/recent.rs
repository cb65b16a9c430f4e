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

use super::super::keys::Keys;
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
    let archived = |table, key, from, to| archived_between(conn, table, key, from, to);
    let mut keys = Keys::window(
        path,
        "flights",
        "seq",
        max_key(conn, "flights", "seq")?,
        window,
    );
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
            keys.next(row.seq, archived)?;
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
    let mut keys = Keys::window(path, "events", "id", max_key(conn, "events", "id")?, window);
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
        keys.next(row.id, archived)?;
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
