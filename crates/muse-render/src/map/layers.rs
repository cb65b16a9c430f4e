//! The map's layers, bottom to top: sea, land, zones, corridors (by load), stations and
//! waypoints, closed elements.

use geo::orient::{Direction, Orient};
use geo_types::Polygon;
use muse_model::{NodeId, NodeKind};
use plotters::element::{
    Circle, DashedPathElement, PathElement, Polygon as PolygonElement, Rectangle,
};
use plotters::style::{Color, ShapeStyle};

use super::{MapCtx, STATION_R, WAYPOINT_R, load_top};
use crate::style::{COAST, EDGE, INK, LAND, MARKED, PAPER, SEA, WAYPOINT, ZONE, ramp};
use crate::{RenderError, drawing_err};

/// With more nodes than this, nodes are drawn smaller so that dense clusters stay readable.
const DENSE_NODES: usize = 600;

/// Land polygons merged into one outline (no seams between neighbours); as given when the
/// union comes out empty.
pub(super) fn merge_land(land: &[Polygon<f64>]) -> Vec<Polygon<f64>> {
    if land.is_empty() {
        return Vec::new();
    }
    // `unary_union` reads the fill rule off the first ring's winding, so give every
    // polygon the same orientation first (files mix them).
    let oriented: Vec<Polygon<f64>> = land.iter().map(|p| p.orient(Direction::Default)).collect();
    let merged = geo::unary_union(oriented.iter());
    if merged.0.is_empty() {
        oriented
    } else {
        merged.0
    }
}

impl MapCtx<'_, '_, '_> {
    /// Everything inside the frame, bottom to top.
    pub(super) fn draw_map(&self) -> Result<(), RenderError> {
        let f = self.frame;
        self.root
            .draw(&Rectangle::new(
                [(f.x0 as i32, f.y0 as i32), (f.x1 as i32, f.y1 as i32)],
                SEA.filled(),
            ))
            .map_err(drawing_err)?;
        self.draw_land_and_zones()?;
        self.draw_corridors()?;
        self.draw_nodes()?;
        self.draw_labels_and_insets()
    }

    fn draw_land_and_zones(&self) -> Result<(), RenderError> {
        let (root, proj) = (self.root, &self.proj);
        // Land, then the coast over it.
        for poly in self.land {
            let ring = proj.keyhole(poly, 0.4);
            if ring.len() >= 3 {
                root.draw(&PolygonElement::new(ring, LAND.filled()))
                    .map_err(drawing_err)?;
            }
        }
        for poly in self.land {
            for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
                let mut pts = proj.ring(ring, 0.4);
                if pts.len() >= 3 {
                    pts.push(pts[0]);
                    root.draw(&PathElement::new(pts, COAST.stroke_width(1)))
                        .map_err(drawing_err)?;
                }
            }
        }
        // Zones: translucent fill and a solid outline.
        for zone in &self.input.zones {
            for poly in &zone.polygons {
                let ring = proj.keyhole(poly, 0.3);
                if ring.len() >= 3 {
                    root.draw(&PolygonElement::new(ring, ZONE.mix(0.18).filled()))
                        .map_err(drawing_err)?;
                }
                for r in std::iter::once(poly.exterior()).chain(poly.interiors()) {
                    let mut pts = proj.ring(r, 0.3);
                    if pts.len() >= 3 {
                        pts.push(pts[0]);
                        root.draw(&PathElement::new(pts, ZONE.mix(0.85).stroke_width(2)))
                            .map_err(drawing_err)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Corridors by load (quiet first, so busy ones stay on top), then closures on top.
    fn draw_corridors(&self) -> Result<(), RenderError> {
        let root = self.root;
        let airspace = self.input.airspace;
        if let Some(load) = &self.input.edge_load {
            let max = load_top(load, self.opts);
            let mut order: Vec<usize> = (0..load.len()).collect();
            order.sort_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b)));
            for i in order {
                let t = if max > 0.0 { load[i] / max } else { 0.0 };
                root.draw(&PathElement::new(
                    self.ends(&airspace.edges()[i]),
                    load_style(t),
                ))
                .map_err(drawing_err)?;
            }
        } else {
            for e in airspace.edges() {
                root.draw(&PathElement::new(self.ends(e), EDGE.stroke_width(2)))
                    .map_err(drawing_err)?;
            }
        }
        let closed_edges = union_sorted(self.input.zones.iter().map(|z| z.closed_edges.as_slice()));
        for &e in &closed_edges {
            let [a, b] = self.ends(airspace.edge(e));
            // A white underlay keeps the dashes readable over a busy corridor.
            root.draw(&PathElement::new([a, b], PAPER.mix(0.9).stroke_width(4)))
                .map_err(drawing_err)?;
            root.draw(&DashedPathElement::new([a, b], 9, 6, ZONE.stroke_width(3)))
                .map_err(drawing_err)?;
        }
        Ok(())
    }

    /// Waypoints small and grey, stations dark with a white rim, closed nodes ringed.
    /// Smaller dots (and rims) when there are more than [`DENSE_NODES`] nodes.
    fn draw_nodes(&self) -> Result<(), RenderError> {
        let root = self.root;
        let airspace = self.input.airspace;
        let dense = airspace.node_count() > DENSE_NODES;
        for kind in [NodeKind::Waypoint, NodeKind::Station] {
            for (i, n) in airspace.nodes().iter().enumerate() {
                if n.kind != kind {
                    continue;
                }
                let p = self.pos(NodeId(i as u32));
                let (r, colour) = match (kind, dense) {
                    (NodeKind::Station, false) => (STATION_R, INK),
                    (NodeKind::Station, true) => (STATION_R - 2, INK),
                    (NodeKind::Waypoint, false) => (WAYPOINT_R, WAYPOINT),
                    (NodeKind::Waypoint, true) => (WAYPOINT_R - 1, WAYPOINT),
                };
                let rim = if dense { 1 } else { 2 };
                root.draw(&Circle::new(p, r + rim, PAPER.filled()))
                    .map_err(drawing_err)?;
                root.draw(&Circle::new(p, r, colour.filled()))
                    .map_err(drawing_err)?;
            }
        }
        for &n in &self.input.marked {
            let p = self.pos(n);
            root.draw(&Circle::new(p, STATION_R + 4, PAPER.filled()))
                .map_err(drawing_err)?;
            root.draw(&Circle::new(p, STATION_R + 2, MARKED.filled()))
                .map_err(drawing_err)?;
        }
        let closed_nodes = union_sorted(self.input.zones.iter().map(|z| z.closed_nodes.as_slice()));
        for &n in &closed_nodes {
            root.draw(&Circle::new(
                self.pos(n),
                STATION_R + 5,
                ZONE.stroke_width(2),
            ))
            .map_err(drawing_err)?;
        }
        Ok(())
    }
}

/// How a corridor with relative load `t` ∈ [0, 1] is stroked: colour ramp and 1–6 px.
fn load_style(t: f64) -> ShapeStyle {
    ShapeStyle {
        color: ramp(t).to_rgba(),
        filled: false,
        stroke_width: 1 + (t * 5.0).round() as u32,
    }
}

/// The sorted union of several lists of ids (each zone's closed nodes or edges).
fn union_sorted<'a, T: Copy + Ord + 'a>(lists: impl Iterator<Item = &'a [T]>) -> Vec<T> {
    let mut all: Vec<T> = lists.flatten().copied().collect();
    all.sort_unstable();
    all.dedup();
    all
}
