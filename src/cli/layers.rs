//! `--layers` and its options (docs/reference.md#layered-airspace): the airspace flown at several
//! cruise altitudes.

use anyhow::Context;
use clap::{ArgMatches, Args};
use muse_formats::layer_params::LayerParams;
use muse_model::{HeadingRule, Layers};
use muse_sim::metrics::recorded::LayersRecord;

use super::common::{World, warn_idle_zones};
use super::overrides::{Overridable, Summary, overridden};
use super::ranges;

/// The layering of the airspace (docs/reference.md#layered-airspace).
#[derive(Args, Debug, Clone)]
pub struct LayersArgs {
    /// Cruise layers `L`, from 1 to 64: the corridor graph is flown at `L` altitudes, joined
    /// by vertical links at every node (1: the paper's single altitude, every output as
    /// without layers).
    #[arg(long, default_value_t = 1, value_name = "L", allow_negative_numbers = true, value_parser = ranges::layers)]
    pub layers: u32,
    /// Altitude of layer 1, metres, from 0 to 10000 (with one layer it changes nothing).
    #[arg(long, default_value_t = 60.0, value_name = "M", allow_negative_numbers = true, value_parser = ranges::altitude_m)]
    pub base_altitude_m: f64,
    /// Spacing between layers, metres, from 0.001 to 1000 (default 9.144: 30 ft, as
    /// Metropolis 2).
    #[arg(long, default_value_t = 9.144, value_name = "M", allow_negative_numbers = true, value_parser = ranges::layer_spacing_m)]
    pub layer_spacing_m: f64,
    /// Vertical speed, metres per second, from 0.001 to 100 (whole millimetres per second).
    #[arg(long, default_value_t = 5.0, value_name = "MPS", allow_negative_numbers = true, value_parser = ranges::climb_mps)]
    pub climb_mps: f64,
    /// Which corridor directions each layer may be flown in: `none` (every direction) or
    /// `sectors` (layer k of L only for initial bearings in [(k−1)·360/L, k·360/L) degrees).
    #[arg(long, value_enum, default_value_t = HeadingArg::None)]
    pub heading_rule: HeadingArg,
}

/// `--heading-rule`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeadingArg {
    /// Every direction at every layer.
    None,
    /// One sector of initial bearings per layer.
    Sectors,
}

impl LayersArgs {
    /// The layering these options describe, in user units.
    pub fn params(&self) -> LayerParams {
        LayerParams {
            count: self.layers,
            base_altitude_m: self.base_altitude_m,
            spacing_m: self.layer_spacing_m,
            climb_mps: self.climb_mps,
            heading_rule: match self.heading_rule {
                HeadingArg::None => HeadingRule::None,
                HeadingArg::Sectors => HeadingRule::Sectors,
            },
        }
    }

    /// The layering these options describe.
    ///
    /// # Errors
    /// A vertical speed that is not a whole number of millimetres per second.
    pub fn layers(&self) -> anyhow::Result<Layers> {
        self.params()
            .to_layers()
            .map_err(|e| anyhow::anyhow!(e.as_option()))
    }
}

/// `world` flown at the layers `args` give (unchanged with one layer); `summary.json` records
/// them. A zone whose heights hold no layer is warned of.
///
/// # Errors
/// Options out of range, or a layer copy's id (`ID@k`) already taken in the airspace.
pub fn layered(world: World, args: &LayersArgs) -> anyhow::Result<World> {
    let layers = args.layers()?;
    let world = world
        .layered(&layers)
        .with_context(|| format!("--layers {}", layers.count))?;
    if layers.is_layered() {
        warn_idle_zones(&world, true);
    }
    Ok(world)
}

/// The layering options, by clap id (the summary's `world.layers` records them as `count`,
/// `base_altitude_m`, `spacing_m`, `climb_mps` and `heading_rule`).
const LAYER_OPTIONS: [&str; 5] = [
    "layers",
    "base_altitude_m",
    "layer_spacing_m",
    "climb_mps",
    "heading_rule",
];

/// The layering of a run, for `muse verify` and `muse view`: the one its summary records
/// (`world.layers`; flat when the world records none), each option the command line gives
/// overriding its own (said in `notes`); the command line's and the defaults without a summary
/// or when it records no world.
///
/// # Errors
/// A recorded layering out of range or inconsistent (its `climb_ms` not that of its spacing
/// and vertical speed), named by the summary's file and field.
pub fn recorded_layers(
    cli: &LayersArgs,
    matches: &ArgMatches,
    summary: Option<&Summary>,
    notes: &mut Vec<String>,
) -> anyhow::Result<LayersArgs> {
    let Some(world) = summary.and_then(|s| s.recorded.world.as_ref().map(|w| (s, w))) else {
        return Ok(cli.clone());
    };
    let (s, world) = world;
    let name = s.path.display();
    let recorded = match &world.layers {
        Some(rec) => args_of(rec).with_context(|| format!("{name}: field `world.layers`"))?,
        None => LayersArgs::flat(),
    };
    Ok(overridden(
        &recorded,
        cli,
        &LAYER_OPTIONS,
        matches,
        s,
        notes,
    ))
}

impl LayersArgs {
    /// One layer, every other option at its default.
    fn flat() -> Self {
        LayersArgs {
            layers: 1,
            base_altitude_m: 60.0,
            layer_spacing_m: 9.144,
            climb_mps: 5.0,
            heading_rule: HeadingArg::None,
        }
    }
}

/// The options a summary's layering stands for, each checked as the option would be.
fn args_of(rec: &LayersRecord) -> anyhow::Result<LayersArgs> {
    let check = |field: &str, text: String, parse: fn(&str) -> Result<f64, String>| {
        parse(&text).map_err(|e| anyhow::anyhow!("`{field}` {text}: {e}"))
    };
    ranges::layers(&rec.count.to_string())
        .map_err(|e| anyhow::anyhow!("`count` {}: {e}", rec.count))?;
    let args = LayersArgs {
        layers: rec.count,
        base_altitude_m: check(
            "base_altitude_m",
            rec.base_altitude_m.to_string(),
            ranges::altitude_m,
        )?,
        layer_spacing_m: check(
            "spacing_m",
            rec.spacing_m.to_string(),
            ranges::layer_spacing_m,
        )?,
        climb_mps: check("climb_mps", rec.climb_mps.to_string(), ranges::climb_mps)?,
        heading_rule: match rec.heading_rule.as_str() {
            "none" => HeadingArg::None,
            "sectors" => HeadingArg::Sectors,
            other => anyhow::bail!("`heading_rule` `{other}`: expected `none` or `sectors`"),
        },
    };
    let layers = args.layers()?;
    let climb = layers.climb_time().0;
    anyhow::ensure!(
        rec.climb_ms == climb,
        "`climb_ms` {}: {} m at {} m/s takes {climb} ms",
        rec.climb_ms,
        rec.spacing_m,
        rec.climb_mps
    );
    Ok(args)
}

/// The layering options by clap id ([`LAYER_OPTIONS`]).
impl Overridable for LayersArgs {
    fn value(&self, id: &str) -> String {
        match id {
            "layers" => self.layers.to_string(),
            "base_altitude_m" => self.base_altitude_m.to_string(),
            "layer_spacing_m" => self.layer_spacing_m.to_string(),
            "climb_mps" => self.climb_mps.to_string(),
            "heading_rule" => match self.heading_rule {
                HeadingArg::None => "none".to_owned(),
                HeadingArg::Sectors => "sectors".to_owned(),
            },
            _ => unreachable!("every id of LAYER_OPTIONS is listed"),
        }
    }

    fn set(&mut self, from: &LayersArgs, id: &str) {
        match id {
            "layers" => self.layers = from.layers,
            "base_altitude_m" => self.base_altitude_m = from.base_altitude_m,
            "layer_spacing_m" => self.layer_spacing_m = from.layer_spacing_m,
            "climb_mps" => self.climb_mps = from.climb_mps,
            "heading_rule" => self.heading_rule = from.heading_rule,
            _ => unreachable!("every id of LAYER_OPTIONS is listed"),
        }
    }
}

#[cfg(test)]
mod tests {
    use muse_model::Metres;

    use super::*;

    #[test]
    fn a_recorded_layering_reads_back_and_is_checked() {
        let layers = Layers {
            count: 4,
            base: Metres::from_mm(45_500),
            spacing: Metres::from_mm(12_000),
            climb_mm_per_s: 2_500,
            heading_rule: HeadingRule::Sectors,
        };
        let rec = LayersRecord::of(&layers);
        assert_eq!(args_of(&rec).unwrap().layers().unwrap(), layers);
        let err = |rec: LayersRecord| format!("{:#}", args_of(&rec).unwrap_err());
        assert_eq!(
            err(LayersRecord {
                climb_ms: 4_000,
                ..rec.clone()
            }),
            "`climb_ms` 4000: 12 m at 2.5 m/s takes 4800 ms"
        );
        assert_eq!(
            err(LayersRecord {
                heading_rule: "north".into(),
                ..rec.clone()
            }),
            "`heading_rule` `north`: expected `none` or `sectors`"
        );
        assert!(
            err(LayersRecord { count: 0, ..rec }).starts_with("`count` 0: must be"),
            "the option's range"
        );
    }
}
