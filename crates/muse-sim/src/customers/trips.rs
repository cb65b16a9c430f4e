//! Trips between customers (docs/reference.md#airspace-from-pads): who sends to whom and when,
//! drawn once by weight, then turned into the requests of any airspace by each customer's serving
//! pad.
//!
//! Trip `i` (0-based) draws, from one `ChaCha8` stream of the seed, its departure (a uniform
//! whole millisecond in `[start, end)`), then its sender and its receiver, each with a chance
//! proportional to the customer's weight (the receiver is drawn again while it is the
//! sender). Ids are `r` followed by `i + 1` zero-padded to the width of the count, as in
//! [`generate`](crate::demand::generate); a [`BookingLead`] draws each trip's lead from a
//! second stream ([`LEAD_STREAM`]) exactly as generated demand does. Trips do not depend on
//! pads: the same seed gives the same trips whatever airspace serves them, which is what lets
//! siting compare pad sets on the same days.

use muse_model::{Instant, Millis, NodeId, Request};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::demand::{BookingLead, DemandError, LEAD_STREAM, MAX_REQUESTS};

/// What to draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TripSpec {
    /// Number of trips.
    pub count: usize,
    /// First possible departure (inclusive).
    pub start: Instant,
    /// End of the departure window (exclusive).
    pub end: Instant,
    /// Seed.
    pub seed: u64,
    /// How far ahead of departure trips are booked.
    pub booking_lead: BookingLead,
}

/// One trip: from customer `from` to customer `to` (indices into the customers drawn from).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Trip {
    /// Request id, e.g. `r0042`.
    pub id: String,
    /// The sender's index.
    pub from: usize,
    /// The receiver's index (never `from`).
    pub to: usize,
    /// Earliest take-off.
    pub departure: Instant,
    /// When it reaches the planner (at most `departure`).
    pub submitted: Instant,
}

/// Why a trip makes no request (docs/reference.md#airspace-from-pads, reason `unserved`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Unserved {
    /// A customer (the sender, the receiver, or both) has no pad within the last mile.
    NoPadInReach {
        /// The sender has none.
        from: bool,
        /// The receiver has none.
        to: bool,
    },
    /// Both customers are served by the same pad: nothing to fly.
    SamePad,
}

impl Unserved {
    /// A few words for reports: `no pad in reach of the sender`, … or `both on one pad`.
    pub fn describe(self) -> &'static str {
        match self {
            Unserved::NoPadInReach {
                from: true,
                to: true,
            } => "no pad in reach of either",
            Unserved::NoPadInReach { from: true, .. } => "no pad in reach of the sender",
            Unserved::NoPadInReach { .. } => "no pad in reach of the receiver",
            Unserved::SamePad => "both on one pad",
        }
    }
}

/// A uniform number in `[0, 1)` from the raw 64-bit output of `rng` (53 bits).
fn unit(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1_u64 << 53) as f64)
}

/// The index whose share of `cumulative` (running sums of weights) holds `u · total`.
fn pick(cumulative: &[f64], rng: &mut ChaCha8Rng) -> usize {
    let total = cumulative[cumulative.len() - 1];
    let target = unit(rng) * total;
    cumulative
        .partition_point(|&c| c <= target)
        .min(cumulative.len() - 1)
}

/// Draws the trips of `spec` between customers of the given `weights` (each above 0; at
/// least two customers), in id order; see the [module documentation](self).
///
/// # Errors
/// An empty window, too many trips, a bad booking lead, or fewer than two customers
/// ([`DemandError::NoPairs`]).
///
/// ```
/// use muse_model::Instant;
/// use muse_sim::customers::trips::{draw_trips, TripSpec};
/// use muse_sim::demand::BookingLead;
/// let spec = TripSpec {
///     count: 1_000, start: Instant(0), end: Instant(3_600_000), seed: 1,
///     booking_lead: BookingLead::NONE,
/// };
/// // Customer 2 weighs 8 times as much as each of the others.
/// let trips = draw_trips(&[1.0, 1.0, 8.0], &spec).unwrap();
/// assert_eq!(trips, draw_trips(&[1.0, 1.0, 8.0], &spec).unwrap());
/// assert!(trips.iter().all(|t| t.from != t.to));
/// let from_heavy = trips.iter().filter(|t| t.from == 2).count();
/// assert!((700..900).contains(&from_heavy), "{from_heavy}");
/// ```
pub fn draw_trips(weights: &[f64], spec: &TripSpec) -> Result<Vec<Trip>, DemandError> {
    if spec.end <= spec.start {
        return Err(DemandError::EmptyWindow);
    }
    if spec.count > MAX_REQUESTS {
        return Err(DemandError::TooMany(spec.count));
    }
    let lead = BookingLead::new(spec.booking_lead.min, spec.booking_lead.max)?;
    if weights.len() < 2 {
        return Err(DemandError::NoPairs(weights.len()));
    }
    let cumulative: Vec<f64> = weights
        .iter()
        .scan(0.0, |sum, &w| {
            *sum += w;
            Some(*sum)
        })
        .collect();
    let width = spec.count.to_string().len();
    let span = spec.end.0 - spec.start.0;
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let mut lead_rng = ChaCha8Rng::seed_from_u64(spec.seed);
    lead_rng.set_stream(LEAD_STREAM);
    Ok((0..spec.count)
        .map(|i| {
            let departure = Instant(spec.start.0 + rng.random_range(0..span));
            let from = pick(&cumulative, &mut rng);
            let mut to = pick(&cumulative, &mut rng);
            while to == from {
                to = pick(&cumulative, &mut rng);
            }
            let submitted = if lead.is_none() {
                departure
            } else {
                departure - Millis(lead_rng.random_range(lead.min.0..=lead.max.0))
            };
            Trip {
                id: format!("r{:0width$}", i + 1),
                from,
                to,
                departure,
                submitted,
            }
        })
        .collect())
}

/// The trip's request when both its customers have a pad and the pads differ (`pads[c]`:
/// customer `c`'s serving pad, if any), else why it is unserved.
///
/// ```
/// use muse_model::{Instant, NodeId};
/// use muse_sim::customers::trips::{request_for, Trip, Unserved};
/// let trip = Trip { id: "r1".into(), from: 0, to: 1, departure: Instant(0), submitted: Instant(0) };
/// let r = request_for(&trip, &[Some(NodeId(4)), Some(NodeId(7))]).unwrap();
/// assert_eq!((r.origin, r.destination), (NodeId(4), NodeId(7)));
/// assert_eq!(request_for(&trip, &[Some(NodeId(4)), None]), Err(Unserved::NoPadInReach { from: false, to: true }));
/// assert_eq!(request_for(&trip, &[Some(NodeId(4)), Some(NodeId(4))]), Err(Unserved::SamePad));
/// ```
pub fn request_for(trip: &Trip, pads: &[Option<NodeId>]) -> Result<Request, Unserved> {
    match (pads[trip.from], pads[trip.to]) {
        (Some(o), Some(d)) if o == d => Err(Unserved::SamePad),
        (Some(origin), Some(destination)) => Ok(Request {
            id: trip.id.clone(),
            origin,
            destination,
            departure: trip.departure,
            submitted: trip.submitted,
        }),
        (o, d) => Err(Unserved::NoPadInReach {
            from: o.is_none(),
            to: d.is_none(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(seed: u64) -> TripSpec {
        TripSpec {
            count: 3_000,
            start: Instant(1_000),
            end: Instant(61_000),
            seed,
            booking_lead: BookingLead::NONE,
        }
    }

    #[test]
    fn trips_follow_the_weights_and_the_window() {
        let weights = [1.0, 2.0, 3.0, 4.0];
        for seed in [1, 2] {
            println!("seed {seed}");
            let trips = draw_trips(&weights, &spec(seed)).unwrap();
            assert_eq!(trips.len(), 3_000);
            assert_eq!(trips[0].id, "r0001");
            assert!(trips.iter().all(|t| t.from != t.to && t.to < 4));
            assert!(
                trips
                    .iter()
                    .all(|t| (Instant(1_000)..Instant(61_000)).contains(&t.departure))
            );
            // Senders are drawn by weight: shares 0.1, 0.2, 0.3, 0.4 within a few points.
            for (c, w) in weights.iter().enumerate() {
                let share = trips.iter().filter(|t| t.from == c).count() as f64 / 3_000.0;
                assert!((share - w / 10.0).abs() < 0.03, "customer {c}: {share}");
            }
        }
        assert_ne!(
            draw_trips(&weights, &spec(1)).unwrap(),
            draw_trips(&weights, &spec(2)).unwrap()
        );
    }

    #[test]
    fn a_booking_lead_moves_only_the_submission() {
        let lead = BookingLead::new(Millis::from_mins(1), Millis::from_mins(5)).unwrap();
        let plain = draw_trips(&[1.0, 1.0, 1.0], &spec(3)).unwrap();
        let booked = draw_trips(
            &[1.0, 1.0, 1.0],
            &TripSpec {
                booking_lead: lead,
                ..spec(3)
            },
        )
        .unwrap();
        for (a, b) in plain.iter().zip(&booked) {
            assert_eq!((a.from, a.to, a.departure), (b.from, b.to, b.departure));
            let ahead = b.departure - b.submitted;
            assert!((Millis::from_mins(1)..=Millis::from_mins(5)).contains(&ahead));
        }
    }

    #[test]
    fn refusals() {
        assert_eq!(draw_trips(&[1.0], &spec(1)), Err(DemandError::NoPairs(1)));
        let empty = TripSpec {
            end: Instant(1_000),
            ..spec(1)
        };
        assert_eq!(
            draw_trips(&[1.0, 1.0], &empty),
            Err(DemandError::EmptyWindow)
        );
    }
}
