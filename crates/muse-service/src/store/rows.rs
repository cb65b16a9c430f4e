//! The store's rows and their checksums: a flight, an event, a zone, a meta entry, each as
//! the columns it is stored in, with the CRC-32 of its content checked whenever it is read.
//!
//! A row's checksum covers every other column of the row, in a fixed order, each value
//! framed by its type and length, with the table's name first: a flipped byte anywhere in the
//! row's data (its key included) changes the checksum, and a row cannot pass for a row of
//! another table.

use std::sync::Arc;

use muse_model::plan::Change;
use muse_model::plan::{Fate, FateKind};
use muse_model::{Airspace, Instant, Millis, Plan, RejectReason, Request, Stay};
use serde::{Deserialize, Serialize};

use super::StoreError;
use crate::events::{Event, EventKind};
use crate::flights::FlightEntry;

/// The CRC-32 of a row's columns (see the module docs).
pub(super) struct RowSum(crc32fast::Hasher);

impl RowSum {
    pub(super) fn new(table: &str) -> Self {
        let mut h = crc32fast::Hasher::new();
        h.update(table.as_bytes());
        h.update(&[0]);
        RowSum(h)
    }

    pub(super) fn int(&mut self, v: i64) -> &mut Self {
        self.0.update(&[1]);
        self.0.update(&v.to_le_bytes());
        self
    }

    pub(super) fn opt_int(&mut self, v: Option<i64>) -> &mut Self {
        match v {
            Some(v) => self.int(v),
            None => self.null(),
        }
    }

    pub(super) fn text(&mut self, v: &str) -> &mut Self {
        self.0.update(&[2]);
        self.0.update(&(v.len() as u64).to_le_bytes());
        self.0.update(v.as_bytes());
        self
    }

    pub(super) fn opt_text(&mut self, v: Option<&str>) -> &mut Self {
        match v {
            Some(v) => self.text(v),
            None => self.null(),
        }
    }

    fn null(&mut self) -> &mut Self {
        self.0.update(&[0]);
        self
    }

    pub(super) fn finish(&self) -> i64 {
        i64::from(self.0.clone().finalize())
    }
}

/// A row as a database client returns it, read by column number: one reading of each row type
/// serves both stores.
pub(super) trait Columns {
    /// The client's error.
    type Error;
    /// An integer column.
    fn int(&self, at: usize) -> Result<i64, Self::Error>;
    /// An integer column that may be NULL.
    fn opt_int(&self, at: usize) -> Result<Option<i64>, Self::Error>;
    /// A text column.
    fn text(&self, at: usize) -> Result<String, Self::Error>;
    /// A text column that may be NULL.
    fn opt_text(&self, at: usize) -> Result<Option<String>, Self::Error>;
}

impl Columns for rusqlite::Row<'_> {
    type Error = rusqlite::Error;
    fn int(&self, at: usize) -> rusqlite::Result<i64> {
        self.get(at)
    }
    fn opt_int(&self, at: usize) -> rusqlite::Result<Option<i64>> {
        self.get(at)
    }
    fn text(&self, at: usize) -> rusqlite::Result<String> {
        self.get(at)
    }
    fn opt_text(&self, at: usize) -> rusqlite::Result<Option<String>> {
        self.get(at)
    }
}

impl Columns for postgres::Row {
    type Error = postgres::Error;
    fn int(&self, at: usize) -> Result<i64, postgres::Error> {
        self.try_get(at)
    }
    fn opt_int(&self, at: usize) -> Result<Option<i64>, postgres::Error> {
        self.try_get(at)
    }
    fn text(&self, at: usize) -> Result<String, postgres::Error> {
        self.try_get(at)
    }
    fn opt_text(&self, at: usize) -> Result<Option<String>, postgres::Error> {
        self.try_get(at)
    }
}

/// A plan's stays as stored: `[[node id, arrive ms, depart ms], ...]`.
type StoredStays = Vec<(String, i64, i64)>;

/// One zone change of a flight as stored in its `changes` column.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct StoredChange {
    zone: String,
    announced_ms: i64,
    airborne: bool,
    outcome: String,
    /// The new plan (replanned, diverted) or the committed part (contingency); absent when
    /// cancelled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    plan: Option<StoredStays>,
}

fn stays(airspace: &Airspace, plan: &Plan) -> StoredStays {
    plan.path
        .iter()
        .map(|s| (airspace.node(s.node).id.clone(), s.arrive.0, s.depart.0))
        .collect()
}

/// The plan of stored stays (as [`stays`] writes them).
pub(super) fn plan_of(airspace: &Airspace, stays: &[(String, i64, i64)]) -> Result<Plan, String> {
    let mut path = Vec::with_capacity(stays.len());
    for (n, a, d) in stays {
        let node = airspace
            .node_id(n)
            .ok_or_else(|| format!("unknown node `{n}` in a plan"))?;
        path.push(Stay {
            node,
            arrive: Instant(*a),
            depart: Instant(*d),
        });
    }
    Ok(Plan { path })
}

/// What a row whose checksum does not match its content is.
const MISMATCH: &str = "its checksum does not match its content (a byte of it changed on disk)";

/// The damage of the row `row` (e.g. `flights row seq 12 (id "r1")`) of the store at `path`.
fn damaged(path: &str, row: &str, what: &str) -> StoreError {
    StoreError::Damaged {
        path: path.to_owned(),
        what: format!("{row}: {what}"),
    }
}

/// JSON of plain strings and numbers: serialising cannot fail.
fn to_json<T: Serialize>(value: &T) -> String {
    serde_json::to_string(value).unwrap_or_default()
}

/// A `flights` row (see the schema for what each column holds).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct FlightRow {
    pub seq: i64,
    pub id: String,
    pub operator: String,
    pub origin: String,
    pub destination: String,
    pub departure_ms: i64,
    pub answered_ms: i64,
    pub plan: Option<String>,
    pub reason: Option<String>,
    pub free_flow_ms: Option<i64>,
    pub expanded: i64,
    pub status: String,
    pub takeoff_ms: i64,
    pub landing_ms: i64,
    pub holds_until_ms: Option<i64>,
    pub cancelled_ms: Option<i64>,
    pub changes: Option<String>,
    pub crc: i64,
}

/// The columns of a `flights` row, in the order [`FlightRow::read`] reads them.
pub(super) const FLIGHT_COLUMNS: &str = "seq, id, operator, origin, destination, departure_ms, \
    answered_ms, plan, reason, free_flow_ms, expanded, status, takeoff_ms, landing_ms, \
    holds_until_ms, cancelled_ms, changes, crc";

impl FlightRow {
    /// The row of a flight as it now stands.
    pub(super) fn of(airspace: &Airspace, e: &FlightEntry) -> Self {
        let node = |n: muse_model::NodeId| airspace.node(n).id.clone();
        let changes = (!e.changes.is_empty()).then(|| {
            let stored: Vec<StoredChange> = e
                .changes
                .iter()
                .zip(&e.fates)
                .map(|(c, f)| StoredChange {
                    zone: c.zone.clone(),
                    announced_ms: c.announced.0,
                    airborne: c.airborne,
                    outcome: c.outcome.as_str().to_owned(),
                    plan: match f {
                        Fate::Replanned(p) | Fate::Diverted(p) | Fate::Contingency(p) => {
                            Some(stays(airspace, p))
                        }
                        Fate::Cancelled => None,
                    },
                })
                .collect();
            to_json(&stored)
        });
        let (takeoff, landing) = e.span();
        let mut row = FlightRow {
            seq: e.seq as i64,
            id: e.request.id.clone(),
            operator: e.operator.clone(),
            origin: node(e.request.origin),
            destination: node(e.request.destination),
            departure_ms: e.request.departure.0,
            answered_ms: e.answered.0,
            plan: e.result.as_ref().ok().map(|p| to_json(&stays(airspace, p))),
            reason: e.result.as_ref().err().map(|r| r.as_str().to_owned()),
            free_flow_ms: e.free_flow.map(|m| m.0),
            expanded: e.expanded as i64,
            status: e.status().as_str().to_owned(),
            takeoff_ms: takeoff.0,
            landing_ms: landing.0,
            holds_until_ms: e.holds_until().map(|t| t.0),
            cancelled_ms: e.cancelled_at.map(|t| t.0),
            changes,
            crc: 0,
        };
        row.crc = row.sum();
        row
    }

    pub(super) fn sum(&self) -> i64 {
        RowSum::new("flights")
            .int(self.seq)
            .text(&self.id)
            .text(&self.operator)
            .text(&self.origin)
            .text(&self.destination)
            .int(self.departure_ms)
            .int(self.answered_ms)
            .opt_text(self.plan.as_deref())
            .opt_text(self.reason.as_deref())
            .opt_int(self.free_flow_ms)
            .int(self.expanded)
            .text(&self.status)
            .int(self.takeoff_ms)
            .int(self.landing_ms)
            .opt_int(self.holds_until_ms)
            .opt_int(self.cancelled_ms)
            .opt_text(self.changes.as_deref())
            .finish()
    }

    /// Reads a row selected with [`FLIGHT_COLUMNS`] (from column `at` on).
    pub(super) fn read<R: Columns>(row: &R, at: usize) -> Result<Self, R::Error> {
        Ok(FlightRow {
            seq: row.int(at)?,
            id: row.text(at + 1)?,
            operator: row.text(at + 2)?,
            origin: row.text(at + 3)?,
            destination: row.text(at + 4)?,
            departure_ms: row.int(at + 5)?,
            answered_ms: row.int(at + 6)?,
            plan: row.opt_text(at + 7)?,
            reason: row.opt_text(at + 8)?,
            free_flow_ms: row.opt_int(at + 9)?,
            expanded: row.int(at + 10)?,
            status: row.text(at + 11)?,
            takeoff_ms: row.int(at + 12)?,
            landing_ms: row.int(at + 13)?,
            holds_until_ms: row.opt_int(at + 14)?,
            cancelled_ms: row.opt_int(at + 15)?,
            changes: row.opt_text(at + 16)?,
            crc: row.int(at + 17)?,
        })
    }

    /// The flight this row describes, once its checksum is checked; `path` names the store in
    /// errors.
    pub(super) fn entry(&self, airspace: &Airspace, path: &str) -> Result<FlightEntry, StoreError> {
        let row = format!("flights row seq {} (id {:?})", self.seq, self.id);
        if self.sum() != self.crc {
            return Err(damaged(path, &row, MISMATCH));
        }
        self.decode(airspace)
            .map_err(|what| damaged(path, &row, &what))
    }

    fn decode(&self, airspace: &Airspace) -> Result<FlightEntry, String> {
        let node = |id: &str| {
            airspace
                .node_id(id)
                .ok_or_else(|| format!("unknown node `{id}`"))
        };
        let json = |what: &str, text: &str| -> Result<StoredStays, String> {
            serde_json::from_str(text).map_err(|e| format!("{what}: {e}"))
        };
        let result = match (&self.plan, &self.reason) {
            (Some(p), None) => Ok(plan_of(airspace, &json("plan", p)?)?),
            (None, Some(r)) => {
                Err(RejectReason::parse(r).ok_or_else(|| format!("unknown reason `{r}`"))?)
            }
            _ => return Err("neither a plan nor a rejection reason".into()),
        };
        let mut changes = Vec::new();
        let mut fates = Vec::new();
        if let Some(text) = &self.changes {
            let stored: Vec<StoredChange> =
                serde_json::from_str(text).map_err(|e| format!("changes: {e}"))?;
            for c in stored {
                let kind = FateKind::parse(&c.outcome)
                    .ok_or_else(|| format!("unknown outcome `{}`", c.outcome))?;
                let plan = || match &c.plan {
                    Some(s) => plan_of(airspace, s),
                    None => Err(format!("a {} change without a plan", c.outcome)),
                };
                fates.push(match kind {
                    FateKind::Replanned => Fate::Replanned(plan()?),
                    FateKind::Diverted => Fate::Diverted(plan()?),
                    FateKind::Contingency => Fate::Contingency(plan()?),
                    FateKind::Cancelled => Fate::Cancelled,
                });
                changes.push(Change {
                    zone: c.zone,
                    announced: Instant(c.announced_ms),
                    airborne: c.airborne,
                    outcome: kind,
                });
            }
        }
        let departure = Instant(self.departure_ms);
        Ok(FlightEntry {
            seq: u64::try_from(self.seq).map_err(|_| "a negative seq".to_owned())?,
            operator: self.operator.clone(),
            request: Request {
                id: self.id.clone(),
                origin: node(&self.origin)?,
                destination: node(&self.destination)?,
                departure,
                submitted: departure,
            },
            result,
            free_flow: self.free_flow_ms.map(Millis),
            expanded: u64::try_from(self.expanded).map_err(|_| "negative effort".to_owned())?,
            answered: Instant(self.answered_ms),
            cancelled_at: self.cancelled_ms.map(Instant),
            changes,
            fates,
        })
    }
}

/// An `events` row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct EventRow {
    pub id: i64,
    pub at_ms: i64,
    pub kind: String,
    pub flight_seq: i64,
    pub zone: Option<String>,
    /// How many zone changes the flight had just after the event.
    pub changes: i64,
    pub crc: i64,
}

/// The columns of an `events` row, in the order [`EventRow::read`] reads them.
pub(super) const EVENT_COLUMNS: &str = "id, at_ms, kind, flight_seq, zone, changes, crc";

impl EventRow {
    pub(super) fn of(event: &Event) -> Self {
        let mut row = EventRow {
            id: event.id as i64,
            at_ms: event.at.0,
            kind: event.kind.as_str().to_owned(),
            flight_seq: event.entry.seq as i64,
            zone: event.zone.clone(),
            changes: event.entry.changes.len() as i64,
            crc: 0,
        };
        row.crc = row.sum();
        row
    }

    fn sum(&self) -> i64 {
        RowSum::new("events")
            .int(self.id)
            .int(self.at_ms)
            .text(&self.kind)
            .int(self.flight_seq)
            .opt_text(self.zone.as_deref())
            .int(self.changes)
            .finish()
    }

    pub(super) fn read<R: Columns>(row: &R, at: usize) -> Result<Self, R::Error> {
        Ok(EventRow {
            id: row.int(at)?,
            at_ms: row.int(at + 1)?,
            kind: row.text(at + 2)?,
            flight_seq: row.int(at + 3)?,
            zone: row.opt_text(at + 4)?,
            changes: row.int(at + 5)?,
            crc: row.int(at + 6)?,
        })
    }

    /// Checks the row's checksum and that it names a stored flight (`changes`: how many zone
    /// changes that flight has, `None` if there is no such flight).
    pub(super) fn check(&self, path: &str, changes: Option<usize>) -> Result<(), StoreError> {
        let row = format!("events row id {}", self.id);
        if self.sum() != self.crc {
            return Err(damaged(path, &row, MISMATCH));
        }
        match changes {
            None => Err(damaged(
                path,
                &row,
                &format!(
                    "it names flight seq {}, which is not stored",
                    self.flight_seq
                ),
            )),
            Some(c) if usize::try_from(self.changes).is_ok_and(|k| k <= c) => Ok(()),
            Some(_) => Err(damaged(
                path,
                &row,
                &format!("{} changes of a flight that has fewer", self.changes),
            )),
        }
    }

    /// The event, with `flight` the current state of its flight (checked by the caller).
    pub(super) fn event(&self, flight: &FlightEntry, path: &str) -> Result<Event, StoreError> {
        self.check(path, Some(flight.changes.len()))?;
        let kind = EventKind::parse(&self.kind).ok_or_else(|| {
            damaged(
                path,
                &format!("events row id {}", self.id),
                &format!("unknown kind `{}`", self.kind),
            )
        })?;
        let changes = usize::try_from(self.changes).unwrap_or(0);
        // An operator's cancellation is a flight's last change: only its own event shows it.
        let cancelled = kind == EventKind::Cancelled && self.zone.is_none();
        Ok(Event {
            id: self.id as u64,
            kind,
            at: Instant(self.at_ms),
            zone: self.zone.clone(),
            entry: Arc::new(flight.as_of(changes, cancelled)),
        })
    }
}

/// A `zones` row: a zone announced during the day.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct ZoneRow {
    pub seq: i64,
    pub id: String,
    pub feature: String,
    pub announced_ms: i64,
    pub withdrawn_ms: Option<i64>,
    pub affected: i64,
    pub crc: i64,
}

/// The columns of a `zones` row, in the order [`ZoneRow::read`] reads them.
pub(super) const ZONE_COLUMNS: &str = "seq, id, feature, announced_ms, withdrawn_ms, affected, crc";

impl ZoneRow {
    pub(super) fn new(seq: i64, zone: &super::StoredZone) -> Self {
        let mut row = ZoneRow {
            seq,
            id: zone.id.clone(),
            feature: zone.feature.clone(),
            announced_ms: zone.announced.0,
            withdrawn_ms: zone.withdrawn.map(|t| t.0),
            affected: zone.affected as i64,
            crc: 0,
        };
        row.crc = row.sum();
        row
    }

    pub(super) fn sum(&self) -> i64 {
        RowSum::new("zones")
            .int(self.seq)
            .text(&self.id)
            .text(&self.feature)
            .int(self.announced_ms)
            .opt_int(self.withdrawn_ms)
            .int(self.affected)
            .finish()
    }

    pub(super) fn read<R: Columns>(row: &R) -> Result<Self, R::Error> {
        Ok(ZoneRow {
            seq: row.int(0)?,
            id: row.text(1)?,
            feature: row.text(2)?,
            announced_ms: row.int(3)?,
            withdrawn_ms: row.opt_int(4)?,
            affected: row.int(5)?,
            crc: row.int(6)?,
        })
    }

    pub(super) fn zone(&self, path: &str) -> Result<super::StoredZone, StoreError> {
        if self.sum() != self.crc {
            let row = format!("zones row seq {} (id {:?})", self.seq, self.id);
            return Err(damaged(path, &row, MISMATCH));
        }
        Ok(super::StoredZone {
            id: self.id.clone(),
            feature: self.feature.clone(),
            announced: Instant(self.announced_ms),
            withdrawn: self.withdrawn_ms.map(Instant),
            affected: usize::try_from(self.affected).unwrap_or(0),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_column_is_covered() {
        let a = RowSum::new("flights")
            .int(1)
            .text("a")
            .opt_int(None)
            .finish();
        assert_ne!(a, RowSum::new("flights").int(1).text("a").int(0).finish());
        assert_ne!(
            a,
            RowSum::new("events")
                .int(1)
                .text("a")
                .opt_int(None)
                .finish()
        );
        // Framing: moving a byte from one text to the next changes the sum.
        assert_ne!(
            RowSum::new("t").text("ab").text("c").finish(),
            RowSum::new("t").text("a").text("bc").finish()
        );
    }
}
