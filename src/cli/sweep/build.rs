//! The paper's sweep a command line describes: its grid (counts, repetitions, demand, flight
//! parameters) and its variants (the levers of `--vary`).

use std::sync::OnceLock;

use anyhow::Context as _;
use muse_sim::experiment::sweep::levers::{Base, variants};
use muse_sim::experiment::sweep::{Airspaces, Sweep, Variant};
use muse_sim::experiment::{Experiment, Grid, Seeds};

use super::args::SweepArgs;
use crate::cli::common::World;
use crate::cli::demand::DemandArgs;
use crate::cli::ranges::{MAX_COUNTS, MAX_REQUESTS, MAX_SWEEP_DAYS};

/// Parses `START:END:STEP` or `a,b,c`: at most [`MAX_COUNTS`] counts, each from 1 to
/// [`MAX_REQUESTS`] (checked before the list is made).
pub fn parse_counts(text: &str) -> anyhow::Result<Vec<usize>> {
    let bad = || {
        anyhow::anyhow!(
            "--counts `{text}`: expected START:END:STEP or a comma-separated list of counts, \
             each from 1 to {MAX_REQUESTS}, at most {MAX_COUNTS} counts"
        )
    };
    let count = |x: &str| {
        x.trim()
            .parse()
            .ok()
            .filter(|n| (1..=MAX_REQUESTS).contains(n))
            .ok_or_else(bad)
    };
    let counts: Vec<usize> = if let [a, b, s] = text.split(':').collect::<Vec<_>>()[..] {
        let (a, b, s): (usize, usize, usize) = (count(a)?, count(b)?, count(s)?);
        if a > b || (b - a) / s >= MAX_COUNTS {
            return Err(bad());
        }
        (a..=b).step_by(s).collect()
    } else {
        let items: Vec<&str> = text.split(',').collect();
        if items.len() > MAX_COUNTS {
            return Err(bad());
        }
        items
            .into_iter()
            .map(count)
            .collect::<anyhow::Result<_>>()?
    };
    Ok(counts)
}

/// Refuses a sweep of more than [`MAX_SWEEP_DAYS`] days (counts × repetitions).
pub fn check_days(counts: usize, reps: usize) -> anyhow::Result<()> {
    let days = counts.saturating_mul(reps);
    if days > MAX_SWEEP_DAYS {
        anyhow::bail!(
            "--counts and --reps: {counts} counts × {reps} repetitions = {days} days, more than \
             the {MAX_SWEEP_DAYS} a sweep runs"
        );
    }
    Ok(())
}

/// The grid `args` describe on `world`, its demand from `demand` (the sweep's own options,
/// or with a kind's default booking lead).
pub fn grid(args: &SweepArgs, demand: &DemandArgs, world: &World) -> anyhow::Result<Grid> {
    let counts = parse_counts(&args.counts)?;
    check_days(counts.len(), args.reps)?;
    let params = args.flight.params()?;
    let d = demand.spec(world, args.flight.range)?;
    Ok(Grid {
        counts,
        reps: args.reps,
        seeds: Seeds::PerDay(d.seed),
        start: d.start,
        end: d.end,
        od: d.od,
        booking_lead: d.booking_lead,
        params,
    })
}

/// How a world's zones are named in legends: `CBD zone` for a built-in scenario's, `no zone`,
/// or the zone ids.
fn zone_label(world: &World) -> String {
    let names: Vec<&str> = world.zones.iter().map(|z| z.id.as_str()).collect();
    if names.is_empty() {
        "no zone".to_owned()
    } else if world.scenario.is_some() && names == [muse_scenario::CBD_ZONE_ID] {
        "CBD zone".to_owned()
    } else {
        format!("zones {}", names.join("+"))
    }
}

/// The paper's sweep `args` describe on `world`, and the line it is announced with; the
/// airspaces its variants fly (flat or layered) are built into `airspaces`, which the sweep
/// borrows.
pub fn paper<'w>(
    args: &SweepArgs,
    world: &'w World,
    airspaces: &'w OnceLock<Airspaces>,
) -> anyhow::Result<(Experiment<Sweep<'w>>, String)> {
    let grid = grid(args, &args.demand, world)?;
    let label = zone_label(world);
    let base = Base {
        params: grid.params,
        zones: &world.zones,
        zone_label: &label,
    };
    let vary: Vec<&str> = args.vary.iter().map(String::as_str).collect();
    let given: Vec<(&str, &str)> = args
        .levers
        .given()
        .iter()
        .map(|(n, v)| (*n, v.as_str()))
        .collect();
    let variants: Vec<Variant> = variants(&base, &vary, &given)?;
    let booked = args.demand.booking_note();
    let heading = format!(
        "sweep: {} variant(s) × {} counts × {} repetitions = {} runs, {} requests{}, {} threads",
        variants.len(),
        grid.counts.len(),
        grid.reps,
        variants.len() * grid.counts.len() * grid.reps,
        variants.len() * grid.requests_per_case(),
        booked.as_deref().map_or(String::new(), |b| format!(" {b}")),
        rayon::current_num_threads()
    );
    let built = Airspaces::new(&world.airspace, &variants).context("--vary layers")?;
    let kind = Sweep::new(airspaces.get_or_init(|| built), &grid, variants, booked)?;
    Ok((Experiment { grid, kind }, heading))
}

#[cfg(test)]
mod tests {
    use super::{check_days, parse_counts};

    #[test]
    fn counts() {
        assert_eq!(
            parse_counts("1000:3000:1000").unwrap(),
            vec![1000, 2000, 3000]
        );
        assert_eq!(parse_counts("5, 10").unwrap(), vec![5, 10]);
        for bad in [
            "",
            "1:2",
            "3:1:1",
            "1:5:0",
            "a,b",
            "0,5",
            "-5",
            "10000001",
            "1:2000000000:1",
            "1:1001:1",
        ] {
            let e = parse_counts(bad).unwrap_err().to_string();
            assert!(
                e.ends_with("each from 1 to 10000000, at most 1000 counts"),
                "{bad}: {e}"
            );
        }
        assert_eq!(parse_counts("1:1000:1").unwrap().len(), 1_000);
        assert_eq!(
            parse_counts(&vec!["5"; 1_001].join(","))
                .unwrap_err()
                .to_string(),
            format!(
                "--counts `{}`: expected START:END:STEP or a comma-separated list of counts, \
                 each from 1 to 10000000, at most 1000 counts",
                vec!["5"; 1_001].join(",")
            )
        );
        assert!(check_days(100, 10_000).is_ok());
        assert_eq!(
            check_days(1_000, 10_000).unwrap_err().to_string(),
            "--counts and --reps: 1000 counts × 10000 repetitions = 10000000 days, more than \
             the 1000000 a sweep runs"
        );
    }
}
