//! The load itself: open-loop dispatch on a fixed schedule, closed-loop clients, or a fixed
//! number of clients paced by the open-loop schedule; each request's latency, HTTP status and
//! outcome recorded.

use std::future::Future;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use muse_model::Millis;
use tokio::sync::Semaphore;
use tokio::time::Instant;

use crate::config::{Mode, Stop};
use crate::demand::Demand;
use crate::error::LoadError;
use crate::outcome::{Outcome, classify};
use crate::schedule::{LATE, OpenSchedule, PACED_LATE, pace};
use crate::server::{Server, system_now};
use crate::stats::nanos;

/// One request as measured.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sample {
    /// The request's index in the run (its id is `PREFIX-index`).
    pub index: u64,
    /// Latency, ns: from the due time (open loop and paced) or from sending (closed loop) to
    /// the whole answer read, or to the failure.
    pub latency_ns: u64,
    /// HTTP status (0: no answer).
    pub status: u16,
    /// What became of it.
    pub outcome: Outcome,
    /// Open loop and paced: how long after its due time it was sent, ns (0 in closed loop).
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
    /// Every request, in completion order per client (closed loop and paced) or overall
    /// (open loop).
    pub samples: Vec<Sample>,
    /// From the start to the last request finished.
    pub wall: Duration,
    /// Open loop: requests that found the in-flight cap reached and waited for a slot.
    /// Paced: requests that fell due while every client was busy and waited for one.
    pub waited_for_slot: u64,
    /// Open loop and paced: requests sent more than `late_threshold` after their due time.
    pub late: u64,
    /// The threshold of `late`: [`LATE`] in open loop, [`PACED_LATE`] paced, zero in closed
    /// loop.
    pub late_threshold: Duration,
}

/// Sends one `POST /v1/flights` and reads the whole answer.
async fn send(server: &Server, body: String) -> (u16, Outcome) {
    match server.post_flight(body.as_bytes()).await {
        Err(kind) => (0, Outcome::Error(kind)),
        Ok(answer) => (answer.status, classify(answer.status, &answer.body)),
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
    let schedule_of = |rate: f64| {
        OpenSchedule::new(rate).ok_or_else(|| {
            LoadError::Config(format!("--rate must be positive and finite, got {rate}"))
        })
    };
    match mode {
        Mode::Open {
            rate,
            max_in_flight,
        } => {
            let schedule = schedule_of(rate)?;
            Ok(open_loop(server, demand, skew, schedule, max_in_flight, stop, live).await)
        }
        Mode::Closed { clients } => {
            Ok(closed_loop(server, demand, skew, clients, stop, live).await)
        }
        Mode::Paced { rate, clients } => {
            let schedule = schedule_of(rate)?;
            paced_loop(server, demand, skew, schedule, clients, stop, live).await
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
    let total = schedule.count_of(stop);
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
        late_threshold: LATE,
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
        late_threshold: Duration::ZERO,
    }
}

async fn paced_loop(
    server: Arc<Server>,
    demand: Demand,
    skew: Millis,
    schedule: OpenSchedule,
    clients: usize,
    stop: Stop,
    live: Arc<Live>,
) -> Result<LoadRun, LoadError> {
    let demand = Mutex::new(demand);
    // Called in index order (see `paced`), so that request `i` is the demand's `i`-th, id
    // `PREFIX-i`; its departure is drawn at send time.
    let draw = move |index: u64| {
        let mut demand = demand.lock().unwrap_or_else(PoisonError::into_inner);
        debug_assert_eq!(demand.issued(), index);
        let request = demand.next_request(system_now() + skew);
        demand.body(&request)
    };
    let work = move |body: String| {
        let server = Arc::clone(&server);
        async move { send(&server, body).await }
    };
    paced(schedule, clients, schedule.count_of(stop), live, draw, work).await
}

/// What one paced client did.
#[derive(Default)]
struct PacedClient {
    samples: Vec<Sample>,
    waited: u64,
    late: u64,
}

/// The paced run, generic in what a request is and how it is sent, so that the assignment
/// can be tested without a service.
///
/// Requests `0..total` are released at their due times `t0 + schedule.due(i)` by [`pace`]
/// on a thread of its own into one queue. `clients` tasks serve it, each with at most one
/// request at a time: a client that is free waits its turn for the queue (first free, first
/// served), takes the next request when it is released (or at once if it already was),
/// makes it with `draw(index)` (called in index order, the queue still held), sends it with
/// `work`, and comes back. A request released while every client is busy stays queued until
/// one is free: it is counted in `waited_for_slot` when the client that takes it became free
/// only after its due time. Latency runs from the due time, lag from the due time to the
/// send, and requests lagging more than [`PACED_LATE`] are counted in `late`.
async fn paced<T, D, W, F>(
    schedule: OpenSchedule,
    clients: usize,
    total: u64,
    live: Arc<Live>,
    draw: D,
    work: W,
) -> Result<LoadRun, LoadError>
where
    T: Send + 'static,
    D: Fn(u64) -> T + Send + Sync + 'static,
    W: Fn(T) -> F + Send + Sync + 'static,
    F: Future<Output = (u16, Outcome)> + Send + 'static,
{
    let (released, queue) = tokio::sync::mpsc::unbounded_channel::<(u64, std::time::Instant)>();
    // Fair: free clients take their turns in the order they asked.
    let queue = Arc::new(tokio::sync::Mutex::new(queue));
    let draw = Arc::new(draw);
    let work = Arc::new(work);
    let mut tasks = tokio::task::JoinSet::new();
    for _ in 0..clients {
        let queue = Arc::clone(&queue);
        let draw = Arc::clone(&draw);
        let work = Arc::clone(&work);
        let live = Arc::clone(&live);
        tasks.spawn(async move {
            let mut done = PacedClient::default();
            loop {
                let free_since = Instant::now();
                let (index, due, job) = {
                    let mut queue = queue.lock().await;
                    let Some((index, due)) = queue.recv().await else {
                        // Everything released and taken.
                        break;
                    };
                    (index, Instant::from_std(due), draw(index))
                };
                let lag = Instant::now().saturating_duration_since(due);
                if free_since > due {
                    done.waited += 1;
                }
                if lag > PACED_LATE {
                    done.late += 1;
                }
                live.sent.fetch_add(1, Ordering::Relaxed);
                let (status, outcome) = work(job).await;
                let latency_ns = nanos(due.elapsed());
                live.record(&outcome);
                done.samples.push(Sample {
                    index,
                    latency_ns,
                    status,
                    outcome,
                    lag_ns: nanos(lag),
                });
            }
            done
        });
    }
    // Only the clients hold the queue now: should they all end, the pacer stops at its next
    // release.
    drop(queue);
    let t0 = Instant::now();
    let start = t0.into_std();
    std::thread::Builder::new()
        .name("muse-load-pacer".into())
        .spawn(move || {
            pace(schedule, start, total, |i, due| {
                released.send((i, due)).is_ok()
            })
        })
        .map_err(|e| LoadError::Config(format!("cannot start the pacing thread: {e}")))?;
    let mut run = LoadRun {
        samples: Vec::with_capacity(usize::try_from(total).unwrap_or(0).min(1 << 24)),
        wall: Duration::ZERO,
        waited_for_slot: 0,
        late: 0,
        late_threshold: PACED_LATE,
    };
    while let Some(result) = tasks.join_next().await {
        // As in closed loop: a client that panicked loses its samples, and the counts say so.
        if let Ok(mut done) = result {
            run.samples.append(&mut done.samples);
            run.waited_for_slot += done.waited;
            run.late += done.late;
        }
    }
    run.wall = t0.elapsed();
    Ok(run)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// Work that takes `delay` and plans, recording how many are in flight at most.
    fn fake(
        delay: Duration,
        most: Arc<AtomicUsize>,
    ) -> impl Fn(u64) -> std::pin::Pin<Box<dyn Future<Output = (u16, Outcome)> + Send>>
    + Send
    + Sync
    + 'static {
        let now = Arc::new(AtomicUsize::new(0));
        move |_index| {
            let now = Arc::clone(&now);
            let most = Arc::clone(&most);
            Box::pin(async move {
                let n = now.fetch_add(1, Ordering::SeqCst) + 1;
                most.fetch_max(n, Ordering::SeqCst);
                if !delay.is_zero() {
                    tokio::time::sleep(delay).await;
                }
                now.fetch_sub(1, Ordering::SeqCst);
                (201, Outcome::Planned)
            })
        }
    }

    /// When each sample was sent: due time plus lag, from the start.
    fn sent_at(schedule: OpenSchedule, s: &Sample) -> Duration {
        schedule.due(s.index) + Duration::from_nanos(s.lag_ns)
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn enough_clients_send_every_request_once_in_order_on_time() {
        let schedule = OpenSchedule::new(2_000.0).unwrap();
        let live = Arc::new(Live::default());
        let drawn = Arc::new(Mutex::new(Vec::new()));
        let record = Arc::clone(&drawn);
        let most = Arc::new(AtomicUsize::new(0));
        let run = paced(
            schedule,
            4,
            40,
            Arc::clone(&live),
            move |i| {
                record.lock().unwrap().push(i);
                i
            },
            fake(Duration::ZERO, Arc::clone(&most)),
        )
        .await
        .unwrap();
        assert_eq!(*drawn.lock().unwrap(), (0..40).collect::<Vec<u64>>());
        let mut indices: Vec<u64> = run.samples.iter().map(|s| s.index).collect();
        indices.sort_unstable();
        assert_eq!(indices, (0..40).collect::<Vec<u64>>());
        assert!(most.load(Ordering::SeqCst) <= 4);
        assert_eq!(live.sent.load(Ordering::SeqCst), 40);
        assert_eq!(live.completed.load(Ordering::SeqCst), 40);
        assert_eq!(live.planned.load(Ordering::SeqCst), 40);
        assert_eq!(run.late_threshold, PACED_LATE);
        assert!(run.late <= 40 && run.waited_for_slot <= 40);
        for s in &run.samples {
            assert!(s.latency_ns >= s.lag_ns, "{s:?}");
            assert_eq!((s.status, &s.outcome), (201, &Outcome::Planned));
        }
        // The last is due 19.5 ms after the start: the run cannot be shorter.
        assert!(run.wall >= schedule.due(39));
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn busy_clients_make_requests_wait_and_the_wait_counts() {
        // 1,000 requests/s for two clients that take 10 ms each: 200/s at most.
        let schedule = OpenSchedule::new(1_000.0).unwrap();
        let live = Arc::new(Live::default());
        let most = Arc::new(AtomicUsize::new(0));
        let run = paced(
            schedule,
            2,
            20,
            live,
            |i| i,
            fake(Duration::from_millis(10), Arc::clone(&most)),
        )
        .await
        .unwrap();
        assert_eq!(run.samples.len(), 20);
        assert_eq!(
            most.load(Ordering::SeqCst),
            2,
            "never more than one per client"
        );
        // Ten rounds of 10 ms.
        assert!(run.wall >= Duration::from_millis(100), "{:?}", run.wall);
        // From request 2 on, both clients were busy when it fell due.
        assert!(run.waited_for_slot >= 16, "{run:?}");
        assert!(run.late >= 16, "{run:?}");
        let last = run.samples.iter().find(|s| s.index == 19).unwrap();
        // Sent with the tenth round, at 90 ms or later; due at 19 ms.
        assert!(last.lag_ns >= 70_000_000, "{last:?}");
        for s in &run.samples {
            // The wait is charged: latency from the due time covers lag and service.
            assert!(s.latency_ns >= s.lag_ns + 10_000_000, "{s:?}");
        }
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn one_client_sends_one_request_at_a_time_in_order() {
        let schedule = OpenSchedule::new(1_000.0).unwrap();
        let most = Arc::new(AtomicUsize::new(0));
        let run = paced(
            schedule,
            1,
            10,
            Arc::new(Live::default()),
            |i| i,
            fake(Duration::from_millis(2), Arc::clone(&most)),
        )
        .await
        .unwrap();
        let indices: Vec<u64> = run.samples.iter().map(|s| s.index).collect();
        assert_eq!(indices, (0..10).collect::<Vec<u64>>());
        assert_eq!(most.load(Ordering::SeqCst), 1);
        for pair in run.samples.windows(2) {
            // The next is sent only once the previous (2 ms) is answered.
            assert!(
                sent_at(schedule, &pair[1])
                    >= sent_at(schedule, &pair[0]) + Duration::from_millis(2),
                "{pair:?}"
            );
        }
    }
}
