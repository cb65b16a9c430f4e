//! The load's one hot request, `POST /v1/flights`, on kept-alive HTTP/1.1 connections of its
//! own: the request written in one call, the answer's head parsed with `httparse`.
//!
//! A general-purpose client spends more processor time per request than the service it
//! measures (URL handling, header maps, pool bookkeeping), and the load generator usually
//! shares the machine with the service: every microsecond it spends is taken from what it
//! measures. The other requests of a run (`/healthz`, `/v1/airspace`, …) are few and go
//! through `reqwest`.

use std::sync::{Mutex, PoisonError};
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::time::Instant;

use crate::outcome::ErrorKind;

/// How long a connection may stay unused in the pool: below the service's idle timeout (60 s
/// by default), so that the pool lets a connection go before the service closes it.
const IDLE: Duration = Duration::from_secs(30);

/// The most header lines an answer may have.
const MAX_HEADERS: usize = 32;

/// The largest answer head or body read, bytes.
const MAX_ANSWER: usize = 16 << 20;

/// Posts JSON bodies to one path of one service over a pool of kept-alive connections,
/// shared by every task of a run.
#[derive(Debug)]
pub(crate) struct Poster {
    /// `host:port` to connect to.
    address: String,
    /// The request line and the fixed headers, up to the `Content-Length` value.
    head: Vec<u8>,
    timeout: Duration,
    connect_timeout: Duration,
    idle: Mutex<Vec<(Connection, Instant)>>,
}

/// One answer: its status and whole body.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct Answer {
    pub status: u16,
    pub body: Vec<u8>,
}

impl Poster {
    /// A poster to `path` (with its query, if any) at `host` and `port`, sending
    /// `authorization` as that header if given; each post gives up after `timeout`.
    pub(crate) fn new(
        host: &str,
        port: u16,
        path: &str,
        authorization: Option<&str>,
        timeout: Duration,
    ) -> Self {
        let mut head = format!(
            "POST {path} HTTP/1.1\r\nHost: {host}:{port}\r\nContent-Type: application/json\r\n"
        );
        if let Some(a) = authorization {
            head.push_str("Authorization: ");
            head.push_str(a);
            head.push_str("\r\n");
        }
        head.push_str("Content-Length: ");
        Poster {
            address: format!("{host}:{port}"),
            head: head.into_bytes(),
            timeout,
            connect_timeout: timeout.min(Duration::from_secs(5)),
            idle: Mutex::new(Vec::new()),
        }
    }

    /// Posts `body` and reads the whole answer, on a pooled connection if one is free.
    pub(crate) async fn post(&self, body: &[u8]) -> Result<Answer, ErrorKind> {
        let mut request = Vec::with_capacity(self.head.len() + 24 + body.len());
        request.extend_from_slice(&self.head);
        request.extend_from_slice(body.len().to_string().as_bytes());
        request.extend_from_slice(b"\r\n\r\n");
        request.extend_from_slice(body);
        tokio::time::timeout(self.timeout, self.exchange(&request))
            .await
            .unwrap_or(Err(ErrorKind::Timeout))
    }

    async fn exchange(&self, request: &[u8]) -> Result<Answer, ErrorKind> {
        let reused = match self.take() {
            Some(mut connection) => Some((connection.exchange(request).await, connection)),
            None => None,
        };
        let (result, connection) = match reused {
            // The service closed the kept-alive connection before it read the request: send
            // it again on a new one (a flight's id makes a resent request idempotent in any
            // case).
            Some((Err(Failure::Closed), _)) | None => {
                let mut connection = self.connect().await?;
                (connection.exchange(request).await, connection)
            }
            Some(done) => done,
        };
        let (answer, keep) = result.map_err(|_| ErrorKind::Transport)?;
        if keep {
            self.give_back(connection);
        }
        Ok(answer)
    }

    fn take(&self) -> Option<Connection> {
        let mut idle = self.idle.lock().unwrap_or_else(PoisonError::into_inner);
        while let Some((connection, since)) = idle.pop() {
            if since.elapsed() < IDLE {
                return Some(connection);
            }
        }
        None
    }

    fn give_back(&self, connection: Connection) {
        self.idle
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push((connection, Instant::now()));
    }

    async fn connect(&self) -> Result<Connection, ErrorKind> {
        let stream = tokio::time::timeout(
            self.connect_timeout,
            TcpStream::connect(self.address.as_str()),
        )
        .await
        .map_err(|_| ErrorKind::Connect)?
        .map_err(|_| ErrorKind::Connect)?;
        stream.set_nodelay(true).map_err(|_| ErrorKind::Connect)?;
        Ok(Connection {
            stream,
            buffer: Vec::with_capacity(4096),
        })
    }
}

/// Why an exchange failed.
#[derive(Debug, PartialEq, Eq)]
enum Failure {
    /// The connection was closed before any byte of the answer came.
    Closed,
    /// Anything else: reset mid-answer, malformed HTTP, an answer too large.
    Broken,
}

/// One kept-alive connection and the bytes read from it but not yet used.
#[derive(Debug)]
struct Connection {
    stream: TcpStream,
    buffer: Vec<u8>,
}

/// How an answer's body is delimited.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Framing {
    Length(usize),
    Chunked,
    UntilClose,
}

impl Connection {
    /// Writes `request` and reads one whole answer; also says whether the connection may be
    /// used again.
    async fn exchange(&mut self, request: &[u8]) -> Result<(Answer, bool), Failure> {
        self.buffer.clear();
        if self.stream.write_all(request).await.is_err() {
            return Err(Failure::Closed);
        }
        let (status, head_len, framing, keep) = loop {
            if self.fill().await? == 0 {
                return Err(if self.buffer.is_empty() {
                    Failure::Closed
                } else {
                    Failure::Broken
                });
            }
            if let Some(head) = parse_head(&self.buffer)? {
                break head;
            }
        };
        self.buffer.drain(..head_len);
        let body = match framing {
            Framing::Length(n) => self.read_exact_body(n).await?,
            Framing::Chunked => self.read_chunked().await?,
            Framing::UntilClose => {
                while self.fill().await? > 0 {}
                std::mem::take(&mut self.buffer)
            }
        };
        let keep = keep && framing != Framing::UntilClose && self.buffer.is_empty();
        Ok((Answer { status, body }, keep))
    }

    /// Reads more bytes into the buffer; how many (0: the peer closed).
    async fn fill(&mut self) -> Result<usize, Failure> {
        if self.buffer.len() >= MAX_ANSWER {
            return Err(Failure::Broken);
        }
        self.buffer.reserve(4096);
        match self.stream.read_buf(&mut self.buffer).await {
            Ok(n) => Ok(n),
            Err(_) if self.buffer.is_empty() => Err(Failure::Closed),
            Err(_) => Err(Failure::Broken),
        }
    }

    async fn read_exact_body(&mut self, n: usize) -> Result<Vec<u8>, Failure> {
        if n > MAX_ANSWER {
            return Err(Failure::Broken);
        }
        while self.buffer.len() < n {
            if self.fill().await? == 0 {
                return Err(Failure::Broken);
            }
        }
        let rest = self.buffer.split_off(n);
        Ok(std::mem::replace(&mut self.buffer, rest))
    }

    async fn read_chunked(&mut self) -> Result<Vec<u8>, Failure> {
        let mut body = Vec::new();
        loop {
            let (start, size) = loop {
                match httparse::parse_chunk_size(&self.buffer) {
                    Ok(httparse::Status::Complete(c)) => break c,
                    Ok(httparse::Status::Partial) => {
                        if self.fill().await? == 0 {
                            return Err(Failure::Broken);
                        }
                    }
                    Err(_) => return Err(Failure::Broken),
                }
            };
            let size = usize::try_from(size).map_err(|_| Failure::Broken)?;
            if body.len() + size > MAX_ANSWER {
                return Err(Failure::Broken);
            }
            self.buffer.drain(..start);
            if size == 0 {
                // No trailers are expected: the last chunk is followed by an empty line.
                while self.buffer.len() < 2 {
                    if self.fill().await? == 0 {
                        return Err(Failure::Broken);
                    }
                }
                if &self.buffer[..2] != b"\r\n" {
                    return Err(Failure::Broken);
                }
                self.buffer.drain(..2);
                return Ok(body);
            }
            while self.buffer.len() < size + 2 {
                if self.fill().await? == 0 {
                    return Err(Failure::Broken);
                }
            }
            if &self.buffer[size..size + 2] != b"\r\n" {
                return Err(Failure::Broken);
            }
            body.extend_from_slice(&self.buffer[..size]);
            self.buffer.drain(..size + 2);
        }
    }
}

/// The answer's head in `bytes`, if whole: its status, length, the body's framing and whether
/// the connection stays open.
fn parse_head(bytes: &[u8]) -> Result<Option<(u16, usize, Framing, bool)>, Failure> {
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut response = httparse::Response::new(&mut headers);
    let head_len = match response.parse(bytes) {
        Ok(httparse::Status::Complete(n)) => n,
        Ok(httparse::Status::Partial) => return Ok(None),
        Err(_) => return Err(Failure::Broken),
    };
    let status = response.code.ok_or(Failure::Broken)?;
    // HTTP/1.0 closes by default, HTTP/1.1 keeps the connection.
    let mut keep = response.version == Some(1);
    let mut framing = Framing::UntilClose;
    for h in response.headers.iter() {
        if h.name.eq_ignore_ascii_case("content-length") {
            let n = std::str::from_utf8(h.value)
                .ok()
                .and_then(|v| v.trim().parse::<usize>().ok())
                .ok_or(Failure::Broken)?;
            if framing != Framing::Chunked {
                framing = Framing::Length(n);
            }
        } else if h.name.eq_ignore_ascii_case("transfer-encoding") {
            if h.value.eq_ignore_ascii_case(b"chunked") {
                framing = Framing::Chunked;
            } else {
                return Err(Failure::Broken);
            }
        } else if h.name.eq_ignore_ascii_case("connection") {
            if h.value.eq_ignore_ascii_case(b"close") {
                keep = false;
            } else if h.value.eq_ignore_ascii_case(b"keep-alive") {
                keep = true;
            }
        }
    }
    if status == 204 || status == 304 || (100..200).contains(&status) {
        framing = Framing::Length(0);
    }
    Ok(Some((status, head_len, framing, keep)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use tokio::net::TcpListener;

    /// A one-connection-at-a-time server that reads a request head and body, then writes
    /// `answers[k]` for the k-th request overall; it closes a connection after `per_conn`
    /// answers. Returns the port and the requests it read.
    async fn serve(
        answers: Vec<&'static [u8]>,
        per_conn: usize,
    ) -> (u16, tokio::task::JoinHandle<Vec<Vec<u8>>>) {
        let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let port = listener.local_addr().unwrap().port();
        let task = tokio::spawn(async move {
            let mut seen = Vec::new();
            let mut answers = answers.into_iter();
            'outer: loop {
                let Ok((mut s, _)) = listener.accept().await else {
                    break;
                };
                for _ in 0..per_conn {
                    let mut buf = Vec::new();
                    loop {
                        let mut chunk = [0u8; 1024];
                        let n = s.read(&mut chunk).await.unwrap();
                        if n == 0 {
                            continue 'outer;
                        }
                        buf.extend_from_slice(&chunk[..n]);
                        let text = String::from_utf8_lossy(&buf).into_owned();
                        if let Some(end) = text.find("\r\n\r\n") {
                            let len: usize = text
                                .lines()
                                .find_map(|l| l.strip_prefix("Content-Length: "))
                                .unwrap()
                                .parse()
                                .unwrap();
                            if buf.len() >= end + 4 + len {
                                break;
                            }
                        }
                    }
                    seen.push(buf);
                    let Some(a) = answers.next() else {
                        break 'outer;
                    };
                    s.write_all(a).await.unwrap();
                    if answers.len() == 0 {
                        break 'outer;
                    }
                }
            }
            seen
        });
        (port, task)
    }

    fn poster(port: u16) -> Poster {
        Poster::new(
            "127.0.0.1",
            port,
            "/v1/flights",
            Some("Bearer abcdefghijklmnop"),
            Duration::from_secs(5),
        )
    }

    #[tokio::test]
    async fn posts_with_a_length_reads_length_and_chunked_answers_and_reuses_the_connection() {
        let (port, server) = serve(
            vec![
                b"HTTP/1.1 201 Created\r\ncontent-length: 5\r\n\r\nhello",
                b"HTTP/1.1 200 OK\r\ntransfer-encoding: chunked\r\n\r\n3\r\nabc\r\n2\r\nde\r\n0\r\n\r\n",
            ],
            2,
        )
        .await;
        let p = poster(port);
        let a = p.post(br#"{"id":"a"}"#).await.unwrap();
        assert_eq!((a.status, a.body.as_slice()), (201, &b"hello"[..]));
        let b = p.post(br#"{"id":"b"}"#).await.unwrap();
        assert_eq!((b.status, b.body.as_slice()), (200, &b"abcde"[..]));
        let seen = server.await.unwrap();
        assert_eq!(seen.len(), 2, "both requests on the one connection");
        let first = String::from_utf8(seen[0].clone()).unwrap();
        assert!(
            first.starts_with("POST /v1/flights HTTP/1.1\r\n"),
            "{first}"
        );
        assert!(first.contains("\r\nHost: 127.0.0.1:"), "{first}");
        assert!(
            first.contains("\r\nContent-Type: application/json\r\n"),
            "{first}"
        );
        assert!(
            first.contains("\r\nAuthorization: Bearer abcdefghijklmnop\r\n"),
            "{first}"
        );
        assert!(
            first.ends_with("Content-Length: 10\r\n\r\n{\"id\":\"a\"}"),
            "{first}"
        );
    }

    #[tokio::test]
    async fn a_connection_the_service_closed_is_replaced_and_the_request_sent_again() {
        // One answer per connection, without `Connection: close`: the second post finds the
        // kept connection closed and must go again on a new one.
        let (port, server) = serve(
            vec![
                b"HTTP/1.1 200 OK\r\ncontent-length: 1\r\n\r\nx",
                b"HTTP/1.1 200 OK\r\ncontent-length: 1\r\n\r\ny",
            ],
            1,
        )
        .await;
        let p = poster(port);
        assert_eq!(p.post(b"{}").await.unwrap().body, b"x");
        assert_eq!(p.post(b"{}").await.unwrap().body, b"y");
        assert_eq!(server.await.unwrap().len(), 2);
    }

    #[tokio::test]
    async fn malformed_cut_and_unreachable_answers_are_errors() {
        let (port, _server) =
            serve(vec![b"HTTP/1.1 200 OK\r\ncontent-length: 9\r\n\r\nabc"], 1).await;
        assert_eq!(
            poster(port).post(b"{}").await,
            Err(ErrorKind::Transport),
            "a body cut short"
        );
        let (port, _server) = serve(vec![b"NOT HTTP AT ALL\r\n\r\n"], 1).await;
        assert_eq!(poster(port).post(b"{}").await, Err(ErrorKind::Transport));
        let closed = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let port = closed.local_addr().unwrap().port();
        drop(closed);
        assert_eq!(poster(port).post(b"{}").await, Err(ErrorKind::Connect));
    }

    #[tokio::test]
    async fn a_silent_service_times_out() {
        let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let port = listener.local_addr().unwrap().port();
        let p = Poster::new("127.0.0.1", port, "/", None, Duration::from_millis(200));
        assert_eq!(p.post(b"{}").await, Err(ErrorKind::Timeout));
        drop(listener);
    }

    #[test]
    fn heads_say_their_framing_and_whether_the_connection_stays() {
        let head = |b: &[u8]| parse_head(b).unwrap().unwrap();
        assert_eq!(
            head(b"HTTP/1.1 200 OK\r\nContent-Length: 12\r\n\r\n"),
            (200, 39, Framing::Length(12), true)
        );
        assert!(
            !head(b"HTTP/1.1 409 Conflict\r\nconnection: close\r\ncontent-length: 0\r\n\r\n").3
        );
        assert_eq!(head(b"HTTP/1.0 200 OK\r\n\r\n").2, Framing::UntilClose);
        assert!(!head(b"HTTP/1.0 200 OK\r\n\r\n").3);
        assert_eq!(
            head(b"HTTP/1.1 204 No Content\r\n\r\n").2,
            Framing::Length(0)
        );
        assert_eq!(parse_head(b"HTTP/1.1 200 OK\r\nContent-Le"), Ok(None));
        assert_eq!(
            parse_head(b"HTTP/1.1 200 OK\r\nContent-Length: x\r\n\r\n"),
            Err(Failure::Broken)
        );
        assert_eq!(
            parse_head(b"HTTP/1.1 200 OK\r\nTransfer-Encoding: gzip\r\n\r\n"),
            Err(Failure::Broken)
        );
    }
}
