//! The MUSE planning service (docs/reference.md#the-planning-service): one live schedule behind a
//! JSON API, planned against first come first served, every acknowledged change durable before it
//! is answered.
//!
//! The public surface is small: [`launch`] (or [`start`]) a service on a [`ServiceWorld`] with
//! [`Options`], then [`Running::serve`]; the pieces `muse serve` and the tests configure it
//! with ([`Tokens`], [`Clock`], [`Limits`]); and, for `muse serve --import-log` and
//! `--check-store`, the store opened without serving ([`Opening`]).
//! Everything else is private, in one module per concept:
//!
//! - `store`: the durable store, one interface and two implementations, SQLite in a data
//!   folder (the default) and PostgreSQL (one transaction per group of decisions, checksummed
//!   rows, reads by index; in a folder, one process per folder and the conversion of an
//!   earlier version's log);
//! - `engine`: the planner task, the only writer of the schedule and the store, fed by a
//!   channel: each command decided, stored, then applied by one function;
//! - `flights`: flights as the service knows them, and the index of those the schedule holds;
//! - `zones`: zones announced during the day (docs/reference.md#zones-announced-during-the-day), in
//!   one folder: the zones known, reading an announcement, deciding what an announcement or a
//!   withdrawal does (the engine stores and applies the decision; the HTTP routes are in `api`,
//!   with every other route);
//! - `events`: the flights' change events, kept and streamed (`GET /v1/events`);
//! - `api`: the HTTP routes (axum), input checks and answers;
//! - `http`: the HTTP server itself: timeouts, connection cap, graceful stop;
//! - `auth`: bearer tokens, operators and the authority, the rate limit;
//! - `metrics`: the Prometheus exposition;
//! - `role`: leader or standby, for several services on one PostgreSQL store (the engine's
//!   `standby` follows the leader; the API's `forward` sends a standby's writes to it);
//! - `state`: what is planned on (airspace, zones, parameters, clock).
//!
//! The planning itself is `muse_planner::Live`, the same planner and schedule as a batch day.
//!
//! ```no_run
//! # async fn demo(world: muse_service::ServiceWorld) -> Result<(), muse_service::ServeError> {
//! use muse_service::{Options, launch};
//! let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
//! // Serves at once (`/healthz` says `starting`), loads the store, then answers everything.
//! let running = launch(world, Options::new(std::path::PathBuf::from("./muse-data")), listener).await?.ready().await?;
//! println!("listening on http://{}", running.addr);
//! running.serve().await?;
//! # Ok(()) }
//! ```
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod api;
mod auth;
mod engine;
mod events;
mod flights;
mod http;
mod metrics;
mod role;
mod state;
mod store;
mod zones;

pub use api::{OPENAPI, ROUTES};
pub use auth::{KnownTokens, Tokens, TokensError};
pub use engine::Restored;
pub use http::{Limits, connection_cap, open_file_limit};
pub use state::{Clock, ServiceWorld};
pub use store::{
    Checked, DB_FILE, ImportReport, LOG_FILE, Opening, RECENT, Recent, StoreAt, StoreError,
};

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, RwLock};
use std::time::Duration;

use tokio::sync::{mpsc, oneshot, watch};

use crate::api::{App, router};
use crate::auth::RateLimiter;
use crate::engine::Ended;
use crate::flights::FlightIndex;
use crate::state::{Phase, State};

/// How a service runs, besides what it plans on.
#[derive(Debug)]
pub struct Options {
    /// Where the store is: a data folder (SQLite, the default) or a PostgreSQL database.
    pub store: StoreAt,
    /// Who may call ([`Tokens::Open`]: anyone, loopback only).
    pub tokens: Tokens,
    /// The clock.
    pub clock: Clock,
    /// Largest request body, bytes.
    pub max_body: usize,
    /// Requests per second per token (0: no limit).
    pub rate_limit: f64,
    /// Burst allowed above the rate.
    pub burst: f64,
    /// Events an event-stream listener may fall behind the live ones by before it reads the
    /// store instead ([`Options::new`] sets the default).
    pub event_buffer: usize,
    /// The page served at `GET /` (the live viewer, built by the caller), if any.
    pub page: Option<String>,
    /// The HTTP server's timeouts and connection cap (see [`Limits`]).
    pub http: Limits,
    /// How long the planner waits, after a request arrives, for others to plan with it as one
    /// batch (docs/reference.md#batch-planning); zero plans each request first come, first served.
    pub batch_window: std::time::Duration,
    /// How many of the last flights, and of the last events, the start reads and checks whole
    /// (rows, their order and the indexes that lead to them): the writes a crash can have
    /// damaged, in time that does not grow with the days served. 0: only what it loads.
    pub check_recent: u64,
    /// The address other services on the same store reach this one at when it leads
    /// (`http://HOST:PORT`; `None`: `http://` and the address it listens on).
    pub advertise: Option<String>,
    /// The archive folder, where archived flights are written and read (`None`: `archive` in
    /// the data folder; none for a PostgreSQL store).
    pub archive_dir: Option<PathBuf>,
    /// Archive the flights that landed more than this many whole days ago (`None`: keep every
    /// flight in the hot tables).
    pub archive_after_days: Option<u32>,
}

impl Options {
    /// The archive folder in force: [`Options::archive_dir`], else `archive` in the data folder.
    pub fn archive_folder(&self) -> Option<PathBuf> {
        self.archive_dir.clone().or_else(|| match &self.store {
            StoreAt::Folder(dir) => Some(dir.join("archive")),
            StoreAt::Postgres(_) => None,
        })
    }
}

impl Options {
    /// The store at `store` (a data folder, or [`StoreAt::Postgres`]), and defaults: open,
    /// system clock, 16 KiB bodies, 20,000 requests per second per token with
    /// bursts of 40,000; HTTP timeouts of 10 s for headers, 30 s for bodies and 60 s idle,
    /// at most 10,000 connections; no batch window; the last [`RECENT`] flights and events checked
    /// at start.
    pub fn new(store: impl Into<StoreAt>) -> Self {
        Options {
            store: store.into(),
            tokens: Tokens::Open,
            clock: Clock::system(),
            max_body: 16 * 1024,
            rate_limit: 20_000.0,
            burst: 40_000.0,
            event_buffer: events::LIVE_CAPACITY,
            page: None,
            http: Limits::default(),
            batch_window: std::time::Duration::ZERO,
            check_recent: store::RECENT,
            advertise: None,
            archive_dir: None,
            archive_after_days: None,
        }
    }
}

/// Why a service could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The store could not be opened or loaded, or failed while serving.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// Open mode on a non-loopback address.
    #[error(
        "refusing to listen on {0} without --tokens: an open service (anyone may plan, read \
         and cancel) listens on loopback addresses only"
    )]
    OpenNotLoopback(SocketAddr),
    /// The planner task stopped unexpectedly.
    #[error("{0}")]
    Stopped(String),
    /// A network error. (The error is part of the message, not a `source`: a chain would
    /// print it twice.)
    #[error("{what}: {error}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// The error.
        error: std::io::Error,
    },
}

/// The HTTP server and the planner task of a launched service.
#[derive(Debug)]
struct Serving {
    app: Arc<App>,
    server: tokio::task::JoinHandle<std::io::Result<()>>,
    ended: oneshot::Receiver<Ended>,
}

impl Serving {
    /// Stops the server (answers under way finish, event streams end) and waits for it.
    async fn stop(self) -> (Result<(), ServeError>, oneshot::Receiver<Ended>) {
        let Serving { app, server, ended } = self;
        app.stopping.send_replace(true);
        drop(app);
        let served = match server.await {
            Ok(Ok(())) => Ok(()),
            Ok(Err(error)) => Err(ServeError::Io {
                what: "serving",
                error,
            }),
            Err(e) => Err(ServeError::Stopped(format!("the server task failed: {e}"))),
        };
        (served, ended)
    }
}

/// A service that serves already (`/healthz` answers `starting`, every other route `503`)
/// while its planner task loads the store; [`Launched::ready`] waits for that.
#[derive(Debug)]
pub struct Launched {
    /// The address it listens on.
    pub addr: SocketAddr,
    /// Whether the service is open (no tokens).
    pub open: bool,
    /// An earlier version's log being converted, if there is one.
    pub importing: Option<PathBuf>,
    ready: oneshot::Receiver<Result<Restored, StoreError>>,
    serving: Serving,
}

/// A started service: the store is loaded and every route answers.
#[derive(Debug)]
pub struct Running {
    /// The address it listens on.
    pub addr: SocketAddr,
    /// What the store held.
    pub restored: Restored,
    /// Whether the service is open (no tokens).
    pub open: bool,
    serving: Serving,
}

/// Opens the store (checking it was written for `world`), starts serving on `listener` and
/// starts the planner task, which loads the store in the background. Fails at once if the
/// folder is locked by another service, or its store is of another world or damaged at its
/// start.
pub async fn launch(
    world: ServiceWorld,
    options: Options,
    listener: tokio::net::TcpListener,
) -> Result<Launched, ServeError> {
    let addr = listener.local_addr().map_err(|error| ServeError::Io {
        what: "reading the listening address",
        error,
    })?;
    if options.tokens.is_open() && !addr.ip().is_loopback() {
        return Err(ServeError::OpenNotLoopback(addr));
    }
    options.http.check().map_err(|message| ServeError::Io {
        what: "checking the HTTP limits",
        error: std::io::Error::new(std::io::ErrorKind::InvalidInput, message),
    })?;
    let description = world.description();
    let legacy = world.legacy_fingerprint();
    let world_offset = world.offset;
    let at = options.store.clone();
    let recent = options.check_recent;
    let opening = tokio::task::spawn_blocking(move || {
        Opening::open(&at, &description, &legacy).map(|o| o.checking_recent(recent))
    })
    .await
    .map_err(|e| ServeError::Stopped(format!("opening the store: {e}")))??;
    let importing = opening.imports().map(std::path::Path::to_path_buf);
    let airspace_geojson = muse_formats::airspace_geojson::write_airspace(&world.airspace);
    let state = Arc::new(State {
        index: RwLock::new(FlightIndex::default()),
        reader: opening.reads(options.archive_folder()),
        phase: Phase::default(),
        metrics: metrics::Metrics::default(),
        clock: options.clock,
        zones: RwLock::new(zones::book::ZoneBook::new(&world.zones)),
        events: events::Events::new(options.event_buffer),
        role: role::Role::default(),
        address: options
            .advertise
            .clone()
            .unwrap_or_else(|| format!("http://{addr}")),
        world,
    });
    let (commands, rx) = mpsc::channel(engine::QUEUE);
    let (ready_tx, ready) = oneshot::channel();
    let (ended_tx, ended) = oneshot::channel();
    let batching = engine::Batching::new(options.batch_window);
    let retention = retention(&options, world_offset)?;
    engine::spawn(
        Arc::clone(&state),
        opening,
        rx,
        engine::Setup {
            batching,
            retention,
        },
        ready_tx,
        ended_tx,
    )
    .map_err(|error| ServeError::Io {
        what: "starting the planner thread",
        error,
    })?;
    let open = options.tokens.is_open();
    let app = Arc::new(App {
        state,
        tokens: options.tokens,
        limiter: RateLimiter::new(options.rate_limit, options.burst),
        commands,
        airspace_geojson,
        page: options.page,
        max_body: options.max_body,
        stopping: watch::channel(false).0,
        forwarder: api::forwarder(),
    });
    let mut stopping = app.stopping.subscribe();
    let limits = options.http;
    let server = tokio::spawn({
        let router = router(Arc::clone(&app));
        async move {
            http::serve(listener, router, limits, async move {
                let _ = stopping.wait_for(|s| *s).await;
            })
            .await;
            Ok(())
        }
    });
    Ok(Launched {
        addr,
        open,
        importing,
        ready,
        serving: Serving { app, server, ended },
    })
}

/// Whether, and how, the service archives (see [`Options::archive_after_days`]).
fn retention(
    options: &Options,
    offset: muse_model::UtcOffset,
) -> Result<Option<store::archive::Retention>, ServeError> {
    match (options.archive_after_days, options.archive_folder()) {
        (Some(after_days), Some(dir)) => Ok(Some(store::archive::Retention {
            dir,
            after_days,
            offset,
        })),
        (Some(_), None) => Err(ServeError::Io {
            what: "archiving",
            error: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "--archive-after-days on a PostgreSQL store needs --archive-dir (a folder every \
                 service on the store reaches)",
            ),
        }),
        (None, _) => Ok(None),
    }
}

/// [`launch`], then [`Launched::ready`]: the service once every route answers.
pub async fn start(
    world: ServiceWorld,
    options: Options,
    listener: tokio::net::TcpListener,
) -> Result<Running, ServeError> {
    launch(world, options, listener).await?.ready().await
}

impl Launched {
    /// Waits until the store is loaded. If it cannot be (damaged, unreadable), the server is
    /// stopped and the error names why.
    pub async fn ready(self) -> Result<Running, ServeError> {
        let Launched {
            addr,
            open,
            ready,
            serving,
            ..
        } = self;
        match ready.await {
            Ok(Ok(restored)) => Ok(Running {
                addr,
                restored,
                open,
                serving,
            }),
            Ok(Err(e)) => {
                let _ = serving.stop().await;
                Err(ServeError::Store(e))
            }
            Err(_) => {
                let _ = serving.stop().await;
                Err(ServeError::Stopped(
                    "the planner task stopped while loading the store".into(),
                ))
            }
        }
    }
}

impl Running {
    /// Whether this service stands by: on a shared store that another service leads, it
    /// follows that leader and sends writes on to it (see [`Running::leader`]).
    pub fn is_standby(&self) -> bool {
        self.serving.app.state.role.is_standby()
    }

    /// The leader's address, for a standby (when one leads).
    pub fn leader(&self) -> Option<String> {
        self.serving.app.state.role.leader()
    }

    /// Serves until `shutdown` completes (then event streams end, the answers under way are
    /// finished, and the store is closed) or the store fails (then the service stops and the
    /// error says why: a restart recovers exactly what is durable).
    pub async fn serve_until(
        self,
        shutdown: impl std::future::Future<Output = ()> + Send + 'static,
    ) -> Result<(), ServeError> {
        let Running { mut serving, .. } = self;
        let failed = tokio::select! {
            () = shutdown => None,
            ended = &mut serving.ended => Some(ended),
        };
        let (served, ended) = serving.stop().await;
        let ended = match failed {
            Some(ended) => ended,
            // A clean stop: the planner task ends once the server let go of its queue.
            None => tokio::time::timeout(Duration::from_secs(10), ended)
                .await
                .unwrap_or(Ok(Ok(()))),
        };
        match ended {
            Ok(Ok(())) => served,
            Ok(Err(e)) => Err(ServeError::Store(e)),
            Err(_) => Err(ServeError::Stopped(
                "the planner task stopped unexpectedly".into(),
            )),
        }
    }

    /// Serves until the process is stopped or the store fails.
    pub async fn serve(self) -> Result<(), ServeError> {
        self.serve_until(std::future::pending()).await
    }
}
