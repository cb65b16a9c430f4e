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

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Instant as WallInstant;

use muse_model::{RejectReason, Request};
use muse_planner::online::CancelError;
use muse_planner::{Live, Planner};
use tokio::sync::{mpsc, oneshot};

use crate::auth::Caller;
use crate::flights::{FlightEntry, Status};
use crate::metrics::PlanOutcome;
use crate::state::State;
use crate::store::{MAX_GROUP_BYTES, Record, Store};

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
    let next_seq = match recover(state, &mut live, &records) {
        Ok((restored, max_seq)) => {
            let _ = ready.send(Ok(restored));
            max_seq + 1
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
        next_seq,
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

/// Replays the store into the index and the schedule; returns what was restored and the
/// highest sequence number seen.
fn recover(
    state: &State,
    live: &mut Live<'_>,
    records: &[Record],
) -> Result<(Restored, u64), String> {
    let airspace = &state.world.airspace;
    let mut entries: HashMap<String, FlightEntry> = HashMap::new();
    let mut order: Vec<String> = Vec::new();
    let mut restored = Restored::default();
    let mut max_seq = 0;
    for record in records {
        match record {
            Record::Header { .. } => {}
            Record::Flight(f) => {
                let entry = FlightEntry::from_record(airspace, f)
                    .map_err(|e| format!("restoring from the store: {e}"))?;
                max_seq = max_seq.max(entry.seq);
                if entries.insert(f.id.clone(), entry).is_some() {
                    return Err(format!("restoring from the store: flight `{}` twice", f.id));
                }
                order.push(f.id.clone());
            }
            Record::Cancel { id, at } => {
                let entry = entries
                    .get_mut(id)
                    .ok_or_else(|| format!("restoring from the store: cancel of unknown `{id}`"))?;
                entry.cancelled_at = Some(muse_model::Instant(*at));
                restored.cancellations += 1;
            }
        }
    }
    let mut index = state
        .index
        .write()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    for id in order {
        let entry = entries.remove(&id).expect("every id was inserted");
        if let Some(plan) = entry.booked_plan() {
            if plan.landing() >= live.now() {
                restored.booked += 1;
            }
            live.restore(entry.seq, &entry.request, plan);
        }
        restored.flights += 1;
        index.put(Arc::new(entry));
    }
    index.evict_ended_before(live.now() - state.retain);
    Ok((restored, max_seq))
}

/// An answer waiting for its group to be durable.
enum Pending {
    Plan(oneshot::Sender<PlanReply>, PlanReply),
    Cancel(oneshot::Sender<CancelReply>, CancelReply),
}

struct Engine<'s, 'a> {
    state: &'s State,
    live: Live<'a>,
    next_seq: u64,
    /// When flights were last evicted from the index.
    last_evict: muse_model::Instant,
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
            self.last_evict = now;
        }
        // Entries changed by this group, visible to its later commands before publication.
        let mut staged: HashMap<String, Arc<FlightEntry>> = HashMap::new();
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
            }
        }
        self.commit(store, &mut staged, &mut answers);
        self.update_gauges(store);
    }

    fn lookup(
        &self,
        staged: &HashMap<String, Arc<FlightEntry>>,
        id: &str,
    ) -> Option<Arc<FlightEntry>> {
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
        staged: &mut HashMap<String, Arc<FlightEntry>>,
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
        });
        store.append(&Record::Flight(entry.to_record(&self.state.world.airspace)));
        staged.insert(entry.request.id.clone(), Arc::clone(&entry));
        PlanReply::New(entry)
    }

    fn cancel(
        &mut self,
        store: &mut Store,
        staged: &mut HashMap<String, Arc<FlightEntry>>,
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
            Status::Planned => {}
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
        staged.insert(id.to_owned(), Arc::clone(&entry));
        CancelReply::Done(entry)
    }

    /// Makes the pending records durable, publishes the staged entries, sends the answers.
    fn commit(
        &mut self,
        store: &mut Store,
        staged: &mut HashMap<String, Arc<FlightEntry>>,
        answers: &mut Vec<Pending>,
    ) {
        let records = store.pending_records();
        if records > 0 {
            let started = WallInstant::now();
            if let Err(e) = store.commit() {
                // After a failed fsync the file's state is unknown: answer nobody as if
                // stored, and stop so that a restart recovers exactly what is durable.
                let message = format!("the store failed ({e}); the service stops");
                eprintln!("muse serve: {message}");
                for a in answers.drain(..) {
                    match a {
                        Pending::Plan(tx, _) => {
                            let _ = tx.send(PlanReply::Failed(message.clone()));
                        }
                        Pending::Cancel(tx, _) => {
                            let _ = tx.send(CancelReply::Failed(message.clone()));
                        }
                    }
                }
                std::process::exit(70);
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
        for a in answers.drain(..) {
            // A client that went away no longer waits for its answer; its work is done.
            match a {
                Pending::Plan(tx, answer) => {
                    let _ = tx.send(answer);
                }
                Pending::Cancel(tx, answer) => {
                    let _ = tx.send(answer);
                }
            }
        }
    }

    fn update_gauges(&mut self, store: &Store) {
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
