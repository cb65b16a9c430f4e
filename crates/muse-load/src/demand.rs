//! Online demand: the requests a load run sends, with departures in the future.
//!
//! Request `i` (0-based, in the order the run issues them) draws, from one `ChaCha8` stream
//! seeded with the run's seed, first its lead time (a uniform whole millisecond in
//! `[A, B]` minutes), then its origin–destination pair with
//! [`muse_sim::demand::draw_request`] over [`muse_sim::demand::allowed_pairs`] — the pairs
//! of `muse simulate` and `muse demand`. Its departure is the server's clock at send time plus
//! the lead, and its id `PREFIX-i`. So a seed fixes every request's pair and lead; only the
//! instant it is sent (and therefore its departure) depends on the run.

use muse_model::{Airspace, FlightParams, Instant, Millis, NodeId, Request, UtcOffset};
use muse_sim::demand::{OdRule, allowed_pairs, draw_request};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::error::LoadError;

/// How origin–destination pairs are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum OdChoice {
    /// Uniform over ordered pairs of distinct stations (the paper's demand).
    Uniform,
    /// Uniform over the pairs whose free-flow time on the empty graph fits the battery.
    InRange,
}

impl OdChoice {
    /// The spelling on the command line: `uniform` or `in-range`.
    pub const fn name(self) -> &'static str {
        match self {
            OdChoice::Uniform => "uniform",
            OdChoice::InRange => "in-range",
        }
    }

    /// The demand rule under the server's flight parameters.
    pub fn rule(self, params: &FlightParams) -> OdRule {
        match self {
            OdChoice::Uniform => OdRule::Uniform,
            OdChoice::InRange => OdRule::InRange {
                speed: params.speed,
                max_flight: params.max_flight,
            },
        }
    }
}

/// The longest id prefix accepted: ids are at most 128 characters and the index takes up to
/// 20 more (with its dash).
pub const MAX_PREFIX_LEN: usize = 100;

/// Whether `prefix` can start service ids (`[A-Za-z0-9._~:-]`, 1 to [`MAX_PREFIX_LEN`]
/// characters).
pub fn valid_prefix(prefix: &str) -> bool {
    !prefix.is_empty()
        && prefix.len() <= MAX_PREFIX_LEN
        && prefix.bytes().all(muse_model::request::is_id_byte)
}

/// The default id prefix of a run: `load-s{seed}-{start in unix ms}`, distinct for every run
/// against one server that does not start two runs with one seed in the same millisecond.
///
/// ```
/// assert_eq!(muse_load::demand::default_prefix(1, 1_767_225_600_000), "load-s1-1767225600000");
/// ```
pub fn default_prefix(seed: u64, start_unix_ms: i64) -> String {
    format!("load-s{seed}-{start_unix_ms}")
}

/// The seeded source of a run's requests (see the module docs).
#[derive(Debug)]
pub struct Demand {
    pairs: Vec<(NodeId, NodeId)>,
    rng: ChaCha8Rng,
    lead: (Millis, Millis),
    prefix: String,
    issued: u64,
    /// Node ids by index, for request bodies.
    names: Vec<String>,
    offset: UtcOffset,
}

/// The body of `POST /v1/flights`.
#[derive(Serialize)]
struct Body<'a> {
    id: &'a str,
    origin: &'a str,
    destination: &'a str,
    departure: String,
}

impl Demand {
    /// Demand on `airspace` (with the server's `params`, for [`OdChoice::InRange`]): leads
    /// uniform in `[lead.0, lead.1]`, ids `prefix-i`, times written in `offset`.
    pub fn new(
        airspace: &Airspace,
        params: &FlightParams,
        od: OdChoice,
        seed: u64,
        lead: (Millis, Millis),
        prefix: &str,
        offset: UtcOffset,
    ) -> Result<Self, LoadError> {
        if lead.0 < Millis::ZERO || lead.1 < lead.0 {
            return Err(LoadError::Config(format!(
                "the lead time must be 0 ≤ A ≤ B minutes, got {}:{}",
                lead.0.as_secs_f64() / 60.0,
                lead.1.as_secs_f64() / 60.0
            )));
        }
        if !valid_prefix(prefix) {
            return Err(LoadError::Config(format!(
                "--id-prefix must be 1 to {MAX_PREFIX_LEN} characters of letters, digits and \
                 `._~:-`, got {prefix:?}"
            )));
        }
        let pairs = allowed_pairs(airspace, od.rule(params));
        if pairs.is_empty() {
            return Err(LoadError::Config(format!(
                "no origin-destination pair satisfies --od {} on the server's airspace ({} stations)",
                od.name(),
                airspace.stations().count()
            )));
        }
        Ok(Demand {
            pairs,
            rng: ChaCha8Rng::seed_from_u64(seed),
            lead,
            prefix: prefix.to_owned(),
            issued: 0,
            names: (0..airspace.node_count())
                .map(|i| airspace.node(NodeId(i as u32)).id.clone())
                .collect(),
            offset,
        })
    }

    /// How many requests have been drawn.
    pub fn issued(&self) -> u64 {
        self.issued
    }

    /// The number of origin–destination pairs drawn from.
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// The id prefix.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// Draws the next request, departing its lead after `now` (the server's clock).
    pub fn next_request(&mut self, now: Instant) -> Request {
        let lead = self.rng.random_range(self.lead.0.0..=self.lead.1.0);
        let id = format!("{}-{}", self.prefix, self.issued);
        self.issued += 1;
        draw_request(&mut self.rng, &self.pairs, id, now + Millis(lead))
    }

    /// The JSON body of `POST /v1/flights` for `request`.
    pub fn body(&self, request: &Request) -> String {
        let body = Body {
            id: &request.id,
            origin: &self.names[request.origin.index()],
            destination: &self.names[request.destination.index()],
            departure: request.departure.to_rfc3339(self.offset),
        };
        // Plain strings: serialising cannot fail.
        serde_json::to_string(&body).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::Speed;
    use muse_model::testing::{edge, station, waypoint};

    /// `A -1 km- B -9 km- C` plus a waypoint `W`: at 30 km/h with a 19-minute battery only
    /// `A–B` and `B–C` are in range.
    fn airspace() -> Airspace {
        muse_model::testing::airspace(
            vec![
                station("A", 103.8, 1.3),
                station("B", 103.81, 1.3),
                station("C", 103.9, 1.3),
                waypoint("W", 103.95, 1.3),
            ],
            vec![
                edge(0, 1, 1_000.0),
                edge(1, 2, 9_000.0),
                edge(2, 3, 1_000.0),
            ],
        )
    }

    fn params() -> FlightParams {
        FlightParams {
            speed: Speed::PAPER,
            max_flight: Millis::from_mins(19),
            ..FlightParams::default()
        }
    }

    fn demand(od: OdChoice, seed: u64) -> Demand {
        let lead = (Millis::from_mins(1), Millis::from_mins(3));
        Demand::new(
            &airspace(),
            &params(),
            od,
            seed,
            lead,
            "t",
            UtcOffset::SINGAPORE,
        )
        .unwrap()
    }

    #[test]
    fn seeded_ids_leads_and_pairs() {
        let mut a = demand(OdChoice::Uniform, 5);
        let mut b = demand(OdChoice::Uniform, 5);
        assert_eq!(a.pair_count(), 6, "stations only, every ordered pair");
        let now = Instant(1_000_000);
        let ra: Vec<Request> = (0..200).map(|_| a.next_request(now)).collect();
        let rb: Vec<Request> = (0..200).map(|_| b.next_request(now)).collect();
        assert_eq!(ra, rb, "same seed, same requests");
        assert_eq!(a.issued(), 200);
        assert_eq!(ra[0].id, "t-0");
        assert_eq!(ra[199].id, "t-199");
        for r in &ra {
            assert_ne!(r.origin, r.destination);
            assert!(
                r.origin.index() < 3 && r.destination.index() < 3,
                "never the waypoint"
            );
            let lead = r.departure - now;
            assert!((Millis::from_mins(1)..=Millis::from_mins(3)).contains(&lead));
        }
        let mut c = demand(OdChoice::Uniform, 6);
        let rc: Vec<Request> = (0..200).map(|_| c.next_request(now)).collect();
        assert_ne!(ra, rc);
    }

    #[test]
    fn in_range_uses_the_server_battery() {
        let mut d = demand(OdChoice::InRange, 1);
        assert_eq!(d.pair_count(), 4);
        for _ in 0..100 {
            let r = d.next_request(Instant(0));
            let pair = (r.origin.index(), r.destination.index());
            assert!(matches!(pair, (0 | 2, 1) | (1, 0 | 2)), "{pair:?}");
        }
    }

    #[test]
    fn body_is_the_api_request() {
        let mut d = demand(OdChoice::Uniform, 1);
        let r = d.next_request(Instant(0));
        let v: serde_json::Value = serde_json::from_str(&d.body(&r)).unwrap();
        assert_eq!(v["id"], "t-0");
        assert_eq!(
            Instant::parse_rfc3339(v["departure"].as_str().unwrap()).unwrap(),
            r.departure
        );
        assert!(v["departure"].as_str().unwrap().ends_with("+08:00"));
        assert_eq!(v.as_object().unwrap().len(), 4);
    }

    #[test]
    fn bad_options() {
        let lead = (Millis::from_mins(3), Millis::from_mins(1));
        let air = airspace();
        let p = params();
        let off = UtcOffset::SINGAPORE;
        assert!(Demand::new(&air, &p, OdChoice::Uniform, 1, lead, "t", off).is_err());
        let lead = (Millis::ZERO, Millis::ZERO);
        assert!(Demand::new(&air, &p, OdChoice::Uniform, 1, lead, "t", off).is_ok());
        assert!(Demand::new(&air, &p, OdChoice::Uniform, 1, lead, "a b", off).is_err());
        assert!(Demand::new(&air, &p, OdChoice::Uniform, 1, lead, "", off).is_err());
        let tiny = FlightParams {
            max_flight: Millis::from_secs(1),
            ..p
        };
        assert!(Demand::new(&air, &tiny, OdChoice::InRange, 1, lead, "t", off).is_err());
        assert!(valid_prefix("load-s1-1767225600000:x~y_z.w"));
    }
}
