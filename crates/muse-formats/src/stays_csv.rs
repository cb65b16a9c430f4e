//! `stays.csv`: one row per stay of every flight that flies, for a table of where each drone
//! is when.
//!
//! The columns, in order, are [`STAYS_COLUMNS`]: the request, the leg (1 for the first; a
//! plan without battery swaps has one), the stay's number in the whole trip (1 for the
//! take-off), the node, the arrival and the departure — each as RFC 3339 text in the world's
//! offset and as seconds since the scenario's local midnight, with milliseconds, as in
//! [`flights_csv`](crate::flights_csv) — and `hover_s`, departure − arrival (0 where the drone
//! flies straight through, and at a take-off or landing).
//!
//! The stays are those of the final plan (docs/reference.md#zones-announced-during-the-day: a
//! replanned or diverted flight's new plan), or of the committed part of a flight left in
//! contingency (which lands nowhere: its last stay is where it is stranded). A multi-leg trip
//! (docs/reference.md#multi-leg-trips) lists the station of a battery swap twice: the landing, the
//! last stay of a leg, then the take-off, the first of the next; the time on the ground between
//! them is no stay. Rejected and cancelled requests fly nothing and have no rows.

use muse_model::plan::Fate;
use muse_model::{Airspace, Instant, UtcOffset};

use crate::flights_csv::{day_s, number};
use crate::plans::PlanRecord;
use crate::table::CsvWriter;

/// The header of `stays.csv` (in a layered airspace, `layer` follows `node`).
pub const STAYS_COLUMNS: [&str; 9] = [
    "request",
    "leg",
    "stay",
    "node",
    "arrive",
    "arrive_day_s",
    "depart",
    "depart_day_s",
    "hover_s",
];

/// The table of the stays of `records`, header first, flights in their order. Instants are
/// written in `offset`, and as seconds since `day_start` (the scenario's local midnight); in a
/// layered `airspace`, each stay's node as its flat id and its layer.
///
/// ```
/// use muse_formats::stays_csv::write_stays_csv;
/// use muse_formats::plans::PlanRecord;
/// use muse_model::{Instant, Millis, NodeId, Plan, Stay, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[103.8, 1.3], [103.81, 1.3]]}, "properties": {"from": "A", "to": "B"}}]}"#, "a").unwrap();
/// let plan = Plan { path: vec![
///     Stay { node: NodeId(0), arrive: Instant(0), depart: Instant(2_500) },
///     Stay { node: NodeId(1), arrive: Instant(136_500), depart: Instant(136_500) },
/// ] };
/// let r = PlanRecord::first("r1".into(), "A".into(), "B".into(), Instant(0), Ok(plan),
///     Some(Millis(134_000)), 2);
/// let csv = write_stays_csv(&[r], &air, UtcOffset(0), Instant(0));
/// assert_eq!(csv, "request,leg,stay,node,arrive,arrive_day_s,depart,depart_day_s,hover_s\n\
///     r1,1,1,A,1970-01-01T00:00:00.000+00:00,0.000,1970-01-01T00:00:02.500+00:00,2.500,2.5\n\
///     r1,1,2,B,1970-01-01T00:02:16.500+00:00,136.500,1970-01-01T00:02:16.500+00:00,136.500,0.0\n");
/// ```
pub fn write_stays_csv(
    records: &[PlanRecord],
    airspace: &Airspace,
    offset: UtcOffset,
    day_start: Instant,
) -> String {
    let layered = airspace.layers().is_some();
    let mut columns = STAYS_COLUMNS.to_vec();
    if layered {
        columns.insert(4, "layer");
    }
    let mut out = CsvWriter::new(&columns);
    for record in records {
        let plan = match (&record.fate, record.final_plan()) {
            (Some(Fate::Contingency(committed)), _) => committed,
            (_, Some(plan)) => plan,
            (_, None) => continue,
        };
        let mut count = 0;
        for (k, leg) in plan.legs().enumerate() {
            for stay in leg {
                count += 1;
                let mut row = vec![
                    record.request.clone(),
                    (k + 1).to_string(),
                    count.to_string(),
                    airspace
                        .flat()
                        .node(airspace.flat_node(stay.node))
                        .id
                        .clone(),
                    stay.arrive.to_rfc3339(offset),
                    day_s(stay.arrive, day_start),
                    stay.depart.to_rfc3339(offset),
                    day_s(stay.depart, day_start),
                    number((stay.depart - stay.arrive).as_secs_f64()),
                ];
                if layered {
                    row.insert(4, airspace.node_layer(stay.node).to_string());
                }
                out.row(&row);
            }
        }
    }
    out.finish()
}

#[cfg(test)]
mod tests {
    use muse_model::testing::plan;
    use muse_model::{Airspace, Layers, Millis};

    use super::*;

    #[test]
    fn layered_stays_have_a_layer_column() {
        let layers = Layers {
            count: 3,
            ..Layers::default()
        };
        let air = Airspace::line(&[1_000.0]).layered(&layers).unwrap();
        // A at layer 1, climbing to 2, along to B at 2, down to B at 1.
        let flown = plan(&[
            (0, 0, 0),
            (2, 1_829, 1_829),
            (3, 121_829, 121_829),
            (1, 123_658, 123_658),
        ]);
        let r = PlanRecord::first(
            "r1".into(),
            "A".into(),
            "B".into(),
            Instant(0),
            Ok(flown.clone()),
            Some(Millis(120_000)),
            2,
        );
        let csv = write_stays_csv(std::slice::from_ref(&r), &air, UtcOffset(0), Instant(0));
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(
            rows[0],
            "request,leg,stay,node,layer,arrive,arrive_day_s,depart,depart_day_s,hover_s"
        );
        let nodes: Vec<(&str, &str)> = rows[1..]
            .iter()
            .map(|r| {
                let cells: Vec<&str> = r.split(',').collect();
                (cells[3], cells[4])
            })
            .collect();
        assert_eq!(nodes, [("A", "1"), ("A", "2"), ("B", "2"), ("B", "1")]);
        // The same flight in the flat airspace, nodes at layer 1: no column.
        let flat = PlanRecord {
            result: Ok(plan(&[(0, 0, 0), (1, 120_000, 120_000)])),
            ..r
        };
        let csv = write_stays_csv(&[flat], air.flat(), UtcOffset(0), Instant(0));
        assert_eq!(csv.lines().next(), Some(STAYS_COLUMNS.join(",").as_str()));
    }
}
