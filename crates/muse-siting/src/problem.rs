//! The prepared siting problem: existing pads, candidate pads, customers and the seeded days of
//! demand between them, with each customer's pads in reach computed once (prepare once,
//! evaluate many pad sets).
//!
//! Pads are numbered in one index space: the existing pads `0..E`, then the candidates
//! `E..E + C`; a pad set is given as the candidates added, by candidate index `0..C`, in the
//! order they are added. The airspace of a set is built from the existing pads followed by the
//! added candidates in that order, so a customer's serving pad (the nearest in reach; ties:
//! the pad first in the airspace) is what [`serving_pads`](muse_sim::customers::serving_pads)
//! finds on the rebuilt airspace.

use muse_airspace::builder::BuildOptions;
use muse_formats::customers::Customer;
use muse_model::{FlightParams, Instant, LonLat, Node, Zone};
use muse_sim::customers::pads_in_reach;
use muse_sim::customers::trips::{Trip, TripSpec, draw_trips};
use muse_sim::day::closure_window;

use crate::SitingError;

/// Everything a siting problem is made of.
#[derive(Clone, Debug)]
pub struct SitingInput {
    /// The pads already there (stations), in airspace order.
    pub existing: Vec<Node>,
    /// The pads that may be added.
    pub candidates: Vec<Node>,
    /// Where deliveries start and end.
    pub customers: Vec<Customer>,
    /// How far a customer is from its pad at most, metres (straight line).
    pub last_mile_m: f64,
    /// The seeded days of demand: every pad set is judged on all of them.
    pub days: Vec<TripSpec>,
    /// Flight parameters (battery swaps included).
    pub params: FlightParams,
    /// No-fly zones, known from the start.
    pub zones: Vec<Zone>,
    /// How airspaces are built from pads.
    pub build: BuildOptions,
}

/// A siting problem, prepared: see the [module documentation](self).
#[derive(Debug)]
pub struct Siting {
    pub(crate) input: SitingInput,
    /// The trips of each day, in planning order `(submitted, id)`.
    pub(crate) trips: Vec<Vec<Trip>>,
    /// For each customer, every pad (existing or candidate) in reach, nearest first.
    pub(crate) reach: Vec<Vec<(usize, f64)>>,
    /// The instants whose zone closures can matter to any day.
    pub(crate) window: (Instant, Instant),
}

impl Siting {
    /// Checks the input, draws the days' trips and finds each customer's pads in reach.
    ///
    /// # Errors
    /// No candidates or days; a candidate with the id or the position of another pad; a zone
    /// announced or withdrawn during the day; demand that cannot be drawn.
    pub fn prepare(input: SitingInput) -> Result<Self, SitingError> {
        if input.candidates.is_empty() {
            return Err(SitingError::NoCandidates);
        }
        if input.days.is_empty() {
            return Err(SitingError::NoDays);
        }
        if let Some(z) = input
            .zones
            .iter()
            .find(|z| z.announced.is_some() || z.withdrawn.is_some())
        {
            return Err(SitingError::ZoneDuringDay(z.id.clone()));
        }
        check_pads(&input.existing, &input.candidates)?;
        let weights: Vec<f64> = input.customers.iter().map(|c| c.weight).collect();
        let trips = input
            .days
            .iter()
            .map(|spec| {
                let mut day = draw_trips(&weights, spec)?;
                day.sort_by(|a, b| a.submitted.cmp(&b.submitted).then_with(|| a.id.cmp(&b.id)));
                Ok(day)
            })
            .collect::<Result<Vec<_>, SitingError>>()?;
        let pads: Vec<LonLat> = input
            .existing
            .iter()
            .chain(&input.candidates)
            .map(|n| n.pos)
            .collect();
        let customers: Vec<LonLat> = input.customers.iter().map(|c| c.pos).collect();
        let reach = pads_in_reach(&pads, &customers, input.last_mile_m);
        let first = trips.iter().flatten().map(|t| t.submitted).min();
        let last = trips.iter().flatten().map(|t| t.departure).max();
        let window = closure_window(
            first.unwrap_or_default(),
            last.unwrap_or_default(),
            &input.params,
        );
        Ok(Siting {
            input,
            trips,
            reach,
            window,
        })
    }

    /// The problem as given.
    pub fn input(&self) -> &SitingInput {
        &self.input
    }

    /// The candidate pads.
    pub fn candidates(&self) -> &[Node] {
        &self.input.candidates
    }

    /// The number of seeded days every pad set is judged on.
    pub fn day_count(&self) -> usize {
        self.trips.len()
    }

    /// The instants whose zone closures can matter to any day (what zones are resolved over).
    pub fn window(&self) -> (Instant, Instant) {
        self.window
    }

    /// The trips of day `d`, in planning order.
    pub fn trips(&self, d: usize) -> &[Trip] {
        &self.trips[d]
    }

    /// For each customer, every pad in reach as `(pad, metres)`, nearest first: pads `0..E`
    /// are the existing ones, `E + c` is candidate `c`.
    pub fn reach(&self) -> &[Vec<(usize, f64)>] {
        &self.reach
    }
}

/// Refuses a candidate with the id or the exact position of an existing pad or of an earlier
/// candidate.
fn check_pads(existing: &[Node], candidates: &[Node]) -> Result<(), SitingError> {
    let mut ids = std::collections::HashSet::new();
    let mut at = std::collections::HashMap::new();
    for n in existing {
        ids.insert(n.id.as_str());
        at.insert((n.pos.lon.to_bits(), n.pos.lat.to_bits()), n.id.as_str());
    }
    for c in candidates {
        if !ids.insert(c.id.as_str()) {
            return Err(SitingError::DuplicateId(c.id.clone()));
        }
        if let Some(other) = at.insert((c.pos.lon.to_bits(), c.pos.lat.to_bits()), &c.id) {
            return Err(SitingError::SamePosition {
                id: c.id.clone(),
                other: other.to_owned(),
            });
        }
    }
    Ok(())
}

/// A small problem for examples and tests: four pads on a 3 km square, five candidates around
/// it, customers on a grid, two seeded days of 300 trips, single legs.
#[doc(hidden)]
pub fn example_input() -> SitingInput {
    use muse_model::NodeKind;
    use muse_sim::demand::BookingLead;
    let pad = |id: String, lon: f64, lat: f64| Node {
        id,
        kind: NodeKind::Station,
        name: String::new(),
        pos: LonLat::new(lon, lat),
    };
    let step = 0.027; // about 3 km
    let existing = (0..4)
        .map(|i| {
            pad(
                format!("P{i}"),
                103.80 + step * f64::from(i % 2),
                1.30 + step * f64::from(i / 2),
            )
        })
        .collect();
    let candidates = [(0.5, 0.5), (1.5, 0.5), (0.5, 1.5), (-0.5, 0.5), (0.5, -0.5)]
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| pad(format!("C{i}"), 103.80 + step * x, 1.30 + step * y))
        .collect();
    let customers = (0..36)
        .map(|i| Customer {
            id: format!("c{i}"),
            pos: LonLat::new(
                103.80 - 0.5 * step + 0.4 * step * f64::from(i % 6),
                1.30 - 0.5 * step + 0.4 * step * f64::from(i / 6),
            ),
            weight: 1.0,
        })
        .collect();
    let day = |seed| TripSpec {
        count: 300,
        start: Instant(0),
        end: Instant(3_600_000),
        seed,
        booking_lead: BookingLead::NONE,
    };
    SitingInput {
        existing,
        candidates,
        customers,
        last_mile_m: 1_000.0,
        days: vec![day(1), day(2)],
        params: FlightParams::default(),
        zones: Vec::new(),
        build: BuildOptions::default(),
    }
}
