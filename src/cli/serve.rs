//! `muse serve`: the planning service (docs/reference.md#the-planning-service) on the embedded
//! Singapore default or any airspace, zones and parameters `muse plan` takes.
//!
//! Routes (see `GET /v1/openapi.json`): `POST|GET /v1/flights`, `GET|DELETE
//! /v1/flights/{id}` (plan, list, read, cancel); `GET /v1/zones` (every zone, announced ones
//! with their instants), `POST /v1/zones` and `DELETE /v1/zones/{id}` (the authority
//! announces a zone now, docs/reference.md#zones-announced-during-the-day, and the flights it hits
//! are replanned; or withdraws one); `GET /v1/events` (the caller's flights' changes as server-sent
//! events, resumable with `Last-Event-ID`); `GET /v1/airspace`, `/healthz`, `/metrics`.
//!
//! HTTP limits (see `muse_service::Limits`): `--header-timeout-s`, `--body-timeout-s`,
//! `--idle-timeout-s`, `--max-connections` (lowered to what the open-file limit allows, after
//! raising the soft limit to the hard one). With `--tokens`, SIGHUP rereads the file.

use std::io::Write as _;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context as _;
use clap::Args;
use muse_model::{Instant, Millis};
use muse_service::{Clock, Limits, Options, ServiceWorld, StoreAt, Tokens, launch};

use super::common::{FlightArgs, WorldArgs, refuse_withdrawn};
use super::layers::{LayersArgs, layered};
use super::ranges;

/// What `muse serve --help` says after the options.
const ROUTES_HELP: &str = "\
Routes (JSON; the full description at GET /v1/openapi.json):
  POST   /v1/flights           plan a request (201 planned, 200 rejected, 409 id taken)
  GET    /v1/flights           the caller's flights (all for the authority), filtered by status
                               (planned, rejected, cancelled, replanned, diverted, contingency)
  GET    /v1/flights/{id}      one flight;  DELETE: cancel it before take-off
  GET    /v1/zones             every zone (ED-318), announced ones with `announced`/`withdrawn`
  POST   /v1/zones             authority: announce an ED-318 zone now; answers with
                               every flight it replanned, diverted, cancelled or left in contingency
  DELETE /v1/zones/{id}        authority: withdraw an announced zone (replans nothing)
  GET    /v1/events            server-sent events of the caller's flights' changes; resume with
                               Last-Event-ID
  GET    /v1/airspace, /healthz, /metrics

Writes with a body need Content-Type: application/json (415 otherwise). Without --tokens,
only requests addressed to a loopback name (Host localhost, 127.0.0.1, [::1]) are answered
(403 otherwise). With --tokens, `kill -HUP <pid>` rereads the tokens file.";

/// Arguments of `muse serve`.
#[derive(Debug, Args)]
#[command(after_long_help = ROUTES_HELP)]
pub struct ServeArgs {
    #[command(flatten)]
    world: WorldArgs,
    #[command(flatten)]
    layers: LayersArgs,
    #[command(flatten)]
    flight: FlightArgs,
    /// Address to listen on (port 0: any free port, printed at start).
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:8080")]
    listen: SocketAddr,
    /// Data folder: the durable store (created if missing; one service per folder).
    #[arg(long, value_name = "DIR", default_value = "./muse-data")]
    data: PathBuf,
    /// Keep the store in this PostgreSQL database instead of a data folder:
    /// `postgres://USER@HOST:PORT/DATABASE` (its tables are made at the first start; the
    /// password, if one is needed, from the URL or PGPASSWORD).
    #[arg(long, value_name = "URL", conflicts_with_all = ["data", "import_log"], value_parser = store_url)]
    store: Option<String>,
    /// With --store: the address the other services on the same store reach this one at,
    /// `http://HOST:PORT` (default: `http://` and the address it listens on). Several services
    /// may share a store: one leads, the others stand by and send writes on to it.
    #[arg(long, value_name = "URL", requires = "store", value_parser = advertise_url)]
    advertise: Option<String>,
    /// Bearer tokens (TOML `[[tokens]]` with `token` (16 characters or more), `operator`,
    /// `role`), reread on SIGHUP. Without it the service is open to anyone on this machine:
    /// it listens on loopback addresses only and answers only requests addressed to a
    /// loopback name (Host `localhost`, `127.0.0.1`, ...).
    #[arg(long, value_name = "FILE")]
    tokens: Option<PathBuf>,
    /// Start the service clock at this instant (RFC 3339) instead of the system time; it runs
    /// at real speed from there. For demonstrations and tests.
    #[arg(long, value_name = "TIME")]
    clock: Option<String>,
    /// Bookings open this many days ahead of now, from 1 to 3650.
    #[arg(long, value_name = "DAYS", default_value_t = 30, allow_negative_numbers = true, value_parser = ranges::booking_horizon_days)]
    booking_horizon_days: u32,
    /// Plan the requests that arrive within this many milliseconds of each other as one
    /// batch, better than first come, first served (docs/reference.md#batch-planning), answered in
    /// order of arrival; from 0 to 10000; 0 plans each as it comes.
    #[arg(long, value_name = "MS", default_value_t = 0, allow_negative_numbers = true, value_parser = ranges::batch_window_ms)]
    batch_window_ms: u64,
    /// Archive the flights that landed more than this many whole days ago, from 1 to 3650:
    /// each day's flights and events move from the store's tables to two gzip-compressed CSV
    /// files in the archive folder, and their ids stay, so that a retried id is answered as
    /// first answered (docs/service.md#retention-without-forgetting). Checked at the start and
    /// every 10 minutes. Without it, every flight stays in the store's tables.
    #[arg(long, value_name = "DAYS", allow_negative_numbers = true, value_parser = ranges::archive_after_days)]
    archive_after_days: Option<u32>,
    /// The archive folder (made if missing): where archived flights are written, and read
    /// back. Default: `archive` in the data folder; with --store, give a folder every service
    /// on the store reaches.
    #[arg(long, value_name = "DIR")]
    archive_dir: Option<PathBuf>,
    /// Convert the data folder's log written by an earlier version (`muse.log`) into the
    /// store and exit, without serving (`muse serve` also converts it at start). The log is
    /// kept, renamed `muse.log.imported`.
    #[arg(long)]
    import_log: bool,
    /// Check the whole store and exit, without serving: every row's checksum (the start
    /// checks only what it loads), after SQLite's check of the database's structure in a data
    /// folder. Exit 0 if it is whole, 2 naming the first damage.
    #[arg(long, conflicts_with = "import_log")]
    check_store: bool,
    /// How many of the last flights, and of the last events, the start reads and checks whole
    /// (each row, their order, the indexes that lead to them), from 0 to 1000000000: what a
    /// crash can have damaged, in time that does not grow with the store. Older rows are
    /// checked when read, and all by `--check-store`.
    #[arg(long, value_name = "N", default_value_t = muse_service::RECENT, allow_negative_numbers = true, value_parser = ranges::check_recent)]
    check_recent: u64,
    /// Largest request body, KiB, from 1 to 1024 (larger: 413).
    #[arg(long, value_name = "KIB", default_value_t = 16, allow_negative_numbers = true, value_parser = ranges::max_body_kib)]
    max_body_kib: usize,
    /// Requests per second allowed per token, from 0 to 1000000 (0: no limit; over it: 429).
    #[arg(long, value_name = "N", default_value_t = 20_000.0, allow_negative_numbers = true, value_parser = ranges::rate_limit)]
    rate_limit: f64,
    /// Burst of requests allowed above the rate, per token, from 1 to 1000000.
    #[arg(long, value_name = "N", default_value_t = 40_000.0, allow_negative_numbers = true, value_parser = ranges::burst)]
    burst: f64,
    /// Seconds a client has, from the first byte of a request, to send all its headers
    /// (slower clients are disconnected), from 0.1 to 86400.
    #[arg(long, value_name = "S", default_value = "10", allow_negative_numbers = true, value_parser = ranges::http_timeout)]
    header_timeout_s: Duration,
    /// Seconds a client has, after the headers, to send the body of a POST (later: 408), from
    /// 0.1 to 86400.
    #[arg(long, value_name = "S", default_value = "30", allow_negative_numbers = true, value_parser = ranges::http_timeout)]
    body_timeout_s: Duration,
    /// Seconds a connection may stay open with no request in progress (an event stream is a
    /// request in progress), from 0.1 to 86400.
    #[arg(long, value_name = "S", default_value = "60", allow_negative_numbers = true, value_parser = ranges::http_timeout)]
    idle_timeout_s: Duration,
    /// Most connections open at once, from 1 to 1000000, lowered to what the open-file limit
    /// allows (the soft limit is raised to the hard one first); connections above it are
    /// answered 503.
    #[arg(long, value_name = "N", default_value = "10000", allow_negative_numbers = true, value_parser = ranges::max_connections)]
    max_connections: usize,
}

/// Runs `muse serve` until the process is stopped (Ctrl-C or SIGTERM stop it cleanly; any
/// other end, even `kill -9`, loses nothing acknowledged).
pub fn run(args: &ServeArgs) -> anyhow::Result<ExitCode> {
    let store = if let Some(url) = &args.store {
        StoreAt::Postgres(url.clone())
    } else {
        check_data(&args.data)?;
        StoreAt::Folder(args.data.clone())
    };
    let params = args.flight.params()?;
    let world = layered(args.world.load()?, &args.layers)?;
    refuse_withdrawn(&world, "serve")?;
    let clock = match &args.clock {
        None => Clock::system(),
        Some(text) => Clock::starting_at(
            Instant::parse_rfc3339(text).with_context(|| format!("--clock {text}"))?,
        ),
    };
    let tokens = match &args.tokens {
        None => Tokens::Open,
        Some(path) => Tokens::read(path)?,
    };
    let label = world_label(&world);
    let stations = world.airspace.stations().count();
    let page = super::view::live_page(&world, clock.now())?;
    let service_world = ServiceWorld::new(
        label.clone(),
        world.airspace,
        world.zones,
        params,
        world.day.offset,
        Millis::from_secs(i64::from(args.booking_horizon_days) * 86_400),
        clock.now(),
    )?;
    let options = service_options(args, store.clone(), tokens.clone(), clock, page)?;
    let http = options.http;
    if args.import_log {
        return import_log(&store, &service_world);
    }
    if args.check_store {
        return check_store(&store, &service_world);
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(args.listen)
            .await
            .with_context(|| format!("listening on {}", args.listen))?;
        let started = std::time::Instant::now();
        let launched = launch(service_world, options, listener).await?;
        let db = store.label();
        let mut out = std::io::stdout().lock();
        writeln!(out, "MUSE serve — {label}, {stations} stations")?;
        if let Some(log) = &launched.importing {
            writeln!(
                out,
                "  converting {} (written by an earlier version) into {db}; it is kept",
                log.display(),
            )?;
        }
        writeln!(
            out,
            "  starting   http://{}/healthz answers \"starting\" until the store is loaded",
            launched.addr
        )?;
        out.flush()?;
        drop(out);
        let running = launched.ready().await?;
        let r = &running.restored;
        let mut out = std::io::stdout().lock();
        report(&mut out, &db, r, started.elapsed().as_secs_f64())?;
        if running.open {
            writeln!(
                out,
                "  access     OPEN: no --tokens, so anyone on this machine may plan, read and cancel, and announce zones (loopback only; requests must name a loopback host)"
            )?;
        } else {
            writeln!(out, "  access     bearer tokens from {} (reread on SIGHUP)", args.tokens.as_ref().map_or_else(String::new, |p| p.display().to_string()))?;
        }
        role_line(&mut out, &running, args.store.is_some())?;
        writeln!(out, "  http       {}", limits_line(&http))?;
        writeln!(out, "  API        http://{}/v1/openapi.json", running.addr)?;
        let token_hint = if running.open { "" } else { "?token=YOUR_TOKEN" };
        writeln!(out, "  viewer     http://{}/{token_hint}", running.addr)?;
        let stop = shutdown_signal();
        // SIGHUP is listened for before the service says it listens: a hang-up that came
        // before the listening task first ran would otherwise end the process.
        if let Some(path) = &args.tokens {
            reload_on_hangup(tokens, path.clone());
        }
        writeln!(out, "listening on http://{}", running.addr)?;
        out.flush()?;
        drop(out);
        running.serve_until(stop).await?;
        anyhow::Ok(())
    })?;
    Ok(ExitCode::SUCCESS)
}

/// The start-up line about the service's role on a shared store (none on a data folder).
fn role_line(
    out: &mut impl std::io::Write,
    running: &muse_service::Running,
    shared: bool,
) -> std::io::Result<()> {
    if running.is_standby() {
        writeln!(
            out,
            "  role       standby: follows the leader{}, sends writes on to it, takes over when \
             it stops",
            running
                .leader()
                .map_or_else(String::new, |l| format!(" at {l}"))
        )
    } else if shared {
        writeln!(out, "  role       leader: plans and writes the store")
    } else {
        Ok(())
    }
}

/// Reads `--store`: a PostgreSQL URL.
fn store_url(text: &str) -> Result<String, String> {
    if text.starts_with("postgres://") || text.starts_with("postgresql://") {
        Ok(text.to_owned())
    } else {
        Err(
            "expected a PostgreSQL URL, postgres://USER@HOST:PORT/DATABASE (for a data folder, \
             give --data DIR)"
                .into(),
        )
    }
}

/// Reads `--advertise`: an `http://` address without a path.
fn advertise_url(text: &str) -> Result<String, String> {
    let rest = text
        .strip_prefix("http://")
        .ok_or("expected http://HOST:PORT")?;
    if rest.is_empty() || rest.contains('/') {
        return Err("expected http://HOST:PORT, without a path".into());
    }
    Ok(text.to_owned())
}

/// Refuses a `--data` that exists and is not a folder (a link to a folder is followed), before
/// anything is loaded: the store is a folder, made if missing.
fn check_data(data: &Path) -> anyhow::Result<()> {
    let shown = data.display();
    match std::fs::metadata(data) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(m) => anyhow::bail!(
            "--data {shown} is {}; give the service's data folder (made if missing)",
            super::output::kind(m.file_type())
        ),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => anyhow::bail!("--data {shown}: {e}"),
    }
}

/// The service's options from the command line: `store`, `tokens`, `clock` and the live
/// `page` made by the caller; the HTTP limits are checked.
fn service_options(
    args: &ServeArgs,
    store: StoreAt,
    tokens: Tokens,
    clock: Clock,
    page: String,
) -> anyhow::Result<Options> {
    let limits = Limits {
        header_timeout: args.header_timeout_s,
        body_timeout: args.body_timeout_s,
        idle_timeout: args.idle_timeout_s,
        max_connections: args.max_connections,
    };
    limits.check().map_err(anyhow::Error::msg)?;
    let mut options = Options::new(store);
    options.tokens = tokens;
    options.http = limits;
    options.clock = clock;
    options.max_body = args.max_body_kib * 1024;
    options.rate_limit = args.rate_limit;
    options.burst = args.burst;
    options.page = Some(page);
    options.batch_window = std::time::Duration::from_millis(args.batch_window_ms);
    options.check_recent = args.check_recent;
    options.advertise.clone_from(&args.advertise);
    options.archive_dir.clone_from(&args.archive_dir);
    options.archive_after_days = args.archive_after_days;
    Ok(options)
}

/// `muse serve --import-log`: converts the folder's log of an earlier version, then exits.
fn import_log(store: &StoreAt, world: &ServiceWorld) -> anyhow::Result<ExitCode> {
    let description = world.description();
    let opening = muse_service::Opening::open(store, &description, &world.legacy_fingerprint())?;
    let Some(log) = opening.imports().map(std::path::Path::to_path_buf) else {
        let StoreAt::Folder(data) = store else {
            anyhow::bail!("--import-log converts a data folder's log; --store has none");
        };
        anyhow::bail!(
            "{} holds no log of an earlier version to convert ({} is missing, or was converted \
             already)",
            data.display(),
            data.join(muse_service::LOG_FILE).display()
        );
    };
    println!("converting {} ...", log.display());
    let started = std::time::Instant::now();
    let import = opening.import_only(&world.airspace, &description, &mut |_| {})?;
    let restored = muse_service::Restored {
        flights: import.as_ref().map_or(0, |i| i.flights),
        import,
        ..Default::default()
    };
    report(
        &mut std::io::stdout().lock(),
        &store.label(),
        &restored,
        started.elapsed().as_secs_f64(),
    )?;
    Ok(ExitCode::SUCCESS)
}

/// `muse serve --check-store`: reads and checks every row of the store, then exits.
fn check_store(store: &StoreAt, world: &ServiceWorld) -> anyhow::Result<ExitCode> {
    let description = world.description();
    let opening = muse_service::Opening::open(store, &description, &world.legacy_fingerprint())?;
    if opening.imports().is_some() {
        anyhow::bail!(
            "{} holds a log of an earlier version, not yet converted: convert it first with \
             `muse serve --import-log`",
            opening.label()
        );
    }
    let started = std::time::Instant::now();
    let checked = opening.check_all(&world.airspace, &description, &mut |_| {})?;
    println!(
        "{}: whole — {} flights, {} events and {} zones checked in {:.2} s",
        store.label(),
        checked.flights,
        checked.events,
        checked.zones,
        started.elapsed().as_secs_f64()
    );
    Ok(ExitCode::SUCCESS)
}

/// What the start found in the store (and, once, converted from an earlier version's log).
fn report(
    out: &mut impl std::io::Write,
    db: &str,
    r: &muse_service::Restored,
    secs: f64,
) -> std::io::Result<()> {
    if let Some(i) = &r.import {
        writeln!(
            out,
            "  converted  {} records: {} flights, {} cancellations, {} zones ({} withdrawn), \
             {} events{}; the log is kept as {}",
            i.records,
            i.flights,
            i.cancellations,
            i.zones,
            i.withdrawn,
            i.events,
            if i.torn_bytes > 0 {
                format!(
                    ", a torn tail of {} bytes left out (never acknowledged)",
                    i.torn_bytes
                )
            } else {
                String::new()
            },
            i.log.display()
        )?;
        for (id, kept_as) in &i.renamed {
            writeln!(
                out,
                "  renamed    flight `{id}` was stored twice by the earlier version: the \
                 second is kept as `{kept_as}`"
            )?;
        }
    }
    writeln!(
        out,
        "  store      {}: {} flight(s) stored, {} still ahead or airborne put back into the \
         schedule, {} zone(s) announced ({} withdrawn), {} event(s); the last {} flight(s) \
         and {} event(s) checked whole; loaded in {:.2} s",
        db,
        r.flights,
        r.held,
        r.zones,
        r.withdrawn,
        r.events,
        r.checked.flights,
        r.checked.events,
        secs
    )?;
    Ok(())
}

/// The service's name for its world: the airspace and its zones.
fn world_label(world: &super::common::World) -> String {
    if world.zones.is_empty() {
        return world.airspace_source.clone();
    }
    let zones: Vec<&str> = world.zones.iter().map(|z| z.id.as_str()).collect();
    format!("{} ({})", world.airspace_source, zones.join(", "))
}

/// The start-up line about the HTTP limits, with the connection cap in force.
fn limits_line(limits: &Limits) -> String {
    let cap = muse_service::connection_cap(limits.max_connections);
    let files = muse_service::open_file_limit().map_or_else(
        || "no open-file limit".to_owned(),
        |f| format!("open-file limit {f}"),
    );
    let lowered = if cap < limits.max_connections {
        format!(
            ", lowered from --max-connections {}",
            limits.max_connections
        )
    } else {
        String::new()
    };
    format!(
        "at most {cap} connections ({files}{lowered}); timeouts: headers {} s, bodies {} s, \
         idle {} s",
        limits.header_timeout.as_secs_f64(),
        limits.body_timeout.as_secs_f64(),
        limits.idle_timeout.as_secs_f64()
    )
}

/// Rereads the tokens file on each SIGHUP: one line on stdout when the new tokens are in
/// force, the error on stderr (naming the file) when the file is refused and the tokens in
/// force are kept.
/// The signal is registered when this is called (inside the runtime), the rereading runs as
/// a task.
#[cfg(unix)]
fn reload_on_hangup(tokens: Tokens, path: PathBuf) {
    use tokio::signal::unix::{SignalKind, signal};
    let mut hangups = match signal(SignalKind::hangup()) {
        Ok(s) => s,
        Err(e) => {
            eprintln!(
                "muse serve: cannot listen for SIGHUP ({e}); the tokens will not be reloaded"
            );
            return;
        }
    };
    tokio::spawn(async move {
        while hangups.recv().await.is_some() {
            reload(&tokens, &path);
        }
    });
}

#[cfg(not(unix))]
fn reload_on_hangup(_tokens: Tokens, _path: PathBuf) {}

fn reload(tokens: &Tokens, path: &Path) {
    match tokens.reload(path) {
        Ok(n) => {
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out, "tokens reloaded from {}: {n} token(s)", path.display());
            let _ = out.flush();
        }
        Err(e) => eprintln!(
            "muse serve: tokens not reloaded, keeping the {} token(s) in force: {e}",
            tokens.len()
        ),
    }
}

/// A future that completes on Ctrl-C or SIGTERM. The handlers are installed when this is
/// called, not when the future is first polled: called before `listening on` is printed, a
/// signal sent as soon as that line is read stops the service cleanly rather than killing it.
fn shutdown_signal() -> impl std::future::Future<Output = ()> {
    #[cfg(unix)]
    let (interrupt, terminate) = {
        use tokio::signal::unix::{SignalKind, signal};
        (
            signal(SignalKind::interrupt()).ok(),
            signal(SignalKind::terminate()).ok(),
        )
    };
    async move {
        #[cfg(unix)]
        {
            let wait = |s: Option<tokio::signal::unix::Signal>| async move {
                match s {
                    Some(mut s) => {
                        s.recv().await;
                    }
                    None => std::future::pending::<()>().await,
                }
            };
            tokio::select! {
                () = wait(interrupt) => {},
                () = wait(terminate) => {},
            }
        }
        #[cfg(not(unix))]
        {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}
