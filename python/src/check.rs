//! `verify`: a plans file checked against every rule (docs/reference.md#flight-model-and-separation
//! and #no-fly-zones, #zones-announced-during-the-day to #layered-airspace), independently of the
//! planner, as `muse verify` checks it.

use std::path::PathBuf;

use muse_formats::plans::read_plan_entries;
use muse_sim::metrics::SeparationSummary;
use muse_verify::recorded::{Recorded, zones_for};
use muse_verify::verify_known_in;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::airspace::Airspace;
use crate::error;
use crate::options::options;
use crate::world::world;

/// Checks the plans JSON Lines `plans` (named `source` in messages) on `airspace` with
/// `zones`, under the flight parameters and layers of the keywords. Returns `ok`, `flights`
/// (the number checked), `lines` (the lines read), `violations` (each as `muse verify`
/// prints it) and `separation`, how close the flights come in metres as JSON (the summary's
/// `separation`, docs/reference.md#metric-separation).
#[pyfunction]
#[pyo3(signature = (plans, source, airspace = None, zones = None, **kwargs))]
pub fn verify<'py>(
    py: Python<'py>,
    plans: &str,
    source: &str,
    airspace: Option<PyRef<'py, Airspace>>,
    zones: Option<Vec<PathBuf>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = options(kwargs)?;
    let world = world(airspace.as_deref(), zones, &opts.layers)?;
    let a = &world.airspace;
    let entries = read_plan_entries(plans, source, a).map_err(error)?;
    let records = entries.iter().filter_map(|e| e.record().cloned()).collect();
    let recorded = Recorded::new(records, a).map_err(|e| error(format!("{source}: {e}")))?;
    let (violations, flights, separation) = py.detach(|| {
        let flights = recorded.flights();
        let zones =
            zones_for(a, &world.zones, &flights).map_err(|e| error(format!("zones: {e}")))?;
        let violations: Vec<String> =
            verify_known_in(a, &zones, &opts.params, &flights, world.day.offset)
                .iter()
                .map(ToString::to_string)
                .collect();
        let separation = SeparationSummary::of(
            a,
            &a.plane(),
            &flights,
            world.day.offset,
            opts.params.separation,
        );
        let separation = serde_json::to_string(&separation).map_err(error)?;
        PyResult::Ok((violations, flights.len(), separation))
    })?;
    let out = PyDict::new(py);
    out.set_item("ok", violations.is_empty())?;
    out.set_item("flights", flights)?;
    out.set_item("lines", entries.len())?;
    out.set_item("violations", violations)?;
    out.set_item("separation", separation)?;
    Ok(out)
}
