//! The PostgreSQL store's reads, shared by the planner task's connection and the handlers':
//! every row read is checked against its checksum before it is used.

use std::collections::{HashMap, HashSet};

use muse_model::{Airspace, Instant};
use postgres::fallible_iterator::FallibleIterator as _;
use postgres::{Client, GenericClient};

use super::super::rows::{
    EVENT_COLUMNS, EventRow, FLIGHT_COLUMNS, FlightRow, ZONE_COLUMNS, ZoneRow,
};
use super::archive::archived_between;
use super::pg;
use crate::events::Event;
use crate::flights::{FlightEntry, ListQuery};
use crate::store::keys::Keys;
use crate::store::{Checked, Recent, StoreError, StoredZone};

/// The damage `what` of the store `label`.
fn damaged(label: &str, what: String) -> StoreError {
    StoreError::Damaged {
        path: label.to_owned(),
        what,
    }
}

/// The flights row whose `column` is `value` (the key `id` or `seq`), as read.
fn flight_row(
    client: &mut Client,
    column: &str,
    value: &(dyn postgres::types::ToSql + Sync),
) -> Result<Option<FlightRow>, StoreError> {
    client
        .query_opt(
            &format!("SELECT {FLIGHT_COLUMNS} FROM flights WHERE {column} = $1"),
            &[value],
        )
        .and_then(|row| row.map(|r| FlightRow::read(&r, 0)).transpose())
        .map_err(pg("reading a flight"))
}

/// The flight with client id `id`.
pub(super) fn flight_by_id(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    id: &str,
) -> Result<Option<FlightEntry>, StoreError> {
    let Some(r) = flight_row(client, "id", &id)? else {
        return Ok(None);
    };
    if r.id != id {
        return Err(damaged(
            label,
            format!(
                "flights row seq {}: found under id {id:?} but names {:?}",
                r.seq, r.id
            ),
        ));
    }
    r.entry(airspace, label).map(Some)
}

/// The flights a listing asks for, in answer order, and whether more follow the page.
pub(super) fn list(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    q: &ListQuery,
) -> Result<(Vec<FlightEntry>, bool), StoreError> {
    let limit = q.limit.map_or(i64::MAX, |l| l as i64);
    // An operator's flights are read by the (operator, seq) index, everyone's by seq.
    let by = if q.operator.is_some() {
        "operator = $2 AND seq > $1"
    } else {
        "seq > $1 AND $2::text IS NULL"
    };
    let rows = client
        .query(
            &format!(
                "SELECT {FLIGHT_COLUMNS} FROM flights WHERE {by}
                   AND ($3::text IS NULL OR status = $3)
                   AND ($4::bigint IS NULL OR landing_ms >= $4)
                   AND ($5::bigint IS NULL OR takeoff_ms < $5)
                 ORDER BY seq LIMIT $6"
            ),
            &[
                &q.after.map_or(0, |a| a as i64),
                &q.operator,
                &q.status.map(crate::flights::Status::as_str),
                &q.from.map(|t| t.0),
                &q.to.map(|t| t.0),
                &limit.saturating_add(1),
            ],
        )
        .map_err(pg("listing flights"))?;
    let mut out = Vec::new();
    for row in rows {
        if out.len() as i64 == limit {
            return Ok((out, true));
        }
        let r = FlightRow::read(&row, 0).map_err(pg("listing flights"))?;
        out.push(r.entry(airspace, label)?);
    }
    Ok((out, false))
}

/// `columns` (comma-separated) each prefixed with `table.`.
fn prefixed(columns: &str, table: &str) -> String {
    columns
        .split(", ")
        .map(|c| format!("{table}.{}", c.trim()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Up to `limit` events with an id above `after`, each with its flight as it stood then,
/// keeping those of `operator` only when it is given.
pub(super) fn events_after(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    after: u64,
    operator: Option<&str>,
    limit: usize,
) -> Result<Vec<Event>, StoreError> {
    let rows = client
        .query(
            &format!(
                "SELECT {}, {} FROM events e JOIN flights f ON f.seq = e.flight_seq
                 WHERE e.id > $1 AND ($2::text IS NULL OR f.operator = $2)
                 ORDER BY e.id LIMIT $3",
                prefixed(EVENT_COLUMNS, "e"),
                prefixed(FLIGHT_COLUMNS, "f")
            ),
            &[&(after as i64), &operator, &(limit as i64)],
        )
        .map_err(pg("reading events"))?;
    let mut out = Vec::with_capacity(rows.len());
    for row in rows {
        let event = EventRow::read(&row, 0).map_err(pg("reading events"))?;
        let flight = FlightRow::read(&row, 7)
            .map_err(pg("reading events"))?
            .entry(airspace, label)?;
        out.push(event.event(&flight, label)?);
    }
    Ok(out)
}

/// Every announced zone, in announcement order.
pub(super) fn zones(
    client: &mut impl GenericClient,
    label: &str,
) -> Result<Vec<StoredZone>, StoreError> {
    let rows = client
        .query(
            &format!("SELECT {ZONE_COLUMNS} FROM zones ORDER BY seq"),
            &[],
        )
        .map_err(pg("reading zones"))?;
    rows.iter()
        .map(|r| ZoneRow::read(r).map_err(pg("reading zones"))?.zone(label))
        .collect()
}

/// The key of the zone `id`: its row's, or the next free one for a new zone.
pub(super) fn zone_seq(client: &mut Client, id: &str) -> Result<i64, StoreError> {
    let row = client
        .query_one(
            "SELECT coalesce((SELECT seq FROM zones WHERE id = $1), \
             (SELECT coalesce(max(seq), 0) + 1 FROM zones))",
            &[&id],
        )
        .map_err(pg("reading a zone"))?;
    row.try_get(0).map_err(pg("reading a zone"))
}

/// How many flights hold a reservation that ends at or after `now`.
pub(super) fn count_holding(client: &mut Client, now: Instant) -> Result<u64, StoreError> {
    let row = client
        .query_one(
            "SELECT count(*) FROM flights WHERE holds_until_ms >= $1",
            &[&now.0],
        )
        .map_err(pg("counting the flights still ahead"))?;
    let n: i64 = row
        .try_get(0)
        .map_err(pg("counting the flights still ahead"))?;
    Ok(n as u64)
}

/// The flights holding a reservation that ends at or after `now`, in answer order (read as
/// they stream in, by the index of flights still ahead); calls `progress` with how many were
/// read so far.
pub(super) fn holding(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    now: Instant,
    progress: &mut dyn FnMut(u64),
) -> Result<Vec<FlightEntry>, StoreError> {
    const WHAT: &str = "reading the flights still ahead";
    let mut rows = client
        .query_raw(
            &format!("SELECT {FLIGHT_COLUMNS} FROM flights WHERE holds_until_ms >= $1"),
            [now.0],
        )
        .map_err(pg(WHAT))?;
    let mut out = Vec::new();
    while let Some(row) = rows.next().map_err(pg(WHAT))? {
        let r = FlightRow::read(&row, 0).map_err(pg(WHAT))?;
        if r.holds_until_ms.is_none_or(|h| h < now.0) {
            return Err(damaged(
                label,
                format!(
                    "flights row seq {} (id {:?}): read as holding a reservation from now on, \
                     but it holds nothing then",
                    r.seq, r.id
                ),
            ));
        }
        out.push(r.entry(airspace, label)?);
        if out.len() % 1_024 == 0 {
            progress(out.len() as u64);
        }
    }
    progress(out.len() as u64);
    out.sort_unstable_by_key(|e| e.seq);
    Ok(out)
}

/// The largest value of an integer key of `table` (0 for an empty table).
pub(super) fn max_key(client: &mut Client, table: &str, key: &str) -> Result<u64, StoreError> {
    let row = client
        .query_one(&format!("SELECT max({key}) FROM {table}"), &[])
        .map_err(pg("reading the last key"))?;
    let n: Option<i64> = row.try_get(0).map_err(pg("reading the last key"))?;
    Ok(n.map_or(0, |n| n as u64))
}

/// Bytes the store's tables take, with their indexes.
pub(super) fn bytes(client: &mut Client) -> Result<u64, StoreError> {
    let row = client
        .query_one(
            "SELECT coalesce(sum(pg_total_relation_size(t::regclass)), 0)::bigint \
             FROM unnest(ARRAY['meta', 'flights', 'zones', 'events']) AS t",
            &[],
        )
        .map_err(pg("measuring the store"))?;
    let n: i64 = row.try_get(0).map_err(pg("measuring the store"))?;
    Ok(n as u64)
}

/// Checks the last `window` flights and events whole (see the module docs of `pg`); `held`
/// are the flights the start read as still holding at `now`.
pub(super) fn check_recent(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    now: Instant,
    held: &HashSet<u64>,
    window: u64,
) -> Result<Recent, StoreError> {
    if window == 0 {
        return Ok(Recent::default());
    }
    let last = max_key(client, "flights", "seq")?;
    let mut keys = Keys::window(label, "flights", "seq", last, window);
    let first = keys.first as i64;
    let rows = client
        .query(
            &format!("SELECT {FLIGHT_COLUMNS} FROM flights WHERE seq >= $1 ORDER BY seq"),
            &[&first],
        )
        .map_err(pg("checking the last flights"))?;
    let mut changes = HashMap::new();
    for row in &rows {
        let r = FlightRow::read(row, 0).map_err(pg("checking the last flights"))?;
        keys.next(r.seq, |t, k, from, to| {
            archived_between(client, t, k, from, to)
        })?;
        let entry = r.entry(airspace, label)?;
        if r.holds_until_ms.is_some_and(|h| h >= now.0) && !held.contains(&entry.seq) {
            return Err(damaged(
                label,
                format!(
                    "flights row seq {} (id {:?}) holds a reservation ahead, but the start did \
                     not read it among the flights still ahead",
                    r.seq, r.id
                ),
            ));
        }
        changes.insert(r.seq, entry.changes.len());
    }
    let flights = keys.finish()?;
    let last = max_key(client, "events", "id")?;
    let mut keys = Keys::window(label, "events", "id", last, window);
    let first = keys.first as i64;
    let rows = client
        .query(
            &format!(
                "SELECT {}, f.seq FROM events e \
                 LEFT JOIN flights f ON f.seq = e.flight_seq WHERE e.id >= $1 ORDER BY e.id",
                prefixed(EVENT_COLUMNS, "e")
            ),
            &[&first],
        )
        .map_err(pg("checking the last events"))?;
    for row in &rows {
        let e = EventRow::read(row, 0).map_err(pg("checking the last events"))?;
        keys.next(e.id, |t, k, from, to| {
            archived_between(client, t, k, from, to)
        })?;
        let found: Option<i64> = row.try_get(7).map_err(pg("checking the last events"))?;
        let of_flight = match changes.get(&e.flight_seq) {
            Some(&c) => Some(c),
            None if found.is_some() => {
                // A flight older than the window: read it to count its changes.
                read_seq(client, airspace, label, e.flight_seq)?.map(|f| f.changes.len())
            }
            None => None,
        };
        e.check(label, of_flight)?;
    }
    let events = keys.finish()?;
    Ok(Recent { flights, events })
}

/// The flight with sequence number `seq`.
fn read_seq(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    seq: i64,
) -> Result<Option<FlightEntry>, StoreError> {
    flight_row(client, "seq", &seq)?
        .map(|r| r.entry(airspace, label))
        .transpose()
}

/// Reads every row of the store and checks its checksum (and that it decodes); the first
/// damage found is the error.
pub(super) fn check_all(
    client: &mut Client,
    airspace: &Airspace,
    label: &str,
    progress: &mut dyn FnMut(u64),
) -> Result<Checked, StoreError> {
    let mut checked = Checked::default();
    let mut flights = HashMap::new();
    {
        let mut rows = client
            .query_raw(
                &format!("SELECT {FLIGHT_COLUMNS} FROM flights ORDER BY seq"),
                std::iter::empty::<i64>(),
            )
            .map_err(pg("checking flights"))?;
        while let Some(row) = rows.next().map_err(pg("checking flights"))? {
            let entry = FlightRow::read(&row, 0)
                .map_err(pg("checking flights"))?
                .entry(airspace, label)?;
            flights.insert(entry.seq as i64, entry.changes.len());
            checked.flights += 1;
            if checked.flights.is_multiple_of(65_536) {
                progress(checked.flights);
            }
        }
    }
    let mut rows = client
        .query_raw(
            &format!("SELECT {EVENT_COLUMNS} FROM events ORDER BY id"),
            std::iter::empty::<i64>(),
        )
        .map_err(pg("checking events"))?;
    while let Some(row) = rows.next().map_err(pg("checking events"))? {
        let e = EventRow::read(&row, 0).map_err(pg("checking events"))?;
        e.check(label, flights.get(&e.flight_seq).copied())?;
        checked.events += 1;
    }
    drop(rows);
    checked.zones = zones(client, label)?.len() as u64;
    progress(checked.flights);
    Ok(checked)
}
