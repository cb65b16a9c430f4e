//! The load itself: open-loop dispatch on a fixed schedule, or closed-loop clients, each
//! request's latency, HTTP status and outcome recorded.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use muse_model::Millis;
use tokio::sync::Semaphore;
use tokio::time::Instant;

use crate::config::{Mode, Stop};
use crate::demand::Demand;
use crate::error::LoadError;
use crate::outcome::{ErrorKind, Outcome, classify};
use crate::schedule::{LATE, OpenSchedule};
use crate::server::{Server, system_now};
use crate::stats::nanos;

/// One request as measured.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sample {
    /// The request's index in the run (its id is `PREFIX-index`).
    pub index: u64,
    /// Latency, ns: from the due time (open loop) or from sending (closed loop) to the whole
    /// answer read, or to the failure.
    pub latency_ns: u64,
    /// HTTP status (0: no answer).
    pub status: u16,
    /// What became of it.
    pub outcome: Outcome,
    /// Open loop: how long after its due time it was sent, ns (0 in closed loop).
    pub lag_ns: u64,
}

/// Counters updated as the run goes, for progress displays.
#[derive(Debug, Default)]
pub struct Live {
    /// Requests sent.
    pub sent: AtomicU64,
    /// Requests finished (answered or failed).
    pub completed: AtomicU64,
    /// Requests planned.
    pub planned: AtomicU64,
    /// Requests that ended in an error.
    pub errors: AtomicU64,
}

impl Live {
    fn record(&self, outcome: &Outcome) {
        self.completed.fetch_add(1, Ordering::Relaxed);
        match outcome {
            Outcome::Planned => {
                self.planned.fetch_add(1, Ordering::Relaxed);
            }
            Outcome::Rejected(_) => {}
            Outcome::Error(_) => {
                self.errors.fetch_add(1, Ordering::Relaxed);
            }
        }
    }
}

/// What a load produced.
#[derive(Debug)]
pub struct LoadRun {
    /// Every request, in completion order per client (closed loop) or overall (open loop).
    pub samples: Vec<Sample>,
    /// From the start to the last request finished.
    pub wall: Duration,
    /// Open loop: requests that found the in-flight cap reached and waited for a slot.
    pub waited_for_slot: u64,
    /// Open loop: requests sent more than [`LATE`] after their due time.
    pub late: u64,
}

/// Sends one `POST /v1/flights` and reads the whole answer.
async fn send(server: &Server, body: String) -> (u16, Outcome) {
    match server.post_flight(body).send().await {
        Err(e) => (0, Outcome::Error(ErrorKind::of(&e))),
        Ok(response) => {
            let status = response.status().as_u16();
            match response.bytes().await {
                Ok(b) => (status, classify(status, &b)),
                Err(e) => (status, Outcome::Error(ErrorKind::of(&e))),
            }
        }
    }
}

/// Runs the load of `mode` until `stop`, drawing requests from `demand` with departures on
/// the server's clock (this machine's plus `skew`), and updating `live` as requests finish.
pub async fn run_load(
    server: Arc<Server>,
    demand: Demand,
    skew: Millis,
    mode: Mode,
    stop: Stop,
    live: Arc<Live>,
) -> Result<LoadRun, LoadError> {
    match mode {
        Mode::Open {
            rate,
            max_in_flight,
        } => {
            let schedule = OpenSchedule::new(rate).ok_or_else(|| {
                LoadError::Config(format!("--rate must be positive and finite, got {rate}"))
            })?;
            Ok(open_loop(server, demand, skew, schedule, max_in_flight, stop, live).await)
        }
        Mode::Closed { clients } => {
            Ok(closed_loop(server, demand, skew, clients, stop, live).await)
        }
    }
}

async fn open_loop(
    server: Arc<Server>,
    mut demand: Demand,
    skew: Millis,
    schedule: OpenSchedule,
    max_in_flight: usize,
    stop: Stop,
    live: Arc<Live>,
) -> LoadRun {
    let total = match stop {
        Stop::Count(n) => n,
        Stop::Duration(d) => schedule.count_within(d),
    };
    let cap = u32::try_from(max_in_flight).unwrap_or(u32::MAX);
    let slots = Arc::new(Semaphore::new(cap as usize));
    let samples = Arc::new(Mutex::new(Vec::with_capacity(
        usize::try_from(total).unwrap_or(0).min(1 << 24),
    )));
    let mut waited_for_slot = 0;
    let mut late = 0;
    let t0 = Instant::now();
    for i in 0..total {
        let due = t0 + schedule.due(i);
        if due > Instant::now() {
            tokio::time::sleep_until(due).await;
        } else if i % 256 == 255 {
            // Behind schedule: let the answers in flight be read.
            tokio::task::yield_now().await;
        }
        let permit = if let Ok(p) = Arc::clone(&slots).try_acquire_owned() {
            p
        } else {
            waited_for_slot += 1;
            match Arc::clone(&slots).acquire_owned().await {
                Ok(p) => p,
                // The semaphore is never closed.
                Err(_) => break,
            }
        };
        let lag = Instant::now().saturating_duration_since(due);
        if lag > LATE {
            late += 1;
        }
        let index = demand.issued();
        let request = demand.next_request(system_now() + skew);
        let body = demand.body(&request);
        live.sent.fetch_add(1, Ordering::Relaxed);
        let server = Arc::clone(&server);
        let samples = Arc::clone(&samples);
        let live = Arc::clone(&live);
        tokio::spawn(async move {
            let (status, outcome) = send(&server, body).await;
            let latency_ns = nanos(due.elapsed());
            live.record(&outcome);
            samples
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .push(Sample {
                    index,
                    latency_ns,
                    status,
                    outcome,
                    lag_ns: nanos(lag),
                });
            drop(permit);
        });
    }
    // Every slot free again: every request has finished.
    let _all = slots.acquire_many(cap).await;
    let wall = t0.elapsed();
    let samples = std::mem::take(&mut *samples.lock().unwrap_or_else(PoisonError::into_inner));
    LoadRun {
        samples,
        wall,
        waited_for_slot,
        late,
    }
}

async fn closed_loop(
    server: Arc<Server>,
    demand: Demand,
    skew: Millis,
    clients: usize,
    stop: Stop,
    live: Arc<Live>,
) -> LoadRun {
    let demand = Arc::new(Mutex::new(demand));
    let t0 = Instant::now();
    let mut tasks = tokio::task::JoinSet::new();
    for _ in 0..clients {
        let server = Arc::clone(&server);
        let demand = Arc::clone(&demand);
        let live = Arc::clone(&live);
        tasks.spawn(async move {
            let mut samples = Vec::new();
            loop {
                if let Stop::Duration(d) = stop
                    && t0.elapsed() >= d
                {
                    break;
                }
                let (index, body) = {
                    let mut demand = demand.lock().unwrap_or_else(PoisonError::into_inner);
                    let index = demand.issued();
                    if let Stop::Count(n) = stop
                        && index >= n
                    {
                        break;
                    }
                    let request = demand.next_request(system_now() + skew);
                    (index, demand.body(&request))
                };
                live.sent.fetch_add(1, Ordering::Relaxed);
                let sent = Instant::now();
                let (status, outcome) = send(&server, body).await;
                let latency_ns = nanos(sent.elapsed());
                live.record(&outcome);
                samples.push(Sample {
                    index,
                    latency_ns,
                    status,
                    outcome,
                    lag_ns: 0,
                });
            }
            samples
        });
    }
    let mut samples = Vec::new();
    while let Some(result) = tasks.join_next().await {
        // A client task cannot panic short of a bug; its samples are then lost, and the
        // counts say so (sent > completed).
        if let Ok(mut s) = result {
            samples.append(&mut s);
        }
    }
    LoadRun {
        samples,
        wall: t0.elapsed(),
        waited_for_slot: 0,
        late: 0,
    }
}
