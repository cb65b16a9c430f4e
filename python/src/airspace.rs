//! The `Airspace` class: the corridor graph a day is planned on (SPEC §2), from a built-in
//! scenario, a GeoJSON file, or a set of pads (SPEC §15).

use std::path::PathBuf;

use muse_airspace::builder::{BuildError, BuildOptions, build_airspace};
use muse_airspace::plane::Plane;
use muse_formats::airspace_geojson::AirspaceFile;
use muse_formats::day::FileDay;
use muse_formats::exclusions::Exclusions;
use muse_model::NodeKind;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error;

/// An airspace: nodes (stations and waypoints) joined by corridors.
#[pyclass(module = "muse._muse", frozen)]
pub struct Airspace {
    /// The graph (flat: layers are applied when a day is planned).
    pub graph: muse_model::Airspace,
    /// The built-in scenario it is, if it is one (its zones are the default zones).
    pub scenario: Option<&'static muse_scenario::Scenario>,
    /// The file it was read from, as an absolute path, if it was read from one.
    pub file: Option<String>,
    /// Where it came from, for messages and the summary's provenance.
    pub source: String,
    /// The land outline it carries (drawn on maps), if any.
    pub land: Vec<geo_types::Polygon<f64>>,
    /// The day it carries (date, UTC offset, time zone), if any; else the default's.
    pub day: Option<FileDay>,
}

#[pymethods]
impl Airspace {
    /// A built-in scenario's airspace: `singapore-77` (the paper's 77 stations) or
    /// `singapore-all` (all 1,115 car parks).
    #[staticmethod]
    #[pyo3(signature = (name = "singapore-77"))]
    fn scenario(name: &str) -> PyResult<Self> {
        let s = muse_scenario::by_name(name).map_err(error)?;
        Ok(Airspace {
            graph: s.airspace.clone(),
            scenario: Some(s),
            file: None,
            source: format!("embedded {}", s.name),
            land: Vec::new(),
            day: None,
        })
    }

    /// An airspace GeoJSON file (SPEC §2), with the land outline and the day it may carry.
    #[staticmethod]
    fn read(path: PathBuf) -> PyResult<Self> {
        let read = AirspaceFile::read(&path).map_err(error)?;
        let file = std::fs::canonicalize(&path)
            .unwrap_or_else(|_| path.clone())
            .display()
            .to_string();
        Ok(Airspace {
            graph: read.airspace,
            scenario: None,
            file: Some(file),
            source: path.display().to_string(),
            land: read.land,
            day: read.day,
        })
    }

    /// The airspace built from pads by the rule of SPEC §15, as `muse airspace build --pads`
    /// builds it: `pads` is the text of a pads CSV (`id,lon,lat[,name]`) named `source` in
    /// messages; `crs` the plane (`utm`, `EPSG:3414`, …); `exclude` GeoJSON files of polygons
    /// no corridor may cross; `max_corridor_m` the longest corridor; `time_zone` (an IANA
    /// name) or `utc_offset`, with `date`, the day it is planned on.
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
        Ok(Airspace {
            graph,
            scenario: None,
            file: None,
            source: format!("built from the pads of {source}"),
            land: Vec::new(),
            day,
        })
    }

    /// Where the airspace came from.
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    /// The nodes as columns: `id`, `kind` (`station` or `waypoint`), `name`, `lon`, `lat`.
    fn node_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let nodes = self.graph.nodes();
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
        let a = &self.graph;
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
        self.graph.stations().count()
    }

    /// The airspace as GeoJSON (SPEC §2), as `muse airspace build` writes it.
    fn to_geojson(&self) -> String {
        muse_formats::airspace_geojson::write_airspace_file(
            &self.graph,
            &self.land,
            self.day.as_ref(),
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "Airspace({}: {} nodes, {} stations, {} corridors)",
            self.source,
            self.graph.node_count(),
            self.graph.stations().count(),
            self.graph.edge_count()
        )
    }
}
