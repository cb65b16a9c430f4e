//! `--vary tau`: the node separation `tau` of the flight model
//! (docs/reference.md#flight-model-and-separation: two stays at a node at least `tau` apart), one
//! variant per `--tau-s` value.

use muse_model::FlightParams;

use super::lever::{Base, Lever, LeverError, Setting, durations, with_params};
use crate::experiment::sweep::variant::Variant;

/// The longest separation `--tau-s` compares: an hour, as `--node-separation-s`.
const MAX_TAU_S: f64 = 3_600.0;

/// The node separation `tau` at each `--tau-s` value; the edge rule is kept as given (a
/// headway that defaults to `tau` is the one of `--node-separation-s`).
pub struct Tau;

impl Lever for Tau {
    fn name(&self) -> &'static str {
        "tau"
    }

    fn help(&self) -> &'static str {
        "The node separation `tau` at each `--tau-s` value (docs/reference.md#flight-model-and-separation)"
    }

    fn setting(&self) -> Option<Setting> {
        Some(Setting {
            name: "tau-s",
            value_name: "S,...",
            help: "`--vary tau`: the node separations `tau` to compare, seconds, \
                   comma-separated, each from 0 to 3600, at most 100 [default: 2,5,10]",
            default: "2,5,10",
        })
    }

    fn apply(
        &self,
        _: &Base<'_>,
        current: &Variant,
        value: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let taus = durations("--tau-s", value, "seconds", 1.0, MAX_TAU_S)?;
        Ok(taus
            .into_iter()
            .map(|tau| {
                let params = FlightParams {
                    node_separation: tau,
                    ..current.params
                };
                (
                    format!("tau {} s", tau.as_secs_f64()),
                    with_params(current, params),
                )
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use muse_model::{FlightParams, Instant, Millis};

    use crate::demand::{BookingLead, OdRule};
    use crate::experiment::sweep::levers::{Base, variants};
    use crate::experiment::sweep::{Airspaces, RunRecord, Sweep};
    use crate::experiment::{Experiment, Grid, Kind as _, Seeds, Shard};

    /// `--vary tau --tau-s 0.5,120` on the embedded default: 2 variants × 400 requests × 2
    /// repetitions, pairs within range, seeds 3 and 4.
    fn tau_sweep(s: &muse_scenario::Scenario) -> Experiment<Sweep<'_>> {
        let at = |h: i64| Instant::at_local(s.date, Millis::from_mins(h * 60), s.offset);
        let params = FlightParams::default();
        let grid = Grid {
            counts: vec![400],
            reps: 2,
            seeds: Seeds::PerDay(3),
            start: at(9),
            end: at(11),
            od: OdRule::InRange {
                speed: params.speed,
                max_flight: params.max_flight,
            },
            booking_lead: BookingLead::NONE,
            params,
        };
        let base = Base {
            params,
            zones: &[],
            zone_label: "no zone",
        };
        let variants = variants(&base, &["tau"], &[("tau-s", "0.5,120")]).unwrap();
        // Tests only: the sweep borrows its airspaces for the test's whole run.
        let airspaces = Box::leak(Box::new(Airspaces::new(&s.airspace, &variants).unwrap()));
        Experiment {
            kind: Sweep::new(airspaces, &grid, variants, None).unwrap(),
            grid,
        }
    }

    #[test]
    fn tau_varies_the_node_separation_on_the_same_seeds() {
        let s = muse_scenario::singapore_77();
        let exp = tau_sweep(&s);
        assert_eq!(exp.kind.cases(), ["tau 0.5 s", "tau 120 s"]);
        let separations: Vec<Millis> = exp
            .kind
            .variants()
            .iter()
            .map(|v| v.params.node_separation)
            .collect();
        assert_eq!(separations, [Millis(500), Millis::from_secs(120)]);
        assert!(
            exp.kind
                .variants()
                .iter()
                .all(|v| v.params.edge_rule == FlightParams::default().edge_rule)
        );

        let records: Vec<RunRecord> = exp
            .run(Shard::WHOLE, &|_| {})
            .unwrap()
            .into_iter()
            .map(|(_, r)| r)
            .collect();
        let results = exp.results(&records).unwrap();
        let runs = &results.files[0].1;
        let rows: Vec<Vec<&str>> = runs.lines().map(|l| l.split(',').collect()).collect();
        assert_eq!(rows[0][..4], ["variant", "count", "rep", "seed"]);
        let cells: Vec<(&str, &str, &str)> = rows[1..].iter().map(|r| (r[0], r[2], r[3])).collect();
        assert_eq!(
            cells,
            [
                ("tau 0.5 s", "0", "3"),
                ("tau 0.5 s", "1", "4"),
                ("tau 120 s", "0", "3"),
                ("tau 120 s", "1", "4"),
            ]
        );
        // The same requests, each a flight in range: two minutes between stays at a node cost
        // plans — waits in the air or refusals — that half a second does not.
        for rep in 0..2 {
            let (near, far) = (&records[rep], &records[2 + rep]);
            assert_eq!((near.seed, near.count), (far.seed, far.count));
            assert_eq!(near.out_of_range + near.unreachable, 0);
            let cost = |r: &RunRecord| (r.count - r.planned, r.mean_air_delay_s);
            assert!(
                far.planned < near.planned || far.mean_air_delay_s > near.mean_air_delay_s,
                "rep {rep}: tau 120 s {:?}, tau 0.5 s {:?}",
                cost(far),
                cost(near)
            );
        }
        let summary = &results.files[1].1;
        assert!(summary.lines().nth(1).unwrap().starts_with("tau 0.5 s,400,2,"));
        assert!(summary.lines().nth(2).unwrap().starts_with("tau 120 s,400,2,"));

        let refused = variants(
            &Base {
                params: FlightParams::default(),
                zones: &[],
                zone_label: "no zone",
            },
            &["tau"],
            &[("tau-s", "5,3601")],
        )
        .unwrap_err();
        assert_eq!(
            refused.to_string(),
            "--tau-s `5,3601`: expected at most 100 comma-separated seconds, each from 0 to 3600"
        );
    }
}
