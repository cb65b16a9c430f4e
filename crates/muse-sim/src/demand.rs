//! Seeded demand: requests with uniform departures in a window and random origin–destination
//! pairs (docs/reference.md#built-in-scenarios).
//!
//! The generator is `ChaCha8` seeded from a `u64`, so a seed gives the same requests on every
//! machine. Request `i` (0-based) draws its departure (a uniform whole millisecond in
//! `[start, end)`) and then its pair; ids are `r` followed by `i + 1` zero-padded to the width
//! of the count (`r0001` … `r5000`).
//!
//! With a [`BookingLead`], each request is also booked ahead of its departure: its lead is a
//! uniform whole millisecond in `[min, max]`, drawn from a second `ChaCha8` stream of the same
//! seed (stream [`LEAD_STREAM`]), and `submitted = departure − lead`. Departures and pairs come
//! from the first stream alone, so a seed gives the same departures and pairs whatever the
//! lead, and with no lead (the paper) exactly the requests it always gave.

use muse_airspace::shortest::Dijkstra;
use muse_model::{Airspace, Instant, Millis, NodeId, Request, Speed};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How origin–destination pairs are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OdRule {
    /// Uniform over ordered pairs of distinct stations (the paper).
    Uniform,
    /// Uniform over ordered pairs of distinct stations whose free-flow time fits the battery.
    InRange {
        /// Cruise speed.
        speed: Speed,
        /// Battery limit `T_max`.
        max_flight: Millis,
    },
}

/// How far ahead of its departure each request is booked (docs/reference.md#requests `submitted`):
/// a lead drawn uniformly in `[min, max]` (whole milliseconds, both ends included).
/// [`BookingLead::NONE`], the default, books every request at its departure (the paper).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BookingLead {
    /// Shortest lead (at least zero).
    pub min: Millis,
    /// Longest lead (at least `min`).
    pub max: Millis,
}

impl BookingLead {
    /// No booking ahead: every request is submitted at its departure.
    pub const NONE: BookingLead = BookingLead {
        min: Millis::ZERO,
        max: Millis::ZERO,
    };

    /// A lead uniform in `[min, max]`, checked: `0 ≤ min ≤ max`.
    ///
    /// ```
    /// use muse_model::Millis;
    /// use muse_sim::demand::BookingLead;
    /// let lead = BookingLead::new(Millis::ZERO, Millis::from_mins(120)).unwrap();
    /// assert!(!lead.is_none());
    /// assert!(BookingLead::new(Millis::from_mins(5), Millis::from_mins(1)).is_err());
    /// assert!(BookingLead::new(Millis::ZERO, Millis::ZERO).unwrap().is_none());
    /// ```
    pub fn new(min: Millis, max: Millis) -> Result<Self, DemandError> {
        let lead = BookingLead { min, max };
        lead.check()?;
        Ok(lead)
    }

    /// Whether every request is submitted at its departure (`max` is zero).
    pub fn is_none(&self) -> bool {
        self.max == Millis::ZERO
    }

    fn check(&self) -> Result<(), DemandError> {
        if self.min < Millis::ZERO || self.max < self.min {
            return Err(DemandError::BookingLead(*self));
        }
        Ok(())
    }
}

/// The `ChaCha8` stream of a seed that booking leads are drawn from (departures and pairs use
/// stream 0).
pub const LEAD_STREAM: u64 = 1;

/// What to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DemandSpec {
    /// Number of requests.
    pub count: usize,
    /// First possible departure (inclusive).
    pub start: Instant,
    /// End of the departure window (exclusive).
    pub end: Instant,
    /// Seed.
    pub seed: u64,
    /// Origin–destination rule.
    pub od: OdRule,
    /// How far ahead of departure requests are booked ([`BookingLead::NONE`]: at departure).
    pub booking_lead: BookingLead,
}

/// Why demand cannot be generated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DemandError {
    /// The window is empty.
    #[error("the departure window is empty (its end must be after its start)")]
    EmptyWindow,
    /// No pair of stations satisfies the rule.
    #[error("no origin-destination pair satisfies the rule ({0} stations)")]
    NoPairs(usize),
    /// The booking lead is negative or its bounds are the wrong way round.
    #[error(
        "the booking lead {} s to {} s is invalid: it must be at least 0 and its lower bound \
         at most its upper bound",
        .0.min.as_secs_f64(),
        .0.max.as_secs_f64()
    )]
    BookingLead(BookingLead),
    /// More requests than [`MAX_REQUESTS`].
    #[error("{0} requests is more than a day of demand can hold: at most {MAX_REQUESTS}")]
    TooMany(usize),
}

/// The most requests [`generate`] makes for one day (ten million: far beyond what any of the
/// built-in airspaces can land in a day, and a few gigabytes of plans): more is refused before
/// anything is allocated. The range of `--count` ([`muse_formats::ranges::REQUESTS`]).
pub const MAX_REQUESTS: usize = muse_formats::ranges::REQUESTS.hi;

/// The ordered station pairs a rule allows, in a fixed order (origin, then destination index).
pub fn allowed_pairs(airspace: &Airspace, od: OdRule) -> Vec<(NodeId, NodeId)> {
    let stations: Vec<NodeId> = airspace.stations().collect();
    let mut pairs = Vec::with_capacity(stations.len() * stations.len());
    let (times, limit) = match od {
        OdRule::Uniform => (None, 0),
        OdRule::InRange { speed, max_flight } => {
            (Some(airspace.traversal_times(speed)), max_flight.0)
        }
    };
    let mut search = Dijkstra::new(airspace.node_count());
    for &o in &stations {
        if let Some(times) = &times {
            search.run(airspace, times, o);
        }
        for &d in &stations {
            if o == d {
                continue;
            }
            let ok = times.is_none() || search.raw_times()[d.index()] <= limit;
            if ok {
                pairs.push((o, d));
            }
        }
    }
    pairs
}

/// Generates the requests of `spec`, in id order.
///
/// ```
/// # let air = muse_scenario_free_airspace();
/// # fn muse_scenario_free_airspace() -> muse_model::Airspace {
/// #     use muse_model::*;
/// #     let n = |id: &str, lon| Node { id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, 1.3) };
/// #     Airspace::new(vec![n("A", 103.8), n("B", 103.81), n("C", 103.82)], vec![]).unwrap()
/// # }
/// use muse_model::{Instant, Millis};
/// use muse_sim::demand::{generate, BookingLead, DemandSpec, OdRule};
/// let spec = DemandSpec {
///     count: 3, start: Instant(0), end: Instant(3_600_000), seed: 1, od: OdRule::Uniform,
///     booking_lead: BookingLead::NONE,
/// };
/// let a = generate(&air, &spec).unwrap();
/// assert_eq!(a, generate(&air, &spec).unwrap()); // same seed, same requests
/// assert_eq!(a[2].id, "r3");
/// assert!(a.iter().all(|r| r.origin != r.destination && r.departure < Instant(3_600_000)));
/// assert!(a.iter().all(|r| r.submitted == r.departure));
///
/// // Booked 10 to 60 minutes ahead: the same departures and pairs, submitted earlier.
/// let lead = BookingLead::new(Millis::from_mins(10), Millis::from_mins(60)).unwrap();
/// let b = generate(&air, &DemandSpec { booking_lead: lead, ..spec }).unwrap();
/// for (a, b) in a.iter().zip(&b) {
///     assert_eq!((a.departure, a.origin, a.destination), (b.departure, b.origin, b.destination));
///     assert!((Millis::from_mins(10)..=Millis::from_mins(60)).contains(&(b.departure - b.submitted)));
/// }
/// ```
pub fn generate(airspace: &Airspace, spec: &DemandSpec) -> Result<Vec<Request>, DemandError> {
    if spec.end <= spec.start {
        return Err(DemandError::EmptyWindow);
    }
    if spec.count > MAX_REQUESTS {
        return Err(DemandError::TooMany(spec.count));
    }
    spec.booking_lead.check()?;
    let pairs = allowed_pairs(airspace, spec.od);
    if pairs.is_empty() && spec.count > 0 {
        return Err(DemandError::NoPairs(airspace.stations().count()));
    }
    let width = spec.count.to_string().len();
    let span = spec.end.0 - spec.start.0;
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let mut lead_rng = ChaCha8Rng::seed_from_u64(spec.seed);
    lead_rng.set_stream(LEAD_STREAM);
    let BookingLead { min, max } = spec.booking_lead;
    Ok((0..spec.count)
        .map(|i| {
            let departure = Instant(spec.start.0 + rng.random_range(0..span));
            let mut request =
                draw_request(&mut rng, &pairs, format!("r{:0width$}", i + 1), departure);
            if !spec.booking_lead.is_none() {
                request.submitted = departure - Millis(lead_rng.random_range(min.0..=max.0));
            }
            request
        })
        .collect())
}

/// Draws one request at a given departure: its origin–destination pair uniform over `pairs`
/// (one draw from `rng`), with id `id`. [`generate`] uses it after drawing each departure, so
/// online demand (e.g. a load generator choosing departures relative to its clock) draws its
/// pairs exactly as a generated day does.
///
/// # Panics
/// If `pairs` is empty (see [`allowed_pairs`] and [`DemandError::NoPairs`]).
///
/// ```
/// use muse_model::{Instant, NodeId};
/// use muse_sim::demand::draw_request;
/// use rand::SeedableRng;
/// let pairs = [(NodeId(0), NodeId(1)), (NodeId(1), NodeId(0))];
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
/// let r = draw_request(&mut rng, &pairs, "q1".into(), Instant(60_000));
/// assert_eq!((r.id.as_str(), r.departure), ("q1", Instant(60_000)));
/// assert!(pairs.contains(&(r.origin, r.destination)));
/// ```
pub fn draw_request<R: Rng + ?Sized>(
    rng: &mut R,
    pairs: &[(NodeId, NodeId)],
    id: String,
    departure: Instant,
) -> Request {
    let (origin, destination) = pairs[rng.random_range(0..pairs.len())];
    Request {
        id,
        origin,
        destination,
        departure,
        submitted: departure,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::testing::{airspace, edge, station};

    fn line_airspace() -> Airspace {
        // A -1 km- B -9 km- C: at 30 km/h A-B is 2 min, B-C 18 min, A-C 20 min.
        airspace(
            vec![
                station("A", 103.8, 1.3),
                station("B", 103.81, 1.3),
                station("C", 103.9, 1.3),
            ],
            vec![edge(0, 1, 1_000.0), edge(1, 2, 9_000.0)],
        )
    }

    #[test]
    fn reproducible_distinct_and_inside_the_window() {
        let air = line_airspace();
        let spec = DemandSpec {
            count: 2_000,
            start: Instant(1_000),
            end: Instant(61_000),
            seed: 42,
            od: OdRule::Uniform,
            booking_lead: BookingLead::NONE,
        };
        let a = generate(&air, &spec).unwrap();
        assert_eq!(a, generate(&air, &spec).unwrap());
        assert_ne!(a, generate(&air, &DemandSpec { seed: 43, ..spec }).unwrap());
        assert!(a.iter().all(|r| r.origin != r.destination));
        assert!(
            a.iter()
                .all(|r| (Instant(1_000)..Instant(61_000)).contains(&r.departure))
        );
        assert_eq!(a[0].id, "r0001");
        // All six ordered pairs occur.
        let mut seen: Vec<_> = a.iter().map(|r| (r.origin, r.destination)).collect();
        seen.sort();
        seen.dedup();
        assert_eq!(seen.len(), 6);
    }

    #[test]
    fn in_range_keeps_only_pairs_within_the_battery() {
        let air = line_airspace();
        let od = OdRule::InRange {
            speed: Speed::PAPER,
            max_flight: Millis::from_mins(19),
        };
        let pairs = allowed_pairs(&air, od);
        // A-B (2 min) and B-C (18 min) fit 19 min; A-C (20 min) does not.
        assert_eq!(
            pairs,
            vec![
                (NodeId(0), NodeId(1)),
                (NodeId(1), NodeId(0)),
                (NodeId(1), NodeId(2)),
                (NodeId(2), NodeId(1))
            ]
        );
        let od20 = OdRule::InRange {
            speed: Speed::PAPER,
            max_flight: Millis::from_mins(20),
        };
        assert_eq!(allowed_pairs(&air, od20).len(), 6, "the limit is inclusive");
    }

    #[test]
    fn draw_request_matches_generate() {
        // A generated day is its departures followed, request by request, by draw_request:
        // the same seed gives the same pairs whichever way they are drawn.
        let air = line_airspace();
        let spec = DemandSpec {
            count: 50,
            start: Instant(0),
            end: Instant(3_600_000),
            seed: 9,
            od: OdRule::Uniform,
            booking_lead: BookingLead::NONE,
        };
        let day = generate(&air, &spec).unwrap();
        let pairs = allowed_pairs(&air, spec.od);
        let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
        for r in &day {
            let departure = Instant(rng.random_range(0..spec.end.0));
            let drawn = draw_request(&mut rng, &pairs, r.id.clone(), departure);
            assert_eq!(&drawn, r);
        }
        // Every pair is reachable by the draw, and only allowed pairs are drawn.
        let one = [(NodeId(2), NodeId(0))];
        let r = draw_request(&mut rng, &one, "x".into(), Instant(5));
        assert_eq!(
            (r.origin, r.destination, r.departure),
            (NodeId(2), NodeId(0), Instant(5))
        );
    }

    #[test]
    fn errors() {
        let air = line_airspace();
        let spec = DemandSpec {
            count: 1,
            start: Instant(5),
            end: Instant(5),
            seed: 1,
            od: OdRule::Uniform,
            booking_lead: BookingLead::NONE,
        };
        assert_eq!(generate(&air, &spec), Err(DemandError::EmptyWindow));
        // Too many requests are refused before anything is allocated.
        let huge = DemandSpec {
            count: 2_000_000_000,
            end: Instant(6),
            ..spec
        };
        assert_eq!(
            generate(&air, &huge),
            Err(DemandError::TooMany(2_000_000_000))
        );
        let od = OdRule::InRange {
            speed: Speed::PAPER,
            max_flight: Millis::from_secs(1),
        };
        let spec = DemandSpec {
            end: Instant(6),
            od,
            ..spec
        };
        assert_eq!(generate(&air, &spec), Err(DemandError::NoPairs(3)));
        let backwards = BookingLead {
            min: Millis::from_mins(5),
            max: Millis::from_mins(1),
        };
        let spec = DemandSpec {
            od: OdRule::Uniform,
            booking_lead: backwards,
            ..spec
        };
        assert_eq!(
            generate(&air, &spec),
            Err(DemandError::BookingLead(backwards))
        );
        let negative = BookingLead {
            min: Millis(-1),
            max: Millis::ZERO,
        };
        assert_eq!(
            BookingLead::new(negative.min, negative.max),
            Err(DemandError::BookingLead(negative))
        );
        assert_eq!(
            DemandError::BookingLead(backwards).to_string(),
            "the booking lead 300 s to 60 s is invalid: it must be at least 0 and its lower \
             bound at most its upper bound"
        );
    }

    #[test]
    fn booking_lead_keeps_departures_and_pairs_and_stays_in_bounds() {
        let air = line_airspace();
        let spec = DemandSpec {
            count: 3_000,
            start: Instant(0),
            end: Instant(43_200_000),
            seed: 5,
            od: OdRule::Uniform,
            booking_lead: BookingLead::NONE,
        };
        let paper = generate(&air, &spec).unwrap();
        assert!(paper.iter().all(|r| r.submitted == r.departure));
        // The paper's requests are the first stream alone: departure, then pair.
        let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
        let pairs = allowed_pairs(&air, spec.od);
        for r in &paper {
            let departure = Instant(rng.random_range(0..spec.end.0));
            assert_eq!(&draw_request(&mut rng, &pairs, r.id.clone(), departure), r);
        }
        let (lo, hi) = (Millis::from_mins(30), Millis::from_mins(120));
        let lead = BookingLead::new(lo, hi).unwrap();
        let booked = generate(
            &air,
            &DemandSpec {
                booking_lead: lead,
                ..spec
            },
        )
        .unwrap();
        assert_eq!(
            booked,
            generate(
                &air,
                &DemandSpec {
                    booking_lead: lead,
                    ..spec
                }
            )
            .unwrap(),
            "reproducible"
        );
        let leads: Vec<Millis> = booked.iter().map(|r| r.departure - r.submitted).collect();
        for (p, b) in paper.iter().zip(&booked) {
            let same = Request {
                submitted: b.departure,
                ..b.clone()
            };
            assert_eq!(&same, p, "only `submitted` differs");
        }
        assert!(leads.iter().all(|l| (lo..=hi).contains(l)));
        // Uniform: the mean is near the middle, both ends are approached.
        let mean = leads.iter().map(|l| l.0 as f64).sum::<f64>() / leads.len() as f64;
        assert!((mean / 60_000.0 - 75.0).abs() < 2.0, "mean lead {mean} ms");
        assert!(leads.iter().any(|l| *l < lo + Millis::from_mins(1)));
        assert!(leads.iter().any(|l| *l > hi - Millis::from_mins(1)));
        // A fixed lead.
        let fixed = BookingLead::new(lo, lo).unwrap();
        let fixed = generate(
            &air,
            &DemandSpec {
                booking_lead: fixed,
                ..spec
            },
        )
        .unwrap();
        assert!(fixed.iter().all(|r| r.departure - r.submitted == lo));
    }
}
