//! `--vary planner`: first come, first served against the optimiser
//! (docs/reference.md#batch-planning), with `--optimize-iterations` steps of search.

use muse_optimize::Options;

use super::lever::{Base, Lever, LeverError, Setting};
use crate::day::Planning;
use crate::experiment::sweep::variant::Variant;

/// The most steps a sweep's optimiser may take per day.
const MAX_ITERATIONS: u64 = 1_000_000_000;

/// First come, first served, and the day planned as one batch.
pub struct Planners;

impl Lever for Planners {
    fn name(&self) -> &'static str {
        "planner"
    }

    fn help(&self) -> &'static str {
        "First come, first served against the day planned as one batch (--optimize-iterations)"
    }

    fn setting(&self) -> Option<Setting> {
        Some(Setting {
            name: "optimize-iterations",
            value_name: "N",
            help: "With --vary planner: the optimiser's steps per day, a whole number from 0 to \
                   1000000000 (seed 1; default 100000)",
            default: "100000",
        })
    }

    fn apply(
        &self,
        _: &Base<'_>,
        current: &Variant,
        value: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let iterations = value
            .trim()
            .parse::<u64>()
            .ok()
            .filter(|n| *n <= MAX_ITERATIONS)
            .ok_or_else(|| {
                LeverError(format!(
                    "--optimize-iterations `{value}`: expected a whole number of steps from 0 \
                     to {MAX_ITERATIONS}"
                ))
            })?;
        let options = Options {
            iterations,
            ..Options::default()
        };
        Ok(vec![
            ("FCFS".to_owned(), current.clone()),
            (
                "optimised".to_owned(),
                Variant {
                    planning: Planning::Optimized(options),
                    ..current.clone()
                },
            ),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::FlightParams;

    #[test]
    fn two_planners_and_a_bad_budget_is_named() {
        let base = Base {
            params: FlightParams::default(),
            zones: &[],
            zone_label: "no zone",
        };
        let current = Variant {
            name: String::new(),
            zones: Vec::new(),
            params: FlightParams::default(),
            planning: Planning::FirstComeFirstServed,
            layers: muse_model::Layers::default(),
        };
        let got = Planners.apply(&base, &current, "500").unwrap();
        assert_eq!(got[0].0, "FCFS");
        assert_eq!(got[0].1.planning, Planning::FirstComeFirstServed);
        let Planning::Optimized(o) = got[1].1.planning else {
            panic!("{:?}", got[1]);
        };
        assert_eq!(o.iterations, 500);
        let e = Planners.apply(&base, &current, "-3").unwrap_err().to_string();
        assert!(e.starts_with("--optimize-iterations `-3`"), "{e}");
    }
}
