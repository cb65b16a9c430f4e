//! `muse siting` (docs/reference.md#airspace-from-pads) on a small made-up place near Vienna: it
//! picks pads with their gains, writes the picks, the curves of the three methods and the airspace,
//! and its numbers agree with one another; bad pads, candidates or customers files and options are
//! refused with a clear message and no output.

use std::fmt::Write as _;
use std::path::Path;

use crate::pads::{VIENNA, write};
use crate::run::{muse, said, stderr};
use crate::support::scratch_dir;

/// Customers on a 7 × 7 grid over the Vienna test points (made up, not real).
pub(crate) fn customers() -> String {
    let mut csv = String::from("id,lon,lat,weight\n");
    for i in 0..7 {
        for j in 0..7 {
            let lon = 16.34 + 0.012 * f64::from(i);
            let lat = 48.185 + 0.0075 * f64::from(j);
            writeln!(csv, "u{i}{j},{lon:.4},{lat:.4},{}", 1 + (i + j) % 3).unwrap();
        }
    }
    csv
}

/// The Vienna points split: the first four are there, the last three are candidates.
fn inputs(dir: &Path) -> (String, String, String) {
    let lines: Vec<&str> = VIENNA.lines().collect();
    let pads = format!("{}\n{}\n", lines[0], lines[1..5].join("\n"));
    let candidates = format!("{}\n{}\n", lines[0], lines[5..].join("\n"));
    (
        write(dir, "pads.csv", &pads),
        write(dir, "candidates.csv", &candidates),
        write(dir, "customers.csv", &customers()),
    )
}

fn siting(
    pads: &str,
    candidates: &str,
    customers: &str,
    out: &Path,
    extra: &[&str],
) -> std::process::Output {
    let mut args = vec![
        "siting",
        "--pads",
        pads,
        "--candidates",
        candidates,
        "--customers",
        customers,
        "--count",
        "400",
        "--days",
        "3",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    muse(&args)
}

/// The rows of a CSV file, split at commas (no quoted cells in these files' numbers).
fn rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

#[test]
fn siting_picks_pads_and_writes_the_curves_of_every_method() {
    let dir = scratch_dir("siting-vienna");
    std::fs::create_dir_all(&dir).unwrap();
    let (pads, candidates, customers) = inputs(&dir);
    let out = dir.join("out");
    let o = siting(&pads, &candidates, &customers, &out, &["--add", "2"]);
    assert!(o.status.success(), "{}", said(&o));
    let err = stderr(&o);
    assert!(err.contains("pick   1"), "{err}");
    assert!(err.contains(" here in "), "{err}");
    let picks = rows(&out.join("siting.csv"));
    assert_eq!(picks.len(), 2);
    let curve = rows(&out.join("curve.csv"));
    // Three methods, k = 0, 1, 2 each.
    assert_eq!(curve.len(), 9);
    let delivered = |method: &str, k: &str| -> f64 {
        curve.iter().find(|r| r[0] == method && r[1] == k).unwrap()[2]
            .parse()
            .unwrap()
    };
    // The greedy's gains are its curve's steps.
    for (k, pick) in picks.iter().enumerate() {
        let gain: f64 = pick[5].parse().unwrap();
        let (before, after) = (k.to_string(), (k + 1).to_string());
        let step = delivered("greedy-simulation", &after) - delivered("greedy-simulation", &before);
        assert!(
            (gain - step).abs() < 1e-3,
            "pick {}: {gain} vs {step}",
            k + 1
        );
    }
    // Every method starts from the same existing pads.
    for m in ["max-coverage", "k-means"] {
        assert!((delivered(m, "0") - delivered("greedy-simulation", "0")).abs() < 1e-9);
    }
    // The first greedy pick is at least as good as any single pad of the other methods.
    for m in ["max-coverage", "k-means"] {
        assert!(
            delivered("greedy-simulation", "1") >= delivered(m, "1"),
            "{m}"
        );
    }
    // The airspace has the two pads added and is a valid airspace file.
    let air = out.join("airspace.geojson");
    let o = muse(&["airspace", "info", "--airspace", air.to_str().unwrap()]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(said(&o).contains("6 stations"), "{}", said(&o));
    assert!(
        std::fs::read_to_string(out.join("curve.svg"))
            .unwrap()
            .starts_with("<svg")
    );
}

#[test]
fn bad_siting_inputs_are_refused_with_no_output() {
    let dir = scratch_dir("siting-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let (pads, candidates, customers) = inputs(&dir);
    let out = dir.join("out");
    let bad_customers = write(
        &dir,
        "bad-customers.csv",
        "id,lon,lat,weight\nu1,16.35,48.19,1\nu2,16.36,48.19,-2\n",
    );
    let one_customer = write(&dir, "one-customer.csv", "id,lon,lat\nu1,16.35,48.19\n");
    let clash = write(&dir, "clash.csv", "id,lon,lat\nV1,16.3550,48.1950\n");
    let at_a_pad = write(&dir, "at-a-pad.csv", "id,lon,lat\nX1,16.3700,48.2080\n");
    let empty = write(&dir, "empty.csv", "id,lon,lat\n");
    for (what, (p, c, u), extra, message) in [
        (
            "a weight below 0",
            (&pads, &candidates, &bad_customers),
            &[][..],
            "bad-customers.csv: line 3: field `weight`: `-2` is not a weight",
        ),
        (
            "one customer",
            (&pads, &candidates, &one_customer),
            &[],
            "1 customer: a demand needs at least 2",
        ),
        (
            "a candidate with a pad's id",
            (&pads, &clash, &customers),
            &[],
            "candidate pad `V1` has the id of an existing pad",
        ),
        (
            "a candidate at a pad",
            (&pads, &at_a_pad, &customers),
            &[],
            "candidate pad `X1` stands where pad `V1` is",
        ),
        (
            "no candidates",
            (&pads, &empty, &customers),
            &[],
            "0 pads: siting needs at least 1",
        ),
        (
            "more pads than candidates",
            (&pads, &candidates, &customers),
            &["--add", "4"],
            "--add 4: there are only 3 candidate pads",
        ),
        (
            "a negative last mile",
            (&pads, &candidates, &customers),
            &["--last-mile-m", "-5"],
            "-5",
        ),
    ] {
        let o = siting(p, c, u, &out, extra);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", said(&o));
        assert!(stderr(&o).contains(message), "{what}: {}", said(&o));
        assert!(!out.exists(), "{what}: no output");
    }
    let o = muse(&["siting", "--pads", &pads, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(stderr(&o).contains("--candidates"), "{}", said(&o));
}

#[test]
fn shards_of_the_first_round_merge_into_the_same_picks() {
    let dir = scratch_dir("siting-shards");
    std::fs::create_dir_all(&dir).unwrap();
    let (pads, candidates, customers) = inputs(&dir);
    let whole = dir.join("whole");
    let o = siting(&pads, &candidates, &customers, &whole, &["--add", "2"]);
    assert!(o.status.success(), "{}", said(&o));
    let parts: Vec<String> = (0..2)
        .map(|i| dir.join(format!("part{i}")).display().to_string())
        .collect();
    for (i, part) in parts.iter().enumerate() {
        let shard = format!("{i}/2");
        let o = siting(
            &pads,
            &candidates,
            &customers,
            Path::new(part),
            &["--shard", &shard],
        );
        assert!(o.status.success(), "{}", said(&o));
        assert!(Path::new(part).join("shard.json").exists());
    }
    let merged = dir.join("merged");
    let mut extra = vec!["--add", "2", "--from-shards"];
    extra.extend(parts.iter().map(String::as_str));
    let o = siting(&pads, &candidates, &customers, &merged, &extra);
    assert!(o.status.success(), "{}", said(&o));
    for file in ["siting.csv", "curve.csv"] {
        assert_eq!(
            std::fs::read_to_string(merged.join(file)).unwrap(),
            std::fs::read_to_string(whole.join(file)).unwrap(),
            "{file}"
        );
    }
    // A missing shard, or shards of another problem, are refused.
    let bad = dir.join("bad");
    let o = siting(
        &pads,
        &candidates,
        &customers,
        &bad,
        &["--add", "2", "--from-shards", &parts[0]],
    );
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(stderr(&o).contains("shard 1/2 is missing"), "{}", said(&o));
    let mut extra = vec!["--add", "2", "--last-mile-m", "700", "--from-shards"];
    extra.extend(parts.iter().map(String::as_str));
    let o = siting(&pads, &candidates, &customers, &bad, &extra);
    assert_eq!(o.status.code(), Some(2), "{}", said(&o));
    assert!(
        stderr(&o).contains("a shard of another siting problem"),
        "{}",
        said(&o)
    );
    assert!(!bad.exists());
}

#[test]
fn siting_takes_the_embedded_singapore_customers_with_pads_files() {
    let dir = scratch_dir("siting-singapore-hdb");
    std::fs::create_dir_all(&dir).unwrap();
    // Six of Singapore's stations are there, two more may be added.
    let stations = muse_scenario::station_nodes().unwrap();
    let csv = |nodes: &[muse_model::Node]| {
        let mut text = String::from("id,lon,lat\n");
        for n in nodes {
            writeln!(text, "{},{},{}", n.id, n.pos.lon, n.pos.lat).unwrap();
        }
        text
    };
    let pads = write(&dir, "pads.csv", &csv(&stations[30..36]));
    let candidates = write(&dir, "candidates.csv", &csv(&stations[36..38]));
    let out = dir.join("out");
    let o = siting(&pads, &candidates, "singapore-hdb", &out, &["--add", "1"]);
    assert!(o.status.success(), "{}", said(&o));
    assert!(
        stderr(&o).contains("customers singapore-hdb (2257 HDB car parks)"),
        "{}",
        said(&o)
    );
    assert_eq!(rows(&out.join("siting.csv")).len(), 1);
    // A shard of the same problem too (its key names the embedded list, not a file).
    let part = dir.join("part");
    let o = siting(
        &pads,
        &candidates,
        "singapore-hdb",
        &part,
        &["--shard", "0/2"],
    );
    assert!(o.status.success(), "{}", said(&o));
    assert!(part.join("shard.json").exists());
    // `muse demand` takes the name the same way.
    let o = muse(&[
        "demand",
        "--customers",
        "singapore-hdb",
        "--count",
        "5",
        "--out",
        "-",
    ]);
    assert!(o.status.success(), "{}", said(&o));
}
