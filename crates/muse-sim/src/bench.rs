//! Scaling benchmarks (`muse bench`): the measurements of one case, peak memory from
//! `/proc/self/status`, power-law fits of the growth, and the table and CSV.
//!
//! A *case* is one graph and one demand level, planned as a single day in its own process so
//! that its peak memory is its own. The measurements travel from the case process to the
//! parent as one JSON line ([`CaseResult::to_json_line`], [`CaseResult::from_json_line`]).
//!
//! Growth is summarised by least-squares slopes on log–log axes ([`fit_power_law`]): per
//! graph, total planner time against requests (1 means linear in demand); per demand level,
//! time per request against the number of nodes.

use crate::sweep::csv_text;
use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

/// The measurements of one case, written by the case process as one JSON line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    /// Graph name, e.g. `singapore-77` or `synthetic-10000`.
    pub graph: String,
    /// Nodes of the graph.
    pub nodes: usize,
    /// Stations of the graph.
    pub stations: usize,
    /// Edges (corridors) of the graph.
    pub edges: usize,
    /// Ids of the zones in force.
    pub zones: Vec<String>,
    /// Requests planned.
    pub requests: usize,
    /// Origin–destination rule: `uniform` or `in-range`.
    pub od: String,
    /// Demand seed.
    pub seed: u64,
    /// Accepted plans.
    pub planned: usize,
    /// Rejected: out of range.
    pub out_of_range: usize,
    /// Rejected: unreachable.
    pub unreachable: usize,
    /// Rejected: no feasible plan.
    pub no_feasible_plan: usize,
    /// Wall time of the planning loop alone, seconds.
    pub planner_s: f64,
    /// Labels expanded, summed over the requests.
    pub expanded: u64,
    /// Wall time of demand generation, seconds (not part of `planner_s`).
    pub demand_s: f64,
    /// Resident memory just before planning (graph and demand loaded), bytes.
    pub rss_before_planning_bytes: Option<u64>,
    /// Peak resident memory of the case process (`VmHWM`), bytes.
    pub peak_rss_bytes: Option<u64>,
}

impl CaseResult {
    /// Requests rejected, for any reason.
    pub fn rejected(&self) -> usize {
        self.out_of_range + self.unreachable + self.no_feasible_plan
    }

    /// Planner wall time per request, microseconds (0 without requests).
    pub fn us_per_request(&self) -> f64 {
        if self.requests == 0 {
            0.0
        } else {
            self.planner_s * 1e6 / self.requests as f64
        }
    }

    /// Labels expanded per request (0 without requests).
    pub fn expanded_per_request(&self) -> f64 {
        if self.requests == 0 {
            0.0
        } else {
            self.expanded as f64 / self.requests as f64
        }
    }

    /// One line of JSON, without a line break.
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(self).expect("a case result serialises")
    }

    /// Reads a line written by [`CaseResult::to_json_line`].
    pub fn from_json_line(line: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(line.trim())
    }
}

/// A case as seen by the parent: what the case process measured and how long it ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// The case process's measurements.
    pub result: CaseResult,
    /// Wall time of the whole case process (loading, demand, planning), seconds.
    pub wall_s: f64,
}

/// A power law `y = coefficient · x^exponent` fitted by least squares on `ln y` against
/// `ln x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerFit {
    /// The slope on log–log axes: the growth exponent.
    pub exponent: f64,
    /// `exp` of the intercept.
    pub coefficient: f64,
    /// Coefficient of determination of the log–log fit (1 when it is exact).
    pub r_squared: f64,
    /// Points fitted.
    pub points: usize,
}

/// Fits `y = c · x^k` to `points` by ordinary least squares on `(ln x, ln y)`.
///
/// `None` when there are fewer than two distinct `x`, or some value is not finite and
/// positive (a logarithm is needed).
///
/// ```
/// use muse_sim::bench::fit_power_law;
/// let pts: Vec<(f64, f64)> = [1e4, 1e5, 1e6].iter().map(|&n| (n, 2e-6 * n)).collect();
/// let fit = fit_power_law(&pts).unwrap();
/// assert!((fit.exponent - 1.0).abs() < 1e-12); // linear
/// assert!((fit.coefficient - 2e-6).abs() < 1e-15);
/// ```
pub fn fit_power_law(points: &[(f64, f64)]) -> Option<PowerFit> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if points.len() < 2 || !points.iter().all(|&(x, y)| ok(x) && ok(y)) {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = logs.iter().map(|p| (p.1 - my) * (p.1 - my)).sum();
    // All x equal (to rounding): no slope.
    if sxx <= 1e-24 * n {
        return None;
    }
    let exponent = sxy / sxx;
    let intercept = my - exponent * mx;
    let residual: f64 = logs
        .iter()
        .map(|p| {
            let e = p.1 - (intercept + exponent * p.0);
            e * e
        })
        .sum();
    let r_squared = if syy <= 1e-24 * n {
        1.0
    } else {
        (1.0 - residual / syy).clamp(0.0, 1.0)
    };
    Some(PowerFit {
        exponent,
        coefficient: intercept.exp(),
        r_squared,
        points: logs.len(),
    })
}

/// The growth exponents of a benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct Exponents {
    /// Per graph (in order of first appearance): total planner time against requests.
    pub by_graph: Vec<(String, Option<PowerFit>)>,
    /// Per demand level (ascending): time per request against the number of nodes.
    pub by_requests: Vec<(usize, Option<PowerFit>)>,
}

impl Exponents {
    /// The fits of `results`.
    pub fn of(results: &[CaseResult]) -> Self {
        let mut graphs: Vec<&str> = Vec::new();
        let mut levels: Vec<usize> = Vec::new();
        for r in results {
            if !graphs.contains(&r.graph.as_str()) {
                graphs.push(&r.graph);
            }
            if !levels.contains(&r.requests) {
                levels.push(r.requests);
            }
        }
        levels.sort_unstable();
        let by_graph = graphs
            .into_iter()
            .map(|g| {
                let pts: Vec<(f64, f64)> = results
                    .iter()
                    .filter(|r| r.graph == g)
                    .map(|r| (r.requests as f64, r.planner_s))
                    .collect();
                (g.to_owned(), fit_power_law(&pts))
            })
            .collect();
        let by_requests = levels
            .into_iter()
            .map(|n| {
                let pts: Vec<(f64, f64)> = results
                    .iter()
                    .filter(|r| r.requests == n)
                    .map(|r| (r.nodes as f64, r.us_per_request()))
                    .collect();
                (n, fit_power_law(&pts))
            })
            .collect();
        Exponents {
            by_graph,
            by_requests,
        }
    }

    /// The fit of total planner time against requests for `graph`.
    pub fn for_graph(&self, graph: &str) -> Option<PowerFit> {
        self.by_graph
            .iter()
            .find(|(g, _)| g == graph)
            .and_then(|(_, f)| *f)
    }

    /// The fit of time per request against nodes for `requests`.
    pub fn for_requests(&self, requests: usize) -> Option<PowerFit> {
        self.by_requests
            .iter()
            .find(|(n, _)| *n == requests)
            .and_then(|(_, f)| *f)
    }
}

/// The value of a `Name:  <n> kB` line of `/proc/<pid>/status`, in bytes.
///
/// ```
/// use muse_sim::bench::status_kib_field;
/// let status = "Name:\tmuse\nVmPeak:\t  20000 kB\nVmHWM:\t    1536 kB\nVmRSS:\t 1024 kB\n";
/// assert_eq!(status_kib_field(status, "VmHWM"), Some(1536 * 1024));
/// assert_eq!(status_kib_field(status, "VmSwap"), None);
/// ```
pub fn status_kib_field(status: &str, name: &str) -> Option<u64> {
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(name)?.strip_prefix(':')?;
        let mut words = rest.split_whitespace();
        let value: u64 = words.next()?.parse().ok()?;
        match words.next() {
            Some("kB") if words.next().is_none() => value.checked_mul(1024),
            _ => None,
        }
    })
}

/// This process's peak resident memory (`VmHWM`), in bytes; `None` where
/// `/proc/self/status` is unavailable (not Linux) or has no such line.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status_kib_field(&status, "VmHWM")
}

/// This process's current resident memory (`VmRSS`), in bytes, where available.
pub fn current_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status_kib_field(&status, "VmRSS")
}

/// Bytes as MiB with one decimal, or `n/a`.
pub fn mib(bytes: Option<u64>) -> String {
    bytes.map_or_else(|| "n/a".to_owned(), |b| format!("{:.1}", b as f64 / MIB))
}

const MIB: f64 = 1024.0 * 1024.0;

/// An exponent with two decimals, or `n/a`.
fn exponent_text(fit: Option<PowerFit>) -> String {
    fit.map_or_else(|| "n/a".to_owned(), |f| format!("{:.2}", f.exponent))
}

/// A count with thousands separators: `1000000` → `1,000,000`.
pub fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// `bench.csv`: one row per case, with the exponents of its graph and of its demand level.
pub fn bench_csv(cases: &[Measured], exponents: &Exponents) -> String {
    let mut out = String::from(
        "graph,nodes,stations,edges,zones,requests,od,seed,planned,out_of_range,unreachable,\
         no_feasible_plan,planner_s,us_per_request,expanded_per_request,peak_rss_mib,\
         rss_before_planning_mib,demand_s,case_wall_s,graph_time_exponent_vs_requests,\
         level_time_per_request_exponent_vs_nodes\n",
    );
    let exp =
        |f: Option<PowerFit>| f.map_or_else(|| "n/a".to_owned(), |f| format!("{:.4}", f.exponent));
    for m in cases {
        let r = &m.result;
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{:.6},{:.4},{:.4},{},{},{:.3},{:.3},{},{}",
            csv_text(&r.graph),
            r.nodes,
            r.stations,
            r.edges,
            csv_text(&r.zones.join(" ")),
            r.requests,
            r.od,
            r.seed,
            r.planned,
            r.out_of_range,
            r.unreachable,
            r.no_feasible_plan,
            r.planner_s,
            r.us_per_request(),
            r.expanded_per_request(),
            mib(r.peak_rss_bytes),
            mib(r.rss_before_planning_bytes),
            r.demand_s,
            m.wall_s,
            exp(exponents.for_graph(&r.graph)),
            exp(exponents.for_requests(r.requests)),
        );
    }
    out
}

/// The table printed at the end of `muse bench`: one row per case, then the exponents.
pub fn bench_table(cases: &[Measured], exponents: &Exponents) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<18} {:>6} {:>10} {:>9} {:>9} {:>10} {:>11} {:>10} {:>9} {:>8}",
        "graph",
        "nodes",
        "requests",
        "planned %",
        "planner s",
        "µs/request",
        "expanded/rq",
        "peak MiB",
        "demand s",
        "case s"
    );
    for m in cases {
        let r = &m.result;
        let planned = if r.requests == 0 {
            0.0
        } else {
            100.0 * r.planned as f64 / r.requests as f64
        };
        let _ = writeln!(
            out,
            "{:<18} {:>6} {:>10} {:>9.1} {:>9.3} {:>10.2} {:>11.2} {:>10} {:>9.2} {:>8.1}",
            r.graph,
            grouped(r.nodes),
            grouped(r.requests),
            planned,
            r.planner_s,
            r.us_per_request(),
            r.expanded_per_request(),
            mib(r.peak_rss_bytes),
            r.demand_s,
            m.wall_s
        );
    }
    let fit_text = |fit: Option<PowerFit>| match fit {
        Some(f) => format!(
            "{} (R² {:.3}, {} points)",
            exponent_text(fit),
            f.r_squared,
            f.points
        ),
        None => "n/a (needs two sizes)".to_owned(),
    };
    let _ = writeln!(
        out,
        "growth exponent of total planner time vs requests (least-squares log-log slope; 1 = linear):"
    );
    for (g, fit) in &exponents.by_graph {
        let _ = writeln!(out, "  {g:<18} {}", fit_text(*fit));
    }
    let _ = writeln!(
        out,
        "growth exponent of planner time per request vs nodes (least-squares log-log slope):"
    );
    for (n, fit) in &exponents.by_requests {
        let _ = writeln!(
            out,
            "  {:<18} {}",
            format!("{} requests", grouped(*n)),
            fit_text(*fit)
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * b.abs().max(1.0)
    }

    #[test]
    fn fit_is_exact_on_power_laws() {
        for (c, k) in [
            (2e-6_f64, 1.0_f64),
            (3.5, 1.5),
            (0.7, -0.5),
            (42.0, 0.0),
            (1e-3, 2.25),
        ] {
            for xs in [
                vec![1e4_f64, 1e5, 1e6],
                vec![77.0, 1_100.0, 10_000.0],
                vec![200.0, 400.0],
                vec![1.0, 2.0, 3.0, 5.0, 8.0, 13.0],
            ] {
                let pts: Vec<(f64, f64)> = xs.iter().map(|&x| (x, c * x.powf(k))).collect();
                let fit = fit_power_law(&pts).unwrap();
                assert!(close(fit.exponent, k), "{c} x^{k} on {xs:?}: {fit:?}");
                assert!(close(fit.coefficient, c), "{c} x^{k} on {xs:?}: {fit:?}");
                assert!(close(fit.r_squared, 1.0), "{fit:?}");
                assert_eq!(fit.points, xs.len());
            }
        }
    }

    #[test]
    fn fit_of_noisy_points_is_the_least_squares_slope() {
        // ln-space points (0, 0), (1, 1), (2, 3): slope 1.5, intercept -1/6.
        let e = std::f64::consts::E;
        let fit = fit_power_law(&[(1.0, 1.0), (e, e), (e * e, e.powi(3))]).unwrap();
        assert!(close(fit.exponent, 1.5), "{fit:?}");
        assert!(close(fit.coefficient, (-1.0f64 / 6.0).exp()), "{fit:?}");
        // Residuals 1/6, -1/3, 1/6: SSres = 1/6, SStot = 14/3.
        assert!(
            close(fit.r_squared, 1.0 - (1.0 / 6.0) / (14.0 / 3.0)),
            "{fit:?}"
        );
    }

    #[test]
    fn fit_needs_two_sizes_and_positive_values() {
        assert_eq!(fit_power_law(&[]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0), (10.0, 2.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0), (20.0, 0.0)]), None);
        assert_eq!(fit_power_law(&[(0.0, 1.0), (20.0, 1.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, f64::NAN), (20.0, 1.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0), (f64::INFINITY, 1.0)]), None);
    }

    #[test]
    fn vm_hwm_parser() {
        let status = "Name:\tmuse\nUmask:\t0022\nState:\tR (running)\nVmPeak:\t  123456 kB\n\
                      VmSize:\t  120000 kB\nVmHWM:\t   51200 kB\nVmRSS:\t   40960 kB\nThreads:\t1\n";
        assert_eq!(status_kib_field(status, "VmHWM"), Some(51_200 * 1024));
        assert_eq!(status_kib_field(status, "VmRSS"), Some(40_960 * 1024));
        // Whole names only; missing, malformed or unitless lines give nothing.
        assert_eq!(status_kib_field(status, "VmH"), None);
        assert_eq!(status_kib_field(status, "Threads"), None);
        assert_eq!(status_kib_field("VmHWM:\t12 MB\n", "VmHWM"), None);
        assert_eq!(status_kib_field("VmHWM:\tlots kB\n", "VmHWM"), None);
        assert_eq!(status_kib_field("VmHWM:\t12 kB extra\n", "VmHWM"), None);
        assert_eq!(status_kib_field("", "VmHWM"), None);
        assert_eq!(status_kib_field("VmHWM:\t0 kB", "VmHWM"), Some(0));
        assert_eq!(
            status_kib_field(&format!("VmHWM:\t{} kB", u64::MAX), "VmHWM"),
            None
        );
        // On Linux the live value is there and at least any earlier size (read the size
        // first: other tests' threads may grow the process in between).
        if cfg!(target_os = "linux") {
            let earlier = current_rss_bytes().expect("VmRSS on Linux");
            let peak = peak_rss_bytes().expect("VmHWM on Linux");
            assert!(peak >= earlier, "{peak} < {earlier}");
        }
        assert_eq!(mib(None), "n/a");
        assert_eq!(mib(Some(3 * 1024 * 1024 / 2)), "1.5");
    }

    fn case(graph: &str, nodes: usize, requests: usize, planner_s: f64) -> CaseResult {
        CaseResult {
            graph: graph.to_owned(),
            nodes,
            stations: nodes,
            edges: 2 * nodes,
            zones: vec!["Z1".to_owned()],
            requests,
            od: "in-range".to_owned(),
            seed: 1,
            planned: requests / 2,
            out_of_range: requests / 4,
            unreachable: 0,
            no_feasible_plan: requests - requests / 2 - requests / 4,
            planner_s,
            expanded: 3 * requests as u64,
            demand_s: 0.01,
            rss_before_planning_bytes: Some(10 << 20),
            peak_rss_bytes: None,
        }
    }

    #[test]
    fn exponents_table_and_csv() {
        // Time = 1e-7 · requests^1.1 · nodes^0.5.
        let mut results = Vec::new();
        for (g, nodes) in [("small", 100usize), ("big", 10_000)] {
            for n in [1_000usize, 10_000, 100_000] {
                let t = 1e-7 * (n as f64).powf(1.1) * (nodes as f64).sqrt();
                results.push(case(g, nodes, n, t));
            }
        }
        let exps = Exponents::of(&results);
        assert_eq!(exps.by_graph.len(), 2);
        assert_eq!(exps.by_graph[0].0, "small");
        for (_, f) in &exps.by_graph {
            assert!(close(f.unwrap().exponent, 1.1));
        }
        assert_eq!(
            exps.by_requests.iter().map(|x| x.0).collect::<Vec<_>>(),
            vec![1_000, 10_000, 100_000]
        );
        for (_, f) in &exps.by_requests {
            assert!(close(f.unwrap().exponent, 0.5));
        }
        let measured: Vec<Measured> = results
            .iter()
            .map(|r| Measured {
                result: r.clone(),
                wall_s: 1.5,
            })
            .collect();
        let csv = bench_csv(&measured, &exps);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 7);
        let header: Vec<&str> = lines[0].split(',').collect();
        for row in &lines[1..] {
            assert_eq!(row.split(',').count(), header.len(), "{row}");
        }
        assert!(lines[1].starts_with("small,100,100,200,Z1,1000,in-range,1,500,250,0,250,"));
        assert!(
            lines[1].ends_with(",n/a,10.0,0.010,1.500,1.1000,0.5000"),
            "{}",
            lines[1]
        );
        let table = bench_table(&measured, &exps);
        assert!(table.contains("100,000"), "{table}");
        assert!(table.contains("1.10 (R² 1.000, 3 points)"), "{table}");
        assert!(table.contains("0.50 (R² 1.000, 2 points)"), "{table}");
        assert!(table.contains("n/a"), "{table}");
        // One graph alone has no exponent against nodes.
        let one = Exponents::of(&results[..3]);
        assert!(one.by_requests.iter().all(|(_, f)| f.is_none()));
        assert!(bench_table(&measured[..3], &one).contains("n/a (needs two sizes)"));
    }

    #[test]
    fn json_round_trip() {
        let r = case("synthetic-10000", 10_000, 1_000_000, 12.5);
        let line = r.to_json_line();
        assert!(!line.contains('\n'));
        assert_eq!(CaseResult::from_json_line(&format!("{line}\n")).unwrap(), r);
        assert!(CaseResult::from_json_line("{\"graph\": 1}").is_err());
        assert!(close(r.us_per_request(), 12.5));
        assert!(close(r.expanded_per_request(), 3.0));
        assert_eq!(r.rejected(), 500_000);
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1_000), "1,000");
        assert_eq!(grouped(1_234_567), "1,234,567");
    }
}
