//! The grid every kind of experiment runs on: request counts × repetitions, each day's seed,
//! its departure window and origin–destination rule, how far ahead requests are booked, and
//! the base flight parameters.

use muse_model::{FlightParams, Instant, Millis};

use crate::demand::{BookingLead, DemandSpec, OdRule};

/// How a day's demand seed follows from its count and repetition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seeds {
    /// Repetition `r` of the count at index `c` uses `base + c · reps + r`: every day of the
    /// grid has its own seed (the sweeps).
    PerDay(u64),
    /// Every day uses this one seed (the benchmark: one run per demand level).
    Same(u64),
}

/// Counts × repetitions and what the demand of each day is made of.
///
/// A *day* is one (count index, repetition): one seeded day of demand, planned once per case
/// of the experiment, so that every case sees the same requests.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Request counts, in the order runs are numbered and reported.
    pub counts: Vec<usize>,
    /// Repetitions per count (at least one).
    pub reps: usize,
    /// The seed of each day.
    pub seeds: Seeds,
    /// Departure window start.
    pub start: Instant,
    /// Departure window end (exclusive).
    pub end: Instant,
    /// Origin–destination rule.
    pub od: OdRule,
    /// How far ahead of departure requests are booked.
    pub booking_lead: BookingLead,
    /// The flight parameters the cases start from.
    pub params: FlightParams,
}

impl Grid {
    /// The seed of repetition `rep` of count index `count_index`.
    ///
    /// ```
    /// # use muse_model::{FlightParams, Instant};
    /// # use muse_sim::demand::{BookingLead, OdRule};
    /// use muse_sim::experiment::{Grid, Seeds};
    /// let grid = Grid {
    ///     counts: vec![100, 200], reps: 3, seeds: Seeds::PerDay(10),
    ///     start: Instant(0), end: Instant(3_600_000), od: OdRule::Uniform,
    ///     booking_lead: BookingLead::NONE, params: FlightParams::default(),
    /// };
    /// assert_eq!(grid.seed(1, 2), 15);
    /// assert_eq!(grid.seed_range(), (10, 15));
    /// assert_eq!(grid.days(), vec![(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2)]);
    /// ```
    pub fn seed(&self, count_index: usize, rep: usize) -> u64 {
        match self.seeds {
            Seeds::PerDay(base) => base + (count_index * self.reps + rep) as u64,
            Seeds::Same(seed) => seed,
        }
    }

    /// The first and last seed of the grid.
    pub fn seed_range(&self) -> (u64, u64) {
        let days = self.counts.len() * self.reps;
        (self.seed(0, 0), self.seed(0, days.max(1) - 1))
    }

    /// Every day's (count index, repetition), in run order: count, then repetition.
    pub fn days(&self) -> Vec<(usize, usize)> {
        (0..self.counts.len())
            .flat_map(|c| (0..self.reps).map(move |r| (c, r)))
            .collect()
    }

    /// The demand of repetition `rep` of count index `count_index`.
    pub fn demand(&self, count_index: usize, rep: usize) -> DemandSpec {
        DemandSpec {
            count: self.counts[count_index],
            start: self.start,
            end: self.end,
            seed: self.seed(count_index, rep),
            od: self.od,
            booking_lead: self.booking_lead,
        }
    }

    /// Requests in one run of every day: the sum of the counts × repetitions.
    pub fn requests_per_case(&self) -> usize {
        self.counts.iter().sum::<usize>() * self.reps
    }

    /// The range zone closures are resolved over for flights of `params`: from a day before
    /// the earliest possible submission to a day after the latest possible landing.
    pub fn closure_range(&self, params: &FlightParams) -> (Instant, Instant) {
        let day = Millis::from_secs(86_400);
        (
            self.start - self.booking_lead.max - day,
            self.end + params.trip_span() + day,
        )
    }
}

/// A booking lead in files: `[min, max]` in milliseconds.
pub(crate) mod booking_lead_ms {
    use muse_model::Millis;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use crate::demand::BookingLead;

    pub fn serialize<S: Serializer>(lead: &BookingLead, s: S) -> Result<S::Ok, S::Error> {
        [lead.min.0, lead.max.0].serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<BookingLead, D::Error> {
        let [min, max] = <[i64; 2]>::deserialize(d)?;
        Ok(BookingLead {
            min: Millis(min),
            max: Millis(max),
        })
    }
}

/// A booking lead's bound in minutes, as the CSV files write it (`0`, `120`, `0.5`).
pub(crate) fn minutes(m: Millis) -> String {
    (m.as_secs_f64() / 60.0).to_string()
}
