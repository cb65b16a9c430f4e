//! The planner task: the one place where the service's state changes.
//!
//! Handlers send [`Command`]s over a channel; one thread takes them in arrival order, in
//! groups of whatever has queued up (up to [`MAX_GROUP`]). Every command goes the same way:
//!
//! 1. it is **decided** against the live schedule, without changing it: planned, rejected,
//!    repeated, conflicting, cancelled, refused; a zone's outcomes are decided on a copy;
//! 2. what it changes is **stored** as rows in the group's transaction (the flight as it now
//!    stands, its event, the zone);
//! 3. the change is **applied** to the schedule by `Engine::apply` — the one function that
//!    changes it, used alike when the service restarts and puts back what its store holds —
//!    so that the group's later commands are decided against it;
//! 4. once the whole group is **committed** (durable), the changed flights and zones become
//!    visible to reads, the events go out, and every answer of the group is sent.
//!
//! So nothing is acknowledged before it is durable, planning is serialized against one
//! schedule (no double booking under any interleaving), and reads never wait for planning. A
//! zone announcement or withdrawal (docs/reference.md#zones-announced-during-the-day) is a group of
//! its own: decided by [`crate::zones::decide`], then stored and applied here like any command.
//!
//! If the store fails, the schedule may hold what the store does not: the task answers the
//! group's commands with an error, stops, and reports the failure to [`crate::Running`],
//! which stops the service (a restart recovers exactly what is durable). At start the task
//! first loads the store (the `load` submodule), then serves.

mod apply;
mod archive;
mod batch;
mod commands;
mod load;
mod standby;
mod writer;

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Instant as WallInstant;

use muse_model::{Instant, Request};
use muse_planner::CancelError;
use muse_planner::{FlightId, Live, Outcome, Planner};
use tokio::sync::{mpsc, oneshot};

use crate::auth::Caller;
use crate::events::{Event, EventKind};
use crate::flights::{FlightEntry, Status};
use crate::metrics::PlanOutcome;
use crate::state::State;
use crate::store::{Opening, StoreError};
use crate::zones::book::{AnnouncedZone, NewZone};
use crate::zones::decide::{self, AnnounceReply, Announcement, WithdrawReply};

pub use commands::{CancelReply, Command, PlanReply, Restored};

pub use batch::Batching;
use commands::Pending;

use apply::Change;

/// How far the clock moves between two evictions of ended flights from the index.
const EVICT_EVERY: muse_model::Millis = muse_model::Millis::from_secs(60);

/// Most commands decided and committed as one group.
pub const MAX_GROUP: usize = 512;
/// Commands that may wait in the channel before senders wait too (back-pressure).
pub const QUEUE: usize = 8_192;

/// How the planner task ended: `Ok` when every sender was gone (a clean stop).
pub type Ended = Result<(), StoreError>;

/// How the planner task works, besides its store.
#[derive(Debug)]
pub struct Setup {
    /// Whether requests that arrive together are planned as one batch.
    pub batching: Batching,
    /// Whether, and how, the leader archives flights that landed long ago.
    pub retention: Option<crate::store::archive::Retention>,
}

/// Starts the planner task on its own thread: it converts and loads the store (`opening`),
/// reports what it restored on `ready`, then serves `commands` until every sender is gone,
/// and reports how it ended on `ended`.
pub fn spawn(
    state: Arc<State>,
    opening: Opening,
    commands: mpsc::Receiver<Command>,
    setup: Setup,
    ready: oneshot::Sender<Result<Restored, StoreError>>,
    ended: oneshot::Sender<Ended>,
) -> Result<(), std::io::Error> {
    std::thread::Builder::new()
        .name("muse-planner".into())
        .spawn(move || {
            let result = run(&state, opening, commands, setup, ready);
            let _ = ended.send(result);
        })
        .map(drop)
}

fn run(
    state: &State,
    opening: Opening,
    mut rx: mpsc::Receiver<Command>,
    setup: Setup,
    ready: oneshot::Sender<Result<Restored, StoreError>>,
) -> Ended {
    let Setup {
        batching,
        retention,
    } = setup;
    let world = &state.world;
    let planner = Planner::new(&world.airspace, world.params);
    let live = Live::new(planner, &world.closures, state.clock.now());
    let description = world.description();
    let phase = &state.phase;
    let opened = opening.finish(&world.airspace, &description, &mut |n| {
        phase.set_imported(n);
    });
    let (mut store, import) = match opened {
        Ok(s) => s,
        Err(e) => {
            // The start fails: `ready` says why.
            let _ = ready.send(Err(e));
            return Ok(());
        }
    };
    let mut engine = Engine {
        state,
        live,
        next_seq: 1,
        next_event: 1,
        group: writer::Batch::default(),
        staged: Staged::default(),
        pipe: None,
        last_evict: state.clock.now(),
        batching,
    };
    let Some(leads) = engine.start(store.as_mut(), import, ready) else {
        // The start failed: `ready` said why.
        return Ok(());
    };
    if !leads && !engine.stand_by(store.as_mut(), &mut rx)? {
        // Stopped while standing by.
        return store.close();
    }
    let archiving = match retention {
        Some(r) => Some((store.archiver()?, r)),
        None => None,
    };
    std::thread::scope(|scope| {
        // Dropped when the planner task ends: the archiver stops then.
        let (_archive_running, archive_stop) = std::sync::mpsc::channel::<()>();
        if let Some((archiver, retention)) = archiving {
            std::thread::Builder::new()
                .name("muse-archive".into())
                .spawn_scoped(scope, move || {
                    archive::run(state, archiver, &retention, &archive_stop);
                })
                .map_err(|error| StoreError::Io {
                    what: "starting the archive thread".into(),
                    error,
                })?;
        }
        let (batches, received) = std::sync::mpsc::sync_channel(PIPELINE);
        let published = Arc::new(writer::Published::default());
        let progress = Arc::clone(&published);
        let writing = std::thread::Builder::new()
            .name("muse-store".into())
            .spawn_scoped(scope, move || {
                writer::run(state, store, &received, &progress)
            })
            .map_err(|error| StoreError::Io {
                what: "starting the store's writer thread".into(),
                error,
            })?;
        engine.pipe = Some(Pipe {
            batches,
            published,
            sent: 0,
        });
        let mut group = Vec::with_capacity(MAX_GROUP);
        while let Some(first) = rx.blocking_recv() {
            group.push(first);
            engine.batching.gather(&mut rx, &mut group);
            if engine.decide_and_send(&mut group).is_err() {
                break;
            }
        }
        // Lets the writer finish what it was sent, then stop.
        engine.pipe = None;
        match writing.join() {
            Ok(Ok(store)) => store.close(),
            Ok(Err(e)) => Err(e),
            Err(_) => Err(StoreError::Io {
                what: "writing the store".into(),
                error: std::io::Error::other("the writer thread panicked"),
            }),
        }
    })
}

/// Groups the planner task may have sent ahead of the writer.
const PIPELINE: usize = 8;

/// The way to the writer thread.
struct Pipe {
    batches: std::sync::mpsc::SyncSender<writer::Batch>,
    published: Arc<writer::Published>,
    /// The number of the last batch sent.
    sent: u64,
}

/// Flights changed by groups not yet published, by id, with the number of the last group
/// that changed each: what later decisions must see before the index and the store do.
type Staged = HashMap<String, (u64, Arc<FlightEntry>)>;

/// A change of the zones known, published with its group.
enum ZoneChange {
    Announced(AnnouncedZone),
    Withdrawn(String, Instant),
}

struct Engine<'s> {
    state: &'s State,
    live: Live<'s>,
    next_seq: u64,
    /// The id of the next event.
    next_event: u64,
    /// What the group being decided writes and changes.
    group: writer::Batch,
    staged: Staged,
    /// The writer thread (`None` while loading: nothing is written then).
    pipe: Option<Pipe>,
    /// When flights were last evicted from the index.
    last_evict: Instant,
    /// Whether requests that arrive together are planned as one batch.
    batching: Batching,
}

/// The writer failed: the planner task stops.
struct Fatal;

impl Engine<'_> {
    /// Decides every command of `group` and sends it to the writer, which answers once it
    /// is durable. `Err` once the writer has failed (the task stops).
    fn decide_and_send(&mut self, group: &mut Vec<Command>) -> Result<(), Fatal> {
        self.tick();
        self.forget_published();
        let mut answers = Vec::with_capacity(group.len());
        let mut commands = group.drain(..);
        let outcome = self
            .decide_all(&mut commands, &mut answers)
            .and_then(|()| self.send(&mut answers));
        if outcome.is_err() {
            let message =
                "the store failed; the service stops (a restart recovers what is durable)";
            for a in answers.drain(..) {
                a.fail(message);
            }
            for command in commands {
                command.refuse(message);
            }
            return Err(Fatal);
        }
        self.update_gauges();
        Ok(())
    }

    /// Moves the schedule to the clock's now, and now and then evicts the flights that ended
    /// from the index.
    fn tick(&mut self) {
        self.live.advance(self.state.clock.now());
        let now = self.live.now();
        if now - self.last_evict >= EVICT_EVERY {
            self.state
                .index
                .write()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .evict_ended_before(now);
            self.last_evict = now;
        }
    }

    /// Drops from the staged flights those the writer has published (the index and the store
    /// hold them now).
    fn forget_published(&mut self) {
        if let Some(pipe) = &self.pipe {
            let done = pipe.published.done();
            self.staged.retain(|_, (n, _)| *n > done);
        }
    }

    fn decide(&mut self, command: Command, answers: &mut Vec<Pending>) -> Result<(), Fatal> {
        match command {
            Command::Plan {
                caller,
                request,
                reply,
            } => {
                let answer = self.plan(&caller, request);
                answers.push(Pending::Plan(reply, answer));
            }
            Command::Cancel { caller, id, reply } => {
                let answer = self.cancel(&caller, &id);
                answers.push(Pending::Cancel(reply, answer));
            }
            // Zone changes are groups of their own, decided once everything before them is
            // published (they read the index and the zones).
            Command::Announce { zone, reply } => {
                self.barrier(answers)?;
                let answer = self.announce(zone);
                answers.push(Pending::Announce(reply, answer));
                self.send(answers)?;
            }
            Command::Withdraw { id, reply } => {
                self.barrier(answers)?;
                let answer = self.withdraw(&id);
                answers.push(Pending::Withdraw(reply, answer));
                self.send(answers)?;
            }
        }
        Ok(())
    }

    /// The flight with client id `id`: as changed by this group, as held, or as stored.
    fn lookup(&self, id: &str) -> Result<Option<Arc<FlightEntry>>, StoreError> {
        if let Some((_, e)) = self.staged.get(id) {
            return Ok(Some(Arc::clone(e)));
        }
        let held = self
            .state
            .index
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get(id)
            .cloned();
        if held.is_some() {
            return Ok(held);
        }
        Ok(self
            .state
            .reader
            .flight(&self.state.world.airspace, id)?
            .map(Arc::new))
    }

    fn plan(&mut self, caller: &Caller, request: Request) -> PlanReply {
        if let Some(reply) = self.known(caller, &request) {
            return reply;
        }
        let started = WallInstant::now();
        let live = &mut self.live;
        let Ok(outcome) = catch_unwind(AssertUnwindSafe(|| live.plan(&request))) else {
            return PlanReply::Failed(format!(
                "internal error while planning `{}`; nothing was booked",
                request.id
            ));
        };
        self.state.metrics.plan_latency.observe(started.elapsed());
        let entry = self.answered(caller, request, outcome);
        self.apply(Change::Flights(vec![Arc::clone(&entry)]));
        PlanReply::New(entry)
    }

    /// The answer to a request whose id is known (ids are forever: a stored id, at any age,
    /// is a retry or a conflict), or that cannot be read; `None` for a new request.
    fn known(&self, caller: &Caller, request: &Request) -> Option<PlanReply> {
        let metrics = &self.state.metrics;
        match self.lookup(&request.id) {
            Ok(Some(known)) => Some(
                if known.operator == caller.operator && known.same_request(request) {
                    metrics.count_plan(PlanOutcome::Repeated);
                    PlanReply::Repeat(known)
                } else {
                    metrics.count_plan(PlanOutcome::Conflict);
                    PlanReply::Conflict
                },
            ),
            Ok(None) => None,
            Err(e) => Some(PlanReply::Failed(format!(
                "reading the store failed ({e}); nothing was booked"
            ))),
        }
    }

    /// The flight a new request's `outcome` makes, numbered next, counted and written with
    /// the group (not yet applied to the schedule).
    fn answered(
        &mut self,
        caller: &Caller,
        request: Request,
        outcome: Outcome,
    ) -> Arc<FlightEntry> {
        let seq = self.next_seq;
        self.next_seq += 1;
        self.state.metrics.count_plan(match &outcome.result {
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
            fates: Vec::new(),
        });
        self.group
            .writes
            .push(writer::Write::Flight(Arc::clone(&entry), true));
        if entry.result.is_ok() {
            self.emit(EventKind::Planned, entry.answered, None, &entry);
        }
        entry
    }

    fn cancel(&mut self, caller: &Caller, id: &str) -> CancelReply {
        let metrics = &self.state.metrics;
        // Only the owner may cancel (docs/reference.md#the-planning-service); to anyone else the
        // flight does not exist.
        let known = match self.lookup(id) {
            Ok(known) => known,
            Err(e) => return CancelReply::Failed(format!("reading the store failed ({e})")),
        };
        let Some(known) = known.filter(|e| e.operator == caller.operator) else {
            return CancelReply::NotFound;
        };
        match known.status() {
            Status::Cancelled => return CancelReply::Already(known),
            Status::Rejected => {
                metrics.count_cancel(false);
                return CancelReply::NotPlanned;
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
        let decided = if took_off {
            Err(CancelError::TookOff)
        } else {
            self.live.can_cancel(FlightId(known.seq)).map(drop)
        };
        match decided {
            Ok(()) => {}
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
        let mut entry = (*known).clone();
        entry.cancelled_at = Some(at);
        let entry = Arc::new(entry);
        self.group
            .writes
            .push(writer::Write::Flight(Arc::clone(&entry), false));
        self.emit(EventKind::Cancelled, at, None, &entry);
        self.apply(Change::Flights(vec![Arc::clone(&entry)]));
        CancelReply::Done(entry)
    }

    /// Announces `zone` now: decided on a copy of the schedule ([`decide::announcement`]),
    /// then the zone, every changed flight and its event stored with the group, and it all
    /// applied.
    fn announce(&mut self, zone: NewZone) -> AnnounceReply {
        let decided = match decide::announcement(self.state, &mut self.live, zone) {
            Ok(decided) => decided,
            Err(reply) => return reply,
        };
        let (id, n) = (decided.zone.id.clone(), decided.zone.announced);
        self.group.writes.push(writer::Write::Zone(decided.stored));
        for (kind, entry) in &decided.changed {
            self.group
                .writes
                .push(writer::Write::Flight(Arc::clone(entry), false));
            self.emit(*kind, n, Some(&id), entry);
        }
        let affected: Vec<Arc<FlightEntry>> = decided.changed.into_iter().map(|(_, e)| e).collect();
        self.apply(Change::Zone {
            zone: decided.zone,
            closures: Some(decided.closures),
        });
        self.apply(Change::Flights(affected.clone()));
        self.state.metrics.count_zone(true);
        AnnounceReply::Done(Announcement {
            zone: id,
            announced: n,
            affected,
        })
    }

    /// Withdraws the announced zone `id` now ([`decide::withdrawal`]; nothing is replanned):
    /// stores it, applies it.
    fn withdraw(&mut self, id: &str) -> WithdrawReply {
        let zone = match decide::withdrawal(self.state, &self.live, id) {
            Ok(zone) => zone,
            Err(reply) => return reply,
        };
        let at = self.live.now();
        self.group
            .writes
            .push(writer::Write::Withdrawal(id.to_owned(), at));
        self.apply(Change::Withdrawal {
            id: id.to_owned(),
            at,
        });
        self.state.metrics.count_zone(false);
        WithdrawReply::Done(zone)
    }

    /// Numbers a change of a flight and writes it with the group, which publishes it.
    fn emit(&mut self, kind: EventKind, at: Instant, zone: Option<&str>, entry: &Arc<FlightEntry>) {
        let event = Arc::new(Event {
            id: self.next_event,
            kind,
            at,
            zone: zone.map(str::to_owned),
            entry: Arc::clone(entry),
        });
        self.group
            .writes
            .push(writer::Write::Event(Arc::clone(&event)));
        self.group.events.push(event);
        self.next_event += 1;
    }

    /// Sends the group decided so far, with `answers`, to the writer (while loading, when
    /// nothing is written, publishes it at once). `Err` if the writer has failed.
    fn send(&mut self, answers: &mut Vec<Pending>) -> Result<(), Fatal> {
        let mut batch = std::mem::take(&mut self.group);
        batch.answers = std::mem::take(answers);
        let Some(pipe) = &mut self.pipe else {
            debug_assert!(batch.writes.is_empty(), "nothing is written while loading");
            writer::publish(self.state, batch);
            return Ok(());
        };
        if batch.writes.is_empty() && batch.answers.is_empty() {
            return Ok(());
        }
        pipe.sent += 1;
        batch.number = pipe.sent;
        if pipe.published.failed() {
            // The writer stopped: this batch is answered, as it would have been.
            writer::Batch::fail_all(batch);
            return Err(Fatal);
        }
        pipe.batches.send(batch).map_err(|e| {
            writer::Batch::fail_all(e.0);
            Fatal
        })
    }

    /// Sends what is decided so far and waits until the writer has published everything
    /// sent: the index, the zones and the store then hold every earlier change.
    fn barrier(&mut self, answers: &mut Vec<Pending>) -> Result<(), Fatal> {
        self.send(answers)?;
        if let Some(pipe) = &self.pipe
            && !pipe.published.wait_for(pipe.sent)
        {
            return Err(Fatal);
        }
        self.forget_published();
        Ok(())
    }

    fn update_gauges(&self) {
        let schedule = self.live.schedule();
        let flights = self
            .state
            .index
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .len();
        self.state
            .metrics
            .set_flights_stored(self.next_seq.saturating_sub(1));
        self.state.metrics.set_sizes(
            schedule.reservations(),
            schedule.reservation_bytes(),
            flights,
        );
    }
}
