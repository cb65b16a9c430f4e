//! `--layers` and its options (SPEC §13): the airspace flown at several cruise altitudes.

use anyhow::Context;
use clap::Args;
use muse_model::{HeadingRule, Layers, Metres};

use super::common::World;
use super::ranges;

/// The layering of the airspace (SPEC §13).
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
    /// The layering these options describe.
    ///
    /// # Errors
    /// A vertical speed that is not a whole number of millimetres per second.
    pub fn layers(&self) -> anyhow::Result<Layers> {
        let mm = self.climb_mps * 1_000.0;
        anyhow::ensure!(
            (mm - mm.round()).abs() < 1e-6,
            "--climb-mps {}: give whole millimetres per second (at most 3 decimals)",
            self.climb_mps
        );
        let metres =
            |m: f64, option: &str| Metres::from_m(m).with_context(|| format!("{option} {m}"));
        let layers = Layers {
            count: self.layers,
            base: metres(self.base_altitude_m, "--base-altitude-m")?,
            spacing: metres(self.layer_spacing_m, "--layer-spacing-m")?,
            climb_mm_per_s: u32::try_from(mm.round() as i64).context("--climb-mps")?,
            heading_rule: match self.heading_rule {
                HeadingArg::None => HeadingRule::None,
                HeadingArg::Sectors => HeadingRule::Sectors,
            },
        };
        layers.validate().context("--layers")?;
        Ok(layers)
    }
}

impl World {
    /// The world flown at the layers `args` give (unchanged with one layer); `summary.json`
    /// records them.
    ///
    /// # Errors
    /// Options out of range, or a layer copy's id (`ID@k`) already taken in the airspace.
    pub fn layered(mut self, args: &LayersArgs) -> anyhow::Result<World> {
        let layers = args.layers()?;
        if layers.is_layered() {
            self.airspace = self
                .airspace
                .layered(&layers)
                .with_context(|| format!("--layers {}", layers.count))?;
            self.record.layers = Some(muse_sim::metrics::recorded::LayersRecord::of(&layers));
        }
        Ok(self)
    }
}
