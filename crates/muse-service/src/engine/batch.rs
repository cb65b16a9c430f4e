//! Requests that arrive together, planned as one batch (docs/reference.md#batch-planning; `muse
//! serve --batch-window-ms W`): after a command arrives the planner task waits up to `W` for
//! others, and each run of plan commands in the group is planned together on top of the live
//! schedule by the optimiser (`muse_optimize::optimize_on`), which never does worse than planning
//! them one by one in order of arrival. The flights are numbered, stored and answered in order of
//! arrival; retries and conflicts are answered as always. A window of zero is first come, first
//! served, as without batching.

use std::mem::take;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::{Duration, Instant as WallInstant};

use muse_model::{RejectReason, Request};
use muse_optimize::{Options, optimize_on};
use muse_planner::{FlightId, Outcome};
use tokio::sync::mpsc::Receiver;
use tokio::sync::mpsc::error::TryRecvError;
use tokio::sync::oneshot;

use super::apply::Change;
use super::commands::{Command, Pending, PlanReply};
use super::{Engine, Fatal, MAX_GROUP};
use crate::auth::Caller;

/// Steps of search per batch (seed 1).
pub const BATCH_ITERATIONS: u64 = 1_000;

/// How long the planner task waits for requests to plan together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Batching {
    window: Duration,
}

/// A plan command of a batch.
type Asked = (Caller, Request, oneshot::Sender<PlanReply>);

impl Batching {
    /// Batches of what arrives within `window` of the first; zero: no batches.
    pub fn new(window: Duration) -> Self {
        Batching { window }
    }

    /// Whether requests are planned in batches.
    pub fn is_on(self) -> bool {
        !self.window.is_zero()
    }

    /// Adds to `group` what is already waiting and, with a window, what arrives within it
    /// after the group's first command, up to [`MAX_GROUP`] commands.
    pub(super) fn gather(self, rx: &mut Receiver<Command>, group: &mut Vec<Command>) {
        let deadline = WallInstant::now() + self.window;
        while group.len() < MAX_GROUP {
            match rx.try_recv() {
                Ok(c) => group.push(c),
                Err(TryRecvError::Disconnected) => break,
                Err(TryRecvError::Empty) => {
                    let now = WallInstant::now();
                    if now >= deadline {
                        break;
                    }
                    std::thread::sleep((deadline - now).min(Duration::from_millis(1)));
                }
            }
        }
    }
}

impl Engine<'_> {
    /// Decides `commands` in order; with batching on, each run of plan commands as one batch.
    pub(super) fn decide_all(
        &mut self,
        commands: &mut impl Iterator<Item = Command>,
        answers: &mut Vec<Pending>,
    ) -> Result<(), Fatal> {
        let mut run: Vec<Asked> = Vec::new();
        for command in commands.by_ref() {
            match command {
                Command::Plan {
                    caller,
                    request,
                    reply,
                } if self.batching.is_on() => run.push((caller, request, reply)),
                other => {
                    if !run.is_empty() {
                        self.plan_batch(take(&mut run), answers);
                    }
                    self.decide(other, answers)?;
                }
            }
        }
        if !run.is_empty() {
            self.plan_batch(run, answers);
        }
        Ok(())
    }

    /// Plans the new requests of `run` as one batch and answers every command of it, in
    /// order of arrival.
    fn plan_batch(&mut self, run: Vec<Asked>, answers: &mut Vec<Pending>) {
        let mut replies: Vec<Option<PlanReply>> = run.iter().map(|_| None).collect();
        // New requests, in order; a second request with the id of one of them is decided
        // after the batch (a retry or a conflict of it).
        let mut fresh: Vec<usize> = Vec::new();
        let mut again: Vec<usize> = Vec::new();
        for (k, (caller, request, _)) in run.iter().enumerate() {
            if fresh.iter().any(|&j| run[j].1.id == request.id) {
                again.push(k);
            } else if let Some(reply) = self.known(caller, request) {
                replies[k] = Some(reply);
            } else {
                fresh.push(k);
            }
        }
        let started = WallInstant::now();
        match self.batch_outcomes(&run, &fresh) {
            Some(outcomes) => {
                let each = started.elapsed() / u32::try_from(fresh.len().max(1)).unwrap_or(1);
                let mut entries = Vec::with_capacity(fresh.len());
                for (&k, outcome) in fresh.iter().zip(outcomes) {
                    self.state.metrics.plan_latency.observe(each);
                    let (caller, request, _) = &run[k];
                    let entry = self.answered(caller, request.clone(), outcome);
                    replies[k] = Some(PlanReply::New(Arc::clone(&entry)));
                    entries.push(entry);
                }
                if !entries.is_empty() {
                    self.apply(Change::Flights(entries));
                }
            }
            None => {
                for &k in &fresh {
                    replies[k] = Some(PlanReply::Failed(format!(
                        "internal error while planning `{}` in a batch; nothing was booked",
                        run[k].1.id
                    )));
                }
            }
        }
        for &k in &again {
            let (caller, request, _) = &run[k];
            replies[k] = Some(self.plan(caller, request.clone()));
        }
        for ((_, _, reply), answer) in run.into_iter().zip(replies) {
            let answer = answer.unwrap_or_else(|| PlanReply::Failed("not decided".into()));
            answers.push(Pending::Plan(reply, answer));
        }
    }

    /// The outcome of each request `fresh` points to in `run` (in that order), numbered from
    /// the next flight number on: a departure before now is rejected as the online planner
    /// rejects it, the rest are optimised together on the live schedule. `None` if the
    /// optimiser failed (nothing is booked then).
    fn batch_outcomes(&self, run: &[Asked], fresh: &[usize]) -> Option<Vec<Outcome>> {
        let now = self.live.now();
        let planner = self.live.planner();
        let (mut requests, mut ids, mut at) = (Vec::new(), Vec::new(), Vec::new());
        let mut outcomes: Vec<Option<Outcome>> = Vec::with_capacity(fresh.len());
        for (n, &k) in fresh.iter().enumerate() {
            let request = &run[k].1;
            if request.departure < now {
                outcomes.push(Some(Outcome {
                    result: Err(RejectReason::DepartureInPast),
                    free_flow: planner.free_flow(request),
                    expanded: 0,
                }));
            } else {
                outcomes.push(None);
                requests.push(request.clone());
                ids.push(FlightId(self.next_seq + n as u64));
                at.push(n);
            }
        }
        if !requests.is_empty() {
            let options = Options {
                iterations: BATCH_ITERATIONS,
                ..Options::default()
            };
            let schedule = self.live.schedule();
            let optimised = catch_unwind(AssertUnwindSafe(|| {
                optimize_on(planner, schedule, &requests, &ids, &options, |_| {})
            }))
            .ok()?;
            for (n, outcome) in at.into_iter().zip(optimised.outcomes) {
                outcomes[n] = Some(outcome);
            }
        }
        outcomes.into_iter().collect()
    }
}
