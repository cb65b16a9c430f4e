//! `--vary ground-delay`: no ground delay against up to ten minutes.

use muse_model::{FlightParams, Millis};

use super::lever::{Base, Lever, LeverError, with_params};
use crate::experiment::sweep::variant::Variant;

/// `G_max` 0 against 10 minutes.
pub struct GroundDelay;

impl Lever for GroundDelay {
    fn name(&self) -> &'static str {
        "ground-delay"
    }

    fn help(&self) -> &'static str {
        "No ground delay versus up to 10 minutes"
    }

    fn apply(
        &self,
        _: &Base<'_>,
        current: &Variant,
        _: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let with = |g: Millis| {
            with_params(
                current,
                FlightParams {
                    max_ground_delay: g,
                    ..current.params
                },
            )
        };
        Ok(vec![
            ("G_max 0".to_owned(), with(Millis::ZERO)),
            ("G_max 10 min".to_owned(), with(Millis::from_mins(10))),
        ])
    }
}
