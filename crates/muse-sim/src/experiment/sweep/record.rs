//! What one run of the paper's sweep measured, and its row of `sweep.csv`.

use muse_model::{Airspace, EdgeKind, RejectReason, Request};
use muse_planner::Outcome;

use crate::demand::BookingLead;
use crate::experiment::grid::{booking_lead_ms, minutes};
use crate::experiment::report::Column;

/// The measurements of one run (serialized in shard files).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunRecord {
    /// Variant name.
    pub variant: String,
    /// Requests.
    pub count: usize,
    /// Repetition index.
    pub rep: usize,
    /// Demand seed.
    pub seed: u64,
    /// How far ahead of departure the run's requests were booked.
    #[serde(with = "booking_lead_ms")]
    pub booking_lead: BookingLead,
    /// Accepted.
    pub planned: usize,
    /// Rejected: out of range.
    pub out_of_range: usize,
    /// Rejected: unreachable.
    pub unreachable: usize,
    /// Rejected: no feasible plan.
    pub no_feasible_plan: usize,
    /// `planned / count`.
    pub success_rate: f64,
    /// Mean air delay of planned requests, seconds.
    pub mean_air_delay_s: f64,
    /// Mean ground delay of planned requests, seconds.
    pub mean_ground_delay_s: f64,
    /// Planner wall time of the run, milliseconds.
    pub planner_ms: f64,
    /// Labels expanded per request.
    pub expanded_per_request: f64,
    /// Mean legs per planned trip (1 without battery swaps).
    pub legs_per_trip: f64,
    /// On a layered airspace (docs/reference.md#layered-airspace), how the vertical links were
    /// used; `None` when flat.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_use: Option<LayerUse>,
    /// How close the day's flights come in metres (docs/reference.md#metric-separation), when
    /// the sweep compares separations; `None` otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach: Option<Approach>,
}

/// How close a day's planned flights come, flown exactly as planned.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Approach {
    /// The closest approach of any two flights, metres (`None`: never two within 5 km).
    pub closest_m: Option<f64>,
    /// Pairs of flights closer than 10 m.
    pub pairs_under_10m: usize,
    /// Pairs of flights closer than 30 m.
    pub pairs_under_30m: usize,
}

impl Approach {
    /// How close the planned `outcomes` of `requests` (one each, in order) come over
    /// `airspace` (its nodes where its plane puts them), with the vertical separation
    /// `vertical_m`.
    #[must_use]
    pub fn of(
        airspace: &Airspace,
        requests: &[Request],
        outcomes: &[Outcome],
        vertical_m: f64,
    ) -> Approach {
        use muse_verify::approach::{Positions, report};
        let flights: Vec<muse_verify::Flight<'_>> = requests
            .iter()
            .zip(outcomes)
            .filter_map(|(r, o)| {
                o.result
                    .as_ref()
                    .ok()
                    .map(|p| muse_verify::Flight::new(&r.id, r, p))
            })
            .collect();
        let positions = Positions::new(airspace, &airspace.plane());
        let r = report(&positions, &flights, &[10.0, 30.0], vertical_m);
        // `under` answers in the order asked: 10 m, then 30 m.
        let under = |k: usize| r.under.get(k).map_or(0, |u| u.1);
        Approach {
            closest_m: r.closest.map(|c| (c.distance_m * 1000.0).round() / 1000.0),
            pairs_under_10m: under(0),
            pairs_under_30m: under(1),
        }
    }
}

/// How a day's planned flights used the vertical links of a layered airspace.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LayerUse {
    /// Time on vertical links over airborne time, all planned flights together.
    pub climb_share: f64,
    /// Vertical links crossed per planned flight.
    pub crossings_per_flight: f64,
    /// Crossings of the busiest vertical link in the day.
    pub busiest_link_crossings: usize,
}

impl LayerUse {
    /// The use of `airspace`'s vertical links by the planned `outcomes`, or `None` if
    /// `airspace` is flat.
    ///
    /// ```
    /// use muse_model::{Airspace, Instant, Layers, NodeId, Plan, Stay};
    /// use muse_planner::Outcome;
    /// use muse_sim::experiment::sweep::LayerUse;
    /// let air = Airspace::line(&[1_000.0]).layered(&Layers { count: 2, ..Layers::default() })
    ///     .unwrap();
    /// let stay = |n, t| Stay { node: NodeId(n), arrive: Instant(t), depart: Instant(t) };
    /// // A → A@2 (1,829 ms) → B@2 (120 s) → B (1,829 ms).
    /// let path = vec![stay(0, 0), stay(2, 1_829), stay(3, 121_829), stay(1, 123_658)];
    /// let flown = Outcome { result: Ok(Plan { path }), free_flow: None, expanded: 0 };
    /// let used = LayerUse::of(&air, &[flown]).unwrap();
    /// assert_eq!((used.crossings_per_flight, used.busiest_link_crossings), (2.0, 1));
    /// assert!((used.climb_share - 3_658.0 / 123_658.0).abs() < 1e-12);
    /// assert!(LayerUse::of(&Airspace::line(&[1_000.0]), &[]).is_none());
    /// ```
    pub fn of(airspace: &Airspace, outcomes: &[Outcome]) -> Option<Self> {
        airspace.layers()?;
        let mut crossings = vec![0usize; airspace.edge_count()];
        let (mut climbing, mut airborne, mut flights) = (0i64, 0i64, 0usize);
        for plan in outcomes.iter().filter_map(|o| o.result.as_ref().ok()) {
            flights += 1;
            for leg in plan.legs() {
                if let (Some(first), Some(last)) = (leg.first(), leg.last()) {
                    airborne += (last.depart - first.arrive).0;
                }
                for hop in leg.windows(2) {
                    let Some(e) = airspace.edge_between(hop[0].node, hop[1].node) else {
                        continue;
                    };
                    if let EdgeKind::Vertical { time, .. } = airspace.edge_kind(e) {
                        climbing += time.0;
                        crossings[e.index()] += 1;
                    }
                }
            }
        }
        let total: usize = crossings.iter().sum();
        Some(LayerUse {
            climb_share: if airborne > 0 {
                climbing as f64 / airborne as f64
            } else {
                0.0
            },
            crossings_per_flight: total as f64 / flights.max(1) as f64,
            busiest_link_crossings: crossings.into_iter().max().unwrap_or(0),
        })
    }
}

impl RunRecord {
    /// The record of `requests` planned with `outcomes` (one each, in order) in `wall`
    /// seconds of planner time, for the variant `variant`, repetition `rep`, demand `seed`.
    pub fn of(
        variant: &str,
        (rep, seed, booking_lead): (usize, u64, BookingLead),
        requests: &[Request],
        outcomes: &[Outcome],
        wall: std::time::Duration,
    ) -> Self {
        let mut rec = RunRecord {
            variant: variant.to_owned(),
            count: requests.len(),
            rep,
            seed,
            booking_lead,
            planned: 0,
            out_of_range: 0,
            unreachable: 0,
            no_feasible_plan: 0,
            success_rate: 0.0,
            mean_air_delay_s: 0.0,
            mean_ground_delay_s: 0.0,
            planner_ms: wall.as_secs_f64() * 1e3,
            expanded_per_request: 0.0,
            legs_per_trip: 0.0,
            layer_use: None,
            approach: None,
        };
        let (mut air, mut ground, mut expanded, mut legs) = (0i64, 0i64, 0u64, 0usize);
        for (req, o) in requests.iter().zip(outcomes) {
            expanded += o.expanded;
            match &o.result {
                Ok(plan) => {
                    rec.planned += 1;
                    air += (plan.airborne() - o.free_flow.unwrap_or(plan.airborne())).0;
                    ground += (plan.takeoff() - req.departure).0;
                    legs += plan.leg_count();
                }
                Err(RejectReason::OutOfRange) => rec.out_of_range += 1,
                Err(RejectReason::Unreachable) => rec.unreachable += 1,
                // A day planned in advance has no clock, so it never answers
                // `departure_in_past`; the planner never sees an `unserved` request.
                Err(
                    RejectReason::NoFeasiblePlan
                    | RejectReason::DepartureInPast
                    | RejectReason::Unserved,
                ) => {
                    rec.no_feasible_plan += 1;
                }
            }
        }
        let n = requests.len().max(1) as f64;
        let planned = rec.planned.max(1) as f64;
        rec.success_rate = rec.planned as f64 / n;
        rec.mean_air_delay_s = air as f64 / 1e3 / planned;
        rec.mean_ground_delay_s = ground as f64 / 1e3 / planned;
        rec.expanded_per_request = expanded as f64 / n;
        rec.legs_per_trip = legs as f64 / planned;
        rec
    }

    /// The record with the use of `airspace`'s vertical links by `outcomes` (none when
    /// `airspace` is flat).
    #[must_use]
    pub fn with_layers(mut self, airspace: &Airspace, outcomes: &[Outcome]) -> Self {
        self.layer_use = LayerUse::of(airspace, outcomes);
        self
    }
}

/// The columns of `sweep.csv`, one row per run; the last two are the run's booking lead
/// (uniform in `[from, to]` minutes; `0,0` for requests submitted at departure).
pub fn columns() -> Vec<Column<'static, RunRecord>> {
    vec![
        Column::new("variant", |r: &RunRecord| r.variant.clone()),
        Column::new("count", |r: &RunRecord| r.count.to_string()),
        Column::new("rep", |r: &RunRecord| r.rep.to_string()),
        Column::new("seed", |r: &RunRecord| r.seed.to_string()),
        Column::new("planned", |r: &RunRecord| r.planned.to_string()),
        Column::new("out_of_range", |r: &RunRecord| r.out_of_range.to_string()),
        Column::new("unreachable", |r: &RunRecord| r.unreachable.to_string()),
        Column::new("no_feasible_plan", |r: &RunRecord| {
            r.no_feasible_plan.to_string()
        }),
        Column::new("success_rate", |r: &RunRecord| {
            format!("{:.6}", r.success_rate)
        }),
        Column::new("mean_air_delay_s", |r: &RunRecord| {
            format!("{:.3}", r.mean_air_delay_s)
        }),
        Column::new("mean_ground_delay_s", |r: &RunRecord| {
            format!("{:.3}", r.mean_ground_delay_s)
        }),
        Column::new("planner_ms", |r: &RunRecord| format!("{:.3}", r.planner_ms)),
        Column::new("expanded_per_request", |r: &RunRecord| {
            format!("{:.3}", r.expanded_per_request)
        }),
        Column::new("legs_per_trip", |r: &RunRecord| {
            format!("{:.4}", r.legs_per_trip)
        }),
        Column::new("booking_lead_min_from", |r: &RunRecord| {
            minutes(r.booking_lead.min)
        }),
        Column::new("booking_lead_min_to", |r: &RunRecord| {
            minutes(r.booking_lead.max)
        }),
    ]
}

/// The columns a sweep that compares separations adds to `sweep.csv`: how close the flights
/// come ([`Approach`]; the closest approach empty when no two come within 5 km).
pub fn approach_columns() -> Vec<Column<'static, RunRecord>> {
    let cell = |f: fn(&Approach) -> String| {
        move |r: &RunRecord| r.approach.as_ref().map_or(String::new(), f)
    };
    vec![
        Column::new(
            "closest_m",
            cell(|a| a.closest_m.map_or(String::new(), |d| format!("{d:.3}"))),
        ),
        Column::new("pairs_under_10m", cell(|a| a.pairs_under_10m.to_string())),
        Column::new("pairs_under_30m", cell(|a| a.pairs_under_30m.to_string())),
    ]
}

/// The columns a sweep with layered variants adds to `sweep.csv`: the vertical links' use
/// ([`LayerUse`]; empty for a flat variant's runs).
pub fn layer_columns() -> Vec<Column<'static, RunRecord>> {
    let cell = |f: fn(&LayerUse) -> String| {
        move |r: &RunRecord| r.layer_use.as_ref().map_or(String::new(), f)
    };
    vec![
        Column::new("climb_share", cell(|u| format!("{:.6}", u.climb_share))),
        Column::new(
            "vertical_crossings_per_flight",
            cell(|u| format!("{:.4}", u.crossings_per_flight)),
        ),
        Column::new(
            "busiest_vertical_link_crossings",
            cell(|u| u.busiest_link_crossings.to_string()),
        ),
    ]
}
