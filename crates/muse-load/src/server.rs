//! The service under load: one keep-alive HTTP client for it, and what it plans on — the
//! airspace (`/v1/airspace`), the zones (`/v1/zones`), the flight parameters and the clock
//! (`/healthz`) — so that a run needs no world arguments of its own.

use std::sync::Arc;
use std::time::Duration;

use muse_formats::airspace_geojson::read_airspace;
use muse_formats::params::ParamsRecord;
use muse_formats::zones::read_zones;
use muse_model::{Airspace, FlightParams, Instant, Millis, UtcOffset, Zone};
use reqwest::{StatusCode, Url, header};
use serde::Deserialize;

use crate::error::LoadError;
use crate::outcome::ErrorKind;
use crate::post::{Answer, Poster};

/// A client for one service: base URL, optional bearer token, and connection pools shared by
/// every task of a run (connections are kept alive and reused): one for the run's
/// `POST /v1/flights`, one for everything else.
#[derive(Debug, Clone)]
pub struct Server {
    base: String,
    auth: Option<header::HeaderValue>,
    client: reqwest::Client,
    poster: Arc<Poster>,
}

/// What a service plans on, as it reports it.
#[derive(Debug)]
pub struct ServerWorld {
    /// The service's description of its airspace and zones (`/healthz` `airspace`).
    pub label: String,
    /// The airspace.
    pub airspace: Airspace,
    /// The no-fly zones.
    pub zones: Vec<Zone>,
    /// The flight parameters.
    pub params: FlightParams,
    /// The parameters exactly as `/healthz` gave them, for the report.
    pub parameters: serde_json::Value,
    /// The UTC offset of the service's times.
    pub offset: UtcOffset,
    /// The service's clock minus this machine's, ms (estimated at the midpoint of the
    /// `/healthz` round trip).
    pub skew: Millis,
    /// Flights the service held before the run.
    pub flights_before: u64,
    /// How long the service keeps a flight in memory after it ends (`None`: not said).
    pub retain: Option<std::time::Duration>,
}

/// This machine's clock.
pub fn system_now() -> Instant {
    let d = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    Instant(i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// An error and its causes, `: `-separated (reqwest's own message alone rarely says why).
pub(crate) fn causes(e: &dyn std::error::Error) -> String {
    let mut out = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let text = s.to_string();
        if !out.contains(&text) {
            out.push_str(": ");
            out.push_str(&text);
        }
        source = s.source();
    }
    out
}

#[derive(Deserialize)]
struct Health {
    now: String,
    flights: u64,
    airspace: String,
    parameters: serde_json::Value,
    #[serde(default)]
    retain_s: Option<f64>,
}

#[derive(Deserialize)]
struct ErrorBody {
    error: ErrorInner,
}

#[derive(Deserialize)]
struct ErrorInner {
    message: String,
}

impl Server {
    /// A client for the service at `url` (e.g. `http://127.0.0.1:8080`), sending `token` as
    /// a bearer token if given; each request gives up after `timeout`.
    pub fn new(url: &str, token: Option<&str>, timeout: Duration) -> Result<Self, LoadError> {
        let base = url.trim_end_matches('/').to_owned();
        let flights = Url::parse(&format!("{base}/v1/flights"))
            .ok()
            .filter(|u| u.scheme() == "http")
            .ok_or_else(|| {
                LoadError::Config(format!(
                    "--url {url} is not an http:// URL (e.g. http://127.0.0.1:8080)"
                ))
            })?;
        let auth = token
            .map(|t| {
                header::HeaderValue::from_str(&format!("Bearer {t}")).map_err(|_| {
                    LoadError::Config("--token holds characters a header cannot".into())
                })
            })
            .transpose()?;
        let client = reqwest::Client::builder()
            .timeout(timeout)
            .connect_timeout(timeout.min(Duration::from_secs(5)))
            .tcp_nodelay(true)
            // Below the service's idle timeout (60 s by default), so that the pool lets an
            // idle connection go before the service closes it under a request.
            .pool_idle_timeout(Duration::from_secs(30))
            .no_proxy()
            .build()
            .map_err(|e| LoadError::Config(format!("building the HTTP client: {}", causes(&e))))?;
        let host = flights.host_str().unwrap_or("localhost");
        let port = flights.port_or_known_default().unwrap_or(80);
        let path = match flights.query() {
            Some(q) => format!("{}?{q}", flights.path()),
            None => flights.path().to_owned(),
        };
        let authorization = auth.as_ref().and_then(|a| a.to_str().ok());
        let poster = Arc::new(Poster::new(host, port, &path, authorization, timeout));
        Ok(Server {
            base,
            auth,
            client,
            poster,
        })
    }

    /// The base URL (without a trailing `/`).
    pub fn url(&self) -> &str {
        &self.base
    }

    /// `POST /v1/flights` with `body` (JSON) on a kept-alive connection: the whole answer,
    /// or why there is none.
    pub(crate) async fn post_flight(&self, body: &[u8]) -> Result<Answer, ErrorKind> {
        self.poster.post(body).await
    }

    /// `GET path` (e.g. `/v1/zones`): the body of a 2xx answer, or why there is none.
    pub async fn get_text(&self, path: &str) -> Result<String, LoadError> {
        let what = format!("GET {path}");
        let mut rq = self.client.get(format!("{}{path}", self.base));
        if let Some(a) = &self.auth {
            rq = rq.header(header::AUTHORIZATION, a.clone());
        }
        let response = rq.send().await.map_err(|e| self.transport(&e))?;
        let status = response.status();
        let text = response
            .text()
            .await
            .map_err(|e| LoadError::bad_answer(&what, causes(&e)))?;
        if status.is_success() {
            return Ok(text);
        }
        let message = serde_json::from_str::<ErrorBody>(&text)
            .map(|b| b.error.message)
            .unwrap_or_default();
        let message = match (status, message.is_empty()) {
            (StatusCode::UNAUTHORIZED, true) => "unauthorized (see --token)".to_owned(),
            (_, true) => status.canonical_reason().unwrap_or_default().to_owned(),
            (_, false) => message,
        };
        Err(LoadError::Http {
            what,
            status: status.as_u16(),
            message,
        })
    }

    /// The error for a request that got no answer.
    fn transport(&self, e: &reqwest::Error) -> LoadError {
        LoadError::Unreachable {
            url: self.base.clone(),
            cause: causes(e),
        }
    }

    /// Fetches what the service plans on: `/healthz` first (which needs no token, so that an
    /// unreachable service is told apart from a refused token), then the airspace and zones.
    pub async fn world(&self) -> Result<ServerWorld, LoadError> {
        let before = system_now();
        let text = self.get_text("/healthz").await?;
        let after = system_now();
        let what = "GET /healthz";
        let health: Health =
            serde_json::from_str(&text).map_err(|e| LoadError::bad_answer(what, e))?;
        let now =
            Instant::parse_rfc3339(&health.now).map_err(|e| LoadError::bad_answer(what, e))?;
        let offset = offset_of(&health.now).map_err(|e| LoadError::bad_answer(what, e))?;
        let params =
            flight_params(&health.parameters).map_err(|e| LoadError::bad_answer(what, e))?;
        let midpoint = Instant(before.0 + (after.0 - before.0) / 2);
        let airspace_text = self.get_text("/v1/airspace").await?;
        let airspace = read_airspace(&airspace_text, "GET /v1/airspace")
            .map_err(|e| LoadError::bad_answer("GET /v1/airspace", e))?;
        let zones_text = self.get_text("/v1/zones").await?;
        let zones = read_zones(&zones_text, "GET /v1/zones")
            .map_err(|e| LoadError::bad_answer("GET /v1/zones", e))?;
        Ok(ServerWorld {
            label: health.airspace,
            airspace,
            zones,
            params,
            parameters: health.parameters,
            offset,
            skew: now - midpoint,
            flights_before: health.flights,
            retain: health
                .retain_s
                .filter(|s| s.is_finite() && *s >= 0.0)
                .map(std::time::Duration::from_secs_f64),
        })
    }
}

/// The UTC offset an RFC 3339 timestamp is written in (`Z`, `+08:00`, …).
fn offset_of(text: &str) -> Result<UtcOffset, String> {
    let t = text.trim();
    if t.ends_with(['Z', 'z']) {
        return Ok(UtcOffset(0));
    }
    let start = t
        .len()
        .checked_sub(6)
        .filter(|&i| t.is_char_boundary(i))
        .ok_or_else(|| format!("`{t}` has no UTC offset"))?;
    UtcOffset::parse(&t[start..]).map_err(|e| format!("`{t}`: {e}"))
}

/// The flight parameters of `/healthz`'s `parameters`.
fn flight_params(v: &serde_json::Value) -> Result<FlightParams, String> {
    let p: ParamsRecord =
        serde_json::from_value(v.clone()).map_err(|e| format!("parameters: {e}"))?;
    p.to_params().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::EdgeRule;
    use serde_json::json;

    #[test]
    fn offsets_of_timestamps() {
        assert_eq!(
            offset_of("2026-11-23T23:31:44.000+08:00"),
            Ok(UtcOffset::SINGAPORE)
        );
        assert_eq!(offset_of("2026-11-23T15:31:44.000Z"), Ok(UtcOffset(0)));
        assert_eq!(
            offset_of("2026-11-23T10:31:44.000-05:30"),
            Ok(UtcOffset(-19_800))
        );
        assert!(offset_of("x").is_err());
    }

    #[test]
    fn parameters_as_healthz_gives_them() {
        let v = json!({"speed_kmh": 30.0, "max_flight_min": 20.0, "node_separation_s": 5.0,
            "edge_rule": "exclusive", "headway_s": null, "max_ground_delay_s": 0.0});
        assert_eq!(flight_params(&v).unwrap(), FlightParams::default());
        let v = json!({"speed_kmh": 30.0, "max_flight_min": 20.0, "node_separation_s": 5.0,
            "edge_rule": "headway", "headway_s": 2.5, "max_ground_delay_s": 600.0});
        let p = flight_params(&v).unwrap();
        assert_eq!(p.edge_rule, EdgeRule::Headway(Millis(2_500)));
        assert_eq!(p.max_ground_delay, Millis::from_mins(10));
        let v = json!({"speed_kmh": 30.0, "max_flight_min": 20.0, "node_separation_s": 5.0,
            "edge_rule": "sideways", "headway_s": null, "max_ground_delay_s": 0.0});
        assert!(flight_params(&v).unwrap_err().contains("sideways"));
    }

    #[test]
    fn only_http_urls() {
        let t = Duration::from_secs(1);
        assert!(Server::new("http://127.0.0.1:8080/", None, t).is_ok());
        assert_eq!(
            Server::new("http://127.0.0.1:8080/", None, t)
                .unwrap()
                .url(),
            "http://127.0.0.1:8080"
        );
        assert!(Server::new("https://example.invalid", None, t).is_err());
        assert!(Server::new("127.0.0.1:8080", None, t).is_err());
        assert!(Server::new("http://127.0.0.1:8080", Some("a\nb"), t).is_err());
    }
}
