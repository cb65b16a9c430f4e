//! The rows the store writes: a flight as it now stands, an event, a zone.

use muse_model::Airspace;
use rusqlite::{Connection, OptionalExtension as _, params};

use super::rows::{EventRow, FlightRow, ZoneRow};
use super::{StoreError, StoredZone, queries, sql};
use crate::events::Event;
use crate::flights::FlightEntry;

/// Writes a flight as it now stands: a new row (`new`) or the new state of a stored one.
pub(super) fn write_flight(
    conn: &Connection,
    label: &str,
    airspace: &Airspace,
    entry: &FlightEntry,
    new: bool,
) -> Result<(), StoreError> {
    let r = FlightRow::of(airspace, entry);
    let sql_text = if new {
        "INSERT INTO flights (seq, id, operator, origin, destination, departure_ms, \
         answered_ms, plan, reason, free_flow_ms, expanded, status, takeoff_ms, landing_ms, \
         holds_until_ms, cancelled_ms, changes, crc) \
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18)"
    } else {
        "UPDATE flights SET id = ?2, operator = ?3, origin = ?4, destination = ?5, \
         departure_ms = ?6, answered_ms = ?7, plan = ?8, reason = ?9, free_flow_ms = ?10, \
         expanded = ?11, status = ?12, takeoff_ms = ?13, landing_ms = ?14, \
         holds_until_ms = ?15, cancelled_ms = ?16, changes = ?17, crc = ?18 WHERE seq = ?1"
    };
    let changed = conn
        .prepare_cached(sql_text)
        .and_then(|mut s| {
            s.execute(params![
                r.seq,
                r.id,
                r.operator,
                r.origin,
                r.destination,
                r.departure_ms,
                r.answered_ms,
                r.plan,
                r.reason,
                r.free_flow_ms,
                r.expanded,
                r.status,
                r.takeoff_ms,
                r.landing_ms,
                r.holds_until_ms,
                r.cancelled_ms,
                r.changes,
                r.crc
            ])
        })
        .map_err(sql("writing a flight"))?;
    if changed != 1 {
        return Err(StoreError::Damaged {
            path: label.to_owned(),
            what: format!("flights row seq {} is missing", r.seq),
        });
    }
    Ok(())
}

/// Writes an event row.
pub(super) fn write_event(conn: &Connection, event: &Event) -> Result<(), StoreError> {
    let r = EventRow::of(event);
    conn.prepare_cached(
        "INSERT INTO events (id, at_ms, kind, flight_seq, zone, changes, crc) \
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
    )
    .and_then(|mut s| {
        s.execute(params![
            r.id,
            r.at_ms,
            r.kind,
            r.flight_seq,
            r.zone,
            r.changes,
            r.crc
        ])
    })
    .map_err(sql("writing an event"))?;
    Ok(())
}

/// Writes a zone row: a new zone (numbered after the last), or a stored one's new state.
pub(super) fn write_zone(conn: &Connection, zone: &StoredZone) -> Result<(), StoreError> {
    let seq: Option<i64> = conn
        .prepare_cached("SELECT seq FROM zones WHERE id = ?1")
        .and_then(|mut s| s.query_row([&zone.id], |r| r.get(0)).optional())
        .map_err(sql("reading a zone"))?;
    let seq = match seq {
        Some(s) => s,
        None => queries::max_key(conn, "zones", "seq")? as i64 + 1,
    };
    let r = ZoneRow::new(seq, zone);
    conn.execute(
        "INSERT OR REPLACE INTO zones (seq, id, feature, announced_ms, withdrawn_ms, \
         affected, crc) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
        params![
            r.seq,
            r.id,
            r.feature,
            r.announced_ms,
            r.withdrawn_ms,
            r.affected,
            r.crc
        ],
    )
    .map_err(sql("writing a zone"))?;
    Ok(())
}
