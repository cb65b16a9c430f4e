//! What a planned day leaves behind: one [`PlanRecord`] per request (the lines of
//! `plans.jsonl`, SPEC §7) and the [`Summary`] (`summary.json`), computed once for every
//! front end — the command line writes them to files, the Python package hands them to
//! notebooks.

use muse_formats::plans::PlanRecord;
use muse_formats::requests::UnservedRequest;
use muse_model::{Airspace, FlightParams, NodeId, RejectReason, UtcOffset};

use crate::day::DayRun;
use crate::demand::BookingLead;
use crate::metrics::recorded::WorldRecord;
use crate::metrics::{OptimizerSummary, Provenance, ReplanSummary, RunItem, Summary};

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
    /// The requests of demand from customers that no pad serves (SPEC §15); `None` for other
    /// demand.
    pub unserved: Option<&'a [UnservedRequest]>,
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
    DayOutputs { records, summary }
}
