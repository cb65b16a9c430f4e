//! A scenario variant of the paper's sweep: a name, the zones in force, the flight parameters,
//! the airspace's layers and how a day is planned.

use muse_model::{FlightParams, Layers, Zone};

use crate::day::Planning;

/// One scenario variant of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// Name shown in files and legends, e.g. `CBD zone` or `no zone`.
    pub name: String,
    /// Zones in force.
    pub zones: Vec<Zone>,
    /// Flight parameters.
    pub params: FlightParams,
    /// First come, first served, or as one batch (docs/reference.md#batch-planning).
    pub planning: Planning,
    /// The layers the airspace is flown at (docs/reference.md#layered-airspace; one: flat).
    pub layers: Layers,
}
