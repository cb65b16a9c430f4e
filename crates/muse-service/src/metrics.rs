//! Counters and histograms, exposed at `/metrics` in the Prometheus text format (0.0.4).

use std::fmt::Write as _;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use muse_model::RejectReason;

/// A histogram with fixed bucket bounds (seconds).
#[derive(Debug)]
pub struct Histogram {
    bounds: &'static [f64],
    counts: Vec<AtomicU64>,
    sum_ns: AtomicU64,
    count: AtomicU64,
}

/// Bounds for latencies: 50 µs to 2.5 s.
const LATENCY_BOUNDS: &[f64] = &[
    0.000_05, 0.000_1, 0.000_25, 0.000_5, 0.001, 0.002_5, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5,
    1.0, 2.5,
];
/// Bounds for group sizes.
const GROUP_BOUNDS: &[f64] = &[1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0];

impl Histogram {
    fn new(bounds: &'static [f64]) -> Self {
        Histogram {
            bounds,
            counts: (0..bounds.len()).map(|_| AtomicU64::new(0)).collect(),
            sum_ns: AtomicU64::new(0),
            count: AtomicU64::new(0),
        }
    }

    /// Records a duration.
    pub fn observe(&self, d: Duration) {
        self.observe_value(d.as_secs_f64());
    }

    /// Records a value.
    pub fn observe_value(&self, v: f64) {
        if let Some(i) = self.bounds.iter().position(|&b| v <= b) {
            self.counts[i].fetch_add(1, Ordering::Relaxed);
        }
        self.sum_ns.fetch_add((v * 1e9) as u64, Ordering::Relaxed);
        self.count.fetch_add(1, Ordering::Relaxed);
    }

    fn write(&self, out: &mut String, name: &str, help: &str) {
        let _ = writeln!(out, "# HELP {name} {help}\n# TYPE {name} histogram");
        let mut cumulative = 0;
        for (b, c) in self.bounds.iter().zip(&self.counts) {
            cumulative += c.load(Ordering::Relaxed);
            let _ = writeln!(out, "{name}_bucket{{le=\"{b}\"}} {cumulative}");
        }
        let count = self.count.load(Ordering::Relaxed);
        let _ = writeln!(out, "{name}_bucket{{le=\"+Inf\"}} {count}");
        let sum = self.sum_ns.load(Ordering::Relaxed) as f64 / 1e9;
        let _ = writeln!(out, "{name}_sum {sum}\n{name}_count {count}");
    }
}

/// The outcomes of `POST /v1/flights`, as counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanOutcome {
    /// A new flight planned.
    Planned,
    /// A new request rejected, for this reason.
    Rejected(RejectReason),
    /// A retry answered with the first answer.
    Repeated,
    /// The same id with other content.
    Conflict,
    /// Bad input (4xx before planning).
    Invalid,
}

/// Every metric of the service.
#[derive(Debug)]
pub struct Metrics {
    planned: AtomicU64,
    rejected: [AtomicU64; RejectReason::SERVICE.len()],
    repeated: AtomicU64,
    conflict: AtomicU64,
    invalid: AtomicU64,
    cancelled: AtomicU64,
    cancel_refused: AtomicU64,
    rate_limited: AtomicU64,
    unauthorized: AtomicU64,
    zones_announced: AtomicU64,
    zones_withdrawn: AtomicU64,
    event_lags: AtomicU64,
    archived_flights: AtomicU64,
    archived_events: AtomicU64,
    archive_failures: AtomicU64,
    /// Time from receiving a `POST /v1/flights` to answering it (queue, plan, durable write).
    pub request_latency: Histogram,
    /// Time the planner spends on one request.
    pub plan_latency: Histogram,
    /// Time of one group commit (`write` + `fdatasync`).
    pub store_latency: Histogram,
    /// Records per group commit.
    pub group_size: Histogram,
    reservations: AtomicU64,
    reservation_bytes: AtomicU64,
    flights: AtomicU64,
    store_bytes: AtomicU64,
    flights_stored: AtomicU64,
}

impl Default for Metrics {
    fn default() -> Self {
        Metrics {
            planned: AtomicU64::new(0),
            rejected: std::array::from_fn(|_| AtomicU64::new(0)),
            repeated: AtomicU64::new(0),
            conflict: AtomicU64::new(0),
            invalid: AtomicU64::new(0),
            cancelled: AtomicU64::new(0),
            cancel_refused: AtomicU64::new(0),
            rate_limited: AtomicU64::new(0),
            unauthorized: AtomicU64::new(0),
            zones_announced: AtomicU64::new(0),
            zones_withdrawn: AtomicU64::new(0),
            event_lags: AtomicU64::new(0),
            archived_flights: AtomicU64::new(0),
            archived_events: AtomicU64::new(0),
            archive_failures: AtomicU64::new(0),
            request_latency: Histogram::new(LATENCY_BOUNDS),
            plan_latency: Histogram::new(LATENCY_BOUNDS),
            store_latency: Histogram::new(LATENCY_BOUNDS),
            group_size: Histogram::new(GROUP_BOUNDS),
            reservations: AtomicU64::new(0),
            reservation_bytes: AtomicU64::new(0),
            flights: AtomicU64::new(0),
            store_bytes: AtomicU64::new(0),
            flights_stored: AtomicU64::new(0),
        }
    }
}

fn inc(c: &AtomicU64) {
    c.fetch_add(1, Ordering::Relaxed);
}

impl Metrics {
    /// Counts one answer to `POST /v1/flights`.
    pub fn count_plan(&self, outcome: PlanOutcome) {
        match outcome {
            PlanOutcome::Planned => inc(&self.planned),
            PlanOutcome::Rejected(r) => {
                let i = RejectReason::SERVICE
                    .iter()
                    .position(|&x| x == r)
                    .unwrap_or_default();
                inc(&self.rejected[i]);
            }
            PlanOutcome::Repeated => inc(&self.repeated),
            PlanOutcome::Conflict => inc(&self.conflict),
            PlanOutcome::Invalid => inc(&self.invalid),
        }
    }

    /// Counts a cancellation, done or refused.
    pub fn count_cancel(&self, done: bool) {
        inc(if done {
            &self.cancelled
        } else {
            &self.cancel_refused
        });
    }

    /// Counts a request refused by the rate limit.
    pub fn count_rate_limited(&self) {
        inc(&self.rate_limited);
    }

    /// Counts a zone announced (`true`) or withdrawn (`false`).
    pub fn count_zone(&self, announced: bool) {
        inc(if announced {
            &self.zones_announced
        } else {
            &self.zones_withdrawn
        });
    }

    /// Counts flights and events moved to the archive by a pass.
    pub fn count_archived(&self, flights: u64, events: u64) {
        self.archived_flights.fetch_add(flights, Ordering::Relaxed);
        self.archived_events.fetch_add(events, Ordering::Relaxed);
    }

    /// Counts an archive pass that failed.
    pub fn count_archive_failure(&self) {
        inc(&self.archive_failures);
    }

    /// Counts an event-stream listener that fell behind the live channel and read the
    /// history instead.
    pub fn count_event_lag(&self) {
        inc(&self.event_lags);
    }

    /// Counts a request refused for want of a valid token.
    pub fn count_unauthorized(&self) {
        inc(&self.unauthorized);
    }

    /// Sets how many flights the store holds.
    pub fn set_flights_stored(&self, n: u64) {
        self.flights_stored.store(n, Ordering::Relaxed);
    }

    /// How many flights the store holds.
    pub fn flights_stored(&self) -> u64 {
        self.flights_stored.load(Ordering::Relaxed)
    }

    /// Sets the size of the store on disk.
    pub fn set_store_bytes(&self, bytes: u64) {
        self.store_bytes.store(bytes, Ordering::Relaxed);
    }

    /// Sets the gauges of the schedule and the flights held.
    pub fn set_sizes(&self, reservations: usize, reservation_bytes: usize, flights: usize) {
        self.reservations
            .store(reservations as u64, Ordering::Relaxed);
        self.reservation_bytes
            .store(reservation_bytes as u64, Ordering::Relaxed);
        self.flights.store(flights as u64, Ordering::Relaxed);
    }

    /// The Prometheus text exposition.
    pub fn render(&self) -> String {
        let mut out = String::with_capacity(4096);
        self.render_counters(&mut out);
        self.render_histograms_and_gauges(&mut out);
        out
    }

    fn render_counters(&self, out: &mut String) {
        let get = |c: &AtomicU64| c.load(Ordering::Relaxed);
        out.push_str("# HELP muse_flight_requests_total Answers to POST /v1/flights, by outcome.\n# TYPE muse_flight_requests_total counter\n");
        let _ = writeln!(
            out,
            "muse_flight_requests_total{{outcome=\"planned\"}} {}",
            get(&self.planned)
        );
        for (r, c) in RejectReason::SERVICE.iter().zip(&self.rejected) {
            let _ = writeln!(
                out,
                "muse_flight_requests_total{{outcome=\"rejected\",reason=\"{}\"}} {}",
                r.as_str(),
                get(c)
            );
        }
        let _ = writeln!(
            out,
            "muse_flight_requests_total{{outcome=\"repeated\"}} {}",
            get(&self.repeated)
        );
        let _ = writeln!(
            out,
            "muse_flight_requests_total{{outcome=\"conflict\"}} {}",
            get(&self.conflict)
        );
        let _ = writeln!(
            out,
            "muse_flight_requests_total{{outcome=\"invalid\"}} {}",
            get(&self.invalid)
        );
        out.push_str("# HELP muse_cancellations_total Cancellations, done or refused (after take-off or not planned).\n# TYPE muse_cancellations_total counter\n");
        let _ = writeln!(
            out,
            "muse_cancellations_total{{outcome=\"done\"}} {}",
            get(&self.cancelled)
        );
        let _ = writeln!(
            out,
            "muse_cancellations_total{{outcome=\"refused\"}} {}",
            get(&self.cancel_refused)
        );
        out.push_str("# HELP muse_refused_requests_total Requests refused before reaching a handler.\n# TYPE muse_refused_requests_total counter\n");
        let _ = writeln!(
            out,
            "muse_refused_requests_total{{reason=\"rate_limited\"}} {}",
            get(&self.rate_limited)
        );
        let _ = writeln!(
            out,
            "muse_refused_requests_total{{reason=\"unauthorized\"}} {}",
            get(&self.unauthorized)
        );
        out.push_str("# HELP muse_zones_total Zones announced and withdrawn during the day (docs/reference.md#zones-announced-during-the-day).\n# TYPE muse_zones_total counter\n");
        let _ = writeln!(
            out,
            "muse_zones_total{{change=\"announced\"}} {}\nmuse_zones_total{{change=\"withdrawn\"}} {}",
            get(&self.zones_announced),
            get(&self.zones_withdrawn)
        );
        out.push_str("# HELP muse_event_lags_total Times an event stream fell behind the live events and read the history instead.\n# TYPE muse_event_lags_total counter\n");
        let _ = writeln!(out, "muse_event_lags_total {}", get(&self.event_lags));
        let _ = writeln!(
            out,
            "# HELP muse_archived_total Rows moved from the hot tables to the archive files by \
             this service.\n# TYPE muse_archived_total counter\n\
             muse_archived_total{{table=\"flights\"}} {}\nmuse_archived_total{{table=\"events\"}} {}\n\
             # HELP muse_archive_failures_total Archive passes that failed (said on standard \
             error; the next pass tries again).\n# TYPE muse_archive_failures_total counter\n\
             muse_archive_failures_total {}",
            get(&self.archived_flights),
            get(&self.archived_events),
            get(&self.archive_failures)
        );
    }

    fn render_histograms_and_gauges(&self, out: &mut String) {
        let get = |c: &AtomicU64| c.load(Ordering::Relaxed);
        self.request_latency.write(
            out,
            "muse_flight_request_seconds",
            "Time from receiving POST /v1/flights to answering it: queue, planning and durable write.",
        );
        self.plan_latency
            .write(out, "muse_plan_seconds", "Planner time per request.");
        self.store_latency.write(
            out,
            "muse_store_commit_seconds",
            "Time of one group commit to the store (write and fdatasync).",
        );
        self.group_size
            .write(out, "muse_store_group_records", "Records per group commit.");
        let gauges = [
            (
                "muse_schedule_reservations",
                "Reservations held by the live schedule.",
                get(&self.reservations),
            ),
            (
                "muse_schedule_reservation_bytes",
                "Memory of the live schedule's reservation lists, bytes.",
                get(&self.reservation_bytes),
            ),
            (
                "muse_flights",
                "Flights held in memory: those the live schedule holds (the store keeps every flight).",
                get(&self.flights),
            ),
            (
                "muse_flights_stored",
                "Flights stored: every request answered, for the life of the store.",
                get(&self.flights_stored),
            ),
            (
                "muse_store_bytes",
                "Size of the store on disk (database and WAL), bytes.",
                get(&self.store_bytes),
            ),
        ];
        for (name, help, v) in gauges {
            let _ = writeln!(out, "# HELP {name} {help}\n# TYPE {name} gauge\n{name} {v}");
        }
        if let Some(rss) = resident_bytes() {
            let _ = writeln!(
                out,
                "# HELP process_resident_memory_bytes Resident memory of the service process.\n\
                 # TYPE process_resident_memory_bytes gauge\nprocess_resident_memory_bytes {rss}"
            );
        }
    }
}

/// Resident memory of this process (Linux: `/proc/self/statm`, in pages of 4 KiB).
fn resident_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096)
}
