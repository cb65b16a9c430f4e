//! Rendering for MUSE: SVG maps drawn with `plotters`, with no system fonts.
//!
//! - [`render_map`]: the airspace map (the paper's Fig. 1): land, no-fly zones, corridors
//!   (optionally coloured by how busy they are), stations with their ids, a scale bar, a
//!   north arrow and lon/lat ticks; [`render_map_panels`]: several such maps side by side
//!   (small multiples, e.g. one per layer of a layered airspace) on one load scale;
//! - [`render_line_plot`]: line plots with 95% confidence bands, one line per series (the
//!   sweep's runtime, success-rate and delay figures).
//!
//! All output is deterministic: the same input gives byte-identical SVG. Text is written as
//! SVG `<text>` in the viewer's sans-serif font; layout that depends on text size uses a
//! conservative width estimate, so nothing needs font files.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod geom;
mod map;
mod plot;
mod style;
mod ticks;

use plotters::backend::SVGBackend;
use plotters::coord::Shift;
use plotters::drawing::DrawingArea;

pub use map::{MapInput, MapOptions, MapPanel, ZoneLayer, render_map, render_map_panels};
pub use plot::{PlotOptions, Point, Series, render_line_plot};

/// Why a map or plot could not be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    /// There is nothing to draw: no nodes, no land and no zone areas.
    #[error("nothing to draw: the airspace has no nodes and there is no land or zone area")]
    Empty,
    /// The input or options are inconsistent (e.g. a load per edge of the wrong length).
    #[error("invalid input: {0}")]
    Input(String),
    /// The drawing backend failed.
    #[error("drawing failed: {0}")]
    Drawing(String),
}

/// The SVG canvas both renderers draw on.
type Area<'b> = DrawingArea<SVGBackend<'b>, Shift>;

/// A drawing backend failure as a [`RenderError`].
fn drawing_err<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError::Drawing(e.to_string())
}
