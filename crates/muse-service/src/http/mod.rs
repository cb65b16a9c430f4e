//! The HTTP/1.1 server the API is served by: hyper's connection handling around the axum
//! router, with the limits a service exposed to misbehaving clients needs.
//!
//! - **Header timeout** ([`Limits::header_timeout`], 10 s by default): once the first byte of
//!   a request has arrived, its request line and headers must be complete within it, or the
//!   connection is closed (a slowloris client dribbling a byte now and then is cut).
//! - **Body timeout** ([`Limits::body_timeout`], 30 s): a body the API reads
//!   (`POST /v1/flights`, `POST /v1/zones`) must have arrived within it of the headers; if not
//!   the answer is `408` and the connection is closed. A route that reads no body answers at
//!   once and closes the connection if a declared body has not arrived by then.
//! - **Idle timeout** ([`Limits::idle_timeout`], 60 s): a connection with no request in
//!   progress (a new one that has sent nothing, or a kept-alive one between requests, counted
//!   from the last byte of the last answer written) is closed once idle that long. A request
//!   in progress is never cut by it, however long its answer takes or streams (the
//!   server-sent events of `GET /v1/events`), unless the client stops reading: an answer
//!   whose writes have made no progress for the idle timeout is cut.
//! - **Connection cap** ([`Limits::max_connections`], 10,000, lowered to what the open-file
//!   limit allows: see [`connection_cap`]): a connection above it is answered at once with a
//!   minimal `503` (`Retry-After: 1`, `Connection: close`) and closed, so a flood of idle
//!   sockets never leaves the service answering no one.
//!
//! A graceful stop (the future given to [`crate::Running::serve_until`]) stops accepting,
//! closes the connections with no request being answered (idle ones, and those still sending
//! headers), lets the answers under way finish (event streams end then) and returns once
//! every connection is closed.

use std::convert::Infallible;
use std::future::Future;
use std::io;
use std::pin::Pin;
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll};
use std::time::Duration;

use axum::Router;
use axum::body::{Body, Bytes};
use axum::http::{Request, Response};
use http_body::{Frame, SizeHint};
use hyper::body::Incoming;
use hyper_util::rt::TokioIo;
use tokio::io::{AsyncRead, AsyncReadExt as _, AsyncWrite, AsyncWriteExt as _, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{Notify, OwnedSemaphorePermit, Semaphore, watch};
use tokio::time::Instant;
use tower_service::Service as _;

mod limits;

pub use limits::{Limits, connection_cap, open_file_limit};

/// Connections above the cap being answered `503` at once: each is given up to
/// [`REFUSAL_LINGER`] to read its answer; beyond this many the socket is closed right after
/// the answer is written (part of [`limits::FILE_RESERVE`]).
const REFUSING: usize = 32;
/// How long a closed connection's unread input is drained so that the client reads the
/// answer rather than a reset.
const LINGER: Duration = Duration::from_secs(1);
/// The same for a connection refused above the cap (shorter: there may be many).
const REFUSAL_LINGER: Duration = Duration::from_millis(250);
/// At most this much unread input is drained before closing.
const LINGER_BYTES: usize = 256 * 1024;
/// How long to wait after an `accept` error (such as running out of open files).
const ACCEPT_BACKOFF: Duration = Duration::from_millis(250);

/// When the body of the request being handled must have arrived (a request extension the
/// server adds; the API's body reader answers `408` past it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyDeadline {
    /// The instant.
    pub(crate) at: Instant,
    /// The body timeout it was set from.
    pub(crate) after: Duration,
}

/// Serves `router` on `listener` with `limits` until `shutdown` completes, then stops
/// gracefully (see the module docs).
pub(crate) async fn serve(
    listener: TcpListener,
    router: Router,
    limits: Limits,
    shutdown: impl Future<Output = ()> + Send,
) {
    let cap = connection_cap(limits.max_connections);
    let permits = Arc::new(Semaphore::new(cap));
    let refusing = Arc::new(Semaphore::new(REFUSING));
    let busy: Arc<[u8]> = busy_answer().into();
    let (stop_tx, stop_rx) = watch::channel(false);
    let mut shutdown = std::pin::pin!(shutdown);
    loop {
        let accepted = tokio::select! {
            () = &mut shutdown => break,
            accepted = listener.accept() => accepted,
        };
        let stream = match accepted {
            Ok((stream, _)) => stream,
            Err(e) if is_connection_error(&e) => continue,
            Err(e) => {
                // Most likely out of open files: the connection waits in the backlog.
                eprintln!(
                    "muse serve: accepting a connection: {e}; retrying in {} ms",
                    ACCEPT_BACKOFF.as_millis()
                );
                tokio::select! {
                    () = &mut shutdown => break,
                    () = tokio::time::sleep(ACCEPT_BACKOFF) => continue,
                }
            }
        };
        match Arc::clone(&permits).try_acquire_owned() {
            Ok(permit) => {
                tokio::spawn(connection(
                    stream,
                    router.clone(),
                    limits,
                    stop_rx.clone(),
                    permit,
                ));
            }
            Err(_) => refuse(stream, &refusing, &busy),
        }
    }
    drop(listener);
    stop_tx.send_replace(true);
    drop(stop_rx);
    // Every connection holds a receiver: this completes when the last one has closed.
    stop_tx.closed().await;
}

/// The answer to a connection above the cap: the project's error JSON, `503`.
fn busy_answer() -> Vec<u8> {
    let body = serde_json::json!({"error": {
        "status": 503,
        "code": "too_many_connections",
        "message": "the service has as many connections open as it allows; retry in a second",
        "field": null,
    }})
    .to_string();
    format!(
        "HTTP/1.1 503 Service Unavailable\r\nretry-after: 1\r\nconnection: close\r\n\
         content-type: application/json\r\ncontent-length: {}\r\n\r\n{body}",
        body.len()
    )
    .into_bytes()
}

/// Answers a connection above the cap with `503` and closes it, without waiting on the client.
fn refuse(stream: TcpStream, refusing: &Arc<Semaphore>, busy: &Arc<[u8]>) {
    // A fresh socket's send buffer is empty: the short answer fits without blocking.
    let _ = stream.try_write(busy);
    if let Ok(permit) = Arc::clone(refusing).try_acquire_owned() {
        tokio::spawn(async move {
            linger(stream, REFUSAL_LINGER).await;
            drop(permit);
        });
    }
    // Else the socket is dropped (closed) here: the client may see a reset.
}

/// Closes a connection politely: ends the sending side, then reads and drops what the client
/// still sends, for at most `wait` and [`LINGER_BYTES`], so that input left unread does not
/// turn the close into a reset that would destroy the answer before the client reads it.
async fn linger(mut stream: TcpStream, wait: Duration) {
    if stream.shutdown().await.is_err() {
        return;
    }
    let drain = async {
        let mut buf = [0u8; 8 * 1024];
        let mut total = 0;
        while total < LINGER_BYTES {
            match stream.read(&mut buf).await {
                Ok(0) | Err(_) => break,
                Ok(n) => total += n,
            }
        }
    };
    let _ = tokio::time::timeout(wait, drain).await;
}

fn is_connection_error(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::ConnectionRefused
            | io::ErrorKind::ConnectionAborted
            | io::ErrorKind::ConnectionReset
    )
}

/// Serves one connection, closing it when a timeout of `limits` expires.
async fn connection(
    stream: TcpStream,
    router: Router,
    limits: Limits,
    mut stop: watch::Receiver<bool>,
    permit: OwnedSemaphorePermit,
) {
    let _ = stream.set_nodelay(true);
    let track = Arc::new(Track::new());
    let io = TokioIo::new(Watched {
        inner: stream,
        track: Arc::clone(&track),
    });
    let service = ConnService {
        router,
        track: Arc::clone(&track),
        body_timeout: limits.body_timeout,
    };
    let mut conn = hyper::server::conn::http1::Builder::new()
        .keep_alive(true)
        .header_read_timeout(None)
        .serve_connection(io, service);
    let mut stopping = false;
    // One timer for the connection's life, moved only when its deadline comes sooner: a
    // deadline that moves later (every answer moves the idle one) is found when the timer
    // fires early and is armed again, so a request costs no timer registration.
    let timer = tokio::time::sleep_until(Instant::now());
    tokio::pin!(timer);
    let mut armed: Option<Instant> = None;
    let timed_out = loop {
        if stopping && !track.busy() {
            // Stopping: a connection with no request being answered (idle, or still
            // sending headers) is closed now rather than at its timeout.
            break true;
        }
        if let Some(at) = track.deadline(&limits)
            && armed.is_none_or(|armed| at < armed)
        {
            timer.as_mut().reset(at);
            armed = Some(at);
        }
        tokio::select! {
            // An error (a malformed request, answered `400` by hyper, or a broken socket)
            // ends the connection like a completed exchange.
            _ = std::future::poll_fn(|cx| conn.poll_without_shutdown(cx)) => break false,
            () = &mut timer, if armed.is_some() => {
                if track.expired(&limits, Instant::now()) {
                    break true;
                }
                armed = None;
            }
            () = track.changed.notified() => {}
            _ = stop.wait_for(|stop| *stop), if !stopping => {
                stopping = true;
                Pin::new(&mut conn).graceful_shutdown();
            }
        }
    };
    if !timed_out {
        // The exchange ended (the client closed, or an answer said `Connection: close`).
        linger(conn.into_parts().io.into_inner().inner, LINGER).await;
    }
    // Else a timeout expired (or the service stops): the socket is dropped, closing it at once.
    drop(permit);
}

/// What a connection is doing, for its timeouts.
#[derive(Clone, Copy, Debug)]
enum Phase {
    /// No request in progress since this instant.
    Idle(Instant),
    /// A request's first byte arrived at this instant; its headers are not complete.
    Head(Instant),
    /// This many requests are being answered (headers read, answer not yet handed over
    /// whole).
    Busy(usize),
}

/// A connection's phase and writes, shared by its socket, its service and its watchdog.
#[derive(Debug)]
struct Track {
    state: Mutex<TrackState>,
    /// Woken when a deadline may have moved.
    changed: Notify,
}

#[derive(Debug)]
struct TrackState {
    phase: Phase,
    /// When the last write proceeded.
    wrote: Option<Instant>,
    /// Since when writes cannot proceed (the client is not reading), if they cannot.
    blocked: Option<Instant>,
}

impl Track {
    fn new() -> Self {
        Track {
            state: Mutex::new(TrackState {
                phase: Phase::Idle(Instant::now()),
                wrote: None,
                blocked: None,
            }),
            changed: Notify::new(),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, TrackState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Bytes arrived.
    fn read(&self) {
        let mut state = self.lock();
        if let Phase::Idle(_) = state.phase {
            state.phase = Phase::Head(Instant::now());
            drop(state);
            self.changed.notify_one();
        }
    }

    /// A write could not proceed (the client is not reading).
    fn write_blocked(&self) {
        let mut state = self.lock();
        if state.blocked.is_none() {
            state.blocked = Some(Instant::now());
            drop(state);
            self.changed.notify_one();
        }
    }

    /// A write proceeded.
    fn wrote(&self) {
        let mut state = self.lock();
        state.wrote = Some(Instant::now());
        state.blocked = None;
    }

    /// A request's headers are complete: it is being answered.
    fn begin(&self) {
        let mut state = self.lock();
        state.phase = match state.phase {
            Phase::Busy(n) => Phase::Busy(n + 1),
            Phase::Idle(_) | Phase::Head(_) => Phase::Busy(1),
        };
    }

    /// A request's answer has been handed over whole to the connection (or abandoned).
    fn end(&self) {
        let mut state = self.lock();
        state.phase = match state.phase {
            Phase::Busy(n) if n > 1 => Phase::Busy(n - 1),
            _ => Phase::Idle(Instant::now()),
        };
        drop(state);
        self.changed.notify_one();
    }

    /// Whether a request is being answered.
    fn busy(&self) -> bool {
        matches!(self.lock().phase, Phase::Busy(_))
    }

    /// When the current phase times out, if it can. Idle counts from the end of the last
    /// answer or from its last write, whichever is later (a long answer still being written
    /// to a client that reads it is not idle); an answer in progress times out only when
    /// its writes have not proceeded for the idle timeout.
    fn deadline(&self, limits: &Limits) -> Option<Instant> {
        let state = self.lock();
        match state.phase {
            Phase::Idle(since) => {
                Some(since.max(state.wrote.unwrap_or(since)) + limits.idle_timeout)
            }
            Phase::Head(since) => Some(since + limits.header_timeout),
            Phase::Busy(_) => state.blocked.map(|since| since + limits.idle_timeout),
        }
    }

    fn expired(&self, limits: &Limits, now: Instant) -> bool {
        self.deadline(limits).is_some_and(|at| at <= now)
    }
}

/// The socket, reporting reads and stalled writes to its [`Track`].
struct Watched {
    inner: TcpStream,
    track: Arc<Track>,
}

impl AsyncRead for Watched {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let before = buf.filled().len();
        let result = Pin::new(&mut self.inner).poll_read(cx, buf);
        if matches!(result, Poll::Ready(Ok(()))) && buf.filled().len() > before {
            self.track.read();
        }
        result
    }
}

impl Watched {
    fn note_write(&self, result: &Poll<io::Result<usize>>) {
        match result {
            Poll::Pending => self.track.write_blocked(),
            Poll::Ready(_) => self.track.wrote(),
        }
    }
}

impl AsyncWrite for Watched {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        let result = Pin::new(&mut self.inner).poll_write(cx, buf);
        self.note_write(&result);
        result
    }

    fn poll_write_vectored(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let result = Pin::new(&mut self.inner).poll_write_vectored(cx, bufs);
        self.note_write(&result);
        result
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

/// The router as one connection's hyper service: marks requests busy until their answer is
/// sent, and gives each its body deadline.
struct ConnService {
    router: Router,
    track: Arc<Track>,
    body_timeout: Duration,
}

impl hyper::service::Service<Request<Incoming>> for ConnService {
    type Response = Response<Answer>;
    type Error = Infallible;
    type Future = Pin<Box<dyn Future<Output = Result<Response<Answer>, Infallible>> + Send>>;

    fn call(&self, mut request: Request<Incoming>) -> Self::Future {
        self.track.begin();
        let busy = Busy(Arc::clone(&self.track));
        request.extensions_mut().insert(BodyDeadline {
            at: Instant::now() + self.body_timeout,
            after: self.body_timeout,
        });
        let mut router = self.router.clone();
        Box::pin(async move {
            let response = match router.call(request).await {
                Ok(response) => response,
                Err(never) => match never {},
            };
            Ok(response.map(|body| Answer { body, _busy: busy }))
        })
    }
}

/// Marks its connection busy while it lives.
struct Busy(Arc<Track>);

impl Drop for Busy {
    fn drop(&mut self) {
        self.0.end();
    }
}

/// An answer's body: the connection is busy until hyper has sent (or dropped) it.
struct Answer {
    body: Body,
    _busy: Busy,
}

impl http_body::Body for Answer {
    type Data = Bytes;
    type Error = axum::Error;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Bytes>, axum::Error>>> {
        Pin::new(&mut self.body).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_busy_answer_is_complete() {
        let text = String::from_utf8(busy_answer()).unwrap();
        let (head, body) = text.split_once("\r\n\r\n").unwrap();
        assert!(head.starts_with("HTTP/1.1 503 "));
        assert!(head.contains("\r\nretry-after: 1\r\n"));
        assert!(head.contains(&format!("content-length: {}", body.len())));
        let v: serde_json::Value = serde_json::from_str(body).unwrap();
        assert_eq!(v["error"]["status"], 503);
    }
}
