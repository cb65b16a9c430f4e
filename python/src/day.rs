//! `plan` and `simulate`: a day planned first come, first served (docs/reference.md#requests and
//! #plans), handed back as the texts the command line writes: `plans.jsonl`, `summary.json`,
//! `flights.csv` and `stays.csv`.

use std::path::PathBuf;

use muse_formats::requests::{Demand, read_demand};
use muse_model::time::parse_clock;
use muse_model::{FlightParams, Instant, Request};
use muse_sim::day::{Planning, plan_requests_by};
use muse_sim::demand::{BookingLead, DemandSpec, OdRule, generate};
use muse_sim::metrics::Provenance;
use muse_sim::outputs::{DayContext, DayFiles, day_outputs};
use muse_sim::world::World;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::airspace::Airspace;
use crate::options::{options, whole};
use crate::world::world;
use crate::{MuseError, error};

/// Plans the requests CSV `requests` (named `source` in messages; columns as
/// docs/reference.md#requests, and the customer columns of docs/reference.md#airspace-from-pads) on
/// `airspace` with `zones` (`None`: the airspace's own; a list: these files), first come, first
/// served. Keywords: flight parameters and layers. Returns `plans`, `summary`, `flights` and
/// `stays`: the texts of the command line's files.
#[pyfunction]
#[pyo3(signature = (requests, source, airspace = None, zones = None, **kwargs))]
pub fn plan<'py>(
    py: Python<'py>,
    requests: &str,
    source: &str,
    airspace: Option<PyRef<'py, Airspace>>,
    zones: Option<Vec<PathBuf>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = options(kwargs)?;
    let world = world_of(airspace.as_deref(), zones, &opts.layers)?;
    let demand = read_demand(requests, source, &world.airspace, world.day).map_err(error)?;
    let provenance = world.provenance(source.to_owned(), None);
    let texts = py.detach(|| run_day(&world, opts.params, demand, provenance, None))?;
    texts_dict(py, &texts)
}

/// Generates a seeded day of `count` requests departing uniformly in `[start, end)` (local
/// `HH:MM[:SS]`) between random station pairs (`od`: `uniform` or `in-range`), as
/// `muse simulate` does, and plans it. `count` and `seed` take the values `--count` and
/// `--seed` take. Keywords: flight parameters and layers.
#[pyfunction]
#[pyo3(signature = (count, seed, start, end, od, airspace = None, zones = None, **kwargs))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    count: &Bound<'py, PyAny>,
    seed: &Bound<'py, PyAny>,
    start: &str,
    end: &str,
    od: &str,
    airspace: Option<PyRef<'py, Airspace>>,
    zones: Option<Vec<PathBuf>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let count = whole("count", count, muse_formats::ranges::REQUESTS)?;
    let seed = whole("seed", seed, muse_formats::ranges::SEED)?;
    let opts = options(kwargs)?;
    let world = world_of(airspace.as_deref(), zones, &opts.layers)?;
    let clock = |name: &str, text: &str| {
        parse_clock(text)
            .map(|t| Instant::at_local(world.day.date, t, world.day.offset))
            .map_err(|e| {
                error(format!(
                    "{name} `{text}` is not a local time HH:MM[:SS]: {e}"
                ))
            })
    };
    let (from, to) = (clock("start", start)?, clock("end", end)?);
    if to <= from {
        return Err(error(format!("end {end} must be after start {start}")));
    }
    let od_rule = match od {
        "uniform" => OdRule::Uniform,
        "in-range" => OdRule::InRange {
            speed: opts.params.speed,
            max_flight: opts.params.max_flight,
        },
        other => {
            return Err(error(format!(
                "od: `{other}` is not `uniform` or `in-range`"
            )));
        }
    };
    let spec = DemandSpec {
        count,
        start: from,
        end: to,
        seed,
        od: od_rule,
        booking_lead: BookingLead::NONE,
    };
    let requests: Vec<Request> = generate(&world.airspace, &spec).map_err(error)?;
    let provenance = world.provenance(
        format!("generated: {count} requests, {start}–{end}, {od} pairs, seed {seed}"),
        Some(seed),
    );
    let demand = Demand {
        requests,
        ..Demand::default()
    };
    let texts = py.detach(|| {
        run_day(
            &world,
            opts.params,
            demand,
            provenance,
            Some(BookingLead::NONE),
        )
    })?;
    texts_dict(py, &texts)
}

/// The world of the arguments, or the error naming what is wrong.
fn world_of(
    airspace: Option<&Airspace>,
    zones: Option<Vec<PathBuf>>,
    layers: &muse_model::Layers,
) -> PyResult<World> {
    let world = world(airspace, zones, layers)?;
    if let Some(z) = world.withdrawn_zone() {
        return Err(error(format!(
            "zones: zone `{}` was withdrawn (`withdrawn`): a day cannot be planned with a \
             withdrawn zone; leave it out",
            z.id
        )));
    }
    Ok(world)
}

/// Plans `demand` on `world` and writes its files' texts.
fn run_day(
    world: &World,
    params: FlightParams,
    demand: Demand,
    provenance: Provenance,
    booking_lead: Option<BookingLead>,
) -> PyResult<DayFiles> {
    let run = plan_requests_by(
        &world.airspace,
        &world.zones,
        params,
        demand.requests,
        Planning::FirstComeFirstServed,
        |_| {},
    )
    .map_err(|e| MuseError::new_err(e.to_string()))?;
    let unserved = demand.rows.is_some().then_some(demand.unserved.as_slice());
    let outputs = day_outputs(
        &run,
        DayContext {
            booking_lead,
            unserved,
            ..DayContext::on(world, &params, provenance).map_err(error)?
        },
    );
    Ok(DayFiles::of(&outputs, &world.airspace, world.day, true))
}

/// The texts as a dict: `plans`, `summary`, `flights` and `stays`.
fn texts_dict<'py>(py: Python<'py>, files: &DayFiles) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("plans", &files.plans)?;
    out.set_item("summary", &files.summary)?;
    out.set_item("flights", &files.flights_csv)?;
    out.set_item("stays", &files.stays_csv)?;
    Ok(out)
}
