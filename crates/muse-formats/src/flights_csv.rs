//! `flights.csv`: one row per request, the plans file flattened into a table for a
//! spreadsheet, pandas or R.
//!
//! The columns, in order, are [`FLIGHTS_COLUMNS`]; the values of a row are those of the
//! request's plans line ([`plan_line`]): the status, the reason, the times and delays of the
//! final plan. Every instant is given twice: as RFC 3339 text in the world's offset (`takeoff`)
//! and as seconds since the start of the scenario's day, 00:00 local time, with milliseconds
//! (`takeoff_day_s`: 08:15 is `29700.000`; a time on the next day is above `86400`), which
//! any reader parses as a number. A cell with no value (a rejected request's take-off, say) is
//! empty. Durations are seconds, as in the plans file.
//!
//! `total_delay_s` is `landing − (requested departure + free flow)`, the ground and the air
//! delay together; `legs` the legs of the final plan (1 without battery swaps); `changes` the
//! zone announcements that changed the flight (docs/reference.md#zones-announced-during-the-day).

use muse_model::{Airspace, Instant, UtcOffset};

use crate::plans::{PlanRecord, plan_line};
use crate::table::CsvWriter;

/// The header of `flights.csv`.
pub const FLIGHTS_COLUMNS: [&str; 22] = [
    "request",
    "status",
    "reason",
    "origin",
    "destination",
    "requested_departure",
    "requested_departure_day_s",
    "takeoff",
    "takeoff_day_s",
    "landing",
    "landing_day_s",
    "airborne_s",
    "free_flow_s",
    "air_delay_s",
    "ground_delay_s",
    "total_delay_s",
    "distance_m",
    "legs",
    "expanded",
    "changes",
    "extra_delay_s",
    "diverted_to",
];

/// The table of `records`, header first: one row per record, in their order. Instants are
/// written in `offset`, and as seconds since `day_start` (the scenario's local midnight).
///
/// ```
/// use muse_formats::flights_csv::write_flights_csv;
/// use muse_formats::plans::PlanRecord;
/// use muse_model::{Instant, Millis, RejectReason, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": []}"#, "a").unwrap();
/// let r = PlanRecord::first("r1".into(), "A".into(), "B".into(), Instant(3_600_000),
///     Err(RejectReason::OutOfRange), Some(Millis(1_500_000)), 0);
/// let midnight = Instant(-8 * 3_600_000); // 1970-01-01T00:00+08:00
/// let csv = write_flights_csv(&[r], &air, UtcOffset::SINGAPORE, midnight);
/// assert_eq!(csv.lines().nth(1).unwrap(),
///     "r1,rejected,out_of_range,A,B,1970-01-01T09:00:00.000+08:00,32400.000,,,,,,1500.0,,,,,,0,0,,");
/// ```
pub fn write_flights_csv(
    records: &[PlanRecord],
    airspace: &Airspace,
    offset: UtcOffset,
    day_start: Instant,
) -> String {
    let mut out = CsvWriter::new(&FLIGHTS_COLUMNS);
    for record in records {
        let line = plan_line(airspace, offset, record);
        let plan = record.final_plan();
        let committed = match &record.fate {
            Some(muse_model::plan::Fate::Contingency(c)) => Some(c),
            _ => None,
        };
        let takeoff = plan.or(committed).map(muse_model::Plan::takeoff);
        let landing = plan.map(muse_model::Plan::landing);
        // Defined where the air delay is: a plan to the destination, a free flow to compare.
        let total_delay = line
            .air_delay_s
            .and_then(|_| Some(landing? - record.requested_departure - record.free_flow?));
        let num = |v: Option<f64>| v.map(number).unwrap_or_default();
        out.row(&[
            line.request,
            line.status,
            line.reason.unwrap_or_default(),
            line.origin.unwrap_or_default(),
            line.destination.unwrap_or_default(),
            line.requested_departure,
            day_s(record.requested_departure, day_start),
            line.takeoff.unwrap_or_default(),
            takeoff.map(|t| day_s(t, day_start)).unwrap_or_default(),
            line.landing.unwrap_or_default(),
            landing.map(|t| day_s(t, day_start)).unwrap_or_default(),
            num(line.airborne_s),
            num(line.free_flow_s),
            num(line.air_delay_s),
            num(line.ground_delay_s),
            num(total_delay.map(muse_model::Millis::as_secs_f64)),
            num(line.distance_m),
            plan.map(|p| p.leg_count().to_string()).unwrap_or_default(),
            line.expanded.to_string(),
            record.changes.len().to_string(),
            num(line.extra_delay_s),
            line.diverted_to.unwrap_or_default(),
        ]);
    }
    out.finish()
}

/// `t` as seconds since `day_start`, with exactly three decimals (milliseconds).
///
/// ```
/// use muse_formats::flights_csv::day_s;
/// use muse_model::Instant;
/// assert_eq!(day_s(Instant(29_700_250), Instant(0)), "29700.250");
/// assert_eq!(day_s(Instant(-1_500), Instant(0)), "-1.500");
/// ```
pub fn day_s(t: Instant, day_start: Instant) -> String {
    let ms = (t - day_start).0;
    let sign = if ms < 0 { "-" } else { "" };
    let ms = ms.unsigned_abs();
    format!("{sign}{}.{:03}", ms / 1_000, ms % 1_000)
}

/// A number of seconds or metres as the plans file writes it (`847.2`, `0.0`).
pub(crate) fn number(x: f64) -> String {
    serde_json::Value::from(x).to_string()
}
