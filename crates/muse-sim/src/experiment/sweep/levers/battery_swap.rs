//! `--vary battery-swap`: single legs against battery swaps of each `--swap-min` time.

use muse_model::{BatterySwap, FlightParams};

use super::lever::{Base, Lever, LeverError, Setting, durations, with_params};
use crate::experiment::sweep::variant::Variant;

/// The longest swap time `--swap-min` compares: a day, as `--battery-swap-s`.
const MAX_SWAP_MIN: f64 = 1_440.0;

/// Single legs against swaps at stations of each `--swap-min` time
/// (docs/reference.md#multi-leg-trips); the leg limit is the base one (`--max-legs`).
pub struct BatterySwaps;

impl Lever for BatterySwaps {
    fn name(&self) -> &'static str {
        "battery-swap"
    }

    fn help(&self) -> &'static str {
        "Single legs versus battery swaps at stations of each `--swap-min` time \
         (docs/reference.md#multi-leg-trips)"
    }

    fn setting(&self) -> Option<Setting> {
        Some(Setting {
            name: "swap-min",
            value_name: "MIN,...",
            help: "`--vary battery-swap`: the swap times to compare with single legs, minutes, \
                   comma-separated, each from 0 to 1440, at most 100 [default: 2,5,10]",
            default: "2,5,10",
        })
    }

    fn apply(
        &self,
        base: &Base<'_>,
        current: &Variant,
        value: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let times = durations("--swap-min", value, "minutes", 60.0, MAX_SWAP_MIN)?;
        let max_legs = base.params.battery_swap.and_then(|s| s.max_legs);
        let with = |battery_swap| {
            with_params(
                current,
                FlightParams {
                    battery_swap,
                    ..current.params
                },
            )
        };
        let mut out = vec![("no swaps".to_owned(), with(None))];
        for time in times {
            out.push((
                format!("swaps {} min", time.as_secs_f64() / 60.0),
                with(Some(BatterySwap { time, max_legs })),
            ));
        }
        Ok(out)
    }
}
