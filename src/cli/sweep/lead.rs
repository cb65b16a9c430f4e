//! `muse sweep --vary announce-lead` on the command line: the leads, the zones to announce,
//! the default booking lead, and the announcement-lead sweep they describe.

use anyhow::Context as _;
use muse_model::{Instant, Millis, Zone};
use muse_sim::demand::BookingLead;
use muse_sim::experiment::Experiment;
use muse_sim::experiment::lead::{Lead, LeadSpec, ScenarioDay};

use super::args::SweepArgs;
use super::build::grid;
use crate::cli::common::World;
use crate::cli::demand::BookingLeadArg;
use crate::cli::ranges::{MAX_LEAD_MIN, MAX_LIST};

/// The leads compared unless `--leads` is given, minutes.
const DEFAULT_LEADS: &str = "0,15,30,60,120";

/// Bookings made up to two hours ahead, unless `--booking-lead-min` is given.
const DEFAULT_BOOKING_MIN: f64 = 120.0;

/// Parses `--leads`: at most [`MAX_LIST`] comma-separated minutes from 0 to
/// [`MAX_LEAD_MIN`], sorted, duplicates dropped.
fn parse_leads(text: &str) -> anyhow::Result<Vec<Millis>> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() > MAX_LIST {
        anyhow::bail!(
            "--leads: {} leads, more than the {MAX_LIST} a sweep compares",
            parts.len()
        );
    }
    let mut leads = Vec::new();
    for part in parts {
        let m: f64 = part.trim().parse().map_err(|_| {
            anyhow::anyhow!(
                "--leads `{text}`: `{}` is not a number of minutes from 0 to {MAX_LEAD_MIN}; \
                 expected e.g. 0,15,30,60,120",
                part.trim()
            )
        })?;
        if !(0.0..=MAX_LEAD_MIN).contains(&m) {
            anyhow::bail!(
                "--leads `{text}`: {m} minutes: a lead must be a number of minutes from 0 to \
                 {MAX_LEAD_MIN}"
            );
        }
        leads.push(Millis::from_secs_f64(m * 60.0)?);
    }
    leads.sort_unstable();
    leads.dedup();
    Ok(leads)
}

/// The base zones (known from the start) and the zones to announce: every zone of the
/// `--announce-zones` files, or the built-in scenario's CBD zone; a base zone with the id of
/// a zone to announce is dropped from the base.
fn split_zones(
    world: &World,
    files: &[std::path::PathBuf],
) -> anyhow::Result<(Vec<Zone>, Vec<Zone>)> {
    let mut read = muse_formats::zones::ZoneFiles::default();
    for path in files {
        read.add(path)
            .with_context(|| format!("reading zones to announce from {}", path.display()))?;
    }
    let mut announce = read.into_zones();
    if files.is_empty() {
        let cbd = world
            .scenario
            .and_then(|s| s.zones.iter().find(|z| z.id == muse_scenario::CBD_ZONE_ID));
        let Some(cbd) = cbd else {
            anyhow::bail!(
                "--vary announce-lead needs a zone to announce: a built-in scenario's CBD zone (the default) or --announce-zones FILE"
            );
        };
        announce.push(cbd.clone());
    }
    if announce.is_empty() {
        anyhow::bail!("--announce-zones: the files hold no zone");
    }
    if let Some(z) = announce.iter().find(|z| z.withdrawn.is_some()) {
        anyhow::bail!(
            "--announce-zones: zone `{}` was withdrawn (`withdrawn`): a sweep announces zones, \
             it never withdraws them; leave the withdrawal out",
            z.id
        );
    }
    let base = world
        .zones
        .iter()
        .filter(|z| !announce.iter().any(|a| a.id == z.id))
        .cloned()
        .collect();
    Ok((base, announce))
}

/// The announcement-lead sweep `args` describe on `world`, and the lines it is announced with.
pub fn lead<'w>(
    args: &SweepArgs,
    world: &'w World,
) -> anyhow::Result<(Experiment<Lead<'w>>, Vec<String>)> {
    let mut demand = args.demand.clone();
    let default_booking = demand.booking_lead_min.is_none();
    if default_booking {
        let max = Millis::from_secs_f64(DEFAULT_BOOKING_MIN * 60.0)?;
        demand.booking_lead_min = Some(BookingLeadArg {
            from_min: 0.0,
            to_min: DEFAULT_BOOKING_MIN,
            lead: BookingLead::new(Millis::ZERO, max)?,
        });
    }
    let grid = grid(args, &demand, world)?;
    let leads = parse_leads(args.leads.as_deref().unwrap_or(DEFAULT_LEADS))?;
    let (base_zones, announce) = split_zones(world, &args.announce_zones)?;
    let booked = match (demand.booking_note(), default_booking) {
        (None, _) => "booked at departure".to_owned(),
        (Some(b), false) => b,
        (Some(b), true) => format!("{b} (this sweep's default)"),
    };
    let day_start = Instant::at_local(world.day.date, Millis::ZERO, world.day.offset);
    let spec = LeadSpec {
        leads,
        base_zones,
        announce,
        day: ScenarioDay {
            start: day_start,
            end: day_start + Millis::from_secs(86_400),
            offset: world.day.offset,
        },
        no_zone_reference: true,
    };
    let kind = Lead::new(&world.airspace, &grid, spec, booked.clone())
        .with_context(|| format!("on the scenario's day {}", world.day.date))?;
    let exp = Experiment { grid, kind };
    let leads: Vec<String> = exp
        .kind
        .lead_cases()
        .iter()
        .filter_map(|c| c.lead_min())
        .map(|m| m.to_string())
        .collect();
    let heading = vec![
        format!(
            "sweep --vary announce-lead: {} announced {} min ahead, plus known from the start and never announced",
            exp.kind.announced().join(", "),
            leads.join(", "),
        ),
        format!(
            "{} cases × {} counts × {} repetitions = {} runs, {} requests {booked}, {} threads",
            exp.kind.lead_cases().len(),
            exp.grid.counts.len(),
            exp.grid.reps,
            exp.runs(),
            exp.total_requests(),
            rayon::current_num_threads()
        ),
    ];
    Ok((exp, heading))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leads() {
        assert_eq!(
            parse_leads("60, 0,15,0").unwrap(),
            [0, 15, 60].map(Millis::from_mins)
        );
        assert_eq!(parse_leads("0.5").unwrap(), [Millis::from_secs(30)]);
        for (bad, message) in [
            ("", "`` is not a number of minutes"),
            ("10,soon", "`soon` is not a number of minutes"),
            (
                "-5",
                "-5 minutes: a lead must be a number of minutes from 0 to 43200",
            ),
            ("inf", "a lead must be a number of minutes from 0 to 43200"),
        ] {
            let e = parse_leads(bad).unwrap_err().to_string();
            assert!(e.contains(message), "{bad}: {e}");
        }
    }
}
