//! The world a call plans on, from its `airspace` and `zones` arguments, loaded as the command
//! line loads it ([`muse_sim::world`]): the built-in Singapore default when no airspace is
//! given, the scenario's own zones when no zones are.

use std::path::PathBuf;

use muse_model::Layers;
use muse_sim::world::{AirspaceSpec, World, ZonesSpec};
use pyo3::prelude::*;

use crate::airspace::Airspace;
use crate::error;

/// The world of `airspace` (the Singapore default when `None`) with `zones` (the airspace's
/// own when `None`, else these files, none when empty), flown at `layers`.
///
/// # Errors
/// A scenario or zone file that cannot be read, or layers the airspace cannot take; the
/// message names the file or keyword.
pub fn world(
    airspace: Option<&Airspace>,
    zones: Option<Vec<PathBuf>>,
    layers: &Layers,
) -> PyResult<World> {
    let airspace = match airspace {
        Some(a) => a.inner.clone(),
        None => AirspaceSpec::default().load().map_err(error)?,
    };
    let zones = zones.map_or(ZonesSpec::Own, ZonesSpec::Files);
    World::new(airspace, &zones)
        .map_err(error)?
        .layered(layers)
        .map_err(|e| error(format!("layers {}: {e}", layers.count)))
}
