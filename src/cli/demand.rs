//! `muse demand`: generate a seeded requests file (docs/reference.md#built-in-scenarios).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use muse_formats::requests::{DemandRow, write_demand, write_requests};
use muse_model::time::{TimeError, parse_clock};
use muse_model::{Instant, Millis, NodeId};
use muse_sim::customers::serving_pads;
use muse_sim::customers::trips::{TripSpec, draw_trips, request_for};
use muse_sim::demand::{BookingLead, DemandSpec, OdRule, generate};

use super::common::{RangeArgs, World, WorldArgs, read_customers};
use super::output;
use super::ranges::{self, MAX_LEAD_MIN};

/// Origin–destination rule on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OdArg {
    /// Uniform over distinct station pairs (the paper).
    Uniform,
    /// Only pairs whose free-flow time fits the battery.
    InRange,
}

/// Demand options shared by `muse demand` and `muse simulate`.
#[derive(Debug, Args, Clone)]
pub struct DemandArgs {
    /// Number of requests, from 1 to 10000000.
    #[arg(long, default_value_t = 5_000, allow_negative_numbers = true, value_parser = ranges::requests)]
    pub count: usize,
    /// Seed of the generator, a whole number from 0 to 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = ranges::seed)]
    pub seed: u64,
    /// Start of the departure window, local time on the scenario's date.
    #[arg(long, default_value = "08:00", value_name = "HH:MM")]
    pub from: String,
    /// End of the departure window (exclusive), local time.
    #[arg(long, default_value = "20:00", value_name = "HH:MM")]
    pub to: String,
    /// Origin–destination rule (generated station pairs; not with `muse demand --customers`).
    #[arg(long, value_enum, default_value_t = OdArg::Uniform)]
    pub od: OdArg,
    /// Book each request ahead of its departure by a lead uniform in [A, B] minutes (whole
    /// milliseconds), each from 0 to 43200 (30 days): `submitted = departure − lead`. A single
    /// number A means exactly A minutes; 0 (the default, the paper) books every request at its
    /// departure; `muse sweep --vary announce-lead` books 0:120 unless given. Departures and
    /// pairs do not depend on it: a seed gives the same ones with any lead.
    #[arg(long, value_name = "A[:B]", allow_hyphen_values = true, value_parser = parse_booking_lead)]
    pub booking_lead_min: Option<BookingLeadArg>,
}

/// `--booking-lead-min A[:B]`: a booking lead uniform in `[A, B]` minutes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BookingLeadArg {
    /// Shortest lead, minutes, as given.
    pub from_min: f64,
    /// Longest lead, minutes, as given.
    pub to_min: f64,
    /// The lead, in milliseconds.
    pub lead: BookingLead,
}

impl std::fmt::Display for BookingLeadArg {
    /// `A` when the bounds are equal, else `A:B` (minutes).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.lead.min == self.lead.max {
            write!(f, "{}", self.from_min)
        } else {
            write!(f, "{}:{}", self.from_min, self.to_min)
        }
    }
}

impl BookingLeadArg {
    /// `booked A–B min ahead` (or `booked A min ahead`), for messages and plot footnotes;
    /// `None` when every request is booked at its departure.
    pub fn note(self) -> Option<String> {
        (!self.lead.is_none())
            .then(|| format!("booked {} min ahead", self.to_string().replace(':', "–")))
    }
}

/// Parses `A` or `A:B` (minutes, `0 ≤ A ≤ B`) for clap; the message is what clap prints after
/// "invalid value".
fn parse_booking_lead(text: &str) -> Result<BookingLeadArg, String> {
    let minutes = |part: &str| -> Result<(f64, Millis), String> {
        let m: f64 = part.trim().parse().map_err(|_| {
            format!(
                "`{part}` is not a number of minutes from 0 to {MAX_LEAD_MIN}; expected A or \
                 A:B, e.g. 0:120"
            )
        })?;
        if !m.is_finite() || !(0.0..=MAX_LEAD_MIN).contains(&m) {
            return Err(format!(
                "{} minutes: a booking lead must be a number of minutes from 0 to {MAX_LEAD_MIN}",
                part.trim()
            ));
        }
        let ms = Millis::from_secs_f64(m * 60.0)
            .map_err(|_| format!("{} minutes is too long a booking lead", part.trim()))?;
        Ok((m, ms))
    };
    let (a, b) = if let Some((a, b)) = text.split_once(':') {
        (minutes(a)?, minutes(b)?)
    } else {
        let a = minutes(text)?;
        (a, a)
    };
    if a.0 > b.0 {
        return Err(format!(
            "the lower bound {} must not exceed the upper bound {} (A:B with A <= B)",
            a.0, b.0
        ));
    }
    let lead = BookingLead::new(a.1, b.1).map_err(|e| e.to_string())?;
    Ok(BookingLeadArg {
        from_min: a.0,
        to_min: b.0,
        lead,
    })
}

impl DemandArgs {
    /// `booked A–B min ahead` when requests are booked ahead of departure, for messages and
    /// plot footnotes; `None` for the paper's demand (so those read as they always did).
    pub fn booking_note(&self) -> Option<String> {
        self.booking_lead_min.and_then(BookingLeadArg::note)
    }

    /// The booking lead given, or none (the paper): every request booked at its departure.
    pub fn booking_lead(&self) -> BookingLead {
        self.booking_lead_min.map_or(BookingLead::NONE, |b| b.lead)
    }

    /// The generation spec for a world.
    pub fn spec(&self, world: &World, range: RangeArgs) -> anyhow::Result<DemandSpec> {
        let clock = |name: &str, v: &str| -> anyhow::Result<Millis> {
            parse_clock(v).map_err(|e| match e {
                TimeError::LeapSecond(_) => anyhow::anyhow!("--{name}: {e}"),
                _ => anyhow::Error::new(e)
                    .context(format!("--{name} `{v}` is not a local time HH:MM[:SS]")),
            })
        };
        let start = Instant::at_local(world.day.date, clock("from", &self.from)?, world.day.offset);
        let end = Instant::at_local(world.day.date, clock("to", &self.to)?, world.day.offset);
        if end <= start {
            anyhow::bail!("--to {} must be after --from {}", self.to, self.from);
        }
        let od = match self.od {
            OdArg::Uniform => OdRule::Uniform,
            OdArg::InRange => OdRule::InRange {
                speed: range.speed()?,
                max_flight: range.t_max()?,
            },
        };
        Ok(DemandSpec {
            count: self.count,
            start,
            end,
            seed: self.seed,
            od,
            booking_lead: self.booking_lead(),
        })
    }
}

/// Arguments of `muse demand`.
#[derive(Debug, Args)]
pub struct DemandCmd {
    #[command(flatten)]
    demand: DemandArgs,
    #[command(flatten)]
    world: WorldArgs,
    #[command(flatten)]
    range: RangeArgs,
    /// Demand from customers (docs/reference.md#demand-from-customers): a CSV
    /// `id,lon,lat[,weight]`; each request joins two customers drawn by weight, from the
    /// nearest pad within `--last-mile-m` of the sender to that of the receiver. The file
    /// keeps the customer ids; a request with a customer out of reach, or both on one pad, is
    /// unserved. `singapore-hdb`: the embedded list of all 2,257 HDB car parks, each of
    /// weight 1, as a proxy for where Singapore's residents live.
    #[arg(long, value_name = "FILE|singapore-hdb", conflicts_with = "od")]
    customers: Option<PathBuf>,
    /// With `--customers`: the last mile, metres (straight line), from 0 to 100000.
    #[arg(long, value_name = "M", default_value_t = 1_000.0, requires = "customers", allow_negative_numbers = true, value_parser = ranges::last_mile_m)]
    last_mile_m: f64,
    /// Output CSV (`-`: standard output).
    #[arg(long, value_name = "FILE", default_value = "requests.csv")]
    out: PathBuf,
}

/// Runs `muse demand`.
pub fn run(args: &DemandCmd) -> anyhow::Result<ExitCode> {
    let inputs = output::Inputs::new()
        .world(&args.world)
        .customers(args.customers.as_deref());
    let out = output::file("--out", &args.out, &inputs)?;
    let world = args.world.load()?;
    let spec = args.demand.spec(&world, args.range)?;
    if let Some(path) = &args.customers {
        return from_customers(args, path, &world, &spec, &out);
    }
    let requests = generate(&world.airspace, &spec)?;
    out.write(&write_requests(
        &requests,
        &world.airspace,
        world.day.offset,
    ))?;
    let booked = args
        .demand
        .booking_note()
        .map_or(String::new(), |b| format!(", {b}"));
    output::say(
        out.is_stdout(),
        format_args!(
            "wrote {} requests (seed {}{booked}) to {out}",
            requests.len(),
            spec.seed,
        ),
    );
    Ok(ExitCode::SUCCESS)
}

/// `muse demand --customers`: trips between customers, each mapped to its customers' pads.
fn from_customers(
    args: &DemandCmd,
    path: &std::path::Path,
    world: &World,
    spec: &DemandSpec,
    out: &output::FileOut,
) -> anyhow::Result<ExitCode> {
    let customers = read_customers(path)?;
    let weights: Vec<f64> = customers.iter().map(|c| c.weight).collect();
    let trips = draw_trips(
        &weights,
        &TripSpec {
            count: spec.count,
            start: spec.start,
            end: spec.end,
            seed: spec.seed,
            booking_lead: spec.booking_lead,
        },
    )?;
    let positions: Vec<_> = customers.iter().map(|c| c.pos).collect();
    let pads: Vec<Option<NodeId>> = serving_pads(&world.airspace, &positions, args.last_mile_m)
        .into_iter()
        .map(|s| s.map(|s| s.pad))
        .collect();
    let mut why: std::collections::BTreeMap<&str, usize> = std::collections::BTreeMap::new();
    let rows: Vec<DemandRow> = trips
        .iter()
        .map(|t| {
            if let Err(u) = request_for(t, &pads) {
                *why.entry(u.describe()).or_default() += 1;
            }
            DemandRow {
                id: t.id.clone(),
                origin: pads[t.from],
                destination: pads[t.to],
                departure: t.departure,
                submitted: t.submitted,
                customers: [customers[t.from].id.clone(), customers[t.to].id.clone()],
            }
        })
        .collect();
    out.write(&write_demand(&rows, &world.airspace, world.day.offset))?;
    let unserved: usize = why.values().sum();
    let causes: Vec<String> = why.iter().map(|(k, v)| format!("{v} {k}")).collect();
    let causes = if causes.is_empty() {
        String::new()
    } else {
        format!(": {}", causes.join(", "))
    };
    let served = customers
        .iter()
        .zip(&pads)
        .filter(|(_, p)| p.is_some())
        .count();
    output::say(
        out.is_stdout(),
        format_args!(
            "wrote {} requests (seed {}) between {} customers ({served} with a pad within {} m) \
             to {out}; {} to fly, {unserved} unserved{causes}",
            rows.len(),
            spec.seed,
            customers.len(),
            args.last_mile_m,
            rows.len() - unserved,
        ),
    );
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn booking_lead_flag() {
        let ok = |t: &str| parse_booking_lead(t).unwrap();
        assert_eq!(ok("0").lead, BookingLead::NONE);
        assert_eq!(
            ok("0:120").lead,
            BookingLead::new(Millis::ZERO, Millis::from_mins(120)).unwrap()
        );
        assert_eq!(
            ok(" 30 ").lead,
            BookingLead::new(Millis::from_mins(30), Millis::from_mins(30)).unwrap()
        );
        assert_eq!(ok("0.5:1.5").lead.max, Millis::from_secs(90));
        assert_eq!(ok("0:120").to_string(), "0:120");
        assert_eq!(ok("30").to_string(), "30");
        for (bad, message) in [
            ("5:1", "the lower bound 5 must not exceed the upper bound 1"),
            (
                "-1",
                "-1 minutes: a booking lead must be a number of minutes from 0 to 43200",
            ),
            (
                "43201",
                "43201 minutes: a booking lead must be a number of minutes from 0 to",
            ),
            ("0:-5", "-5 minutes: a booking lead must be"),
            ("abc", "`abc` is not a number of minutes"),
            ("1:2:3", "`2:3` is not a number of minutes"),
            ("", "`` is not a number of minutes"),
            ("inf", "inf minutes: a booking lead must be"),
            ("NaN", "NaN minutes: a booking lead must be"),
        ] {
            let e = parse_booking_lead(bad).unwrap_err();
            assert!(e.contains(message), "{bad}: {e}");
        }
    }
}
