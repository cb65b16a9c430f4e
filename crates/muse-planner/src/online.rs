//! Online planning (docs/reference.md#the-planning-service): requests arrive one at a time, in any
//! order of departure, and are planned against one live schedule that moves forward with a clock.
//!
//! [`Live`] is the same [`Planner`] and the same [`Schedule`] as a batch day
//! ([`plan_day`](crate::plan_day)), with three differences:
//!
//! - the schedule's horizon is the clock's *now*, not the next departure, so requests may
//!   come in any order of departure; a request whose departure is before now is rejected with
//!   [`RejectReason::DepartureInPast`];
//! - reservations that ended before now are dropped from memory as the clock moves
//!   ([`Schedule::forget_past`]): memory stays bounded by the traffic still ahead, however
//!   many days the service runs (the store, not the planner, keeps history);
//! - a flight can be cancelled before take-off, which frees its reservations;
//! - zones can be announced while it runs (docs/reference.md#zones-announced-during-the-day):
//!   [`Live::announce`] closes the airspace from now on and [replans](crate::replan) the flights
//!   the zone hits; [`Live::withdraw`] lifts an announced zone and replans nothing. A service
//!   restoring from its store puts an announcement back without replanning: [`Live::add_announced`]
//!   for the zone, [`Live::apply_fate`] for what it made of each flight.
//!
//! It keeps every flight that has not landed yet (its request and current plan), which is
//! what replanning needs; landed flights are dropped with the reservations they held.
//!
//! The clock never goes back: an earlier `now` than one already seen is ignored, so a clock
//! step backwards cannot resurrect forgotten instants.
//!
//! ```
//! use muse_airspace::closures::Closures;
//! use muse_model::{Airspace, Edge, FlightParams, Instant, LonLat, Node, NodeId, NodeKind, RejectReason, Request};
//! use muse_planner::{FlightId, Live, Planner};
//! use muse_planner::CancelError;
//!
//! let node = |id: &str, lon| Node {
//!     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3),
//! };
//! let airspace = Airspace::new(
//!     vec![node("A", 103.80), node("B", 103.81)],
//!     vec![Edge { id: "A-B".into(), from: NodeId(0), to: NodeId(1), length_m: 1_000.0 }],
//! ).unwrap();
//! let planner = Planner::new(&airspace, FlightParams::default());
//! let mut live = Live::new(planner, &Closures::none(&airspace), Instant(0));
//! let r = |id: &str, t| Request { id: id.into(), origin: NodeId(0), destination: NodeId(1), departure: Instant(t), submitted: Instant(t) };
//!
//! // A later departure first, then an earlier one: both fit, in arrival order.
//! let late = live.book(FlightId(1), &r("late", 600_000)).result.unwrap();
//! let early = live.book(FlightId(2), &r("early", 0)).result.unwrap();
//! assert_eq!((early.takeoff(), late.takeoff()), (Instant(0), Instant(600_000)));
//!
//! // At 60 s the early flight is in the air: it can no longer be cancelled; the late one can.
//! live.advance(Instant(60_000));
//! assert_eq!(live.cancel(FlightId(2)), Err(CancelError::TookOff));
//! assert_eq!(live.cancel(FlightId(1)), Ok(late));
//! // And the past is closed.
//! assert_eq!(live.book(FlightId(3), &r("old", 0)).result, Err(RejectReason::DepartureInPast));
//! ```

use std::collections::HashMap;

use muse_airspace::closures::Closures;
use muse_model::{Instant, Millis, Plan, RejectReason, Request};

use crate::planner::{Outcome, Planner, plan_and_book};
use crate::replan::{Affected, Booking, Fate, replan};
use crate::schedule::{FlightId, Schedule};
use crate::sipp::Scratch;

/// How far the clock moves, by default, between two sweeps of forgotten reservations.
/// Sweeping visits every node and edge once, so it is done now and then, not on every request.
pub const FORGET_EVERY: Millis = Millis::from_secs(60);

/// Why a cancellation was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CancelError {
    /// The flight has taken off (take-off at or before now): it is committed.
    #[error("the flight has taken off; it is committed and cannot be cancelled")]
    TookOff,
    /// The schedule holds no such flight (never booked, cancelled, or landed).
    #[error("the schedule holds no such flight")]
    NotHeld,
}

/// Why a zone could not be announced or withdrawn.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ZoneError {
    /// A zone with this id is already announced.
    #[error("a zone `{0}` is already announced")]
    Taken(String),
    /// No announced zone has this id.
    #[error("no announced zone `{0}`")]
    Unknown(String),
}

/// What a flight holds in a live schedule (see [`Live::hold`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Holding<'p> {
    /// A booked plan: reserved, and the flight can be cancelled or replanned.
    Booked(&'p Plan),
    /// The committed part of a flight left in contingency by a zone
    /// (docs/reference.md#zones-announced-during-the-day): reserved, so that others keep their
    /// separation from it, but neither cancellable nor replanned.
    Committed(&'p Plan),
    /// Nothing (rejected, cancelled, or landed).
    Nothing,
}

impl<'p> Holding<'p> {
    /// What a flight with `fate` holds.
    pub fn of_fate(fate: &'p Fate) -> Self {
        match fate {
            Fate::Replanned(p) | Fate::Diverted(p) => Holding::Booked(p),
            Fate::Contingency(p) => Holding::Committed(p),
            Fate::Cancelled => Holding::Nothing,
        }
    }
}

/// A live schedule with its planner and clock (see the module docs).
#[derive(Debug)]
pub struct Live<'a> {
    planner: Planner<'a>,
    schedule: Schedule,
    scratch: Scratch,
    now: Instant,
    last_forget: Instant,
    forget_every: Millis,
    /// Flights that have not landed yet.
    bookings: HashMap<FlightId, Booking>,
    /// Closures known from the start.
    base: Closures,
    /// Zones announced since, by id, in announcement order.
    announced: Vec<(String, Closures)>,
}

impl<'a> Live<'a> {
    /// An empty live schedule over `closures`, with the clock at `now`.
    pub fn new(planner: Planner<'a>, closures: &Closures, now: Instant) -> Self {
        let mut schedule = planner.schedule(closures);
        schedule.set_horizon(now);
        Live {
            planner,
            schedule,
            scratch: Scratch::new(),
            now,
            last_forget: now,
            forget_every: FORGET_EVERY,
            bookings: HashMap::new(),
            base: closures.clone(),
            announced: Vec::new(),
        }
    }

    /// Sweeps forgotten reservations whenever the clock has moved by `every` (default
    /// [`FORGET_EVERY`]; `Millis::ZERO` sweeps on every move, as tests do).
    #[must_use]
    pub fn with_forget_every(mut self, every: Millis) -> Self {
        self.forget_every = every;
        self
    }

    /// The planner.
    pub fn planner(&self) -> &Planner<'a> {
        &self.planner
    }

    /// The schedule (for monitoring; change it only through `Live`).
    pub fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// The clock's now.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// Moves the clock to `now` (ignored if earlier than the current now) and, every [`FORGET_EVERY`]
    /// of clock time, drops the reservations that ended before it.
    pub fn advance(&mut self, now: Instant) {
        if now <= self.now {
            return;
        }
        self.now = now;
        self.schedule.set_horizon(now);
        if now - self.last_forget >= self.forget_every {
            self.schedule.forget_past();
            self.bookings.retain(|_, b| b.plan.landing() >= now);
            self.last_forget = now;
        }
    }

    /// Plans `request` against everything booked so far and, if a plan exists, books it as
    /// `flight` (an id unique among the flights booked). A departure before now is rejected
    /// with [`RejectReason::DepartureInPast`] without searching.
    pub fn book(&mut self, flight: FlightId, request: &Request) -> Outcome {
        if request.departure < self.now {
            return Outcome {
                result: Err(RejectReason::DepartureInPast),
                free_flow: self.planner.free_flow(request),
                expanded: 0,
            };
        }
        let outcome = plan_and_book(
            &self.planner,
            &mut self.schedule,
            flight,
            request,
            &mut self.scratch,
        );
        if let Ok(plan) = &outcome.result {
            self.bookings.insert(
                flight,
                Booking {
                    request: request.clone(),
                    plan: plan.clone(),
                },
            );
        }
        outcome
    }

    /// Plans `request` against everything booked so far *without booking it*: the decision
    /// half of [`Live::book`], for a caller that stores the answer first and then books it
    /// with [`Live::hold`]. A departure before now is rejected with
    /// [`RejectReason::DepartureInPast`] without searching.
    pub fn plan(&mut self, request: &Request) -> Outcome {
        if request.departure < self.now {
            return Outcome {
                result: Err(RejectReason::DepartureInPast),
                free_flow: self.planner.free_flow(request),
                expanded: 0,
            };
        }
        self.planner
            .plan(&self.schedule, request, &mut self.scratch)
    }

    /// Whether `flight` could be cancelled now (the decision half of [`Live::cancel`]):
    /// `Ok` with its plan if it is booked and has not taken off.
    pub fn can_cancel(&self, flight: FlightId) -> Result<&Plan, CancelError> {
        let booking = self.bookings.get(&flight).ok_or(CancelError::NotHeld)?;
        if booking.plan.takeoff() <= self.now {
            return Err(CancelError::TookOff);
        }
        Ok(&booking.plan)
    }

    /// Sets what `flight` holds in the schedule, whatever it held before: what it held is
    /// released, then `holding` is reserved. This is the one way a service changes the
    /// schedule, live (after deciding an answer, a cancellation or a zone's outcomes) and when
    /// it restarts from its store (putting each flight back as it stands). A plan or part that
    /// ended before now is not reserved: it can no longer matter. `request` is the flight's
    /// original request.
    pub fn hold(&mut self, flight: FlightId, request: &Request, holding: Holding<'_>) {
        self.hold_all(&[(flight, request, holding)]);
    }

    /// [`Live::hold`] for several flights at once: every one releases what it held before any
    /// reserves its new holding, so that holdings decided together (a zone's outcomes, each
    /// planned once the others were out of the way) never meet an old plan in the schedule.
    pub fn hold_all(&mut self, flights: &[(FlightId, &Request, Holding<'_>)]) {
        let airspace = self.planner.airspace();
        for &(flight, _, _) in flights {
            if let Some(old) = self.bookings.remove(&flight) {
                self.schedule.release(airspace, flight, &old.plan);
            }
        }
        for &(flight, request, holding) in flights {
            match holding {
                Holding::Booked(plan) => self.restore(flight, request, plan),
                Holding::Committed(part) => {
                    if part.landing() >= self.now {
                        self.schedule.insert(airspace, flight, part);
                    }
                }
                Holding::Nothing => {}
            }
        }
    }

    /// Decides what announcing a zone now would do
    /// (docs/reference.md#zones-announced-during-the-day) *without changing anything*: the affected
    /// flights and their fates, exactly as [`Live::announce`] would return them, computed on a copy
    /// of the schedule. The caller stores the outcome, then applies it with [`Live::add_announced`]
    /// and [`Live::hold_all`], which leaves the schedule exactly as [`Live::announce`] would have.
    pub fn decide_announcement(
        &mut self,
        id: &str,
        zone: &Closures,
    ) -> Result<Vec<Affected>, ZoneError> {
        if self.announced.iter().any(|(z, _)| z == id) {
            return Err(ZoneError::Taken(id.to_owned()));
        }
        let mut closures = self.known_closures();
        closures.add(zone);
        let mut schedule = self.schedule.clone();
        schedule.set_closures(&closures);
        let mut bookings = self.bookings.clone();
        Ok(replan(
            &self.planner,
            &mut schedule,
            &mut bookings,
            zone,
            self.now,
            &mut self.scratch,
        ))
    }

    /// Books a plan accepted earlier (when a service restarts from its store) without
    /// planning it again; `plan` is the flight's plan as it stands (after any replanning).
    /// Plans that ended before now are skipped: they can no longer matter.
    pub fn restore(&mut self, flight: FlightId, request: &Request, plan: &Plan) {
        if plan.landing() < self.now {
            return;
        }
        self.schedule.insert(self.planner.airspace(), flight, plan);
        self.bookings.insert(
            flight,
            Booking {
                request: request.clone(),
                plan: plan.clone(),
            },
        );
    }

    /// Cancels a booked flight, freeing its reservations; only before take-off. Returns the
    /// plan it had.
    pub fn cancel(&mut self, flight: FlightId) -> Result<Plan, CancelError> {
        let booking = self.bookings.get(&flight).ok_or(CancelError::NotHeld)?;
        if booking.plan.takeoff() <= self.now {
            return Err(CancelError::TookOff);
        }
        if !self
            .schedule
            .remove(self.planner.airspace(), flight, &booking.plan)
        {
            return Err(CancelError::NotHeld);
        }
        Ok(self
            .bookings
            .remove(&flight)
            .expect("the booking was just read")
            .plan)
    }

    /// Announces a zone now (docs/reference.md#zones-announced-during-the-day): its closures bind
    /// everything from now on, and the flights it hits are replanned, diverted, cancelled or left
    /// as contingencies (see [`Fate`](crate::Fate)). Returns the affected flights in the order they
    /// were replanned.
    pub fn announce(&mut self, id: &str, zone: Closures) -> Result<Vec<Affected>, ZoneError> {
        if self.announced.iter().any(|(z, _)| z == id) {
            return Err(ZoneError::Taken(id.to_owned()));
        }
        self.announced.push((id.to_owned(), zone));
        self.schedule.set_closures(&self.known_closures());
        let zone = &self.announced.last().expect("just pushed").1;
        Ok(replan(
            &self.planner,
            &mut self.schedule,
            &mut self.bookings,
            zone,
            self.now,
            &mut self.scratch,
        ))
    }

    /// Adds an announced zone's closures *without replanning anything*: for a service that
    /// restores its schedule from a store, where what the announcement did to each flight is
    /// stored too and is put back with [`Live::apply_fate`]. From then on the zone binds
    /// planning exactly as after [`Live::announce`], and it can be [withdrawn](Live::withdraw).
    pub fn add_announced(&mut self, id: &str, zone: Closures) -> Result<(), ZoneError> {
        if self.announced.iter().any(|(z, _)| z == id) {
            return Err(ZoneError::Taken(id.to_owned()));
        }
        self.announced.push((id.to_owned(), zone));
        self.schedule.set_closures(&self.known_closures());
        Ok(())
    }

    /// Replaces a flight's booking with a known `fate` (what a zone announcement made of it,
    /// as [`Live::announce`] reported it), without planning: the plan it holds, if any, is
    /// released; a [replanned](Fate::Replanned) or [diverted](Fate::Diverted) flight is booked
    /// with its new plan (as [`Live::restore`]: skipped if it landed before now), a
    /// [contingency](Fate::Contingency) keeps its committed part reserved (not booked: it can
    /// be neither cancelled nor replanned again), a [cancelled](Fate::Cancelled) one holds
    /// nothing. `request` is the flight's original request.
    ///
    /// [`Fate::Cancelled`] also replays a cancellation by the flight's operator: unlike
    /// [`Live::cancel`] it does not look at the clock (the cancellation was accepted before
    /// take-off, whatever the time of the replay).
    ///
    /// Applied in announcement order to flights [restored](Live::restore) with their first
    /// plans, with each zone [added](Live::add_announced) before its outcomes, this rebuilds
    /// the schedule the announcements left.
    pub fn apply_fate(&mut self, flight: FlightId, request: &Request, fate: &Fate) {
        self.hold(flight, request, Holding::of_fate(fate));
    }

    /// Withdraws an announced zone: it closes nothing from now on. Nothing is replanned.
    pub fn withdraw(&mut self, id: &str) -> Result<(), ZoneError> {
        let k = self
            .announced
            .iter()
            .position(|(z, _)| z == id)
            .ok_or_else(|| ZoneError::Unknown(id.to_owned()))?;
        self.announced.remove(k);
        self.schedule.set_closures(&self.known_closures());
        Ok(())
    }

    /// The closures in force: those known from the start and every zone announced since.
    fn known_closures(&self) -> Closures {
        let mut all = self.base.clone();
        for (_, zone) in &self.announced {
            all.add(zone);
        }
        all
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::testing::{joined, request, station};
    use muse_model::{Airspace, FlightParams};

    /// A line of `n` stations 1 km apart.
    fn line(n: u32) -> Airspace {
        Airspace::line(&vec![1_000.0; n as usize - 1])
    }

    #[test]
    fn memory_stays_bounded_as_the_clock_moves() {
        let a = line(4);
        let planner = Planner::new(&a, FlightParams::default());
        let mut live = Live::new(planner, &Closures::none(&a), Instant(0));
        // One flight every 3 minutes, booked an hour ahead, for a simulated week.
        let mut peak = 0;
        for k in 0..(7 * 24 * 20_i64) {
            let now = Instant(k * 180_000);
            live.advance(now);
            let r = request(&format!("r{k}"), 0, 3, now.0 + 3_600_000);
            assert!(live.book(FlightId(k as u64), &r).result.is_ok());
            peak = peak.max(live.schedule().reservations());
        }
        // About 20 flights ahead and a minute's worth behind, 7 reservations each, plus one
        // kept per list: far below the week's 23,520.
        assert!(peak < 1_000, "peak reservations {peak}");
    }

    #[test]
    fn cancelled_slots_are_free_again_and_the_clock_never_goes_back() {
        let a = line(2);
        let params = FlightParams {
            max_ground_delay: Millis::from_mins(10),
            ..FlightParams::default()
        };
        let planner = Planner::new(&a, params);
        let mut live = Live::new(planner, &Closures::none(&a), Instant(0));
        let first = live
            .book(FlightId(1), &request("a", 0, 1, 60_000))
            .result
            .unwrap();
        let second = live
            .book(FlightId(2), &request("b", 0, 1, 60_000))
            .result
            .unwrap();
        assert_eq!(second.takeoff(), Instant(180_000));
        assert_eq!(live.cancel(FlightId(1)), Ok(first.clone()));
        assert_eq!(live.cancel(FlightId(1)), Err(CancelError::NotHeld));
        let third = live
            .book(FlightId(3), &request("c", 0, 1, 60_000))
            .result
            .unwrap();
        assert_eq!(third, first);
        live.advance(Instant(100_000));
        live.advance(Instant(10_000));
        assert_eq!(live.now(), Instant(100_000));
        assert_eq!(
            live.book(FlightId(4), &request("d", 0, 1, 99_999)).result,
            Err(RejectReason::DepartureInPast)
        );
    }

    #[test]
    fn an_announced_zone_cancels_what_it_hits_and_a_withdrawn_one_closes_nothing() {
        let a = line(2);
        let planner = Planner::new(&a, FlightParams::default());
        let mut live = Live::new(planner, &Closures::none(&a), Instant(0));
        assert!(
            live.book(FlightId(1), &request("r", 0, 1, 600_000))
                .result
                .is_ok()
        );
        // B closed for the first hour, announced now: the flight cannot land, and has not
        // taken off: cancelled.
        let zone = muse_model::Zone {
            id: "Z".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: vec![],
            announced: None,
            withdrawn: None,
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
            periods: vec![muse_model::Period {
                start: Some(Instant(0)),
                end: Some(Instant(3_600_000)),
                daily: vec![],
            }],
        };
        let closed =
            muse_airspace::closures::resolve(&a, &[zone], Instant(0), Instant(86_400_000)).unwrap();
        let hit = live.announce("Z", closed.clone()).unwrap();
        assert_eq!(hit.len(), 1);
        assert_eq!(hit[0].fate, crate::replan::Fate::Cancelled);
        assert_eq!(live.cancel(FlightId(1)), Err(CancelError::NotHeld));
        assert!(live.announce("Z", closed).is_err());
        assert_eq!(
            live.book(FlightId(2), &request("s", 0, 1, 600_000)).result,
            Err(RejectReason::NoFeasiblePlan)
        );
        live.withdraw("Z").unwrap();
        assert!(live.withdraw("Z").is_err());
        assert!(
            live.book(FlightId(3), &request("t", 0, 1, 600_000))
                .result
                .is_ok()
        );
    }

    /// A ring `A — B — C — D — A`: `A-B`, `B-C`, `A-D` 1 km, `D-C` 1.5 km, so `A` to `C`
    /// goes by `B` unless `B` is closed.
    fn ring() -> Airspace {
        joined(
            vec![
                station("A", 103.80, 1.30),
                station("B", 103.81, 1.30),
                station("C", 103.81, 1.31),
                station("D", 103.80, 1.31),
            ],
            &[
                ("A", "B", 1_000.0),
                ("B", "C", 1_000.0),
                ("A", "D", 1_000.0),
                ("D", "C", 1_500.0),
            ],
        )
    }

    /// Flights on the ring around B, whom a zone closing B announced at 60 s treats each its
    /// own way.
    fn around_b() -> [Request; 5] {
        [
            request("via-b", 0, 2, 600_000), // not taken off: replanned by D
            request("to-b", 0, 1, 900_000),  // not taken off, B closed: cancelled
            request("in-a-b", 0, 2, 0),      // in A-B at the announcement: contingency
            request("d-a-b", 3, 1, 0),       // in D-A: lands at A instead (diverted)
            request("c-d", 2, 3, 1_200_000), // never near B: unaffected
        ]
    }

    /// The closures of a zone `Z` that closes node B for the first day.
    fn closing_b(a: &Airspace) -> Closures {
        let zone = muse_model::Zone {
            id: "Z".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: vec!["B".into()],
            edge_ids: vec![],
            announced: None,
            withdrawn: None,
            vertical: muse_model::VerticalLimits::WHOLE_SKY,
            periods: vec![],
        };
        muse_airspace::closures::resolve(a, &[zone], Instant(0), Instant(86_400_000)).unwrap()
    }

    #[test]
    fn stored_outcomes_rebuild_the_schedule_an_announcement_left_without_replanning() {
        let a = ring();
        let params = FlightParams::default();
        let closures = Closures::none(&a);
        let requests = around_b();
        let mut live = Live::new(Planner::new(&a, params), &closures, Instant(0));
        let mut first = Vec::new();
        for (k, r) in requests.iter().enumerate() {
            first.push(live.book(FlightId::from(k), r).result.unwrap());
        }
        live.advance(Instant(60_000));
        let resolve = || closing_b(&a);
        let hit = live.announce("Z", resolve()).unwrap();
        let mut kinds: Vec<(FlightId, &str)> = hit
            .iter()
            .map(|h| (h.flight, h.fate.kind().as_str()))
            .collect();
        kinds.sort_unstable();
        assert_eq!(
            kinds,
            [
                (FlightId(0), "replanned"),
                (FlightId(1), "cancelled"),
                (FlightId(2), "contingency"),
                (FlightId(3), "diverted")
            ]
        );

        // A service restarting at the same instant: first plans back, then the zone and the
        // stored fates, in that order; nothing is planned.
        let mut back = Live::new(Planner::new(&a, params), &closures, Instant(60_000));
        for (k, (r, p)) in requests.iter().zip(&first).enumerate() {
            back.restore(FlightId::from(k), r, p);
        }
        back.add_announced("Z", resolve()).unwrap();
        assert_eq!(
            back.add_announced("Z", resolve()),
            Err(ZoneError::Taken("Z".into()))
        );
        for h in &hit {
            back.apply_fate(h.flight, &requests[h.flight.index()], &h.fate);
        }
        assert_eq!(back.schedule().flights(), live.schedule().flights());
        assert_eq!(back.bookings, live.bookings);
        // Both answer every later request alike (the contingency's committed part and the
        // new plans are held, the cancelled flight's slot is free, B is closed) ...
        let mut n = 10;
        for from in 0..4 {
            for to in 0..4 {
                for t in [60_000, 300_000, 600_000, 900_000] {
                    if from == to {
                        continue;
                    }
                    let r = request(&format!("p{n}"), from, to, t);
                    assert_eq!(
                        back.book(FlightId(n), &r).result,
                        live.book(FlightId(n), &r).result,
                        "{from} to {to} at {t}"
                    );
                    n += 1;
                }
            }
        }
        // ... and a replanned flight can still be cancelled before its new take-off, in both.
        let replanned = hit[hit.iter().position(|h| h.flight == FlightId(0)).unwrap()]
            .fate
            .plan()
            .cloned();
        assert_eq!(back.cancel(FlightId(0)).ok(), replanned);
        assert_eq!(live.cancel(FlightId(0)).ok(), replanned);
        // The restored zone can be withdrawn like an announced one.
        back.withdraw("Z").unwrap();
    }

    #[test]
    fn a_decided_announcement_applied_leaves_the_schedule_announce_leaves() {
        let a = ring();
        let params = FlightParams::default();
        let closures = Closures::none(&a);
        let requests = around_b();
        let resolve = || closing_b(&a);
        let mut one = Live::new(Planner::new(&a, params), &closures, Instant(0));
        let mut two = Live::new(Planner::new(&a, params), &closures, Instant(0));
        for (k, r) in requests.iter().enumerate() {
            // Decide, then hold: the same as booking.
            let outcome = two.plan(r);
            let plan = outcome.result.clone().unwrap();
            two.hold(FlightId::from(k), r, Holding::Booked(&plan));
            assert_eq!(one.book(FlightId::from(k), r), outcome);
        }
        one.advance(Instant(60_000));
        two.advance(Instant(60_000));
        let announced = one.announce("Z", resolve()).unwrap();
        let decided = two.decide_announcement("Z", &resolve()).unwrap();
        assert_eq!(decided, announced);
        // Deciding changed nothing: the decision is the same when taken again.
        assert_eq!(two.decide_announcement("Z", &resolve()).unwrap(), announced);
        two.add_announced("Z", resolve()).unwrap();
        let holdings: Vec<(FlightId, &Request, Holding<'_>)> = decided
            .iter()
            .map(|h| {
                (
                    h.flight,
                    &requests[h.flight.index()],
                    Holding::of_fate(&h.fate),
                )
            })
            .collect();
        two.hold_all(&holdings);
        assert_eq!(two.bookings, one.bookings);
        assert_eq!(two.schedule().reservations(), one.schedule().reservations());
        let mut n = 10;
        for from in 0..4 {
            for to in 0..4 {
                for t in [60_000, 300_000, 600_000, 900_000] {
                    if from != to {
                        let r = request(&format!("p{n}"), from, to, t);
                        assert_eq!(
                            two.book(FlightId(n), &r).result,
                            one.book(FlightId(n), &r).result
                        );
                        n += 1;
                    }
                }
            }
        }
        assert_eq!(
            two.can_cancel(FlightId(0)).cloned(),
            one.cancel(FlightId(0))
        );
    }
}
