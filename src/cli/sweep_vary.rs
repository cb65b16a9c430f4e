//! The levers `muse sweep --vary` compares: each `--vary` value's settings, and the variants
//! of a sweep as their cartesian product on the same seeds.

use muse_model::{EdgeRule, FlightParams, Millis};
use muse_sim::sweep::Variant;

use super::common::World;
use super::ranges::MAX_LIST;

/// A policy to compare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Vary {
    /// With and without the no-fly zones.
    Zones,
    /// `exclusive` versus `headway` edges (headway = the node separation unless given).
    EdgeRule,
    /// No ground delay versus up to 10 minutes.
    GroundDelay,
    /// Single legs versus battery swaps at stations of each `--swap-min` time
    /// (docs/reference.md#multi-leg-trips).
    BatterySwap,
    /// How much warning before a zone's first active window it is announced (`--leads`,
    /// `--announce-zones`); replays each day (docs/reference.md#zones-announced-during-the-day)
    /// with bookings made 0–120 min ahead unless `--booking-lead-min` says otherwise. Not
    /// combinable with other `--vary` values.
    AnnounceLead,
}

/// How a world's zones are named in legends: `CBD zone` for a built-in scenario's, `no zone`,
/// or the zone ids.
fn zone_label(world: &World) -> String {
    let names: Vec<&str> = world.zones.iter().map(|z| z.id.as_str()).collect();
    if names.is_empty() {
        "no zone".to_owned()
    } else if world.scenario.is_some() && names == [muse_scenario::CBD_ZONE_ID] {
        "CBD zone".to_owned()
    } else {
        format!("zones {}", names.join("+"))
    }
}

/// Parses `--swap-min`: positive minutes, comma-separated.
pub(super) fn parse_swap_times(text: &str) -> anyhow::Result<Vec<Millis>> {
    let bad = || {
        anyhow::anyhow!(
            "--swap-min `{text}`: expected at most {MAX_LIST} comma-separated minutes, each \
             from 0 to {MAX_SWAP_MIN}"
        )
    };
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() > MAX_LIST {
        return Err(bad());
    }
    parts
        .into_iter()
        .map(|x| {
            let m: f64 = x.trim().parse().map_err(|_| bad())?;
            if !(0.0..=MAX_SWAP_MIN).contains(&m) {
                return Err(bad());
            }
            Millis::from_secs_f64(m * 60.0).map_err(|_| bad())
        })
        .collect()
}

/// The longest swap time `--swap-min` compares: a day, as `--battery-swap-s`.
const MAX_SWAP_MIN: f64 = 1_440.0;

/// The settings `vary` compares, applied to `cur`, with their labels.
fn options(
    vary: Vary,
    cur: &Variant,
    world: &World,
    base: FlightParams,
    swap_times: &[Millis],
) -> anyhow::Result<Vec<(String, Variant)>> {
    let with_params = |params: FlightParams| Variant {
        params,
        ..cur.clone()
    };
    Ok(match vary {
        Vary::BatterySwap => {
            let limit = base.battery_swap.and_then(|s| s.max_legs);
            let mut out = vec![(
                "no swaps".to_owned(),
                with_params(FlightParams {
                    battery_swap: None,
                    ..cur.params
                }),
            )];
            for &time in swap_times {
                out.push((
                    format!("swaps {} min", time.as_secs_f64() / 60.0),
                    with_params(FlightParams {
                        battery_swap: Some(muse_model::BatterySwap {
                            time,
                            max_legs: limit,
                        }),
                        ..cur.params
                    }),
                ));
            }
            out
        }
        Vary::Zones => {
            if world.zones.is_empty() {
                anyhow::bail!("--vary zones needs zones (the embedded CBD zone, or --zones FILE)");
            }
            let with = zone_label(world);
            vec![
                (with, cur.clone()),
                (
                    "no zone".to_owned(),
                    Variant {
                        zones: Vec::new(),
                        ..cur.clone()
                    },
                ),
            ]
        }
        Vary::EdgeRule => {
            let h = match base.edge_rule {
                EdgeRule::Headway(h) => h,
                EdgeRule::Exclusive => base.node_separation,
            };
            vec![
                (
                    "exclusive".to_owned(),
                    with_params(FlightParams {
                        edge_rule: EdgeRule::Exclusive,
                        ..cur.params
                    }),
                ),
                (
                    format!("headway {:.0} s", h.as_secs_f64()),
                    with_params(FlightParams {
                        edge_rule: EdgeRule::Headway(h),
                        ..cur.params
                    }),
                ),
            ]
        }
        // Its own sweep (`sweep_lead`), refused in combination before variants are built.
        Vary::AnnounceLead => {
            anyhow::bail!("--vary announce-lead cannot be combined with other --vary values")
        }
        Vary::GroundDelay => vec![
            (
                "G_max 0".to_owned(),
                with_params(FlightParams {
                    max_ground_delay: Millis::ZERO,
                    ..cur.params
                }),
            ),
            (
                "G_max 10 min".to_owned(),
                with_params(FlightParams {
                    max_ground_delay: Millis::from_mins(10),
                    ..cur.params
                }),
            ),
        ],
    })
}

/// The variants: the cartesian product of the `--vary` choices (one base variant if none).
pub(super) fn variants(
    world: &World,
    base: FlightParams,
    vary: &[Vary],
    swap_times: &[Millis],
) -> anyhow::Result<Vec<Variant>> {
    let mut out = vec![Variant {
        name: String::new(),
        zones: world.zones.clone(),
        params: base,
    }];
    for &v in vary {
        let mut next = Vec::new();
        for cur in &out {
            for (label, mut variant) in options(v, cur, world, base, swap_times)? {
                variant.name = if cur.name.is_empty() {
                    label
                } else {
                    format!("{} / {label}", cur.name)
                };
                next.push(variant);
            }
        }
        out = next;
    }
    if out.len() == 1 && out[0].name.is_empty() {
        out[0].name = zone_label(world);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    #[test]
    fn swap_times() {
        use muse_model::Millis;
        assert_eq!(
            super::parse_swap_times("2, 0.5").unwrap(),
            vec![Millis::from_mins(2), Millis::from_secs(30)]
        );
        for bad in ["", "x", "-1", "2,,5"] {
            assert!(super::parse_swap_times(bad).is_err(), "{bad}");
        }
    }
}
