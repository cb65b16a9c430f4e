//! The MUSE planning service (SPEC §10): one live schedule behind a JSON API, planned against
//! first come first served, every acknowledged change durable before it is answered.
//!
//! - [`store`]: the append-only log of checksummed records (group commit, torn-tail
//!   recovery, one process per data folder);
//! - [`engine`]: the planner task, the only writer of the schedule, fed by a channel;
//! - [`flights`]: flights as the service knows them and the index reads are served from;
//! - [`zones`]: zones announced during the day (SPEC §11): reading them, knowing them;
//! - [`events`]: the flights' change events, kept and streamed (`GET /v1/events`);
//! - [`api`]: the HTTP routes (axum), input checks and answers;
//! - [`http`]: the HTTP server itself: timeouts, connection cap, graceful stop;
//! - [`auth`]: bearer tokens, operators and the authority, the rate limit;
//! - [`metrics`]: the Prometheus exposition;
//! - [`state`]: what is planned on (airspace, zones, parameters, clock).
//!
//! The planning itself is `muse_planner::Live`, the same planner and schedule as a batch day.
//!
//! ```no_run
//! # async fn demo(world: muse_service::state::ServiceWorld) -> Result<(), muse_service::ServeError> {
//! use muse_service::{Options, start};
//! let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
//! let running = start(world, Options::new("./muse-data".into()), listener).await?;
//! println!("listening on http://{}", running.addr);
//! running.serve().await?;
//! # Ok(()) }
//! ```

pub mod api;
pub mod auth;
pub mod engine;
pub mod events;
pub mod flights;
pub mod http;
pub mod metrics;
pub mod state;
pub mod store;
pub mod zones;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, RwLock};

use muse_model::Millis;

use crate::api::{App, router};
use crate::auth::{RateLimiter, Tokens};
use crate::engine::Restored;
use crate::flights::FlightIndex;
use crate::state::{Clock, ServiceWorld, State};
use crate::store::{Recovery, Store, StoreError};

/// How a service runs, besides what it plans on.
#[derive(Debug)]
pub struct Options {
    /// The data folder (the store).
    pub data: PathBuf,
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
    /// How long after its end (landing, or departure for a rejection) a flight is kept in
    /// memory for reads, listings and idempotent retries; the store keeps it for ever. Events
    /// are kept as long after they happened.
    pub retain: Millis,
    /// Events an event-stream listener may fall behind the live ones by before it reads the
    /// history instead ([`events::LIVE_CAPACITY`] by default).
    pub event_buffer: usize,
    /// The page served at `GET /` (the live viewer, built by the caller), if any.
    pub page: Option<String>,
    /// The HTTP server's timeouts and connection cap (see [`http`]).
    pub http: http::Limits,
}

impl Options {
    /// Defaults: open, system clock, 16 KiB bodies, 20,000 requests per second per token with
    /// bursts of 40,000, flights kept in memory for a day after they end; HTTP timeouts of
    /// 10 s for headers, 30 s for bodies and 60 s idle, at most 10,000 connections.
    pub fn new(data: PathBuf) -> Self {
        Options {
            data,
            tokens: Tokens::Open,
            clock: Clock::system(),
            max_body: 16 * 1024,
            rate_limit: 20_000.0,
            burst: 40_000.0,
            retain: Millis::from_secs(86_400),
            event_buffer: events::LIVE_CAPACITY,
            page: None,
            http: http::Limits::default(),
        }
    }
}

/// Why a service could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The store could not be opened.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// Open mode on a non-loopback address.
    #[error(
        "refusing to listen on {0} without --tokens: an open service (anyone may plan, read \
         and cancel) listens on loopback addresses only"
    )]
    OpenNotLoopback(SocketAddr),
    /// Restoring the schedule from the store failed.
    #[error("{0}")]
    Recovery(String),
    /// A network error.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// The error.
        source: std::io::Error,
    },
}

/// A started service: the store is open, the schedule rebuilt, the listener bound.
#[derive(Debug)]
pub struct Running {
    /// The address it listens on.
    pub addr: SocketAddr,
    /// What the store's recovery found.
    pub recovery: Recovery,
    /// What was restored into the schedule.
    pub restored: Restored,
    /// Whether the service is open (no tokens).
    pub open: bool,
    listener: tokio::net::TcpListener,
    app: Arc<App>,
    http: http::Limits,
}

/// Opens the store, rebuilds the schedule from it and prepares to serve on `listener`.
pub async fn start(
    world: ServiceWorld,
    options: Options,
    listener: tokio::net::TcpListener,
) -> Result<Running, ServeError> {
    let addr = listener.local_addr().map_err(|source| ServeError::Io {
        what: "reading the listening address",
        source,
    })?;
    if options.tokens.is_open() && !addr.ip().is_loopback() {
        return Err(ServeError::OpenNotLoopback(addr));
    }
    let fingerprint = world.fingerprint();
    let data = options.data.clone();
    let (store, records, recovery) =
        tokio::task::spawn_blocking(move || Store::open(&data, &fingerprint))
            .await
            .map_err(|e| ServeError::Recovery(format!("opening the store: {e}")))??;
    let airspace_geojson = muse_formats::airspace_geojson::write_airspace(&world.airspace);
    let state = Arc::new(State {
        index: RwLock::new(FlightIndex::default()),
        metrics: metrics::Metrics::default(),
        clock: options.clock,
        retain: options.retain,
        zones: RwLock::new(zones::ZoneBook::new(&world.zones)),
        events: events::Events::new(options.event_buffer),
        world,
    });
    let engine_state = Arc::clone(&state);
    let (commands, restored) =
        tokio::task::spawn_blocking(move || engine::start(engine_state, store, records))
            .await
            .map_err(|e| ServeError::Recovery(format!("restoring: {e}")))?
            .map_err(ServeError::Recovery)?;
    let open = options.tokens.is_open();
    let app = Arc::new(App {
        state,
        tokens: options.tokens,
        limiter: RateLimiter::new(options.rate_limit, options.burst),
        commands,
        airspace_geojson,
        page: options.page,
        max_body: options.max_body,
        stopping: tokio::sync::watch::channel(false).0,
    });
    Ok(Running {
        addr,
        recovery,
        restored,
        open,
        listener,
        app,
        http: options.http,
    })
}

impl Running {
    /// Serves until the process is stopped (or `shutdown` completes: then event streams
    /// end, and the answers under way are finished), with the HTTP limits of
    /// [`Options::http`] (see [`http`]).
    pub async fn serve_until(
        self,
        shutdown: impl std::future::Future<Output = ()> + Send + 'static,
    ) -> Result<(), ServeError> {
        self.http.check().map_err(|message| ServeError::Io {
            what: "checking the HTTP limits",
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, message),
        })?;
        let app = Arc::clone(&self.app);
        let stop = async move {
            shutdown.await;
            app.stopping.send_replace(true);
        };
        http::serve(self.listener, router(self.app), self.http, stop).await;
        Ok(())
    }

    /// Serves until the process is stopped.
    pub async fn serve(self) -> Result<(), ServeError> {
        self.serve_until(std::future::pending()).await
    }
}
