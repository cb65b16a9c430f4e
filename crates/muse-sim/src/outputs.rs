//! What a planned day leaves behind: one [`PlanRecord`] per request (the lines of
//! `plans.jsonl`, docs/reference.md#plans) and the [`Summary`] (`summary.json`), and the texts of
//! its files ([`DayFiles`]: `plans.jsonl`, `summary.json`, `flights.csv`, `stays.csv`), computed
//! once for every front end — the command line writes them to files, the Python package hands them
//! to notebooks.

use muse_formats::day::LocalDay;
use muse_formats::flights_csv::write_flights_csv;
use muse_formats::plans::{PlanRecord, write_plan_line};
use muse_formats::requests::UnservedRequest;
use muse_formats::stays_csv::write_stays_csv;
use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId, RejectReason, UtcOffset};

use crate::day::DayRun;
use crate::demand::BookingLead;
use crate::metrics::recorded::WorldRecord;
use crate::metrics::{
    OptimizerSummary, Provenance, ReplanSummary, RunItem, SeparationSummary, Summary,
};
use crate::world::World;

/// Where a day was planned and from what, for its summary.
#[derive(Clone, Debug)]
pub struct DayContext<'a> {
    /// The airspace planned on (layered, when it is).
    pub airspace: &'a Airspace,
    /// The day's UTC offset (for the replanning section's local times).
    pub offset: UtcOffset,
    /// The flight parameters planned with.
    pub params: &'a FlightParams,
    /// Where the airspace, zones and requests came from.
    pub provenance: Provenance,
    /// The world as `summary.json` records it.
    pub world: WorldRecord,
    /// The booking lead of generated demand (`None` for requests read from a file).
    pub booking_lead: Option<BookingLead>,
    /// The requests of demand from customers that no pad serves
    /// (docs/reference.md#airspace-from-pads); `None` for other demand.
    pub unserved: Option<&'a [UnservedRequest]>,
    /// Where the airspace's flat nodes are in its plane, metres (the world's
    /// [`World::plane_positions`]): the summary then says how close the flights come
    /// (docs/reference.md#metric-separation); `None` leaves that out.
    pub plane: Option<Vec<[f64; 2]>>,
}

impl<'a> DayContext<'a> {
    /// A day planned on `world` with `params`, from requests read from a file (no booking
    /// lead) and not from customers (no unserved requests), its summary saying how close the
    /// flights come.
    ///
    /// # Errors
    /// A node the world's plane cannot take ([`World::plane_positions`]).
    pub fn on(
        world: &'a World,
        params: &'a FlightParams,
        provenance: Provenance,
    ) -> Result<Self, muse_airspace::plane::PlaneError> {
        Ok(DayContext {
            airspace: &world.airspace,
            offset: world.day.offset,
            params,
            provenance,
            world: world.record.clone(),
            booking_lead: None,
            unserved: None,
            plane: Some(world.plane_positions()?),
        })
    }
}

/// A planned day's records and summary.
#[derive(Clone, Debug)]
pub struct DayOutputs {
    /// One record per request, in planning order, then the unserved requests (rejected with
    /// reason `unserved`).
    pub records: Vec<PlanRecord>,
    /// The day's summary.
    pub summary: Summary,
}

/// The records and the summary of `run`, planned in `context`.
///
/// ```
/// use muse_model::{Airspace, FlightParams, Instant, NodeId, Request, UtcOffset};
/// use muse_sim::day::{Planning, plan_requests_by};
/// use muse_sim::outputs::{DayContext, day_outputs};
/// let air = Airspace::line(&[1_000.0]);
/// let params = FlightParams::default();
/// let (at, from, to) = (Instant(0), NodeId(0), NodeId(1));
/// let request = Request { id: "r1".into(), origin: from, destination: to, departure: at, submitted: at };
/// let run = plan_requests_by(&air, &[], params, vec![request], Planning::default(), |_| {})
///     .unwrap();
/// let context = DayContext {
///     airspace: &air,
///     offset: UtcOffset(0),
///     params: &params,
///     provenance: Default::default(),
///     world: Default::default(),
///     booking_lead: None,
///     unserved: None,
///     plane: None,
/// };
/// let day = day_outputs(&run, context);
/// assert_eq!((day.records.len(), day.summary.planned), (1, 1));
/// ```
pub fn day_outputs(run: &DayRun, context: DayContext<'_>) -> DayOutputs {
    let a = context.airspace;
    let mut records = Vec::with_capacity(run.requests.len());
    for (i, (r, o)) in run.requests.iter().zip(&run.replay.outcomes).enumerate() {
        records.push(PlanRecord {
            changes: run.replay.changes[i].clone(),
            fate: run.replay.fate(i).cloned(),
            ..PlanRecord::first(
                r.id.clone(),
                a.node(r.origin).id.clone(),
                a.node(r.destination).id.clone(),
                r.departure,
                o.result.clone(),
                o.free_flow,
                o.expanded,
            )
        });
    }
    let pad = |n: Option<NodeId>| n.map_or_else(String::new, |n| a.node(n).id.clone());
    for u in context.unserved.unwrap_or_default() {
        records.push(PlanRecord::first(
            u.id.clone(),
            pad(u.origin),
            pad(u.destination),
            u.departure,
            Err(RejectReason::Unserved),
            None,
            0,
        ));
    }
    let items = run
        .requests
        .iter()
        .zip(&run.replay.outcomes)
        .map(|(r, o)| RunItem {
            departure: r.departure,
            result: &o.result,
            free_flow: o.free_flow,
            expanded: o.expanded,
        });
    let mut summary = Summary::compute(
        items,
        context.params,
        run.replay.planner_wall,
        context.provenance,
    )
    .with_world(context.world);
    if let Some(lead) = context.booking_lead {
        summary = summary.with_booking_lead(lead);
    }
    if let Some(unserved) = context.unserved {
        summary = summary.with_unserved(unserved.len());
    }
    if !run.zones.announced.is_empty() {
        summary = summary.with_replanning(ReplanSummary::of(&run.replay, context.offset));
    }
    if let Some(report) = &run.optimizer {
        summary = summary.with_optimizer(OptimizerSummary::of(report, &run.requests));
    }
    if let Some(plane) = &context.plane {
        let flights = run.flights();
        summary = summary.with_separation(SeparationSummary::of(
            a,
            plane,
            &flights,
            context.offset,
            context.params.separation,
        ));
    }
    DayOutputs { records, summary }
}

/// The texts of a planned day's files.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DayFiles {
    /// `plans.jsonl`: one line per record.
    pub plans: String,
    /// `summary.json`.
    pub summary: String,
    /// `flights.csv`: one row per request; `None` when the tables are not wanted.
    pub flights_csv: Option<String>,
    /// `stays.csv`: one row per stay of every flight that flies; `None` when the tables are
    /// not wanted.
    pub stays_csv: Option<String>,
}

impl DayFiles {
    /// The texts of `outputs`, a day planned on `airspace` on `day` (its local times at the
    /// day's offset, the tables' times from its midnight); with `tables`, `flights.csv` and
    /// `stays.csv` too.
    ///
    /// ```
    /// use muse_formats::day::LocalDay;
    /// use muse_model::{Airspace, FlightParams, Instant, NodeId, Request, UtcOffset};
    /// use muse_sim::day::{Planning, plan_requests_by};
    /// use muse_sim::outputs::{DayContext, DayFiles, day_outputs};
    /// let air = Airspace::line(&[1_000.0]);
    /// let params = FlightParams::default();
    /// let (at, from, to) = (Instant(0), NodeId(0), NodeId(1));
    /// let request = Request { id: "r1".into(), origin: from, destination: to, departure: at, submitted: at };
    /// let run = plan_requests_by(&air, &[], params, vec![request], Planning::default(), |_| {})
    ///     .unwrap();
    /// let context = DayContext {
    ///     airspace: &air,
    ///     offset: UtcOffset(0),
    ///     params: &params,
    ///     provenance: Default::default(),
    ///     world: Default::default(),
    ///     booking_lead: None,
    ///     unserved: None,
    ///     plane: None,
    /// };
    /// let day = LocalDay { date: jiff::civil::date(1970, 1, 1), offset: UtcOffset(0) };
    /// let files = DayFiles::of(&day_outputs(&run, context), &air, day, true);
    /// assert_eq!(files.plans.lines().count(), 1);
    /// assert_eq!(files.iter().map(|(name, _)| name).collect::<Vec<_>>(),
    ///     ["plans.jsonl", "summary.json", "flights.csv", "stays.csv"]);
    /// ```
    pub fn of(outputs: &DayOutputs, airspace: &Airspace, day: LocalDay, tables: bool) -> Self {
        let records = &outputs.records;
        let mut plans = String::with_capacity(records.len() * 400);
        for record in records {
            write_plan_line(&mut plans, airspace, day.offset, record);
        }
        let midnight = Instant::at_local(day.date, Millis::ZERO, day.offset);
        DayFiles {
            plans,
            summary: outputs.summary.to_json(),
            flights_csv: tables.then(|| write_flights_csv(records, airspace, day.offset, midnight)),
            stays_csv: tables.then(|| write_stays_csv(records, airspace, day.offset, midnight)),
        }
    }

    /// Each file's name and text, in the order they are written: `plans.jsonl`,
    /// `summary.json`, then the tables when there are.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &str)> {
        [
            ("plans.jsonl", Some(&self.plans)),
            ("summary.json", Some(&self.summary)),
            ("flights.csv", self.flights_csv.as_ref()),
            ("stays.csv", self.stays_csv.as_ref()),
        ]
        .into_iter()
        .filter_map(|(name, text)| Some((name, text?.as_str())))
    }
}
