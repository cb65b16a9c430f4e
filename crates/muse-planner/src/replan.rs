//! Replanning the flights a newly announced zone hits
//! (docs/reference.md#zones-announced-during-the-day).
//!
//! A zone announced at instant `n` binds every stay and traversal that *begins* at or after
//! `n`. The accepted flights that would break it are *affected*; [`replan`] then, exactly as
//! the reference states:
//!
//! 1. takes every affected flight out of the schedule; an airborne one (take-off before `n`)
//!    keeps its *committed part*: its path up to the first node it reaches at or after `n` —
//!    it cannot turn inside a corridor — including the arrival there (a stay of zero length,
//!    so that others keep their separation from it);
//! 2. replans them one at a time in order of original take-off, then request id, each against
//!    the schedule as it then stands (which already holds the new zone's closures):
//!    - not yet taken off: the plan of docs/reference.md#planning for its request with take-off in
//!      `[max(departure, n), max(departure + G_max, n)]`; if none exists it is
//!      [cancelled](Fate::Cancelled);
//!    - airborne: from the committed node at its arrival instant with the battery it has left,
//!      to its destination ([replanned](Fate::Replanned)); if that is impossible, to the
//!      station where it can land earliest ([diverted](Fate::Diverted)); if neither exists,
//!      it is a [contingency](Fate::Contingency): its committed part stays reserved and it
//!      is reported. A committed part that itself breaks the zone (a drone hovering at a node
//!      at `n` is committed to the corridor it leaves by, which begins at or after `n`) leaves
//!      no plan that complies: a contingency too.
//!
//! With battery swaps (docs/reference.md#multi-leg-trips) the rest of an airborne flight may itself
//! land and swap on the way, and a multi-leg flight on the ground between legs at `n` keeps the
//! legs it has flown and is replanned from the ground at that station, taking off no earlier than
//! `n` and than its swap allows; if its destination cannot be reached any more it ends there
//! ([diverted](Fate::Diverted)).
//!
//! Both searches are the planner's own, exact ([`Planner::plan_within`],
//! [`Planner::resume`]). A stay or traversal that begins before `n` is exempt from the
//! zone, so flights whose every violation begins before `n` (landed, or past the zone) are
//! not affected.

use std::collections::HashMap;
use std::hash::BuildHasher;

use muse_airspace::closures::Closures;
use muse_model::plan::Change;
pub use muse_model::plan::{Fate, FateKind};
use muse_model::{Airspace, Instant, Millis, Plan, Request};

use crate::planner::{Landing, Planner, Resume};
use crate::schedule::{FlightId, Schedule};
use crate::sipp::Scratch;

/// A flight a live schedule holds: its request and its current plan.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Booking {
    /// The request it was planned for.
    pub request: Request,
    /// Its plan as it stands (after any replanning).
    pub plan: Plan,
}

/// One affected flight and its fate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Affected {
    /// The flight.
    pub flight: FlightId,
    /// Its plan before the announcement.
    pub before: Plan,
    /// Whether it had taken off at the announcement.
    pub airborne: bool,
    /// What became of it.
    pub fate: Fate,
    /// Search effort spent on it (labels expanded).
    pub expanded: u64,
}

impl Affected {
    /// The record of this change, the announcement being `zone`'s at `announced`.
    pub fn change(&self, zone: &str, announced: Instant) -> Change {
        Change::new(zone, announced, self.airborne, &self.fate)
    }
}

/// Whether `plan` would break `zone` announced at `at`: some stay or traversal that begins
/// at or after `at` shares an instant with one of the zone's windows.
///
/// ```
/// use muse_airspace::closures::resolve;
/// use muse_model::{Airspace, Instant, NodeId, Period, Plan, Stay, Zone};
/// use muse_planner::breaks;
/// let airspace = Airspace::line(&[1_000.0]);
/// let zone = Zone { id: "Z".into(), name: String::new(), restriction: String::new(), area: None,
///     node_ids: vec!["B".into()], edge_ids: vec![], announced: None, withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
///     periods: vec![Period { start: Some(Instant(0)), end: Some(Instant(1_000_000)), daily: vec![] }] };
/// let closed = resolve(&airspace, &[zone], Instant(0), Instant(86_400_000)).unwrap();
/// let stay = |n, a, d| Stay { node: NodeId(n), arrive: Instant(a), depart: Instant(d) };
/// let plan = Plan { path: vec![stay(0, 0, 0), stay(1, 120_000, 120_000)] };
/// assert!(breaks(&airspace, &closed, &plan, Instant(100_000)), "it lands in B after the announcement");
/// assert!(!breaks(&airspace, &closed, &plan, Instant(120_001)), "it landed before the announcement");
/// ```
pub fn breaks(airspace: &Airspace, zone: &Closures, plan: &Plan, at: Instant) -> bool {
    let stays = plan.path.iter().any(|stay| {
        stay.arrive >= at
            && zone
                .node_conflict(stay.node, stay.arrive, stay.depart)
                .is_some()
    });
    stays
        || plan.hops().any(|(from, to)| {
            from.depart >= at
                && airspace
                    .edge_between(from.node, to.node)
                    .is_some_and(|e| zone.edge_conflict(e, from.depart, to.arrive).is_some())
        })
}

/// The committed part of a flight airborne at `at`: its stays before the first one it
/// arrives at at or after `at`, then that arrival as a stay of zero length. `None` if the
/// plan ends before `at`. (A multi-leg flight on the ground between legs at `at` is
/// committed to the legs it has flown: [`Commitment`].)
///
/// ```
/// use muse_model::{Instant, NodeId, Plan, Stay};
/// use muse_planner::committed_part;
/// let stay = |n, a, d| Stay { node: NodeId(n), arrive: Instant(a), depart: Instant(d) };
/// let plan = Plan { path: vec![stay(0, 0, 10), stay(1, 50, 70), stay(2, 90, 90)] };
/// // At 60 it hovers at node 1 (arrived at 50): it is committed to flying on to node 2.
/// assert_eq!(committed_part(&plan, Instant(60)).unwrap().path,
///            vec![stay(0, 0, 10), stay(1, 50, 70), stay(2, 90, 90)]);
/// // At 30 it is in the corridor to node 1: committed to arriving there at 50.
/// assert_eq!(committed_part(&plan, Instant(30)).unwrap().path, vec![stay(0, 0, 10), stay(1, 50, 50)]);
/// ```
pub fn committed_part(plan: &Plan, at: Instant) -> Option<Plan> {
    let k = plan.path.iter().position(|s| s.arrive >= at)?;
    let mut path = plan.path[..=k].to_vec();
    path[k].depart = path[k].arrive;
    Some(Plan { path })
}

/// What a flight that has taken off before `at` is committed to
/// (docs/reference.md#zones-announced-during-the-day, with #multi-leg-trips).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Commitment {
    /// In the air: the [`committed_part`], ending with its arrival at the node it resumes
    /// from.
    Airborne(Plan),
    /// On the ground between legs: the legs flown, ending with the landing at the station it
    /// resumes from.
    Landed(Plan),
}

impl Commitment {
    /// What `plan` (which took off before `at`) is committed to at `at`; `None` if it ends
    /// before `at`.
    ///
    /// ```
    /// use muse_model::{Instant, NodeId, Plan, Stay};
    /// use muse_planner::Commitment;
    /// let stay = |n, a, d| Stay { node: NodeId(n), arrive: Instant(a), depart: Instant(d) };
    /// // Lands at node 1 at 50, swaps, takes off again at 80.
    /// let plan = Plan { path: vec![stay(0, 0, 0), stay(1, 50, 50), stay(1, 80, 80), stay(2, 120, 120)] };
    /// assert_eq!(Commitment::at(&plan, Instant(60)),
    ///            Some(Commitment::Landed(Plan { path: vec![stay(0, 0, 0), stay(1, 50, 50)] })));
    /// assert_eq!(Commitment::at(&plan, Instant(90)),
    ///            Some(Commitment::Airborne(Plan { path: plan.path.clone() })));
    /// ```
    pub fn at(plan: &Plan, at: Instant) -> Option<Commitment> {
        let k = plan.path.iter().position(|s| s.arrive >= at)?;
        if k > 0 && plan.path[k - 1].node == plan.path[k].node {
            return Some(Commitment::Landed(Plan {
                path: plan.path[..k].to_vec(),
            }));
        }
        committed_part(plan, at).map(Commitment::Airborne)
    }

    /// The committed plan.
    pub fn plan(&self) -> &Plan {
        match self {
            Commitment::Airborne(p) | Commitment::Landed(p) => p,
        }
    }

    /// The committed plan, owned.
    pub fn into_plan(self) -> Plan {
        match self {
            Commitment::Airborne(p) | Commitment::Landed(p) => p,
        }
    }
}

/// Replans the flights `zone` (announced at `at`) affects, as
/// docs/reference.md#zones-announced-during-the-day states (see the module docs). `schedule` must
/// hold every booking's plan and already include the zone's closures; `bookings` is updated:
/// replanned and diverted flights get their new plan, cancelled and contingency flights are removed
/// (a contingency's committed part stays in the schedule). Returns the affected flights in the
/// order they were replanned.
pub fn replan<S: BuildHasher>(
    planner: &Planner<'_>,
    schedule: &mut Schedule,
    bookings: &mut HashMap<FlightId, Booking, S>,
    zone: &Closures,
    at: Instant,
    scratch: &mut Scratch,
) -> Vec<Affected> {
    let airspace = planner.airspace();
    let mut hit: Vec<(Instant, &str, FlightId)> = bookings
        .iter()
        .filter(|(_, b)| breaks(airspace, zone, &b.plan, at))
        .map(|(&f, b)| (b.plan.takeoff(), b.request.id.as_str(), f))
        .collect();
    hit.sort_unstable();
    let order: Vec<FlightId> = hit.into_iter().map(|(_, _, f)| f).collect();

    // 1. Everything affected out; the committed parts of airborne flights back in.
    let mut committed: HashMap<FlightId, Commitment> = HashMap::default();
    for &f in &order {
        let plan = &bookings[&f].plan;
        schedule.release(airspace, f, plan);
        if plan.takeoff() < at {
            let part = Commitment::at(plan, at).expect("an affected flight ends after `at`");
            schedule.insert(airspace, f, part.plan());
            committed.insert(f, part);
        }
    }

    // 2. One at a time, in order of original take-off, then id.
    let params = *planner.params();
    let mut out = Vec::with_capacity(order.len());
    for f in order {
        let booking = &bookings[&f];
        let before = booking.plan.clone();
        let (fate, expanded) = match committed.remove(&f) {
            None => {
                let r = &booking.request;
                let earliest = r.departure.max(at);
                let latest = (r.departure + params.max_ground_delay).max(at);
                let outcome = planner.plan_within(schedule, r, earliest, latest, scratch);
                let fate = outcome.result.map_or(Fate::Cancelled, Fate::Replanned);
                (fate, outcome.expanded)
            }
            Some(part) => {
                schedule.release(airspace, f, part.plan());
                fly_on(planner, schedule, zone, at, part, &booking.request, scratch)
            }
        };
        match &fate {
            Fate::Replanned(plan) | Fate::Diverted(plan) => {
                schedule.insert(airspace, f, plan);
                bookings.get_mut(&f).expect("booked").plan = plan.clone();
            }
            Fate::Contingency(part) => {
                schedule.insert(airspace, f, part);
                bookings.remove(&f);
            }
            Fate::Cancelled => {
                bookings.remove(&f);
            }
        }
        out.push(Affected {
            flight: f,
            airborne: before.takeoff() < at,
            before,
            fate,
            expanded,
        });
    }
    out
}

/// The fate of a flight that has taken off, committed to `part` (taken out of `schedule`).
fn fly_on(
    planner: &Planner<'_>,
    schedule: &Schedule,
    zone: &Closures,
    at: Instant,
    part: Commitment,
    request: &Request,
    scratch: &mut Scratch,
) -> (Fate, u64) {
    let plan = part.plan();
    let legs = plan.leg_count() as u32;
    let last = *plan.path.last().expect("a committed part is not empty");
    let from = match &part {
        // Committed to a stay or traversal the zone closes: nothing can comply.
        Commitment::Airborne(p) if breaks(planner.airspace(), zone, p, at) => {
            return (Fate::Contingency(part.into_plan()), 0);
        }
        Commitment::Airborne(p) => Resume {
            leg_origin: p.legs().last().expect("not empty")[0].node,
            departure: request.departure,
            node: last.node,
            at: last.arrive,
            airborne_since: Some(p.legs().last().expect("not empty")[0].arrive),
            first_takeoff: p.takeoff(),
            legs,
        },
        Commitment::Landed(p) => {
            let swap = planner
                .params()
                .battery_swap
                .map_or(Millis::ZERO, |s| s.time);
            Resume {
                leg_origin: last.node,
                departure: request.departure,
                node: last.node,
                at: (last.depart + swap).max(at),
                airborne_since: None,
                first_takeoff: p.takeoff(),
                legs,
            }
        }
    };
    let home = planner.resume(schedule, &from, Landing::At(request.destination), scratch);
    let e1 = home.expanded;
    if let Ok(rest) = home.result {
        return (Fate::Replanned(join(&part, rest)), e1);
    }
    if let Commitment::Landed(p) = part {
        // Already on the ground at a station: the trip ends there.
        return (Fate::Diverted(p), e1);
    }
    let other = planner.resume(schedule, &from, Landing::AnyStation, scratch);
    let expanded = e1 + other.expanded;
    match other.result {
        Ok(rest) => (Fate::Diverted(join(&part, rest)), expanded),
        Err(_) => (Fate::Contingency(part.into_plan()), expanded),
    }
}

/// The committed part followed by the rest planned from where it ends. In the air the rest
/// starts with the stay at the committed part's last node, which replaces its zero-length
/// arrival there; on the ground the rest starts with the next take-off.
fn join(part: &Commitment, rest: Plan) -> Plan {
    let mut path = match part {
        Commitment::Airborne(p) => p.path[..p.path.len() - 1].to_vec(),
        Commitment::Landed(p) => p.path.clone(),
    };
    path.extend(rest.path);
    Plan { path }
}
