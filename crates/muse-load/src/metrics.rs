//! The service's own gauges, sampled from `/metrics` during a run: the schedule's
//! reservations and their bytes, the flights held, the store's size and the process's
//! resident memory — a time series that shows whether memory stays flat on long runs.

use std::collections::BTreeMap;

use serde::Serialize;

/// The gauges sampled, by their Prometheus names.
pub const GAUGES: [&str; 5] = [
    "muse_schedule_reservations",
    "muse_schedule_reservation_bytes",
    "process_resident_memory_bytes",
    "muse_flights",
    "muse_store_bytes",
];

/// One sample of the gauges.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MetricPoint {
    /// Seconds since the run's load started (negative: before it).
    pub t_s: f64,
    /// Each gauge of [`GAUGES`] the service reported, by name.
    pub values: BTreeMap<String, f64>,
}

/// First, last and largest value of one gauge over a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Extent {
    /// The first sample.
    pub first: f64,
    /// The last sample.
    pub last: f64,
    /// The largest sample.
    pub max: f64,
}

/// The values of the gauges of [`GAUGES`] in a Prometheus text exposition (unlabelled series
/// only; a gauge missing from the text is missing from the result).
///
/// ```
/// let text = "# TYPE muse_flights gauge\nmuse_flights 12\nmuse_flights_total 3\n";
/// let v = muse_load::metrics::parse_gauges(text);
/// assert_eq!(v.get("muse_flights"), Some(&12.0));
/// assert_eq!(v.len(), 1);
/// ```
pub fn parse_gauges(text: &str) -> BTreeMap<String, f64> {
    let mut out = BTreeMap::new();
    for line in text.lines() {
        if line.starts_with('#') {
            continue;
        }
        let mut parts = line.split_whitespace();
        let (Some(name), Some(value)) = (parts.next(), parts.next()) else {
            continue;
        };
        if GAUGES.contains(&name)
            && let Ok(v) = value.parse::<f64>()
        {
            out.insert(name.to_owned(), v);
        }
    }
    out
}

/// First, last and largest value of each gauge over `series` (only gauges sampled at least
/// once).
pub fn extents(series: &[MetricPoint]) -> BTreeMap<String, Extent> {
    let mut out: BTreeMap<String, Extent> = BTreeMap::new();
    for point in series {
        for (name, &v) in &point.values {
            out.entry(name.clone())
                .and_modify(|e| {
                    e.last = v;
                    e.max = e.max.max(v);
                })
                .or_insert(Extent {
                    first: v,
                    last: v,
                    max: v,
                });
        }
    }
    out
}

/// A byte count for people: `812 B`, `12.3 KiB`, `45.6 MiB`, `1.20 GiB`.
pub fn bytes(v: f64) -> String {
    const K: f64 = 1024.0;
    if v < K {
        format!("{v:.0} B")
    } else if v < K * K {
        format!("{:.1} KiB", v / K)
    } else if v < K * K * K {
        format!("{:.1} MiB", v / (K * K))
    } else {
        format!("{:.2} GiB", v / (K * K * K))
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use super::*;

    #[test]
    fn parses_the_service_exposition() {
        let text = "\
# HELP muse_schedule_reservations Reservations held.
# TYPE muse_schedule_reservations gauge
muse_schedule_reservations 1234
muse_schedule_reservation_bytes 29616
muse_flight_request_seconds_bucket{le=\"0.001\"} 5
muse_flights 77
muse_store_bytes 1.5e6
process_resident_memory_bytes 23068672
garbage
muse_flights_extra 1
";
        let v = parse_gauges(text);
        assert_eq!(v.len(), 5);
        assert_eq!(v["muse_schedule_reservations"], 1234.0);
        assert_eq!(v["muse_store_bytes"], 1.5e6);
        assert_eq!(v["process_resident_memory_bytes"], 23_068_672.0);
    }

    #[test]
    fn first_last_max() {
        let p = |t, r| MetricPoint {
            t_s: t,
            values: BTreeMap::from([("muse_flights".to_owned(), r)]),
        };
        let e = extents(&[p(0.0, 3.0), p(1.0, 9.0), p(2.0, 5.0)]);
        assert_eq!(
            e["muse_flights"],
            Extent {
                first: 3.0,
                last: 5.0,
                max: 9.0
            }
        );
        assert!(extents(&[]).is_empty());
    }

    #[test]
    fn byte_formatting() {
        assert_eq!(bytes(812.0), "812 B");
        assert_eq!(bytes(12_595.0), "12.3 KiB");
        assert_eq!(bytes(23_068_672.0), "22.0 MiB");
        assert_eq!(bytes(1.3e9), "1.21 GiB");
    }
}
