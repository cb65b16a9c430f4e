//! The planner task: the one place where the live schedule changes.
//!
//! Handlers send [`Command`]s over a channel; one thread takes them in arrival order, in
//! groups of whatever has queued up (up to [`MAX_GROUP`]):
//!
//! 1. each command of the group is decided against the live schedule (planned, rejected,
//!    repeated, conflicting, cancelled, refused) and its record appended to the store;
//! 2. the group is made durable with one `write` + `fdatasync` (group commit);
//! 3. only then is the read index updated and every answer of the group sent.
//!
//! So nothing is acknowledged before it is durable, planning is serialized against one
//! schedule (no double booking under any interleaving), and reads, served from the index,
//! never wait for planning. A crash at any point loses only unacknowledged work: a group is
//! a prefix of the log, whole or torn (see [`crate::store`]).
//!
//! A zone announcement or withdrawal (SPEC §11, in the `zones` submodule) is a group of its
//! own: what is pending is committed first, then the zone's record alone (it holds the
//! outcome of every flight it changed and may be large). Each change of a flight is also an
//! [`Event`], numbered in log order and published with the index, after the commit.
//!
//! At start the log is replayed (the `recover` submodule) into the index, the schedule, the
//! zones and the event history, without planning anything: a zone's stored outcomes are
//! applied as they were acknowledged.

mod recover;
mod zones;

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Instant as WallInstant;

use muse_model::{Instant, RejectReason, Request};
use muse_planner::online::CancelError;
use muse_planner::{Live, Planner};
use tokio::sync::{mpsc, oneshot};

use crate::auth::Caller;
use crate::events::Event;
use crate::flights::{FlightEntry, Status};
use crate::metrics::PlanOutcome;
use crate::state::State;
use crate::store::{MAX_GROUP_BYTES, Record, Store};
use crate::zones::{AnnouncedZone, NewZone};

pub use zones::{AnnounceReply, Announcement, WithdrawReply};

/// How far the clock moves between two evictions of ended flights from the index.
const EVICT_EVERY: muse_model::Millis = muse_model::Millis::from_secs(60);

/// Most commands decided and committed as one group.
pub const MAX_GROUP: usize = 512;
/// Commands that may wait in the channel before senders wait too (back-pressure).
pub const QUEUE: usize = 8_192;

/// A change asked of the planner task.
#[derive(Debug)]
pub enum Command {
    /// Plan a new flight (or answer a retry of one).
    Plan {
        /// Who asks.
        caller: Caller,
        /// The request, validated.
        request: Request,
        /// Where to send the answer.
        reply: oneshot::Sender<PlanReply>,
    },
    /// Cancel a flight.
    Cancel {
        /// Who asks.
        caller: Caller,
        /// The flight's id.
        id: String,
        /// Where to send the answer.
        reply: oneshot::Sender<CancelReply>,
    },
    /// Announce a zone now (SPEC §11); the caller is the authority.
    Announce {
        /// The zone, read and checked.
        zone: NewZone,
        /// Where to send the answer.
        reply: oneshot::Sender<AnnounceReply>,
    },
    /// Withdraw an announced zone; the caller is the authority.
    Withdraw {
        /// The zone's id.
        id: String,
        /// Where to send the answer.
        reply: oneshot::Sender<WithdrawReply>,
    },
}

/// The answer to [`Command::Plan`].
#[derive(Debug)]
pub enum PlanReply {
    /// A new request, answered (planned or rejected) and stored.
    New(Arc<FlightEntry>),
    /// A retry with the same id and content: the flight as it stands.
    Repeat(Arc<FlightEntry>),
    /// The id is taken by another request (or another operator).
    Conflict,
    /// The service could not answer (nothing was booked).
    Failed(String),
}

/// The answer to [`Command::Cancel`].
#[derive(Debug)]
pub enum CancelReply {
    /// Cancelled now, durably.
    Done(Arc<FlightEntry>),
    /// Already cancelled earlier.
    Already(Arc<FlightEntry>),
    /// No such flight for this caller.
    NotFound,
    /// It has taken off: committed.
    TookOff(Arc<FlightEntry>),
    /// It was rejected: there is nothing to cancel.
    NotPlanned(Arc<FlightEntry>),
    /// The service could not answer.
    Failed(String),
}

/// What recovery found, for the start-up message.
#[derive(Clone, Copy, Debug, Default)]
pub struct Restored {
    /// Flights read from the store (every status).
    pub flights: usize,
    /// Of those, booked flights still ahead or in the air, put back into the schedule.
    pub booked: usize,
    /// Cancellations read.
    pub cancellations: usize,
    /// Zone announcements read (their outcomes applied as stored).
    pub zones: usize,
    /// Of those, zones withdrawn since.
    pub withdrawn: usize,
    /// Events numbered (the id of the last one).
    pub events: u64,
}

/// Starts the planner task on its own thread: rebuilds the schedule from `records` (the
/// store's content), then serves commands until every sender is gone. Returns the command
/// sender once recovery is done.
pub fn start(
    state: Arc<State>,
    store: Store,
    records: Vec<Record>,
) -> Result<(mpsc::Sender<Command>, Restored), String> {
    let (tx, rx) = mpsc::channel(QUEUE);
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .name("muse-planner".into())
        .spawn(move || run(&state, store, records, rx, &ready_tx))
        .map_err(|e| format!("starting the planner thread: {e}"))?;
    let restored = ready_rx
        .recv()
        .map_err(|_| "the planner thread stopped during recovery".to_owned())??;
    Ok((tx, restored))
}

fn run(
    state: &State,
    mut store: Store,
    records: Vec<Record>,
    mut rx: mpsc::Receiver<Command>,
    ready: &std::sync::mpsc::Sender<Result<Restored, String>>,
) {
    let world = &state.world;
    let planner = Planner::new(&world.airspace, world.params);
    let mut live = Live::new(planner, &world.closures, state.clock.now());
    let recovered = match recover::recover(state, &mut live, &records) {
        Ok(r) => {
            let _ = ready.send(Ok(r.restored));
            r
        }
        Err(e) => {
            let _ = ready.send(Err(e));
            return;
        }
    };
    drop(records);
    let now = live.now();
    let mut engine = Engine {
        state,
        live,
        next_seq: recovered.max_seq + 1,
        next_event: recovered.restored.events + 1,
        events: Vec::new(),
        last_evict: now,
    };
    engine.update_gauges(&store);
    let mut group = Vec::with_capacity(MAX_GROUP);
    while let Some(first) = rx.blocking_recv() {
        group.push(first);
        while group.len() < MAX_GROUP {
            match rx.try_recv() {
                Ok(c) => group.push(c),
                Err(_) => break,
            }
        }
        engine.decide_and_commit(&mut store, &mut group);
    }
}

/// An answer waiting for its group to be durable.
enum Pending {
    Plan(oneshot::Sender<PlanReply>, PlanReply),
    Cancel(oneshot::Sender<CancelReply>, CancelReply),
    /// With the zone to record as announced once durable.
    Announce(
        oneshot::Sender<AnnounceReply>,
        AnnounceReply,
        Option<AnnouncedZone>,
    ),
    /// With the withdrawal to record once durable.
    Withdraw(
        oneshot::Sender<WithdrawReply>,
        WithdrawReply,
        Option<(String, Instant)>,
    ),
}

impl Pending {
    /// Answers that the store failed.
    fn fail(self, message: &str) {
        let m = message.to_owned();
        match self {
            Pending::Plan(tx, _) => drop(tx.send(PlanReply::Failed(m))),
            Pending::Cancel(tx, _) => drop(tx.send(CancelReply::Failed(m))),
            Pending::Announce(tx, _, _) => drop(tx.send(AnnounceReply::Failed(m))),
            Pending::Withdraw(tx, _, _) => drop(tx.send(WithdrawReply::Failed(m))),
        }
    }

    /// Sends the answer (a client that went away no longer waits for it; its work is done).
    fn send(self) {
        match self {
            Pending::Plan(tx, answer) => drop(tx.send(answer)),
            Pending::Cancel(tx, answer) => drop(tx.send(answer)),
            Pending::Announce(tx, answer, _) => drop(tx.send(answer)),
            Pending::Withdraw(tx, answer, _) => drop(tx.send(answer)),
        }
    }
}

/// Entries changed by the current group, by id: visible to its later commands before they
/// are published.
type Staged = HashMap<String, Arc<FlightEntry>>;

struct Engine<'s, 'a> {
    state: &'s State,
    live: Live<'a>,
    next_seq: u64,
    /// The id of the next event.
    next_event: u64,
    /// Events of the current group, published after its commit.
    events: Vec<Arc<Event>>,
    /// When flights were last evicted from the index.
    last_evict: Instant,
}

impl Engine<'_, '_> {
    /// Decides every command of `group`, commits the group, then publishes and answers.
    fn decide_and_commit(&mut self, store: &mut Store, group: &mut Vec<Command>) {
        self.live.advance(self.state.clock.now());
        let now = self.live.now();
        if now - self.last_evict >= EVICT_EVERY {
            self.state
                .index
                .write()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .evict_ended_before(now - self.state.retain);
            self.state.events.forget_before(now - self.state.retain);
            self.last_evict = now;
        }
        let mut staged = Staged::new();
        let mut answers = Vec::with_capacity(group.len());
        for command in group.drain(..) {
            if store.pending_bytes() > MAX_GROUP_BYTES / 2 {
                // Keep every group well under the torn-tail bound.
                self.commit(store, &mut staged, &mut answers);
            }
            match command {
                Command::Plan {
                    caller,
                    request,
                    reply,
                } => {
                    let answer = self.plan(store, &mut staged, &caller, request);
                    answers.push(Pending::Plan(reply, answer));
                }
                Command::Cancel { caller, id, reply } => {
                    let answer = self.cancel(store, &mut staged, &caller, &id);
                    answers.push(Pending::Cancel(reply, answer));
                }
                // Zone changes are groups of their own (see the module docs).
                Command::Announce { zone, reply } => {
                    self.commit(store, &mut staged, &mut answers);
                    let (answer, known) = self.announce(store, &mut staged, zone);
                    answers.push(Pending::Announce(reply, answer, known));
                    self.commit(store, &mut staged, &mut answers);
                }
                Command::Withdraw { id, reply } => {
                    self.commit(store, &mut staged, &mut answers);
                    let (answer, withdrawn) = self.withdraw(store, &id);
                    answers.push(Pending::Withdraw(reply, answer, withdrawn));
                    self.commit(store, &mut staged, &mut answers);
                }
            }
        }
        self.commit(store, &mut staged, &mut answers);
        self.update_gauges(store);
    }

    fn lookup(&self, staged: &Staged, id: &str) -> Option<Arc<FlightEntry>> {
        staged.get(id).cloned().or_else(|| {
            self.state
                .index
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .get(id)
                .cloned()
        })
    }

    fn plan(
        &mut self,
        store: &mut Store,
        staged: &mut Staged,
        caller: &Caller,
        request: Request,
    ) -> PlanReply {
        let metrics = &self.state.metrics;
        if let Some(known) = self.lookup(staged, &request.id) {
            return if known.operator == caller.operator && known.same_request(&request) {
                metrics.count_plan(PlanOutcome::Repeated);
                PlanReply::Repeat(known)
            } else {
                metrics.count_plan(PlanOutcome::Conflict);
                PlanReply::Conflict
            };
        }
        if request.departure < self.live.now() - self.state.retain {
            // Older than anything the index keeps: a retry of such an id would not be
            // recognised, so the answer is given without storing it (it can only be
            // `departure_in_past`, and storing it could duplicate an evicted id).
            metrics.count_plan(PlanOutcome::Rejected(RejectReason::DepartureInPast));
            return PlanReply::New(Arc::new(FlightEntry {
                seq: 0,
                operator: caller.operator.clone(),
                free_flow: self.live.planner().free_flow(&request),
                request,
                result: Err(RejectReason::DepartureInPast),
                expanded: 0,
                answered: self.live.now(),
                cancelled_at: None,
                changes: Vec::new(),
                fate: None,
            }));
        }
        let seq = self.next_seq;
        let started = WallInstant::now();
        let live = &mut self.live;
        let Ok(outcome) = catch_unwind(AssertUnwindSafe(|| live.book(seq, &request))) else {
            return PlanReply::Failed(format!(
                "internal error while planning `{}`; nothing was booked",
                request.id
            ));
        };
        metrics.plan_latency.observe(started.elapsed());
        self.next_seq += 1;
        metrics.count_plan(match &outcome.result {
            Ok(_) => PlanOutcome::Planned,
            Err(r) => PlanOutcome::Rejected(*r),
        });
        let entry = Arc::new(FlightEntry {
            seq,
            operator: caller.operator.clone(),
            request,
            result: outcome.result,
            free_flow: outcome.free_flow,
            expanded: outcome.expanded,
            answered: self.live.now(),
            cancelled_at: None,
            changes: Vec::new(),
            fate: None,
        });
        store.append(&Record::Flight(entry.to_record(&self.state.world.airspace)));
        if entry.result.is_ok() {
            self.emit("planned", entry.answered, None, &entry);
        }
        staged.insert(entry.request.id.clone(), Arc::clone(&entry));
        PlanReply::New(entry)
    }

    fn cancel(
        &mut self,
        store: &mut Store,
        staged: &mut Staged,
        caller: &Caller,
        id: &str,
    ) -> CancelReply {
        let metrics = &self.state.metrics;
        // Only the owner may cancel (SPEC §10); to anyone else the flight does not exist.
        let Some(known) = self
            .lookup(staged, id)
            .filter(|e| e.operator == caller.operator)
        else {
            return CancelReply::NotFound;
        };
        match known.status() {
            Status::Cancelled => return CancelReply::Already(known),
            Status::Rejected => {
                metrics.count_cancel(false);
                return CancelReply::NotPlanned(known);
            }
            // Airborne when a zone was announced: it took off.
            Status::Contingency => {
                metrics.count_cancel(false);
                return CancelReply::TookOff(known);
            }
            Status::Planned | Status::Replanned | Status::Diverted => {}
        }
        // A flight that has landed is no longer held by the live schedule; it took off.
        let took_off = known
            .booked_plan()
            .is_some_and(|p| p.takeoff() <= self.live.now());
        let cancelled = if took_off {
            Err(CancelError::TookOff)
        } else {
            self.live.cancel(known.seq)
        };
        match cancelled {
            Ok(_) => {}
            Err(CancelError::TookOff) => {
                metrics.count_cancel(false);
                return CancelReply::TookOff(known);
            }
            Err(CancelError::NotHeld) => {
                return CancelReply::Failed(format!(
                    "internal error: the schedule does not hold flight `{id}`"
                ));
            }
        }
        metrics.count_cancel(true);
        let at = self.live.now();
        store.append(&Record::Cancel {
            id: id.to_owned(),
            at: at.0,
        });
        let mut entry = (*known).clone();
        entry.cancelled_at = Some(at);
        let entry = Arc::new(entry);
        self.emit("cancelled", at, None, &entry);
        staged.insert(id.to_owned(), Arc::clone(&entry));
        CancelReply::Done(entry)
    }

    /// Numbers a change of a flight; it is published with the group.
    fn emit(
        &mut self,
        kind: &'static str,
        at: Instant,
        zone: Option<&str>,
        entry: &Arc<FlightEntry>,
    ) {
        self.events.push(Arc::new(Event {
            id: self.next_event,
            kind,
            at,
            zone: zone.map(str::to_owned),
            entry: Arc::clone(entry),
        }));
        self.next_event += 1;
    }

    /// Makes the pending records durable, publishes the staged entries, the zone changes and
    /// the events, sends the answers.
    fn commit(&mut self, store: &mut Store, staged: &mut Staged, answers: &mut Vec<Pending>) {
        let records = store.pending_records();
        if records > 0 {
            let started = WallInstant::now();
            if let Err(e) = store.commit() {
                store_failed(&e, answers);
            }
            self.state.metrics.store_latency.observe(started.elapsed());
            self.state.metrics.group_size.observe_value(records as f64);
        }
        if !staged.is_empty() {
            // In sequence order: the index lists flights in that order.
            let mut entries: Vec<Arc<FlightEntry>> = staged.drain().map(|(_, e)| e).collect();
            entries.sort_unstable_by_key(|e| e.seq);
            let mut index = self
                .state
                .index
                .write()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            for entry in entries {
                index.put(entry);
            }
        }
        for a in answers.iter_mut() {
            match a {
                Pending::Announce(_, _, known @ Some(_)) => {
                    let zone = known.take().expect("matched Some");
                    self.state
                        .zones
                        .write()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .announce(zone);
                }
                Pending::Withdraw(_, _, withdrawn @ Some(_)) => {
                    let (id, at) = withdrawn.take().expect("matched Some");
                    self.state
                        .zones
                        .write()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .withdraw(&id, at);
                }
                _ => {}
            }
        }
        if !self.events.is_empty() {
            self.state.events.publish(self.events.drain(..));
        }
        for a in answers.drain(..) {
            a.send();
        }
    }

    fn update_gauges(&self, store: &Store) {
        let schedule = self.live.schedule();
        let flights = self
            .state
            .index
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .len();
        self.state.metrics.set_sizes(
            schedule.reservations(),
            schedule.reservation_bytes(),
            flights,
            store.bytes(),
        );
    }
}

/// After a failed write or fsync the file's state is unknown: answers nobody as if stored,
/// and stops so that a restart recovers exactly what is durable.
fn store_failed(e: &crate::store::StoreError, answers: &mut Vec<Pending>) -> ! {
    let message = format!("the store failed ({e}); the service stops");
    eprintln!("muse serve: {message}");
    for a in answers.drain(..) {
        a.fail(&message);
    }
    std::process::exit(70);
}
