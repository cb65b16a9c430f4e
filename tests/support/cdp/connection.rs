//! The WebSocket to the browser endpoint: commands matched to replies by id, events kept by
//! session.

use std::collections::HashMap;
use std::io::ErrorKind;
use std::net::TcpStream;
use std::time::Instant;

use serde_json::Value;
use tungstenite::{Message, WebSocket};

use super::TIMEOUT;

/// The WebSocket to the browser endpoint, with the events received so far.
pub(super) struct Connection {
    /// The socket.
    socket: WebSocket<TcpStream>,
    /// The id of the next command.
    next_id: u64,
    /// Every event received, by session id (`""` for the browser's own), in arrival order.
    events: HashMap<String, Vec<Value>>,
}

impl Connection {
    /// Connects to a `ws://127.0.0.1:PORT/devtools/browser/…` endpoint.
    pub(super) fn open(endpoint: &str) -> Result<Self, String> {
        let authority = endpoint
            .strip_prefix("ws://")
            .and_then(|rest| rest.split('/').next())
            .ok_or_else(|| format!("unexpected DevTools address {endpoint}"))?;
        let stream = TcpStream::connect(authority)
            .map_err(|e| format!("connecting to DevTools at {endpoint}: {e}"))?;
        stream
            .set_read_timeout(Some(TIMEOUT))
            .and_then(|()| stream.set_write_timeout(Some(TIMEOUT)))
            .map_err(|e| format!("setting socket timeouts: {e}"))?;
        let (socket, _) = tungstenite::client(endpoint, stream)
            .map_err(|e| format!("WebSocket handshake with {endpoint}: {e}"))?;
        Ok(Self {
            socket,
            next_id: 1,
            events: HashMap::new(),
        })
    }

    /// Sends a command without waiting for its reply; returns its id.
    pub(super) fn send(
        &mut self,
        session: Option<&str>,
        method: &str,
        params: Value,
    ) -> Result<u64, String> {
        let id = self.next_id;
        self.next_id += 1;
        let mut message = serde_json::Map::new();
        message.insert("id".into(), id.into());
        message.insert("method".into(), method.into());
        message.insert("params".into(), params);
        if let Some(session) = session {
            message.insert("sessionId".into(), session.into());
        }
        let message = Value::Object(message);
        self.socket
            .send(Message::text(message.to_string()))
            .map_err(|e| format!("sending {method}: {e}"))?;
        Ok(id)
    }

    /// Sends a command and waits for its reply; returns its `result`, or the protocol's error.
    pub(super) fn command(
        &mut self,
        session: Option<&str>,
        method: &str,
        params: Value,
    ) -> Result<Value, String> {
        let id = self.send(session, method, params)?;
        let deadline = Instant::now() + TIMEOUT;
        let what = format!("the reply to {method}");
        loop {
            let Some(mut reply) = self.receive(deadline, &what)? else {
                continue;
            };
            // A different id is a late reply to a command that timed out: ignore it.
            if reply["id"].as_u64() != Some(id) {
                continue;
            }
            if let Some(error) = reply.get("error") {
                return Err(format!("{method} failed: {error}"));
            }
            return Ok(reply["result"].take());
        }
    }

    /// How many events `session` has received so far.
    pub(super) fn event_count(&self, session: &str) -> usize {
        self.events.get(session).map_or(0, Vec::len)
    }

    /// The events `session` has received so far.
    pub(super) fn events(&self, session: &str) -> &[Value] {
        self.events.get(session).map_or(&[], Vec::as_slice)
    }

    /// Waits until `session` has an event at index `from` or later for which `matches` holds
    /// (given the method and params), and returns its index.
    pub(super) fn wait_event(
        &mut self,
        session: &str,
        from: usize,
        deadline: Instant,
        what: &str,
        matches: impl Fn(&str, &Value) -> bool,
    ) -> Result<usize, String> {
        let mut seen = from;
        loop {
            let events = self.events(session);
            if let Some(offset) = events
                .get(seen..)
                .unwrap_or_default()
                .iter()
                .position(|e| matches(e["method"].as_str().unwrap_or(""), &e["params"]))
            {
                return Ok(seen + offset);
            }
            seen = seen.max(events.len());
            self.receive(deadline, what)?;
        }
    }

    /// Reads one message before `deadline`: records an event and returns `None`, or returns a
    /// reply. The error names `what` was being awaited.
    pub(super) fn receive(
        &mut self,
        deadline: Instant,
        what: &str,
    ) -> Result<Option<Value>, String> {
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(format!("timed out waiting for {what}"));
            }
            self.socket
                .get_mut()
                .set_read_timeout(Some(left))
                .map_err(|e| format!("setting the read timeout: {e}"))?;
            let text = match self.socket.read() {
                Ok(Message::Text(text)) => text,
                Ok(Message::Close(frame)) => {
                    return Err(format!(
                        "the browser closed the connection ({frame:?}) while we waited for {what}"
                    ));
                }
                // Pings are answered by tungstenite itself; nothing else is expected.
                Ok(_) => continue,
                Err(tungstenite::Error::Io(e))
                    if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) =>
                {
                    continue;
                }
                Err(e) => return Err(format!("reading from the browser, awaiting {what}: {e}")),
            };
            let message: Value = serde_json::from_str(text.as_str())
                .map_err(|e| format!("a DevTools message is not JSON ({e}): {text}"))?;
            if message.get("id").is_some() {
                return Ok(Some(message));
            }
            let session = message["sessionId"].as_str().unwrap_or("").to_owned();
            self.events.entry(session).or_default().push(message);
            return Ok(None);
        }
    }
}
