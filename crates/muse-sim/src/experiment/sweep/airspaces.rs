//! The airspace each variant of a sweep is flown on: the flat one, or it layered
//! (docs/reference.md#layered-airspace), each built once before the sweep runs. Demand is drawn on
//! the flat airspace, whose station indices layer 1 keeps, so every variant plans the same days.

use muse_model::{Airspace, AirspaceError, Layers};

use super::variant::Variant;

/// The flat airspace and every layering the variants need.
#[derive(Debug)]
pub struct Airspaces {
    flat: Airspace,
    layered: Vec<(Layers, Airspace)>,
}

impl Airspaces {
    /// The airspaces of `variants` on the flat airspace `flat`.
    ///
    /// # Errors
    /// When a layer copy's id is already taken in `flat` ([`Airspace::layered`]).
    pub fn new(flat: &Airspace, variants: &[Variant]) -> Result<Self, AirspaceError> {
        let flat = flat.flat().clone();
        let mut layered: Vec<(Layers, Airspace)> = Vec::new();
        for v in variants.iter().filter(|v| v.layers.is_layered()) {
            if !layered.iter().any(|(l, _)| *l == v.layers) {
                layered.push((v.layers, flat.layered(&v.layers)?));
            }
        }
        Ok(Airspaces { flat, layered })
    }

    /// The flat airspace.
    pub fn flat(&self) -> &Airspace {
        &self.flat
    }

    /// The airspace flown at `layers` (the flat one for one layer).
    ///
    /// # Panics
    /// If `layers` was not among the variants given to [`Airspaces::new`].
    pub fn of(&self, layers: &Layers) -> &Airspace {
        if !layers.is_layered() {
            return &self.flat;
        }
        self.layered
            .iter()
            .find(|(l, _)| l == layers)
            .map(|(_, a)| a)
            .expect("every variant's layering was built")
    }
}
