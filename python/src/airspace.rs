//! The `Airspace` class: the corridor graph a day is planned on (docs/reference.md#airspace), from
//! a built-in scenario, a GeoJSON file, or a set of pads (docs/reference.md#airspace-from-pads).

use std::path::PathBuf;

use muse_airspace::builder::{BuildError, BuildOptions, build_airspace};
use muse_airspace::plane::Plane;
use muse_formats::day::FileDay;
use muse_formats::exclusions::Exclusions;
use muse_model::NodeKind;
use muse_sim::world::{AirspaceSpec, LoadedAirspace};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error;

/// An airspace: nodes (stations and waypoints) joined by corridors.
#[pyclass(module = "muse._muse", frozen)]
pub struct Airspace {
    /// The graph (flat: layers are applied when a day is planned) and where it came from: a
    /// built-in scenario (whose zones are the default zones), a file, or pads.
    pub inner: LoadedAirspace,
}

#[pymethods]
impl Airspace {
    /// A built-in scenario's airspace: `singapore-77` (the paper's 77 stations) or
    /// `singapore-all` (all 1,115 car parks).
    #[staticmethod]
    #[pyo3(signature = (name = "singapore-77"))]
    fn scenario(name: &str) -> PyResult<Self> {
        let inner = AirspaceSpec::Scenario(name.to_owned())
            .load()
            .map_err(error)?;
        Ok(Airspace { inner })
    }

    /// An airspace GeoJSON file (docs/reference.md#airspace), with the land outline and the day it
    /// may carry.
    #[staticmethod]
    fn read(path: PathBuf) -> PyResult<Self> {
        let inner = AirspaceSpec::File(path).load().map_err(error)?;
        Ok(Airspace { inner })
    }

    /// The airspace built from pads by the rule of docs/reference.md#airspace-from-pads, as `muse
    /// airspace build --pads` builds it: `pads` is the text of a pads CSV (`id,lon,lat[,name]`)
    /// named `source` in messages; `crs` the plane (`utm`, `EPSG:3414`, …); `exclude` GeoJSON files
    /// of polygons no corridor may cross; `max_corridor_m` the longest corridor; `time_zone` (an
    /// IANA name) or `utc_offset`, with `date`, the day it is planned on.
    #[staticmethod]
    #[pyo3(signature = (pads, source, crs = None, exclude = Vec::new(), max_corridor_m = None, time_zone = None, utc_offset = None, date = None))]
    #[allow(clippy::too_many_arguments)]
    fn from_pads_csv(
        pads: &str,
        source: &str,
        crs: Option<&str>,
        exclude: Vec<PathBuf>,
        max_corridor_m: Option<f64>,
        time_zone: Option<&str>,
        utc_offset: Option<&str>,
        date: Option<&str>,
    ) -> PyResult<Self> {
        let default = muse_scenario::by_name(muse_scenario::SINGAPORE_77).map_err(error)?;
        let day = FileDay::asked(time_zone, utc_offset, date, &default.date.to_string())
            .map_err(|e| error(format!("{}: {}", e.field, e.message)))?;
        let plane = match crs {
            Some(text) => Plane::parse(text).map_err(|e| error(format!("crs: {e}")))?,
            None => Plane::Utm,
        };
        let nodes = muse_formats::pads::read_pads(pads, source).map_err(error)?;
        let mut exclusions = Exclusions::read_files(&exclude).map_err(error)?;
        let opts = BuildOptions {
            plane,
            max_edge_length_m: max_corridor_m,
            exclusions: std::mem::take(&mut exclusions.polygons),
            ..BuildOptions::default()
        };
        let graph = build_airspace(nodes, &opts).map_err(|e| match e {
            BuildError::Excluded { id, polygon } => {
                error(exclusions.pad_inside(source, &id, polygon))
            }
            e => error(format!("building the airspace of {source}: {e}")),
        })?;
        let source = format!("built from the pads of {source}");
        Ok(Airspace {
            inner: LoadedAirspace::built(graph, source, day),
        })
    }

    /// Where the airspace came from.
    #[getter]
    fn source(&self) -> &str {
        &self.inner.source
    }

    /// The nodes as columns: `id`, `kind` (`station` or `waypoint`), `name`, `lon`, `lat`.
    fn node_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let nodes = self.inner.airspace.nodes();
        let columns = PyDict::new(py);
        columns.set_item(
            "id",
            nodes.iter().map(|n| n.id.as_str()).collect::<Vec<_>>(),
        )?;
        let kind = |k: NodeKind| match k {
            NodeKind::Station => "station",
            NodeKind::Waypoint => "waypoint",
        };
        columns.set_item(
            "kind",
            nodes.iter().map(|n| kind(n.kind)).collect::<Vec<_>>(),
        )?;
        columns.set_item(
            "name",
            nodes.iter().map(|n| n.name.as_str()).collect::<Vec<_>>(),
        )?;
        columns.set_item("lon", nodes.iter().map(|n| n.pos.lon).collect::<Vec<_>>())?;
        columns.set_item("lat", nodes.iter().map(|n| n.pos.lat).collect::<Vec<_>>())?;
        Ok(columns)
    }

    /// The corridors as columns: `id`, `from`, `to`, `length_m`.
    fn edge_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let a = &self.inner.airspace;
        let edges = a.edges();
        let columns = PyDict::new(py);
        columns.set_item(
            "id",
            edges.iter().map(|e| e.id.as_str()).collect::<Vec<_>>(),
        )?;
        let end = |n| a.node(n).id.as_str();
        columns.set_item(
            "from",
            edges.iter().map(|e| end(e.from)).collect::<Vec<_>>(),
        )?;
        columns.set_item("to", edges.iter().map(|e| end(e.to)).collect::<Vec<_>>())?;
        columns.set_item(
            "length_m",
            edges.iter().map(|e| e.length_m).collect::<Vec<_>>(),
        )?;
        Ok(columns)
    }

    /// Number of stations (pads).
    #[getter]
    fn station_count(&self) -> usize {
        self.inner.airspace.stations().count()
    }

    /// The airspace as GeoJSON (docs/reference.md#airspace), as `muse airspace build` writes it.
    fn to_geojson(&self) -> String {
        let a = &self.inner;
        muse_formats::airspace_geojson::write_airspace_file(
            &a.airspace,
            &a.land_outline,
            a.file_day.as_ref(),
        )
    }

    fn __repr__(&self) -> String {
        let a = &self.inner;
        format!(
            "Airspace({}: {} nodes, {} stations, {} corridors)",
            a.source,
            a.airspace.node_count(),
            a.airspace.stations().count(),
            a.airspace.edge_count()
        )
    }
}
