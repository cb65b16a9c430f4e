//! The flights of a plans file (docs/reference.md#built-in-scenarios) as the verifier checks them:
//! each line's request resolved against the airspace, and the flight as it finally stands after
//! zone announcements (docs/reference.md#zones-announced-during-the-day).

use muse_airspace::announced::KnownZones;
use muse_airspace::closures::ClosureError;
use muse_formats::plans::PlanRecord;
use muse_model::{Airspace, Millis, Request, Zone};

use crate::Flight;

/// The records of a plans file with their requests: what [`Recorded::flights`] lends to
/// [`verify`](crate::verify) and [`verify_known`](crate::verify_known).
///
/// ```
/// use muse_formats::plans::read_plans;
/// use muse_model::Airspace;
/// use muse_verify::recorded::Recorded;
///
/// let air = Airspace::line(&[1_000.0]); // A -1 km- B: 120 s at 30 km/h
/// let line = r#"{"request": "r1", "status": "planned", "reason": null, "origin": "A",
///   "destination": "B", "requested_departure": "2026-01-05T09:00:00.000+08:00",
///   "takeoff": "2026-01-05T09:00:00.000+08:00", "landing": "2026-01-05T09:02:00.000+08:00",
///   "airborne_s": 120.0, "free_flow_s": 120.0, "air_delay_s": 0.0, "ground_delay_s": 0.0,
///   "distance_m": 1000.0, "expanded": 2, "path": [
///     {"node": "A", "arrive": "2026-01-05T09:00:00.000+08:00", "depart": "2026-01-05T09:00:00.000+08:00"},
///     {"node": "B", "arrive": "2026-01-05T09:02:00.000+08:00", "depart": "2026-01-05T09:02:00.000+08:00"}]}"#;
/// let records = read_plans(&line.replace('\n', ""), "p.jsonl", &air).unwrap();
/// let recorded = Recorded::new(records, &air).unwrap();
/// let flights = recorded.flights();
/// assert_eq!((flights.len(), flights[0].id), (1, "r1"));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Recorded {
    records: Vec<PlanRecord>,
    /// Each record's request; `None` for an unserved request
    /// (docs/reference.md#airspace-from-pads), which flies nothing and may lack a pad.
    requests: Vec<Option<Request>>,
}

/// A record whose origin or destination the airspace does not have.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("flight `{request}`: field `{field}`: unknown node id `{id}`")]
pub struct UnknownStation {
    /// The record's request id.
    pub request: String,
    /// `origin` or `destination`.
    pub field: &'static str,
    /// The station id the record gives.
    pub id: String,
}

impl Recorded {
    /// The records, each with its request (submitted at its requested departure) on
    /// `airspace`; a station `airspace` does not have is an error naming the flight.
    ///
    /// # Errors
    /// [`UnknownStation`] for the first record whose origin or destination is unknown.
    pub fn new(records: Vec<PlanRecord>, airspace: &Airspace) -> Result<Self, UnknownStation> {
        let requests = records
            .iter()
            .map(|r| {
                if r.result == Err(muse_model::RejectReason::Unserved) {
                    return Ok(None);
                }
                let node = |field: &'static str, id: &str| {
                    airspace.node_id(id).ok_or_else(|| UnknownStation {
                        request: r.request.clone(),
                        field,
                        id: id.to_owned(),
                    })
                };
                Ok(Some(Request {
                    id: r.request.clone(),
                    origin: node("origin", &r.origin)?,
                    destination: node("destination", &r.destination)?,
                    departure: r.requested_departure,
                    submitted: r.requested_departure,
                }))
            })
            .collect::<Result<_, _>>()?;
        Ok(Recorded { records, requests })
    }

    /// The flights that fly, each as it finally stands ([`Flight::last`]): rejected requests
    /// and cancelled flights are left out.
    pub fn flights(&self) -> Vec<Flight<'_>> {
        self.records
            .iter()
            .zip(&self.requests)
            .filter_map(|(r, q)| {
                Flight::last(
                    &r.request,
                    q.as_ref()?,
                    r.result.as_ref().ok(),
                    r.fate.as_ref(),
                )
            })
            .collect()
    }

    /// The records, in the order given.
    pub fn records(&self) -> &[PlanRecord] {
        &self.records
    }
}

/// The zones `flights` are checked against: `zones` resolved on `airspace` over the flights'
/// day and a day either side (from the earliest announcement, if that is sooner), as
/// `muse verify` and the Python package's `verify` check them.
///
/// # Errors
/// A zone that cannot be resolved on the airspace.
pub fn zones_for(
    airspace: &Airspace,
    zones: &[Zone],
    flights: &[Flight<'_>],
) -> Result<KnownZones, ClosureError> {
    let day = Millis::from_secs(86_400);
    let first = flights
        .iter()
        .map(|f| f.plan.takeoff())
        .min()
        .unwrap_or_default();
    let last = flights
        .iter()
        .map(|f| f.plan.landing())
        .max()
        .unwrap_or_default();
    let from = zones
        .iter()
        .filter_map(|z| z.announced)
        .min()
        .map_or(first - day, |n| n.min(first - day));
    KnownZones::resolve(airspace, zones, from, last + day)
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::plan::Fate;
    use muse_model::{Instant, Plan, RejectReason};

    fn record(id: &str, origin: &str, result: Result<Plan, RejectReason>) -> PlanRecord {
        PlanRecord::first(
            id.into(),
            origin.into(),
            "B".into(),
            Instant(0),
            result,
            None,
            0,
        )
    }

    #[test]
    fn rejected_and_cancelled_flights_do_not_fly() {
        let air = Airspace::line(&[1_000.0]);
        let mut cancelled = record("c", "A", Ok(Plan::default()));
        cancelled.fate = Some(Fate::Cancelled);
        let records = vec![
            record("p", "A", Ok(Plan::default())),
            record("r", "A", Err(RejectReason::Unreachable)),
            cancelled,
        ];
        let recorded = Recorded::new(records, &air).unwrap();
        let ids: Vec<&str> = recorded.flights().iter().map(|f| f.id).collect();
        assert_eq!(ids, ["p"]);
        assert_eq!(recorded.records().len(), 3);
    }

    #[test]
    fn an_unserved_request_may_lack_a_pad_and_flies_nothing() {
        let air = Airspace::line(&[1_000.0]);
        let records = vec![
            record("u", "", Err(RejectReason::Unserved)),
            record("p", "A", Ok(Plan::default())),
        ];
        let recorded = Recorded::new(records, &air).unwrap();
        let ids: Vec<&str> = recorded.flights().iter().map(|f| f.id).collect();
        assert_eq!(ids, ["p"]);
        // Any other record still needs its stations.
        let bad = vec![record("r", "", Err(RejectReason::OutOfRange))];
        assert!(Recorded::new(bad, &air).is_err());
    }

    #[test]
    fn an_unknown_station_names_the_flight_and_field() {
        let air = Airspace::line(&[1_000.0]);
        let e = Recorded::new(vec![record("x", "Q", Err(RejectReason::Unreachable))], &air)
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "flight `x`: field `origin`: unknown node id `Q`"
        );
    }
}
