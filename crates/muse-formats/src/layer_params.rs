//! The layering (docs/reference.md#layered-airspace) in the units a user gives it — a number of
//! layers, metres, metres per second — as the command line's options (`--layers`,
//! `--base-altitude-m`, …) and the Python package's keywords (`layers=`, `base_altitude_m=`, …)
//! take it: one type, [`LayerParams`], turned into the model's [`Layers`] by one function,
//! [`LayerParams::to_layers`]. Each value's range is checked where it is read ([`crate::ranges`]);
//! what is left here is what the model's units require.
//!
//! ```
//! use muse_formats::layer_params::LayerParams;
//! use muse_model::HeadingRule;
//! let params = LayerParams { count: 4, heading_rule: HeadingRule::Sectors, ..LayerParams::default() };
//! let layers = params.to_layers().unwrap();
//! assert_eq!((layers.count, layers.climb_mm_per_s), (4, 5_000));
//! ```

use muse_model::{HeadingRule, Layers, Metres};

/// The layering in user units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerParams {
    /// Cruise layers `L` (1: the flat airspace).
    pub count: u32,
    /// Altitude of layer 1, metres.
    pub base_altitude_m: f64,
    /// Spacing between layers, metres.
    pub spacing_m: f64,
    /// Vertical speed, metres per second (whole millimetres per second).
    pub climb_mps: f64,
    /// Which directions each layer may be flown in.
    pub heading_rule: HeadingRule,
}

impl Default for LayerParams {
    /// The model's default layering: one layer at 60 m; when layered, 9.144 m apart, climbing
    /// at 5 m/s, no heading rule.
    ///
    /// ```
    /// use muse_formats::layer_params::LayerParams;
    /// let flat = LayerParams::default();
    /// assert_eq!((flat.count, flat.base_altitude_m, flat.spacing_m), (1, 60.0, 9.144));
    /// assert_eq!(flat.to_layers().unwrap(), muse_model::Layers::default());
    /// ```
    fn default() -> Self {
        let layers = Layers::default();
        LayerParams {
            count: layers.count,
            base_altitude_m: layers.base.m(),
            spacing_m: layers.spacing.m(),
            climb_mps: f64::from(layers.climb_mm_per_s) / 1e3,
            heading_rule: layers.heading_rule,
        }
    }
}

crate::fields::fields! {
    /// A member of [`LayerParams`], to name in an error: as the Python package's keyword
    /// (`base_altitude_m`) or as the command-line option that sets it (`--base-altitude-m`);
    /// in the order of the options.
    pub enum LayerField {
        /// The count, and the layering as a whole.
        Layers = "layers",
        BaseAltitudeM = "base_altitude_m",
        LayerSpacingM = "layer_spacing_m",
        ClimbMps = "climb_mps",
        HeadingRule = "heading_rule",
    }
}

/// Why [`LayerParams`] stand for no layering: the member, its value when the value is to
/// blame, and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.message(self.field.name()))]
pub struct LayerParamsError {
    /// The member.
    pub field: LayerField,
    /// The value refused, when it is the value that is refused.
    pub value: Option<f64>,
    /// What is wrong.
    pub problem: String,
}

impl LayerParamsError {
    fn new(field: LayerField, value: Option<f64>, problem: impl std::fmt::Display) -> Self {
        LayerParamsError {
            field,
            value,
            problem: problem.to_string(),
        }
    }

    /// The message with the member called `name`: `name value: problem`, or `name: problem`.
    fn message(&self, name: &str) -> String {
        match self.value {
            Some(v) => format!("{name} {v}: {}", self.problem),
            None => format!("{name}: {}", self.problem),
        }
    }

    /// The message with the member named as its command-line option
    /// (`--climb-mps 0.0005: …`).
    ///
    /// ```
    /// use muse_formats::layer_params::LayerParams;
    /// let e = LayerParams { climb_mps: 0.0005, ..LayerParams::default() }.to_layers().unwrap_err();
    /// assert_eq!(e.to_string(), "climb_mps 0.0005: give whole millimetres per second (at most 3 decimals)");
    /// assert!(e.as_option().starts_with("--climb-mps 0.0005: "));
    /// ```
    pub fn as_option(&self) -> String {
        self.message(&self.field.option())
    }
}

impl LayerParams {
    /// The layering these stand for: the vertical speed in whole millimetres per second, the
    /// heights in micrometres, checked as the model checks a layering
    /// ([`Layers::validate`]).
    ///
    /// # Errors
    /// A vertical speed that is not a whole number of millimetres per second, a height the
    /// model cannot hold, or a layering the model refuses.
    pub fn to_layers(&self) -> Result<Layers, LayerParamsError> {
        let mm = self.climb_mps * 1_000.0;
        let off = (mm - mm.round()).abs();
        if off.is_nan() || off >= 1e-6 {
            return Err(LayerParamsError::new(
                LayerField::ClimbMps,
                Some(self.climb_mps),
                "give whole millimetres per second (at most 3 decimals)",
            ));
        }
        let metres = |field: LayerField, m: f64| {
            Metres::from_m(m).map_err(|e| LayerParamsError::new(field, Some(m), e))
        };
        let layers = Layers {
            count: self.count,
            base: metres(LayerField::BaseAltitudeM, self.base_altitude_m)?,
            spacing: metres(LayerField::LayerSpacingM, self.spacing_m)?,
            climb_mm_per_s: u32::try_from(mm.round() as i64)
                .map_err(|e| LayerParamsError::new(LayerField::ClimbMps, None, e))?,
            heading_rule: self.heading_rule,
        };
        layers
            .validate()
            .map_err(|e| LayerParamsError::new(LayerField::Layers, None, e))?;
        Ok(layers)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_problem_is_named_as_a_keyword_and_as_an_option() {
        let bad = |params: LayerParams| params.to_layers().unwrap_err();
        let e = bad(LayerParams {
            base_altitude_m: 2e9,
            ..LayerParams::default()
        });
        assert_eq!(e.field, LayerField::BaseAltitudeM);
        assert!(
            e.to_string()
                .starts_with("base_altitude_m 2000000000: length")
        );
        assert!(
            e.as_option()
                .starts_with("--base-altitude-m 2000000000: length")
        );
        let e = bad(LayerParams {
            count: 0,
            ..LayerParams::default()
        });
        assert_eq!(e.to_string(), "layers: 0 layers: give 1 to 64");
        assert_eq!(e.as_option(), "--layers: 0 layers: give 1 to 64");
        let e = bad(LayerParams {
            climb_mps: 1e7,
            ..LayerParams::default()
        });
        assert_eq!(e.field, LayerField::ClimbMps);
        assert!(
            e.as_option().starts_with("--climb-mps: "),
            "{}",
            e.as_option()
        );
    }

    #[test]
    fn the_names_are_the_keywords() {
        assert_eq!(
            LayerField::NAMES,
            [
                "layers",
                "base_altitude_m",
                "layer_spacing_m",
                "climb_mps",
                "heading_rule"
            ]
        );
        assert_eq!(LayerField::LayerSpacingM.option(), "--layer-spacing-m");
    }
}
