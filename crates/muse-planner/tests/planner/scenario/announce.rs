//! docs/reference.md#zones-announced-during-the-day against the oracle: a zone announced while
//! flights are booked and in the air.
//!
//! The instance's last zone is held back and announced at instant `n`; the others are known
//! from the start. Every request is booked first (on the online planner), then the clock
//! moves to `n` (forgetting the past) and the zone is announced. The test then replays
//! docs/reference.md#zones-announced-during-the-day by itself: it finds the affected flights from
//! the raw zone windows with the exemption rule, orders them by original take-off then id, and for
//! each one, against the flights as they then stand, asks the oracle for the earliest plan: from
//! the take-off window `[max(departure, n), max(departure + G_max, n)]`, or from the committed node
//! with the battery left, to the destination and else to any station. The library must agree on the
//! set, the order, every fate and every landing (and take-off), and the final set of flights must
//! pass the verifier with the exemption rule.

use std::collections::HashMap;

use muse_airspace::announced::{Announced, KnownZones};
use muse_model::{Airspace, FlightParams, Instant, Millis, Plan, Request};
use muse_planner::{Affected, Fate};
use muse_planner::{FlightId, Live, Planner};
use muse_verify::{Ending, Flight, verify_known};

use super::{Built, Instance, Tally};
use crate::oracle::{self, Goal, RawClosures};

/// What the announcement did, to check that the generator reaches every case.
#[derive(Clone, Copy, Debug, Default)]
pub struct Announcements {
    /// Flights affected.
    pub affected: usize,
    /// Of those, airborne at the announcement.
    pub airborne: usize,
    /// Fates.
    pub replanned: usize,
    /// Diverted.
    pub diverted: usize,
    /// Cancelled.
    pub cancelled: usize,
    /// Contingency.
    pub contingency: usize,
}

impl Announcements {
    /// Adds another run's counts.
    pub fn add(&mut self, o: &Announcements) {
        self.affected += o.affected;
        self.airborne += o.airborne;
        self.replanned += o.replanned;
        self.diverted += o.diverted;
        self.cancelled += o.cancelled;
        self.contingency += o.contingency;
    }
}

/// Whether `plan` breaks the raw windows of a zone announced at `n`
/// (docs/reference.md#zones-announced-during-the-day, written out).
fn breaks(
    airspace: &Airspace,
    params: &FlightParams,
    raw: &RawClosures,
    plan: &Plan,
    n: i64,
) -> bool {
    let overlaps = |list: &[(i64, i64)], a: i64, d: i64| list.iter().any(|&(s, e)| d >= s && a < e);
    let stays = plan
        .path
        .iter()
        .any(|s| s.arrive.0 >= n && overlaps(&raw.nodes[s.node.index()], s.arrive.0, s.depart.0));
    let traversals = plan.path.windows(2).any(|p| {
        let e = airspace
            .edge_between(p[0].node, p[1].node)
            .expect("plans follow edges");
        let w = crate::oracle::weight(airspace, params, e);
        p[0].depart.0 >= n && overlaps(&raw.edges[e.index()], p[0].depart.0, p[0].depart.0 + w)
    });
    stays || traversals
}

/// The stays up to the first arrival at or after `n`, that arrival as a zero-length stay.
fn committed(plan: &Plan, n: i64) -> Plan {
    let k = plan
        .path
        .iter()
        .position(|s| s.arrive.0 >= n)
        .expect("lands after n");
    let mut path = plan.path[..=k].to_vec();
    path[k].depart = path[k].arrive;
    Plan { path }
}

fn merged(a: &RawClosures, b: &RawClosures) -> RawClosures {
    let join = |x: &[Vec<(i64, i64)>], y: &[Vec<(i64, i64)>]| {
        x.iter()
            .zip(y)
            .map(|(p, q)| p.iter().chain(q).copied().collect())
            .collect()
    };
    RawClosures {
        nodes: join(&a.nodes, &b.nodes),
        edges: join(&a.edges, &b.edges),
    }
}

/// Everything the replay of one announcement needs.
struct Replay<'a> {
    base: &'a Built,
    only: &'a Built,
    /// Base and announced windows together, for the oracle.
    raw: RawClosures,
    n: i64,
    unit: i64,
    /// The plans before the announcement.
    plans: HashMap<FlightId, Plan>,
    /// The flights as they stand.
    current: HashMap<FlightId, (Plan, Ending)>,
    counts: Announcements,
}

impl Replay<'_> {
    fn request(&self, f: FlightId) -> &Request {
        &self.base.requests[f.index()]
    }

    /// The affected flights by the reference, in their order.
    fn affected(&self) -> Vec<FlightId> {
        let b = self.base;
        let mut hit: Vec<FlightId> = self
            .plans
            .iter()
            .filter(|(_, p)| breaks(&b.airspace, &b.params, &self.only.raw, p, self.n))
            .map(|(&f, _)| f)
            .collect();
        hit.sort_by(|&x, &y| {
            (self.plans[&x].takeoff(), &self.request(x).id)
                .cmp(&(self.plans[&y].takeoff(), &self.request(y).id))
        });
        hit
    }

    /// Step 1: affected flights out, committed parts of airborne ones in.
    fn take_out(&mut self, affected: &[FlightId]) {
        for &f in affected {
            let plan = &self.plans[&f];
            if plan.takeoff().0 < self.n {
                let part = committed(plan, self.n);
                self.current.insert(f, (part, Ending::Committed));
            } else {
                self.current.remove(&f);
            }
        }
    }

    /// Step 2 for one flight: the oracle's answer against the library's.
    fn judge(&mut self, a: &Affected) -> Result<(), String> {
        let f = a.flight;
        self.counts.affected += 1;
        let judged = if self.plans[&f].takeoff().0 >= self.n {
            self.grounded(f, &a.fate)
        } else {
            self.counts.airborne += 1;
            self.airborne(f, &a.fate)
        };
        let fail = |what: String| {
            format!(
                "flight {} (announced at {}): {what}; library {:?}",
                self.request(f).id,
                self.n,
                a.fate
            )
        };
        let next = judged.map_err(fail)?;
        match next {
            Some(state) => self.current.insert(f, state),
            None => self.current.remove(&f),
        };
        Ok(())
    }

    fn others(&self, f: FlightId) -> Vec<&Plan> {
        self.current
            .iter()
            .filter(|(g, _)| **g != f)
            .map(|(_, (p, _))| p)
            .collect()
    }

    /// Not taken off: the plan of docs/reference.md#planning with take-off in `[max(dep, n),
    /// max(dep + G, n)]`.
    fn grounded(&mut self, f: FlightId, fate: &Fate) -> Result<Option<(Plan, Ending)>, String> {
        let (r, params, n) = (self.request(f), self.base.params, self.n);
        let earliest = r.departure.0.max(n);
        let latest = (r.departure.0 + params.max_ground_delay.0).max(n);
        let shifted = Request {
            departure: Instant(earliest),
            submitted: Instant(earliest),
            ..r.clone()
        };
        let window = FlightParams {
            max_ground_delay: Millis(latest - earliest),
            ..params
        };
        let others = self.others(f);
        let answer = oracle::solve(
            &self.base.airspace,
            &window,
            &self.raw,
            &others,
            &shifted,
            self.unit,
        );
        match (fate, answer.result) {
            (Fate::Replanned(p), Ok((takeoff, landing)))
                if (p.takeoff(), p.landing()) == (takeoff, landing) =>
            {
                self.counts.replanned += 1;
                Ok(Some((p.clone(), Ending::Destination)))
            }
            (Fate::Cancelled, Err(_)) => {
                self.counts.cancelled += 1;
                Ok(None)
            }
            (_, want) => Err(format!("oracle {want:?}")),
        }
    }

    /// Airborne: from the committed node, home, else anywhere, else a contingency.
    fn airborne(&mut self, f: FlightId, fate: &Fate) -> Result<Option<(Plan, Ending)>, String> {
        let original = &self.plans[&f];
        let part = committed(original, self.n);
        let b = self.base;
        if breaks(&b.airspace, &b.params, &self.only.raw, &part, self.n) {
            if *fate != Fate::Contingency(part.clone()) {
                return Err("its committed part breaks the zone: expected a contingency".into());
            }
            self.counts.contingency += 1;
            return Ok(Some((part, Ending::Committed)));
        }
        let last = *part.path.last().expect("not empty");
        let others = self.others(f);
        let solve = |goal| {
            oracle::solve_airborne(
                &b.airspace,
                &b.params,
                &self.raw,
                &others,
                last.node,
                last.arrive,
                original.takeoff(),
                goal,
                self.unit,
            )
        };
        let keep = part.path.len() - 1;
        let same = |p: &Plan, want: &Plan| {
            p.landing() == want.landing()
                && p.path.last().map(|s| s.node) == want.path.last().map(|s| s.node)
                && p.path[..keep] == part.path[..keep]
        };
        let home = solve(Goal::Node(self.request(f).destination));
        let away = if home.is_none() {
            solve(Goal::AnyStation)
        } else {
            None
        };
        match (fate, home, away) {
            (Fate::Replanned(p), Some(want), _) if same(p, &want) => {
                self.counts.replanned += 1;
                Ok(Some((p.clone(), Ending::Destination)))
            }
            (Fate::Diverted(p), None, Some(want)) if same(p, &want) => {
                self.counts.diverted += 1;
                Ok(Some((p.clone(), Ending::Diverted)))
            }
            (Fate::Contingency(p), None, None) if *p == part => {
                self.counts.contingency += 1;
                Ok(Some((part, Ending::Committed)))
            }
            (_, home, away) => {
                let end =
                    |w: Option<Plan>| w.map(|w| (w.path.last().unwrap().node.0, w.landing().0));
                Err(format!(
                    "oracle: home {:?}, diverted {:?}",
                    end(home),
                    end(away)
                ))
            }
        }
    }

    /// The final set, with the exemption rule.
    fn check_final(&self) -> Result<(), String> {
        let known = KnownZones {
            base: self.base.closures.clone(),
            announced: vec![Announced {
                zone: "A".into(),
                at: Instant(self.n),
                withdrawn: None,
                closures: self.only.closures.clone(),
            }],
        };
        let flights: Vec<Flight<'_>> = self
            .current
            .iter()
            .map(|(f, (p, ending))| {
                let r = self.request(*f);
                Flight::new(&r.id, r, p).ending(*ending)
            })
            .collect();
        let violations = verify_known(&self.base.airspace, &known, &self.base.params, &flights);
        if violations.is_empty() {
            return Ok(());
        }
        let list: Vec<String> = violations.iter().map(ToString::to_string).collect();
        Err(format!("the final set is invalid: {}", list.join("; ")))
    }
}

/// Runs the instance with its last zone announced at `at` units (see the module docs).
pub fn run_announce(instance: &Instance, at: i64) -> Result<(Tally, Announcements), String> {
    let Some(zone) = instance.zones.last().cloned() else {
        return Ok((Tally::default(), Announcements::default()));
    };
    let base = Instance {
        zones: instance.zones[..instance.zones.len() - 1].to_vec(),
        ..instance.clone()
    }
    .build();
    let only = Instance {
        zones: vec![zone],
        ..instance.clone()
    }
    .build();
    let n = at * instance.unit;

    // Book everything, then move to `n` and announce.
    let planner = Planner::new(&base.airspace, base.params);
    let mut live =
        Live::new(planner, &base.closures, Instant(0)).with_forget_every(Millis(instance.unit));
    let mut plans: HashMap<FlightId, Plan> = HashMap::new();
    for (i, r) in base.requests.iter().enumerate() {
        if let Ok(plan) = live.book(FlightId::from(i), r).result {
            plans.insert(FlightId::from(i), plan);
        }
    }
    live.advance(Instant(n));
    let affected = live
        .announce("A", only.closures.clone())
        .map_err(|e| e.to_string())?;

    let mut replay = Replay {
        base: &base,
        only: &only,
        raw: merged(&base.raw, &only.raw),
        n,
        unit: instance.unit,
        current: plans
            .iter()
            .map(|(&f, p)| (f, (p.clone(), Ending::Destination)))
            .collect(),
        plans,
        counts: Announcements::default(),
    };
    let expected = replay.affected();
    let got: Vec<FlightId> = affected.iter().map(|a| a.flight).collect();
    if got != expected {
        return Err(format!(
            "affected flights: library {got:?}, reference {expected:?}"
        ));
    }
    replay.take_out(&expected);
    for a in &affected {
        replay.judge(a)?;
    }
    replay.check_final()?;
    let tally = Tally {
        planned: replay.plans.len(),
        ..Tally::default()
    };
    Ok((tally, replay.counts))
}
