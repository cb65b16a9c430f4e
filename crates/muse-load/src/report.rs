//! The report of a run: counts, throughput, latency, the service's gauges over time and the
//! verification — written as JSON and summarised for the terminal.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::client::{LoadRun, Sample};
use crate::config::ConfigSummary;
use crate::metrics::{Extent, MetricPoint, bytes, extents};
use crate::outcome::Outcome;
use crate::stats::Latency;
use crate::verify::Verification;

/// How the requests ended.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Counts {
    /// Requests sent.
    pub sent: u64,
    /// Requests that got an HTTP answer (any status).
    pub answered: u64,
    /// Planned (`201`).
    pub planned: u64,
    /// Rejected by the planner (`200`), all reasons.
    pub rejected: u64,
    /// Rejected, by reason.
    pub rejected_by_reason: BTreeMap<String, u64>,
    /// Requests without a planning answer: transport failures and HTTP errors.
    pub errors: u64,
    /// Errors by kind (`transport: connect`, `429 rate_limited`, …).
    pub errors_by_kind: BTreeMap<String, u64>,
    /// Answers by HTTP status.
    pub http_status: BTreeMap<String, u64>,
}

impl Counts {
    /// The counts of `samples`, of `sent` requests.
    pub fn of(samples: &[Sample], sent: u64) -> Self {
        let mut c = Counts {
            sent,
            ..Counts::default()
        };
        for s in samples {
            if s.status != 0 {
                c.answered += 1;
                *c.http_status.entry(s.status.to_string()).or_default() += 1;
            }
            match &s.outcome {
                Outcome::Planned => c.planned += 1,
                Outcome::Rejected(r) => {
                    c.rejected += 1;
                    *c.rejected_by_reason
                        .entry(r.as_str().to_owned())
                        .or_default() += 1;
                }
                Outcome::Error(kind) => {
                    c.errors += 1;
                    *c.errors_by_kind.entry(kind.to_string()).or_default() += 1;
                }
            }
        }
        c
    }

    /// Requests sent whose end was never recorded (0 unless a client task failed).
    pub fn unaccounted(&self) -> u64 {
        self.sent
            .saturating_sub(self.planned + self.rejected + self.errors)
    }
}

/// Requests per second over the run's wall time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Throughput {
    /// HTTP answers per second.
    pub answered_per_s: f64,
    /// Planned flights per second.
    pub planned_per_s: f64,
    /// Requests sent per second.
    pub sent_per_s: f64,
}

/// How well an open-loop or paced run kept to its schedule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OpenLoop {
    /// Open loop: requests due while the in-flight cap was reached, which waited for a slot.
    /// Paced: requests due while every client was busy, which waited for one.
    pub waited_for_slot: u64,
    /// Requests sent more than `late_threshold_ms` after their due time (the generator could
    /// not keep up, or in a paced run every client was busy; their latency still counts from
    /// the due time).
    pub late: u64,
    /// The lateness threshold, ms: 10 in open loop, 1 paced.
    pub late_threshold_ms: f64,
    /// Send time minus due time: in open loop the dispatcher's own lateness, including the
    /// async timer's millisecond granularity; paced, also the wait for a free client.
    pub send_lag_ms: Latency,
    /// Latency of the planning answers measured from sending instead of from the due time:
    /// what the service alone took, without the generator's lag.
    pub from_send_ms: Latency,
}

/// The service's gauges over the run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Gauges {
    /// First, last and largest value of each gauge.
    pub extents: BTreeMap<String, Extent>,
    /// Every sample (about one a second, one just before the load and one after it).
    pub series: Vec<MetricPoint>,
}

/// What the service is, as the run found it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ServerSummary {
    /// Its description of the airspace and zones.
    pub airspace: String,
    /// Stations.
    pub stations: usize,
    /// Origin–destination pairs drawn from.
    pub od_pairs: usize,
    /// Flight parameters, as `/healthz` gives them.
    pub parameters: serde_json::Value,
    /// Its clock minus this machine's, ms.
    pub clock_skew_ms: i64,
    /// Flights it held before the run.
    pub flights_before: u64,
}

/// Everything a run measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// When the load started (the service's clock, RFC 3339).
    pub started: String,
    /// The parameters of the run.
    pub config: ConfigSummary,
    /// The service.
    pub server: ServerSummary,
    /// How the requests ended.
    pub counts: Counts,
    /// From the first request due (or sent) to the last finished, s.
    pub wall_s: f64,
    /// Throughput over `wall_s`.
    pub throughput: Throughput,
    /// Latency of the planning answers (planned or rejected), ms.
    pub latency_ms: Latency,
    /// Latency of every request, errors included (to the failure), ms.
    pub latency_all_ms: Latency,
    /// Open loop and paced only: schedule keeping.
    pub open_loop: Option<OpenLoop>,
    /// The service's gauges.
    pub gauges: Gauges,
    /// The verification of every planned flight; `None` with `--no-verify`.
    pub verification: Option<Verification>,
}

impl Report {
    /// Assembles the report of a finished run.
    pub fn new(
        started: String,
        config: ConfigSummary,
        server: ServerSummary,
        run: &LoadRun,
        sent: u64,
        series: Vec<MetricPoint>,
        verification: Option<Verification>,
    ) -> Self {
        let counts = Counts::of(&run.samples, sent);
        let wall_s = run.wall.as_secs_f64();
        let per_s = |n: u64| if wall_s > 0.0 { n as f64 / wall_s } else { 0.0 };
        let mut planning: Vec<u64> = run
            .samples
            .iter()
            .filter(|s| !matches!(s.outcome, Outcome::Error(_)))
            .map(|s| s.latency_ns)
            .collect();
        let mut all: Vec<u64> = run.samples.iter().map(|s| s.latency_ns).collect();
        let open_loop = matches!(config.mode, "open" | "paced").then(|| {
            let mut lag: Vec<u64> = run.samples.iter().map(|s| s.lag_ns).collect();
            let mut from_send: Vec<u64> = run
                .samples
                .iter()
                .filter(|s| !matches!(s.outcome, Outcome::Error(_)))
                .map(|s| s.latency_ns.saturating_sub(s.lag_ns))
                .collect();
            OpenLoop {
                waited_for_slot: run.waited_for_slot,
                late: run.late,
                late_threshold_ms: run.late_threshold.as_secs_f64() * 1e3,
                send_lag_ms: Latency::from_nanos(&mut lag),
                from_send_ms: Latency::from_nanos(&mut from_send),
            }
        });
        Report {
            started,
            config,
            server,
            throughput: Throughput {
                answered_per_s: per_s(counts.answered),
                planned_per_s: per_s(counts.planned),
                sent_per_s: per_s(counts.sent),
            },
            counts,
            wall_s,
            latency_ms: Latency::from_nanos(&mut planning),
            latency_all_ms: Latency::from_nanos(&mut all),
            open_loop,
            gauges: Gauges {
                extents: extents(&series),
                series,
            },
            verification,
        }
    }

    /// The report as pretty JSON, with a final newline.
    pub fn to_json(&self) -> String {
        // Plain data (finite numbers, strings, maps with string keys): cannot fail.
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }

    /// Whether the run found nothing wrong with the service's flights (verification passed or
    /// was not asked for).
    pub fn verified_ok(&self) -> bool {
        self.verification.as_ref().is_none_or(Verification::ok)
    }

    /// The terminal summary, one aligned line per topic (and the first violations, if any).
    pub fn text(&self) -> String {
        let mut o = String::new();
        let c = &self.counts;
        let _ = writeln!(
            o,
            "MUSE load — {}, {}",
            self.config.url, self.server.airspace
        );
        let _ = writeln!(o, "  load          {}", self.describe_load());
        let _ = writeln!(
            o,
            "  ids           {}-0 …, {} flight(s) held before",
            self.config.id_prefix, self.server.flights_before
        );
        let _ = writeln!(
            o,
            "  answered      {} of {} sent in {:.2} s: {:.1} answered/s, {:.1} planned/s",
            c.answered,
            c.sent,
            self.wall_s,
            self.throughput.answered_per_s,
            self.throughput.planned_per_s
        );
        let _ = writeln!(
            o,
            "  planned       {} of {} ({:.1}%)",
            c.planned,
            c.sent,
            if c.sent > 0 {
                100.0 * c.planned as f64 / c.sent as f64
            } else {
                0.0
            }
        );
        let _ = writeln!(
            o,
            "  rejected      {}{}",
            c.rejected,
            listing(&c.rejected_by_reason)
        );
        let lost = c.unaccounted();
        let _ = writeln!(
            o,
            "  errors        {}{}{}",
            c.errors,
            listing(&c.errors_by_kind),
            if lost > 0 {
                format!("; {lost} request(s) unaccounted for")
            } else {
                String::new()
            }
        );
        let from = if self.open_loop.is_some() {
            "from due time"
        } else {
            "from send"
        };
        let _ = writeln!(o, "  latency       {} ({from})", self.latency_ms.line());
        if let Some(ol) = &self.open_loop {
            let _ = writeln!(o, "  from send     {}", ol.from_send_ms.line());
            let waited = if self.config.mode == "paced" {
                let n = self.config.clients.unwrap_or_default();
                if n == 1 {
                    format!("{} due while the one client was busy", ol.waited_for_slot)
                } else {
                    format!("{} due while all {n} clients were busy", ol.waited_for_slot)
                }
            } else {
                format!(
                    "{} waited for a slot (cap {})",
                    ol.waited_for_slot,
                    self.config.max_in_flight.unwrap_or_default()
                )
            };
            let _ = writeln!(
                o,
                "  schedule      send lag p50 {}, p99 {}, max {}; {} sent over {} ms late, {waited}",
                crate::stats::ms(ol.send_lag_ms.p50_ms),
                crate::stats::ms(ol.send_lag_ms.p99_ms),
                crate::stats::ms(ol.send_lag_ms.max_ms),
                ol.late,
                ol.late_threshold_ms,
            );
        }
        self.gauge_lines(&mut o);
        self.verification_lines(&mut o);
        o
    }

    /// The gauges' lines of [`Report::text`].
    fn gauge_lines(&self, o: &mut String) {
        let gauge = |label: &str, name: &str, fmt: &dyn Fn(f64) -> String, o: &mut String| {
            if let Some(e) = self.gauges.extents.get(name) {
                let _ = writeln!(
                    o,
                    "  {label:<13} {} → {}, max {}",
                    fmt(e.first),
                    fmt(e.last),
                    fmt(e.max)
                );
            }
        };
        let count = |v: f64| format!("{v:.0}");
        gauge("reservations", "muse_schedule_reservations", &count, o);
        gauge("reserved", "muse_schedule_reservation_bytes", &bytes, o);
        gauge("resident", "process_resident_memory_bytes", &bytes, o);
        if self.gauges.extents.is_empty() {
            let _ = writeln!(o, "  gauges        none read from /metrics");
        } else {
            let _ = writeln!(
                o,
                "  samples       {} of /metrics, about one a second",
                self.gauges.series.len()
            );
        }
    }

    /// The verification's lines of [`Report::text`].
    fn verification_lines(&self, o: &mut String) {
        let c = &self.counts;
        match &self.verification {
            None => {
                let _ = writeln!(o, "  verified      skipped (--no-verify)");
            }
            Some(v) => {
                let what = format!(
                    "{} planned flights ({} from this run)",
                    v.flights, v.this_run
                );
                if v.violations == 0 {
                    let _ = writeln!(o, "  verified      {what}: OK");
                } else {
                    let _ = writeln!(
                        o,
                        "  verified      FAILED: {what}, {} violation(s); the first:",
                        v.violations
                    );
                    for line in &v.first_violations {
                        let _ = writeln!(o, "    {line}");
                    }
                }
                if v.duplicates > 0 {
                    let _ = writeln!(
                        o,
                        "  listing       FAILED: GET /v1/flights returned {} flight(s) more than once across pages (each checked once): {}",
                        v.duplicates,
                        v.first_duplicates.join(", ")
                    );
                }
                if !v.completeness_checked {
                    let _ = writeln!(
                        o,
                        "  listing       not checked for completeness: the run outlasted the service's retention, so flights that ended have left its memory by design"
                    );
                }
                if v.missing > 0 {
                    let _ = writeln!(
                        o,
                        "  listing       FAILED: {} of the {} flight(s) this run was answered `planned` for are not listed as planned (cancelled since, or lost): {}",
                        v.missing,
                        c.planned,
                        v.first_missing.join(", ")
                    );
                }
            }
        }
    }

    fn describe_load(&self) -> String {
        let s = &self.config;
        let clients = |n: usize| format!("{n} client{}", if n == 1 { "" } else { "s" });
        let mode = match (s.mode, s.rate, s.clients) {
            ("paced", Some(rate), Some(n)) => format!(
                "paced at {rate} requests/s (open-loop schedule) by {}",
                clients(n)
            ),
            (_, Some(rate), _) => format!("open loop at {rate} requests/s"),
            (_, None, Some(n)) => format!("closed loop, {}", clients(n)),
            (_, None, None) => s.mode.to_owned(),
        };
        let stop = match (s.count, s.duration_s) {
            (Some(n), _) => format!("{n} request{}", if n == 1 { "" } else { "s" }),
            (None, Some(d)) => format!("for {d} s"),
            (None, None) => String::new(),
        };
        format!(
            "{mode}, {stop}, seed {}, departures now + {}–{} min, {} pairs ({} pairs)",
            s.seed,
            s.lead_min[0],
            s.lead_min[1],
            s.od.name(),
            self.server.od_pairs
        )
    }
}

/// ` (a 1, b 2)`, or nothing for an empty map.
fn listing(m: &BTreeMap<String, u64>) -> String {
    if m.is_empty() {
        return String::new();
    }
    let parts: Vec<String> = m.iter().map(|(k, v)| format!("{k} {v}")).collect();
    format!(" ({})", parts.join(", "))
}

#[cfg(test)]
#[allow(clippy::float_cmp)] // the values compared are exact by construction
mod tests {
    use super::*;
    use crate::config::{LoadConfig, Mode, Stop};
    use crate::outcome::ErrorKind;
    use muse_model::RejectReason;
    use std::time::Duration;

    fn sample(ms: u64, status: u16, outcome: Outcome) -> Sample {
        Sample {
            index: 0,
            latency_ns: ms * 1_000_000,
            status,
            outcome,
            lag_ns: 0,
        }
    }

    fn server() -> ServerSummary {
        ServerSummary {
            airspace: "test".into(),
            stations: 2,
            od_pairs: 2,
            parameters: serde_json::Value::Null,
            clock_skew_ms: 0,
            flights_before: 0,
        }
    }

    #[test]
    fn counts_add_up_and_latency_excludes_errors() {
        let samples = vec![
            sample(1, 201, Outcome::Planned),
            sample(2, 200, Outcome::Rejected(RejectReason::OutOfRange)),
            sample(3, 200, Outcome::Rejected(RejectReason::OutOfRange)),
            sample(
                50,
                429,
                Outcome::Error(ErrorKind::Http {
                    status: 429,
                    code: "rate_limited".into(),
                }),
            ),
            sample(900, 0, Outcome::Error(ErrorKind::Timeout)),
        ];
        let run = LoadRun {
            samples,
            wall: Duration::from_secs(2),
            waited_for_slot: 0,
            late: 0,
            late_threshold: Duration::ZERO,
        };
        let config = LoadConfig::new("http://x").summary("p");
        let r = Report::new(String::new(), config, server(), &run, 5, Vec::new(), None);
        let c = &r.counts;
        assert_eq!(
            (c.sent, c.answered, c.planned, c.rejected, c.errors),
            (5, 4, 1, 2, 2)
        );
        assert_eq!(c.rejected_by_reason["out_of_range"], 2);
        assert_eq!(c.errors_by_kind["429 rate_limited"], 1);
        assert_eq!(c.errors_by_kind["transport: timeout"], 1);
        assert_eq!(c.http_status["200"], 2);
        assert_eq!(c.unaccounted(), 0);
        assert_eq!(r.latency_ms.count, 3);
        assert_eq!(r.latency_ms.max_ms, 3.0);
        assert_eq!(r.latency_all_ms.max_ms, 900.0);
        assert_eq!(r.throughput.answered_per_s, 2.0);
        assert_eq!(r.throughput.planned_per_s, 0.5);
        assert!(r.open_loop.is_none());
        assert!(r.verified_ok());
        let text = r.text();
        assert!(
            text.contains("  rejected      2 (out_of_range 2)\n"),
            "{text}"
        );
        assert!(
            text.contains("  errors        2 (429 rate_limited 1, transport: timeout 1)\n"),
            "{text}"
        );
        assert!(text.contains("verified      skipped"), "{text}");
    }

    #[test]
    fn open_loop_report_and_failed_verification() {
        let mut config = LoadConfig::new("http://x");
        config.mode = Mode::Open {
            rate: 10.0,
            max_in_flight: 5,
        };
        config.stop = Stop::Count(1);
        let run = LoadRun {
            samples: vec![Sample {
                lag_ns: 2_000_000,
                ..sample(4, 201, Outcome::Planned)
            }],
            wall: Duration::from_secs(1),
            waited_for_slot: 0,
            late: 0,
            late_threshold: crate::schedule::LATE,
        };
        let v = Verification {
            flights: 2,
            this_run: 1,
            span: None,
            violations: 1,
            first_violations: vec!["edge rule violated by a, b".into()],
            duplicates: 1,
            first_duplicates: vec!["p-0".into()],
            missing: 0,
            first_missing: Vec::new(),
            completeness_checked: true,
        };
        let r = Report::new(
            String::new(),
            config.summary("p"),
            server(),
            &run,
            1,
            Vec::new(),
            Some(v),
        );
        let ol = r.open_loop.unwrap();
        assert_eq!(ol.send_lag_ms.max_ms, 2.0);
        assert_eq!(ol.from_send_ms.max_ms, 2.0);
        assert!(!r.verified_ok());
        let text = r.text();
        assert!(text.contains("FAILED: 2 planned flights (1 from this run), 1 violation(s)"));
        assert!(text.contains("    edge rule violated by a, b\n"));
        assert!(
            text.contains(
                "listing       FAILED: GET /v1/flights returned 1 flight(s) more than once"
            )
        );
        assert!(text.contains("(from due time)"));
        assert!(text.contains("  load          open loop at 10 requests/s, 1 request,"));
        assert!(text.contains(" sent over 10 ms late, 0 waited for a slot (cap 5)\n"));
        let json = serde_json::to_value(&r).unwrap();
        assert_eq!(json["config"]["mode"], "open");
        assert_eq!(json["open_loop"]["late_threshold_ms"], 10.0);
        assert_eq!(json["counts"]["planned"], 1);
    }

    #[test]
    fn paced_report() {
        let mut config = LoadConfig::new("http://x");
        config.mode = Mode::Paced {
            rate: 2_000.0,
            clients: 16,
        };
        config.stop = Stop::Duration(Duration::from_secs(30));
        let run = LoadRun {
            samples: vec![
                Sample {
                    lag_ns: 3_000_000,
                    ..sample(5, 201, Outcome::Planned)
                },
                Sample {
                    lag_ns: 100_000,
                    ..sample(1, 200, Outcome::Rejected(RejectReason::OutOfRange))
                },
            ],
            wall: Duration::from_secs(1),
            waited_for_slot: 1,
            late: 1,
            late_threshold: crate::schedule::PACED_LATE,
        };
        let r = Report::new(
            String::new(),
            config.summary("p"),
            server(),
            &run,
            2,
            Vec::new(),
            None,
        );
        let ol = r.open_loop.unwrap();
        assert_eq!(
            (ol.late, ol.waited_for_slot, ol.late_threshold_ms),
            (1, 1, 1.0)
        );
        assert_eq!(ol.send_lag_ms.max_ms, 3.0);
        assert_eq!(ol.from_send_ms.max_ms, 2.0);
        let text = r.text();
        assert!(
            text.contains(
                "  load          paced at 2000 requests/s (open-loop schedule) by 16 clients, for 30 s,"
            ),
            "{text}"
        );
        assert!(text.contains("(from due time)"), "{text}");
        assert!(
            text.contains(" 1 sent over 1 ms late, 1 due while all 16 clients were busy\n"),
            "{text}"
        );
        let json = serde_json::to_value(&r).unwrap();
        assert_eq!(json["config"]["mode"], "paced");
        assert_eq!(json["config"]["rate"], 2_000.0);
        assert_eq!(json["config"]["clients"], 16);
        assert_eq!(json["config"]["max_in_flight"], serde_json::Value::Null);
        assert_eq!(json["open_loop"]["late_threshold_ms"], 1.0);
    }
}
