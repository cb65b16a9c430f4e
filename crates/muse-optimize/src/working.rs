//! A schedule being improved: which requests hold which plan, the reservations they make,
//! where they stay (to find the flights in a request's way), and the objective, all kept in
//! step as flights are taken out and planned again.

use muse_model::{FlightParams, Instant, Millis, Plan, RejectReason, Request};
use muse_planner::{FlightId, Planner, Schedule, Scratch};

use crate::objective::Objective;

/// One stay of a planned flight at a node: `[arrive, depart]`, by request index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Visit {
    pub(crate) arrive: Instant,
    pub(crate) depart: Instant,
    pub(crate) request: u32,
}

/// The schedule of a batch as it is being improved, on top of a base schedule whose flights
/// stay as they are. Request `i` books as flight `ids[i]`.
pub(crate) struct Working<'a> {
    planner: &'a Planner<'a>,
    requests: &'a [Request],
    ids: &'a [FlightId],
    free_flow: &'a [Option<Millis>],
    schedule: Schedule,
    plans: Vec<Option<Plan>>,
    /// The stays of the planned flights at each node, in no order.
    visits: Vec<Vec<Visit>>,
    objective: Objective,
    scratch: Scratch,
    /// Each request's last search: labels expanded, and why it found no plan (if it did not).
    last: Vec<(u64, Option<RejectReason>)>,
    /// Labels expanded by every search so far.
    pub(crate) expanded: u64,
}

impl<'a> Working<'a> {
    /// No request of the batch planned yet: the schedule is `base` (its zones and any flights
    /// booked before the batch); request `i` will book as flight `ids[i]`, an id `base` does
    /// not use.
    pub(crate) fn new(
        planner: &'a Planner<'a>,
        base: Schedule,
        requests: &'a [Request],
        ids: &'a [FlightId],
        free_flow: &'a [Option<Millis>],
    ) -> Self {
        let airspace = planner.airspace();
        Working {
            planner,
            requests,
            ids,
            free_flow,
            schedule: base,
            plans: vec![None; requests.len()],
            visits: vec![Vec::new(); airspace.node_count()],
            objective: Objective::default(),
            scratch: Scratch::new(),
            last: vec![(0, None); requests.len()],
            expanded: 0,
        }
    }

    /// The objective of the schedule as it stands.
    pub(crate) fn objective(&self) -> Objective {
        self.objective
    }

    /// The flight parameters planned with.
    pub(crate) fn params(&self) -> &FlightParams {
        self.planner.params()
    }

    /// Request `i`'s plan, if it holds one.
    pub(crate) fn plan(&self, i: usize) -> Option<&Plan> {
        self.plans[i].as_ref()
    }

    /// Every request's plan, or `None`.
    pub(crate) fn plans(&self) -> &[Option<Plan>] {
        &self.plans
    }

    /// Request `i`'s last search: labels expanded, and the reason it found no plan.
    pub(crate) fn last_search(&self, i: usize) -> (u64, Option<RejectReason>) {
        self.last[i]
    }

    /// The stays of planned flights at node `node`.
    pub(crate) fn visits(&self, node: usize) -> &[Visit] {
        &self.visits[node]
    }

    /// Plans request `i` (which holds no plan) against everything booked and books the plan
    /// if there is one. Returns whether it was planned.
    pub(crate) fn try_plan(&mut self, i: usize) -> bool {
        debug_assert!(self.plans[i].is_none(), "request {i} is already planned");
        let outcome = self
            .planner
            .plan(&self.schedule, &self.requests[i], &mut self.scratch);
        self.expanded += outcome.expanded;
        self.last[i] = (outcome.expanded, outcome.result.as_ref().err().copied());
        match outcome.result {
            Ok(plan) => {
                self.book(i, plan);
                true
            }
            Err(_) => false,
        }
    }

    /// Books `plan` for request `i`, which holds none: a plan it held before (put back), so
    /// it is valid against the schedule.
    pub(crate) fn book(&mut self, i: usize, plan: Plan) {
        let free_flow = self.free_flow[i].expect("a planned request has a free-flow time");
        self.objective =
            self.objective
                .with(Objective::delay_of(&self.requests[i], &plan, free_flow));
        self.schedule
            .insert(self.planner.airspace(), self.ids[i], &plan);
        let request = u32::try_from(i).expect("fewer than 2^32 requests");
        for s in &plan.path {
            self.visits[s.node.index()].push(Visit {
                arrive: s.arrive,
                depart: s.depart,
                request,
            });
        }
        self.plans[i] = Some(plan);
    }

    /// Makes `plans` (one per request, as [`Working::plans`] gave them) the schedule.
    pub(crate) fn restore(&mut self, plans: Vec<Option<Plan>>) {
        for i in 0..self.plans.len() {
            if self.plans[i].is_some() {
                self.take_out(i);
            }
        }
        for (i, plan) in plans.into_iter().enumerate() {
            if let Some(plan) = plan {
                self.book(i, plan);
            }
        }
    }

    /// Takes request `i`'s plan out of the schedule and returns it.
    pub(crate) fn take_out(&mut self, i: usize) -> Plan {
        let plan = self.plans[i]
            .take()
            .expect("only a planned request is taken out");
        let free_flow = self.free_flow[i].expect("a planned request has a free-flow time");
        self.objective =
            self.objective
                .without(Objective::delay_of(&self.requests[i], &plan, free_flow));
        self.schedule
            .release(self.planner.airspace(), self.ids[i], &plan);
        let request = u32::try_from(i).expect("fewer than 2^32 requests");
        for s in &plan.path {
            let list = &mut self.visits[s.node.index()];
            if let Some(k) = list
                .iter()
                .position(|v| v.request == request && v.arrive == s.arrive && v.depart == s.depart)
            {
                list.swap_remove(k);
            }
        }
        plan
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_airspace::closures::Closures;
    use muse_model::{Airspace, NodeId};

    fn request(id: &str, departure_s: i64) -> Request {
        Request {
            id: id.into(),
            origin: NodeId(0),
            destination: NodeId(1),
            departure: Instant(departure_s * 1_000),
            submitted: Instant(0),
        }
    }

    #[test]
    fn taking_out_and_putting_back_restores_the_objective_and_the_visits() {
        let air = Airspace::line(&[1_000.0]);
        let planner = Planner::new(&air, FlightParams::default());
        let requests = [request("a", 0), request("b", 0)];
        let free_flow = [Some(Millis(120_000)); 2];
        let ids = [FlightId(0), FlightId(1)];
        let base = Schedule::new(&air, planner.params(), &Closures::none(&air));
        let mut w = Working::new(&planner, base, &requests, &ids, &free_flow);
        assert!(w.try_plan(0));
        // Same departure, no ground delay: B is taken at the landing instant, A at take-off.
        assert!(!w.try_plan(1));
        assert_eq!(
            w.objective(),
            Objective {
                planned: 1,
                delay: Millis::ZERO
            }
        );
        assert_eq!((w.visits(0).len(), w.visits(1).len()), (1, 1));
        let plan = w.take_out(0);
        assert_eq!(w.objective(), Objective::default());
        assert!(w.visits(0).is_empty() && w.visits(1).is_empty());
        assert!(w.try_plan(1), "with a out of the way, b flies");
        w.take_out(1);
        w.book(0, plan);
        assert_eq!(w.objective().planned, 1);
    }
}
