//! The end of a run: every planned flight the service holds — this run's and every earlier
//! one's — fetched page by page and checked together by the independent verifier
//! (`muse_verify`) against the service's airspace, zones and parameters.

use std::collections::HashSet;

use muse_airspace::closures::resolve;
use muse_formats::plans::read_listed_plans;
use muse_model::{Instant, Millis};
use muse_verify::recorded::Recorded;
use muse_verify::verify;
use serde::{Deserialize, Serialize};

use crate::error::LoadError;
use crate::server::{Server, ServerWorld};

/// Flights per page when fetching.
pub const PAGE: usize = 2_000;

/// Most violations (and duplicated or missing ids) kept in a [`Verification`].
pub const KEPT: usize = 20;

/// What the verifier found, and whether the listing holds what the run was told.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verification {
    /// Distinct planned flights checked (every one the service lists).
    pub flights: usize,
    /// Of which this run's (ids with its prefix).
    pub this_run: usize,
    /// Take-off of the earliest flight and landing of the latest, RFC 3339 (the range the
    /// zones were resolved over, give or take a day).
    pub span: Option<[String; 2]>,
    /// Number of violations.
    pub violations: usize,
    /// The first [`KEPT`] violations, as the verifier words them.
    pub first_violations: Vec<String>,
    /// Flights the listing returned more than once (across pages); each is checked once.
    pub duplicates: usize,
    /// The first [`KEPT`] duplicated ids.
    pub first_duplicates: Vec<String>,
    /// Flights this run was answered `planned` for that the listing does not show as planned
    /// (cancelled since by someone, or lost).
    pub missing: usize,
    /// The first [`KEPT`] missing ids.
    pub first_missing: Vec<String>,
    /// Whether the listing was checked for completeness (every flight of the run answered
    /// `planned` listed): only for runs shorter than the service's retention, after which
    /// ended flights leave its memory by design.
    pub completeness_checked: bool,
}

impl Verification {
    /// Whether every rule holds and the listing is exactly consistent: no flight listed twice,
    /// none of this run's planned flights missing.
    pub fn ok(&self) -> bool {
        self.violations == 0 && self.duplicates == 0 && self.missing == 0
    }
}

#[derive(Deserialize)]
struct Page {
    flights: Vec<serde_json::Value>,
    next_after: Option<u64>,
}

/// Fetches every planned flight (`GET /v1/flights?status=planned`, page by page), as the text
/// of a plans JSON Lines file (one docs/reference.md#plans object a line). `progress` is told the
/// number fetched so far after each page.
pub async fn fetch_planned(
    server: &Server,
    mut progress: impl FnMut(usize),
) -> Result<String, LoadError> {
    let mut text = String::new();
    let mut after: Option<u64> = None;
    let mut fetched = 0;
    loop {
        let path = match after {
            None => format!("/v1/flights?status=planned&limit={PAGE}"),
            Some(a) => format!("/v1/flights?status=planned&limit={PAGE}&after={a}"),
        };
        let body = server.get_text(&path).await?;
        let page: Page = serde_json::from_str(&body)
            .map_err(|e| LoadError::bad_answer(format!("GET {path}"), e))?;
        for flight in &page.flights {
            text.push_str(&flight.to_string());
            text.push('\n');
        }
        fetched += page.flights.len();
        progress(fetched);
        match page.next_after {
            Some(a) if after.is_none_or(|b| a > b) => after = Some(a),
            Some(a) => {
                return Err(LoadError::bad_answer(
                    format!("GET {path}"),
                    format!("the page cursor went backwards (next_after {a})"),
                ));
            }
            None => return Ok(text),
        }
    }
}

/// Verifies the planned flights of `plans` (JSON Lines, as [`fetch_planned`] returns them)
/// together, on the service's `world`. Flights whose id starts with `prefix-` are this run's;
/// `acknowledged` are the indices of this run's requests answered `planned`, each of which
/// must be listed. A flight listed twice is counted and checked once.
pub fn check(
    world: &ServerWorld,
    plans: &str,
    prefix: &str,
    acknowledged: &[u64],
) -> Result<Verification, LoadError> {
    const FILE: &str = "GET /v1/flights";
    let records = read_listed_plans(plans, FILE, &world.airspace)
        .map_err(|e| LoadError::bad_answer(FILE, e))?;
    let mut seen: HashSet<String> = HashSet::with_capacity(records.len());
    let mut duplicated: Vec<String> = Vec::new();
    let mut planned = Vec::with_capacity(records.len());
    for r in records {
        if r.result.is_err() {
            continue;
        }
        if seen.insert(r.request.clone()) {
            planned.push(r);
        } else {
            duplicated.push(r.request);
        }
    }
    let recorded =
        Recorded::new(planned, &world.airspace).map_err(|e| LoadError::bad_answer(FILE, e))?;
    let flights = recorded.flights();
    let own = format!("{prefix}-");
    let this_run = seen.iter().filter(|id| id.starts_with(&own)).count();
    let missing: Vec<String> = acknowledged
        .iter()
        .map(|i| format!("{own}{i}"))
        .filter(|id| !seen.contains(id))
        .collect();
    let mut v = Verification {
        flights: flights.len(),
        this_run,
        span: None,
        violations: 0,
        first_violations: Vec::new(),
        duplicates: duplicated.len(),
        first_duplicates: duplicated.into_iter().take(KEPT).collect(),
        missing: missing.len(),
        first_missing: missing.into_iter().take(KEPT).collect(),
        completeness_checked: true,
    };
    let first = flights.iter().map(|f| f.plan.takeoff()).min();
    let last = flights.iter().map(|f| f.plan.landing()).max();
    let (Some(first), Some(last)) = (first, last) else {
        return Ok(v);
    };
    let day = Millis::from_secs(86_400);
    let closures = resolve(
        &world.airspace,
        &world.zones,
        first - day,
        Instant(last.0 + 1) + day,
    )
    .map_err(|e| LoadError::bad_answer("GET /v1/zones", e))?;
    let violations = verify(&world.airspace, &closures, &world.params, &flights);
    v.span = Some([
        first.to_rfc3339(world.offset),
        last.to_rfc3339(world.offset),
    ]);
    v.violations = violations.len();
    v.first_violations = violations
        .iter()
        .take(KEPT)
        .map(ToString::to_string)
        .collect();
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::{FlightParams, UtcOffset};

    /// `A -1 km- B`: 120 s at 30 km/h.
    fn world() -> ServerWorld {
        let airspace = muse_model::Airspace::line(&[1_000.0]);
        ServerWorld {
            label: "test".into(),
            airspace,
            zones: Vec::new(),
            params: FlightParams::default(),
            parameters: serde_json::Value::Null,
            offset: UtcOffset::SINGAPORE,
            skew: Millis::ZERO,
            flights_before: 0,
            retain: None,
        }
    }

    /// A flight `A → B` taking off at `t` s, as the service lists it.
    fn line(id: &str, t: i64) -> String {
        let at = |s: i64| Instant(s * 1_000).to_rfc3339(UtcOffset::SINGAPORE);
        serde_json::json!({
            "request": id, "status": "planned", "reason": null, "origin": "A",
            "destination": "B", "requested_departure": at(t), "takeoff": at(t),
            "landing": at(t + 120), "airborne_s": 120.0, "free_flow_s": 120.0,
            "air_delay_s": 0.0, "ground_delay_s": 0.0, "distance_m": 1000.0, "expanded": 1,
            "path": [{"node": "A", "arrive": at(t), "depart": at(t)},
                     {"node": "B", "arrive": at(t + 120), "depart": at(t + 120)}],
            "operator": "open"
        })
        .to_string()
    }

    #[test]
    fn separated_flights_pass_and_this_run_is_counted() {
        let text = [line("run-1", 0), line("run-2", 1_000), line("old-1", 2_000)].join("\n");
        let v = check(&world(), &text, "run", &[1, 2]).unwrap();
        assert!(v.ok(), "{v:?}");
        assert_eq!(
            (v.flights, v.this_run, v.duplicates, v.missing),
            (3, 2, 0, 0)
        );
        assert_eq!(
            v.span,
            Some([
                "1970-01-01T08:00:00.000+08:00".to_owned(),
                "1970-01-01T08:35:20.000+08:00".to_owned()
            ])
        );
    }

    #[test]
    fn overlapping_flights_are_violations() {
        // Both on A-B at once: the exclusive edge rule and node separation break.
        let text = [line("a", 0), line("b", 60)].join("\n");
        let v = check(&world(), &text, "run", &[]).unwrap();
        assert!(!v.ok());
        assert_eq!(v.this_run, 0);
        assert_eq!(v.violations, v.first_violations.len());
        assert!(
            v.first_violations
                .iter()
                .any(|s| s.starts_with("edge rule"))
        );
    }

    #[test]
    fn a_listing_with_repeats_or_gaps_is_not_ok() {
        // `run-1` listed twice (as a page boundary gone wrong would): checked once, so no
        // self-conflict, but counted; `run-3` was answered planned but is not listed.
        let text = [line("run-1", 0), line("run-2", 1_000), line("run-1", 0)].join("\n");
        let v = check(&world(), &text, "run", &[1, 2, 3]).unwrap();
        assert_eq!(v.violations, 0, "{:?}", v.first_violations);
        assert_eq!((v.flights, v.this_run), (2, 2));
        assert_eq!(
            (v.duplicates, v.first_duplicates.clone()),
            (1, vec!["run-1".to_owned()])
        );
        assert_eq!(
            (v.missing, v.first_missing.clone()),
            (1, vec!["run-3".to_owned()])
        );
        assert!(!v.ok());
    }

    #[test]
    fn nothing_to_check() {
        let v = check(&world(), "", "run", &[]).unwrap();
        assert!(v.ok());
        assert_eq!(v.flights, 0);
        assert!(check(&world(), "{", "run", &[]).is_err());
    }
}
