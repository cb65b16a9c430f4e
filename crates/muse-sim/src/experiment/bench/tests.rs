//! The benchmark's numbers: fits, `bench.csv`, the table, the case's JSON line.

use super::*;
use crate::experiment::csv_text;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
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
    let csv = csv_text("bench.csv", &columns(&measured), &measured).unwrap();
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
    let table = table(&measured);
    assert!(table.contains("100,000"), "{table}");
    assert!(table.contains("1.10 (R² 1.000, 3 points)"), "{table}");
    assert!(table.contains("0.50 (R² 1.000, 2 points)"), "{table}");
    assert!(table.contains("n/a"), "{table}");
    // One graph alone has no exponent against nodes.
    let one = Exponents::of(&results[..3]);
    assert!(one.by_requests.iter().all(|(_, f)| f.is_none()));
    assert!(super::table(&measured[..3]).contains("n/a (needs two sizes)"));
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

#[test]
fn series_skip_unknown_values() {
    let case = |graph: &str, requests: usize, peak: Option<u64>| Measured {
        result: CaseResult {
            peak_rss_bytes: peak,
            rss_before_planning_bytes: None,
            zones: Vec::new(),
            ..case(graph, 10, requests, 1.0)
        },
        wall_s: 1.0,
    };
    let cases = [
        case("a", 100, Some(1 << 20)),
        case("a", 200, None),
        case("b", 100, None),
    ];
    let s = series_by_graph(&cases, |r| r.peak_rss_bytes.map(|b| b as f64));
    assert_eq!(s.len(), 1);
    assert_eq!(s[0].points.len(), 1);
    let s = series_by_graph(&cases, |r| Some(r.expanded_per_request()));
    assert_eq!(s.len(), 2);
    assert_eq!(s[0].points.len(), 2);
    assert!(
        s.iter()
            .flat_map(|s| &s.points)
            .all(|p| (p.mean - 3.0).abs() < 1e-12)
    );
}
