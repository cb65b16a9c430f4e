//! The airspace map (the paper's Fig. 1): land, no-fly zones, corridors, stations.

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use geo::orient::{Direction, Orient};
use geo::{BoundingRect, Destination, Geodesic};
use geo_types::{LineString, Point, Polygon};
use muse_model::{Airspace, EdgeId, LonLat, NodeId, NodeKind, ZoneArea};
use plotters::backend::SVGBackend;
use plotters::coord::Shift;
use plotters::drawing::{DrawingArea, IntoDrawingArea};
use plotters::element::{
    Circle, DashedPathElement, PathElement, Polygon as PolygonElement, Rectangle,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters::style::{Color, ShapeStyle};

use crate::RenderError;
use crate::geom::{Extent, LabelPlacer, Projection, Rect};
use crate::style::{
    COAST, EDGE, INK, LAND, MUTED, PAPER, SEA, WAYPOINT, ZONE, fmt_num, ramp, text, text_width,
};

/// What to draw.
#[derive(Clone, Debug)]
pub struct MapInput<'a> {
    /// The airspace graph.
    pub airspace: &'a Airspace,
    /// Land polygons in lon/lat degrees (e.g. the 55 URA planning areas). They are merged
    /// and filled in one colour with a thin coastline, so they read as one outline.
    pub land: &'a [Polygon<f64>],
    /// No-fly zones, shaded and labelled, with the elements they close.
    pub zones: Vec<ZoneLayer>,
    /// Per-edge busyness, indexed by [`EdgeId`] (any non-negative unit, e.g. flights per
    /// day). When present, corridors are coloured and widened by load and a colour legend is
    /// drawn.
    pub edge_load: Option<Vec<f64>>,
}

impl<'a> MapInput<'a> {
    /// A map of `airspace` alone: no land, no zones, no load.
    pub fn new(airspace: &'a Airspace) -> Self {
        MapInput {
            airspace,
            land: &[],
            zones: Vec::new(),
            edge_load: None,
        }
    }
}

/// One no-fly zone on the map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ZoneLayer {
    /// Shown next to the zone and in the legend, e.g. `Downtown Core 10:00–12:00`.
    pub label: String,
    /// The zone's area in lon/lat degrees; a circle can be passed as a polygon (see
    /// [`zone_area_polygons`] and [`circle_polygon`]). May be empty for a zone that only
    /// lists elements.
    pub polygons: Vec<Polygon<f64>>,
    /// Nodes the zone closes (ringed in red).
    pub closed_nodes: Vec<NodeId>,
    /// Edges the zone closes (drawn red and dashed).
    pub closed_edges: Vec<EdgeId>,
}

/// How to draw it.
#[derive(Clone, Debug, PartialEq)]
pub struct MapOptions {
    /// Width of the SVG in pixels (the height follows from the map's shape). 1800 suits a
    /// full A4 page width; at least 400.
    pub width_px: u32,
    /// Title above the map (none if empty).
    pub title: String,
    /// Whether to write each station's id next to it.
    pub label_stations: bool,
    /// Caption of the load colour legend.
    pub load_label: String,
    /// Small print under the legend, e.g. the data attribution a licence requires.
    pub attribution: String,
}

impl Default for MapOptions {
    fn default() -> Self {
        MapOptions {
            width_px: 1_800,
            title: "MUSE airspace".to_owned(),
            label_stations: true,
            load_label: "Corridor load".to_owned(),
            attribution: String::new(),
        }
    }
}

/// The polygons of a zone's area: as given, or a 72-gon for a circle.
///
/// ```
/// use muse_model::{LonLat, ZoneArea};
/// use muse_render::zone_area_polygons;
/// let circle = ZoneArea::Circle { centre: LonLat::new(103.99, 1.36), radius_m: 5_000.0 };
/// let polygons = zone_area_polygons(&circle);
/// assert_eq!(polygons.len(), 1);
/// assert_eq!(polygons[0].exterior().0.len(), 73);
/// ```
pub fn zone_area_polygons(area: &ZoneArea) -> Vec<Polygon<f64>> {
    match area {
        ZoneArea::Polygons(mp) => mp.0.clone(),
        ZoneArea::Circle { centre, radius_m } => vec![circle_polygon(*centre, *radius_m, 72)],
    }
}

/// A geodesic circle of `radius_m` metres around `centre` as a polygon with `segments`
/// vertices (at least 8), in lon/lat degrees.
pub fn circle_polygon(centre: LonLat, radius_m: f64, segments: usize) -> Polygon<f64> {
    let n = segments.max(8);
    let c = Point::new(centre.lon, centre.lat);
    let mut ring: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let p = Geodesic.destination(c, 360.0 * i as f64 / n as f64, radius_m);
            (p.x(), p.y())
        })
        .collect();
    ring.push(ring[0]);
    Polygon::new(LineString::from(ring), vec![])
}

// Layout, in pixels.
const MARGIN_LEFT: f64 = 84.0;
const MARGIN_RIGHT: f64 = 28.0;
const TITLE_BAND: f64 = 64.0;
const TOP_NO_TITLE: f64 = 24.0;
const TICK_BAND: f64 = 36.0;
const LEGEND_ROW: f64 = 34.0;
const TITLE_PX: f64 = 28.0;
const SUBTITLE_PX: f64 = 16.0;
const LABEL_PX: f64 = 14.0;
const TICK_PX: f64 = 14.0;
const LEGEND_PX: f64 = 16.0;
const ZONE_LABEL_PX: f64 = 17.0;
const SMALL_PX: f64 = 12.0;
const STATION_R: u32 = 5;
const WAYPOINT_R: u32 = 3;
/// With more nodes than this, nodes are drawn smaller so that dense clusters stay readable.
const DENSE_NODES: usize = 600;

type Area<'b> = DrawingArea<SVGBackend<'b>, Shift>;

fn drawing_err<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError::Drawing(e.to_string())
}

/// Renders the map as an SVG document.
///
/// Equirectangular projection with the longitude axis scaled for the mean latitude, so that
/// distances look right; lon/lat ticks on the frame, a kilometre scale bar and a north arrow.
/// Text is SVG `<text>` (the viewer's sans-serif font); no font files are read. The output
/// depends only on the input: the same input gives the same bytes.
///
/// ```
/// use muse_model::{Airspace, Edge, LonLat, Node, NodeId, NodeKind};
/// use muse_render::{render_map, MapInput, MapOptions};
///
/// let node = |id: &str, lon, lat| Node {
///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, lat),
/// };
/// let airspace = Airspace::new(
///     vec![node("S001", 103.80, 1.30), node("S002", 103.85, 1.35)],
///     vec![Edge { id: "S001-S002".into(), from: NodeId(0), to: NodeId(1), length_m: 7_850.0 }],
/// )
/// .unwrap();
/// let svg = render_map(&MapInput::new(&airspace), &MapOptions::default()).unwrap();
/// assert!(svg.starts_with("<svg"));
/// assert!(svg.contains(">\nS002\n</text>"));
/// ```
pub fn render_map(input: &MapInput<'_>, opts: &MapOptions) -> Result<String, RenderError> {
    validate(input, opts)?;
    let airspace = input.airspace;

    // Land first: merge the polygons into one outline (no seams between neighbours).
    let land = if input.land.is_empty() {
        Vec::new()
    } else {
        // `unary_union` reads the fill rule off the first ring's winding, so give every
        // polygon the same orientation first (files mix them).
        let oriented: Vec<Polygon<f64>> = input
            .land
            .iter()
            .map(|p| p.orient(Direction::Default))
            .collect();
        let merged = geo::unary_union(oriented.iter());
        if merged.0.is_empty() {
            oriented
        } else {
            merged.0
        }
    };

    // Extent: everything that is drawn.
    let extent = Extent::of(
        airspace
            .nodes()
            .iter()
            .map(|n| (n.pos.lon, n.pos.lat))
            .chain(
                land.iter()
                    .chain(input.zones.iter().flat_map(|z| &z.polygons))
                    .flat_map(|p| {
                        p.bounding_rect()
                            .map(|r| [(r.min().x, r.min().y), (r.max().x, r.max().y)])
                            .into_iter()
                            .flatten()
                    }),
            ),
    )
    .ok_or(RenderError::Empty)?
    .padded(0.03, 0.02)
    .with_min_aspect(0.75);

    let width = f64::from(opts.width_px);
    let top = if opts.title.is_empty() {
        TOP_NO_TITLE
    } else {
        TITLE_BAND
    };
    let map_w = width - MARGIN_LEFT - MARGIN_RIGHT;
    let map_h = (map_w / extent.aspect()).round();
    let proj = Projection::fit(extent, MARGIN_LEFT, top, map_w);
    let frame = Rect::new(MARGIN_LEFT, top, map_w, map_h);

    let legend = Legend::new(input, opts, width);
    let height = top
        + map_h
        + TICK_BAND
        + legend.height()
        + if opts.attribution.is_empty() {
            8.0
        } else {
            26.0
        };

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (opts.width_px, height.round() as u32))
            .into_drawing_area();
        root.fill(&PAPER).map_err(drawing_err)?;
        let ctx = MapCtx {
            root: &root,
            input,
            opts,
            proj,
            frame,
            land: &land,
        };
        ctx.draw_map()?;
        ctx.draw_frame_and_ticks(extent)?;
        ctx.draw_title()?;
        legend.draw(&root, frame.y1 + TICK_BAND)?;
        if !opts.attribution.is_empty() {
            root.draw_text(
                &opts.attribution,
                &text(SMALL_PX, false, MUTED, HPos::Left, VPos::Center),
                (MARGIN_LEFT as i32, (height - 13.0) as i32),
            )
            .map_err(drawing_err)?;
        }
        root.present().map_err(drawing_err)?;
    }
    Ok(svg)
}

fn validate(input: &MapInput<'_>, opts: &MapOptions) -> Result<(), RenderError> {
    let a = input.airspace;
    if !(400..=20_000).contains(&opts.width_px) {
        return Err(RenderError::Input(format!(
            "width {} px is outside 400..=20000",
            opts.width_px
        )));
    }
    for z in &input.zones {
        if let Some(n) = z.closed_nodes.iter().find(|n| n.index() >= a.node_count()) {
            return Err(RenderError::Input(format!(
                "zone `{}` closes {n}, which does not exist",
                z.label
            )));
        }
        if let Some(e) = z.closed_edges.iter().find(|e| e.index() >= a.edge_count()) {
            return Err(RenderError::Input(format!(
                "zone `{}` closes {e}, which does not exist",
                z.label
            )));
        }
    }
    if let Some(load) = &input.edge_load {
        if load.len() != a.edge_count() {
            return Err(RenderError::Input(format!(
                "edge_load has {} values for {} edges",
                load.len(),
                a.edge_count()
            )));
        }
        if let Some(i) = load.iter().position(|v| !v.is_finite() || *v < 0.0) {
            return Err(RenderError::Input(format!(
                "edge_load[{i}] = {} is not a finite number >= 0",
                load[i]
            )));
        }
    }
    Ok(())
}

struct MapCtx<'r, 'b, 'i> {
    root: &'r Area<'b>,
    input: &'r MapInput<'i>,
    opts: &'r MapOptions,
    proj: Projection,
    frame: Rect,
    land: &'r [Polygon<f64>],
}

impl MapCtx<'_, '_, '_> {
    /// Pixel position of node `n`.
    fn pos(&self, n: NodeId) -> (i32, i32) {
        let p = self.input.airspace.node(n).pos;
        self.proj.px(p.lon, p.lat)
    }

    /// Both ends of an edge in pixels.
    fn ends(&self, e: &muse_model::Edge) -> [(i32, i32); 2] {
        [self.pos(e.from), self.pos(e.to)]
    }

    /// Everything inside the frame, bottom to top.
    fn draw_map(&self) -> Result<(), RenderError> {
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
            let max = load.iter().copied().fold(0.0, f64::max);
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

    /// Scale bar and north arrow first (labels avoid them), then zone and station labels.
    fn draw_labels_and_insets(&self) -> Result<(), RenderError> {
        let airspace = self.input.airspace;
        let dots: Vec<Rect> = (0..airspace.node_count())
            .map(|i| {
                let n = NodeId(i as u32);
                let (x, y) = self.pos(n);
                let r = if airspace.is_station(n) {
                    STATION_R
                } else {
                    WAYPOINT_R
                } + 2;
                Rect::around(f64::from(x), f64::from(y), f64::from(r))
            })
            .collect();
        let segments = airspace
            .edges()
            .iter()
            .map(|e| {
                let [a, b] = self.ends(e);
                (
                    (f64::from(a.0), f64::from(a.1)),
                    (f64::from(b.0), f64::from(b.1)),
                )
            })
            .collect();
        let mut placer = LabelPlacer::new(self.frame, dots, segments);
        placer.reserve(self.draw_scale_bar()?);
        placer.reserve(self.draw_north_arrow()?);
        self.draw_zone_labels(&mut placer)?;
        if self.opts.label_stations {
            self.draw_station_labels(&mut placer)?;
        }
        Ok(())
    }

    fn draw_zone_labels(&self, placer: &mut LabelPlacer) -> Result<(), RenderError> {
        let proj = &self.proj;
        for zone in &self.input.zones {
            if zone.label.is_empty() || zone.polygons.is_empty() {
                continue;
            }
            let mut b: Option<Rect> = None;
            for p in &zone.polygons {
                if let Some(r) = p.bounding_rect() {
                    let (x0, y1) = proj.xy(r.min().x, r.min().y);
                    let (x1, y0) = proj.xy(r.max().x, r.max().y);
                    let r = Rect { x0, y0, x1, y1 };
                    b = Some(match b {
                        None => r,
                        Some(o) => Rect {
                            x0: o.x0.min(r.x0),
                            y0: o.y0.min(r.y0),
                            x1: o.x1.max(r.x1),
                            y1: o.y1.max(r.y1),
                        },
                    });
                }
            }
            let Some(b) = b else { continue };
            let w = text_width(&zone.label, ZONE_LABEL_PX, true) + 12.0;
            let h = ZONE_LABEL_PX + 10.0;
            let (cx, cy) = (f64::midpoint(b.x0, b.x1), f64::midpoint(b.y0, b.y1));
            let gap = 6.0;
            let candidates = [
                Rect::new(cx - w / 2.0, b.y1 + gap, w, h),
                Rect::new(cx - w / 2.0, b.y0 - gap - h, w, h),
                Rect::new(b.x1 + gap, cy - h / 2.0, w, h),
                Rect::new(b.x0 - gap - w, cy - h / 2.0, w, h),
                Rect::new(b.x1 + gap, b.y1 + gap, w, h),
                Rect::new(b.x0 - gap - w, b.y1 + gap, w, h),
                Rect::new(b.x1 + gap, b.y0 - gap - h, w, h),
                Rect::new(b.x0 - gap - w, b.y0 - gap - h, w, h),
                Rect::new(cx - w / 2.0, cy - h / 2.0, w, h),
            ];
            let Some(i) = placer.place(&candidates, None) else {
                continue;
            };
            let r = candidates[i];
            let corners = [(r.x0 as i32, r.y0 as i32), (r.x1 as i32, r.y1 as i32)];
            self.root
                .draw(&Rectangle::new(corners, PAPER.mix(0.88).filled()))
                .map_err(drawing_err)?;
            self.root
                .draw(&Rectangle::new(corners, ZONE.stroke_width(1)))
                .map_err(drawing_err)?;
            let (lx, ly) = (f64::midpoint(r.x0, r.x1), f64::midpoint(r.y0, r.y1));
            self.root
                .draw_text(
                    &zone.label,
                    &text(ZONE_LABEL_PX, true, ZONE, HPos::Center, VPos::Center),
                    (lx.round() as i32, ly.round() as i32),
                )
                .map_err(drawing_err)?;
        }
        Ok(())
    }

    fn draw_station_labels(&self, placer: &mut LabelPlacer) -> Result<(), RenderError> {
        let airspace = self.input.airspace;
        let style = text(LABEL_PX, false, INK, HPos::Left, VPos::Center);
        let h = LABEL_PX + 2.0;
        for n in airspace.stations() {
            let id = &airspace.node(n).id;
            let (x, y) = self.pos(n);
            let (x, y) = (f64::from(x), f64::from(y));
            let w = text_width(id, LABEL_PX, false) + 2.0;
            let r = f64::from(STATION_R) + 3.0;
            let d = r * 0.75;
            let candidates = [
                Rect::new(x + r, y - h / 2.0, w, h),
                Rect::new(x + d, y - d - h, w, h),
                Rect::new(x + d, y + d, w, h),
                Rect::new(x - r - w, y - h / 2.0, w, h),
                Rect::new(x - d - w, y - d - h, w, h),
                Rect::new(x - d - w, y + d, w, h),
                Rect::new(x - w / 2.0, y - r - h, w, h),
                Rect::new(x - w / 2.0, y + r, w, h),
            ];
            if let Some(i) = placer.place(&candidates, Some(n.index())) {
                let c = candidates[i];
                // A faint backing keeps the id readable over corridors.
                let backing = [
                    (c.x0 as i32, (c.y0 + 1.0) as i32),
                    (c.x1.ceil() as i32, (c.y1 - 1.0) as i32),
                ];
                self.root
                    .draw(&Rectangle::new(backing, LAND.mix(0.75).filled()))
                    .map_err(drawing_err)?;
                self.root
                    .draw_text(
                        id,
                        &style,
                        (
                            (c.x0 + 1.0).round() as i32,
                            f64::midpoint(c.y0, c.y1).round() as i32,
                        ),
                    )
                    .map_err(drawing_err)?;
            }
        }
        Ok(())
    }

    /// Draws a kilometre scale bar in the lower left of the frame; returns its box.
    fn draw_scale_bar(&self) -> Result<Rect, RenderError> {
        let f = self.frame;
        let target_px = (f.x1 - f.x0) / 5.0;
        let km_per_px = 1.0 / self.proj.px_per_km;
        let km = nice_step(target_px * km_per_px);
        let bar = km * self.proj.px_per_km;
        let (x0, y) = (f.x0 + 22.0, f.y1 - 26.0);
        let bx = Rect {
            x0: f.x0 + 8.0,
            y0: y - 30.0,
            x1: x0 + bar + 48.0,
            y1: f.y1 - 8.0,
        };
        let root = self.root;
        root.draw(&Rectangle::new(
            [(bx.x0 as i32, bx.y0 as i32), (bx.x1 as i32, bx.y1 as i32)],
            PAPER.mix(0.85).filled(),
        ))
        .map_err(drawing_err)?;
        // Two alternating halves.
        let half = bar / 2.0;
        for (k, fill) in [(0.0, INK), (1.0, PAPER)] {
            let a = (x0 + k * half).round() as i32;
            let b = (x0 + (k + 1.0) * half).round() as i32;
            let corners = [(a, (y - 3.0) as i32), (b, (y + 3.0) as i32)];
            root.draw(&Rectangle::new(corners, fill.filled()))
                .map_err(drawing_err)?;
            root.draw(&Rectangle::new(corners, INK.stroke_width(1)))
                .map_err(drawing_err)?;
        }
        let st = text(TICK_PX, false, INK, HPos::Center, VPos::Bottom);
        for k in 0..=2 {
            let v = km * f64::from(k) / 2.0;
            let mut lx = x0 + f64::from(k) * half;
            let label = if k == 2 {
                // Keep the number over the bar's end; the unit trails after it.
                lx += text_width(" km", TICK_PX, false) / 2.0;
                format!("{} km", fmt_num(v))
            } else {
                fmt_num(v)
            };
            root.draw_text(&label, &st, (lx.round() as i32, (y - 6.0) as i32))
                .map_err(drawing_err)?;
        }
        Ok(bx)
    }

    /// Draws a north arrow in the upper right of the frame; returns its box.
    fn draw_north_arrow(&self) -> Result<Rect, RenderError> {
        let f = self.frame;
        let (cx, top) = (f.x1 - 34.0, f.y0 + 12.0);
        let bx = Rect {
            x0: cx - 20.0,
            y0: top - 4.0,
            x1: cx + 20.0,
            y1: top + 62.0,
        };
        let root = self.root;
        root.draw(&Rectangle::new(
            [(bx.x0 as i32, bx.y0 as i32), (bx.x1 as i32, bx.y1 as i32)],
            PAPER.mix(0.85).filled(),
        ))
        .map_err(drawing_err)?;
        root.draw_text(
            "N",
            &text(18.0, true, INK, HPos::Center, VPos::Top),
            (cx as i32, top as i32),
        )
        .map_err(drawing_err)?;
        let (tip, base) = (top + 22.0, top + 56.0);
        let c = cx as i32;
        root.draw(&PolygonElement::new(
            [
                (c, tip as i32),
                (c + 9, base as i32),
                (c, (base - 9.0) as i32),
            ],
            INK.filled(),
        ))
        .map_err(drawing_err)?;
        root.draw(&PolygonElement::new(
            [
                (c, tip as i32),
                (c - 9, base as i32),
                (c, (base - 9.0) as i32),
            ],
            MUTED.mix(0.45).filled(),
        ))
        .map_err(drawing_err)?;
        Ok(bx)
    }

    /// White margins (clipping anything drawn past the frame), the frame, and lon/lat ticks.
    fn draw_frame_and_ticks(&self, extent: Extent) -> Result<(), RenderError> {
        let root = self.root;
        let f = self.frame;
        let (w, h) = root.dim_in_pixel();
        let (w, h) = (w as i32, h as i32);
        let (fx0, fy0, fx1, fy1) = (f.x0 as i32, f.y0 as i32, f.x1 as i32, f.y1 as i32);
        for corners in [
            [(0, 0), (w, fy0)],
            [(0, fy1), (w, h)],
            [(0, fy0), (fx0, fy1)],
            [(fx1, fy0), (w, fy1)],
        ] {
            root.draw(&Rectangle::new(corners, PAPER.filled()))
                .map_err(drawing_err)?;
        }

        // Graticule lines are drawn faintly over the map, ticks and labels outside.
        let lon_step = nice_step((extent.lon1 - extent.lon0) / 7.0);
        let lat_step = nice_step((extent.lat1 - extent.lat0) / 6.0);
        let decimals = |step: f64| {
            (-step.log10().floor()).max(0.0) as usize
                + usize::from((step / 10f64.powf(step.log10().floor())).fract() > 1e-9)
        };
        let bottom = text(TICK_PX, false, MUTED, HPos::Center, VPos::Top);
        let left = text(TICK_PX, false, MUTED, HPos::Right, VPos::Center);
        let grid = INK.mix(0.10).stroke_width(1);
        let tick = MUTED.stroke_width(1);
        for lon in ticks(extent.lon0, extent.lon1, lon_step) {
            let (x, _) = self.proj.px(lon, extent.lat1);
            root.draw(&PathElement::new([(x, fy0), (x, fy1)], grid))
                .map_err(drawing_err)?;
            root.draw(&PathElement::new([(x, fy1), (x, fy1 + 6)], tick))
                .map_err(drawing_err)?;
            let hemi = if lon < 0.0 { 'W' } else { 'E' };
            let label = format!("{:.*}°{hemi}", decimals(lon_step), lon.abs());
            // Skip a label that would run off the page.
            let half = (text_width(&label, TICK_PX, false) / 2.0) as i32;
            if x - half >= 0 && x + half <= w {
                root.draw_text(&label, &bottom, (x, fy1 + 9))
                    .map_err(drawing_err)?;
            }
        }
        for lat in ticks(extent.lat0, extent.lat1, lat_step) {
            let (_, y) = self.proj.px(extent.lon0, lat);
            root.draw(&PathElement::new([(fx0, y), (fx1, y)], grid))
                .map_err(drawing_err)?;
            root.draw(&PathElement::new([(fx0 - 6, y), (fx0, y)], tick))
                .map_err(drawing_err)?;
            let hemi = if lat < 0.0 { 'S' } else { 'N' };
            let label = format!("{:.*}°{hemi}", decimals(lat_step), lat.abs());
            root.draw_text(&label, &left, (fx0 - 9, y))
                .map_err(drawing_err)?;
        }
        root.draw(&Rectangle::new(
            [(fx0, fy0), (fx1, fy1)],
            MUTED.stroke_width(1),
        ))
        .map_err(drawing_err)?;
        Ok(())
    }

    fn draw_title(&self) -> Result<(), RenderError> {
        if self.opts.title.is_empty() {
            return Ok(());
        }
        let a = self.input.airspace;
        let stations = a.stations().count();
        let waypoints = a.node_count() - stations;
        let waypoints = if waypoints > 0 {
            format!(" · {waypoints} waypoints")
        } else {
            String::new()
        };
        let summary = format!(
            "{stations} stations{waypoints} · {} corridors",
            a.edge_count()
        );
        let y = (TITLE_BAND / 2.0) as i32;
        self.root
            .draw_text(
                &self.opts.title,
                &text(TITLE_PX, true, INK, HPos::Left, VPos::Center),
                (self.frame.x0 as i32, y),
            )
            .map_err(drawing_err)?;
        self.root
            .draw_text(
                &summary,
                &text(SUBTITLE_PX, false, MUTED, HPos::Right, VPos::Center),
                (self.frame.x1 as i32, y),
            )
            .map_err(drawing_err)?;
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

/// Multiples of `step` in `[lo, hi]`, computed from integer indices (no drift).
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// The "nice" number (1, 2, 2.5 or 5 × 10ⁿ) nearest below `x`, for ticks and scale bars.
fn nice_step(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let m = x / p;
    let nice = if m >= 5.0 {
        5.0
    } else if m >= 2.5 {
        2.5
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    nice * p
}

/// The legend strip under the map.
struct Legend {
    rows: Vec<Vec<LegendItem>>,
    load: Option<(f64, String)>,
    x0: f64,
}

enum LegendItem {
    Station,
    Waypoint,
    Corridor,
    ClosedCorridor,
    ClosedNode,
    Zone(String),
}

impl LegendItem {
    fn label(&self) -> &str {
        match self {
            LegendItem::Station => "Station",
            LegendItem::Waypoint => "Waypoint",
            LegendItem::Corridor => "Corridor",
            LegendItem::ClosedCorridor => "Closed corridor",
            LegendItem::ClosedNode => "Closed node",
            LegendItem::Zone(s) => s,
        }
    }

    fn width(&self) -> f64 {
        40.0 + text_width(self.label(), LEGEND_PX, false) + 28.0
    }
}

impl Legend {
    fn new(input: &MapInput<'_>, opts: &MapOptions, width: f64) -> Legend {
        let a = input.airspace;
        let mut items = vec![LegendItem::Station];
        if a.nodes().iter().any(|n| n.kind == NodeKind::Waypoint) {
            items.push(LegendItem::Waypoint);
        }
        if input.edge_load.is_none() {
            items.push(LegendItem::Corridor);
        }
        if input.zones.iter().any(|z| !z.closed_edges.is_empty()) {
            items.push(LegendItem::ClosedCorridor);
        }
        if input.zones.iter().any(|z| !z.closed_nodes.is_empty()) {
            items.push(LegendItem::ClosedNode);
        }
        for z in &input.zones {
            let label = if z.label.is_empty() {
                "No-fly zone".to_owned()
            } else {
                format!("No-fly zone: {}", z.label)
            };
            items.push(LegendItem::Zone(label));
        }
        // Flow the items into rows that fit the width.
        let usable = width - MARGIN_LEFT - MARGIN_RIGHT;
        let mut rows: Vec<Vec<LegendItem>> = vec![Vec::new()];
        let mut used = 0.0;
        for item in items {
            let w = item.width();
            if used + w > usable && !rows.last().is_some_and(Vec::is_empty) {
                rows.push(Vec::new());
                used = 0.0;
            }
            used += w;
            if let Some(row) = rows.last_mut() {
                row.push(item);
            }
        }
        let load = input.edge_load.as_ref().map(|l| {
            (
                l.iter().copied().fold(0.0, f64::max),
                opts.load_label.clone(),
            )
        });
        Legend {
            rows,
            load,
            x0: MARGIN_LEFT,
        }
    }

    fn height(&self) -> f64 {
        LEGEND_ROW * self.rows.len() as f64
            + if self.load.is_some() {
                LEGEND_ROW + 22.0
            } else {
                0.0
            }
    }

    fn draw(&self, root: &Area<'_>, top: f64) -> Result<(), RenderError> {
        let label_style = text(LEGEND_PX, false, INK, HPos::Left, VPos::Center);
        let mut y = top + LEGEND_ROW / 2.0;
        for row in &self.rows {
            let mut x = self.x0;
            for item in row {
                let (xi, yi) = (x as i32, y as i32);
                match item {
                    LegendItem::Station => {
                        root.draw(&Circle::new((xi + 14, yi), STATION_R, INK.filled()))
                            .map_err(drawing_err)?;
                    }
                    LegendItem::Waypoint => {
                        root.draw(&Circle::new((xi + 14, yi), WAYPOINT_R, WAYPOINT.filled()))
                            .map_err(drawing_err)?;
                    }
                    LegendItem::Corridor => {
                        root.draw(&PathElement::new(
                            [(xi, yi), (xi + 30, yi)],
                            EDGE.stroke_width(2),
                        ))
                        .map_err(drawing_err)?;
                    }
                    LegendItem::ClosedCorridor => {
                        root.draw(&DashedPathElement::new(
                            [(xi, yi), (xi + 30, yi)],
                            9,
                            6,
                            ZONE.stroke_width(3),
                        ))
                        .map_err(drawing_err)?;
                    }
                    LegendItem::ClosedNode => {
                        root.draw(&Circle::new((xi + 14, yi), STATION_R, INK.filled()))
                            .map_err(drawing_err)?;
                        root.draw(&Circle::new(
                            (xi + 14, yi),
                            STATION_R + 5,
                            ZONE.stroke_width(2),
                        ))
                        .map_err(drawing_err)?;
                    }
                    LegendItem::Zone(_) => {
                        let c = [(xi, yi - 9), (xi + 30, yi + 9)];
                        root.draw(&Rectangle::new(c, ZONE.mix(0.18).filled()))
                            .map_err(drawing_err)?;
                        root.draw(&Rectangle::new(c, ZONE.mix(0.85).stroke_width(2)))
                            .map_err(drawing_err)?;
                    }
                }
                root.draw_text(item.label(), &label_style, (xi + 40, yi))
                    .map_err(drawing_err)?;
                x += item.width();
            }
            y += LEGEND_ROW;
        }
        if let Some((max, caption)) = &self.load {
            self.draw_ramp(root, y, *max, caption)?;
        }
        Ok(())
    }

    /// The load colour ramp: caption, a bar of 100 steps, and ticks at 0, ½ and max.
    fn draw_ramp(
        &self,
        root: &Area<'_>,
        y: f64,
        max: f64,
        caption: &str,
    ) -> Result<(), RenderError> {
        let yi = y as i32;
        root.draw_text(
            caption,
            &text(LEGEND_PX, true, INK, HPos::Left, VPos::Center),
            (self.x0 as i32, yi),
        )
        .map_err(drawing_err)?;
        let bar_x = self.x0 + text_width(caption, LEGEND_PX, true) + 24.0;
        let (steps, step_w) = (100, 4);
        for s in 0..steps {
            let t = f64::from(s) / f64::from(steps - 1);
            let x = bar_x as i32 + s * step_w;
            // One pixel of overlap avoids hairline seams between the steps.
            let right = x + step_w + i32::from(s + 1 < steps);
            root.draw(&Rectangle::new(
                [(x, yi - 8), (right, yi + 8)],
                ramp(t).filled(),
            ))
            .map_err(drawing_err)?;
        }
        let end = bar_x as i32 + steps * step_w;
        root.draw(&Rectangle::new(
            [(bar_x as i32, yi - 8), (end, yi + 8)],
            MUTED.stroke_width(1),
        ))
        .map_err(drawing_err)?;
        let tick_style = text(TICK_PX, false, INK, HPos::Center, VPos::Top);
        for k in 0..=2 {
            let x = bar_x as i32 + k * steps * step_w / 2;
            root.draw(&PathElement::new(
                [(x, yi + 8), (x, yi + 13)],
                MUTED.stroke_width(1),
            ))
            .map_err(drawing_err)?;
            root.draw_text(
                &fmt_num(max * f64::from(k) / 2.0),
                &tick_style,
                (x, yi + 15),
            )
            .map_err(drawing_err)?;
        }
        Ok(())
    }
}

/// The sorted union of several lists of ids (each zone's closed nodes or edges).
fn union_sorted<'a, T: Copy + Ord + 'a>(lists: impl Iterator<Item = &'a [T]>) -> Vec<T> {
    let mut all: Vec<T> = lists.flatten().copied().collect();
    all.sort_unstable();
    all.dedup();
    all
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo_types::polygon;
    use muse_model::{Edge, Node};

    fn node(id: &str, kind: NodeKind, lon: f64, lat: f64) -> Node {
        Node {
            id: id.into(),
            kind,
            name: String::new(),
            pos: LonLat::new(lon, lat),
        }
    }

    fn edge(a: u32, b: u32) -> Edge {
        Edge {
            id: format!("{a}-{b}"),
            from: NodeId(a),
            to: NodeId(b),
            length_m: 1_000.0,
        }
    }

    /// Three stations and a waypoint on a square island, with a zone in the middle.
    fn sample() -> (Airspace, Vec<Polygon<f64>>, ZoneLayer) {
        let airspace = Airspace::new(
            vec![
                node("S001", NodeKind::Station, 103.70, 1.30),
                node("S002", NodeKind::Station, 103.80, 1.35),
                node("S003", NodeKind::Station, 103.90, 1.30),
                node("W004", NodeKind::Waypoint, 103.80, 1.25),
            ],
            vec![edge(0, 1), edge(1, 2), edge(0, 3), edge(3, 2), edge(0, 2)],
        )
        .unwrap();
        // Two land halves sharing a border, and a lake in one of them.
        let land = vec![
            polygon!(
                exterior: [(x: 103.65, y: 1.20), (x: 103.80, y: 1.20), (x: 103.80, y: 1.40), (x: 103.65, y: 1.40)],
                interiors: [[(x: 103.70, y: 1.35), (x: 103.72, y: 1.35), (x: 103.72, y: 1.37), (x: 103.70, y: 1.37)]],
            ),
            // Clockwise on purpose: inputs mix orientations.
            polygon![(x: 103.80, y: 1.20), (x: 103.80, y: 1.40), (x: 103.95, y: 1.40), (x: 103.95, y: 1.20)],
        ];
        let zone = ZoneLayer {
            label: "Test zone 10:00–12:00".into(),
            polygons: vec![polygon![
                (x: 103.78, y: 1.28), (x: 103.83, y: 1.28), (x: 103.83, y: 1.32), (x: 103.78, y: 1.32),
            ]],
            closed_nodes: vec![],
            closed_edges: vec![EdgeId(4)],
        };
        (airspace, land, zone)
    }

    #[test]
    fn svg_has_labels_zone_and_frame() {
        let (airspace, land, zone) = sample();
        let input = MapInput {
            airspace: &airspace,
            land: &land,
            zones: vec![zone],
            edge_load: None,
        };
        let svg = render_map(&input, &MapOptions::default()).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..80]);
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("width=\"1800\""));
        // One <text> per station label, none for the waypoint.
        for id in ["S001", "S002", "S003"] {
            assert_eq!(svg.matches(&format!(">\n{id}\n</text>")).count(), 1, "{id}");
        }
        assert!(!svg.contains(">\nW004\n</text>"));
        // The zone: a translucent red polygon, its label on the map and in the legend.
        assert!(svg.contains("<polygon opacity=\"0.18\" fill=\"#D62728\""));
        assert!(svg.contains(">\nTest zone 10:00–12:00\n</text>"));
        assert!(svg.contains(">\nNo-fly zone: Test zone 10:00–12:00\n</text>"));
        assert!(svg.contains(">\nClosed corridor\n</text>"));
        // Scale bar, north arrow, ticks, title.
        assert!(svg.contains(" km\n</text>"));
        assert!(svg.contains(">\nN\n</text>"));
        assert!(svg.contains("°E\n</text>") && svg.contains("°N\n</text>"));
        assert!(svg.contains(">\nMUSE airspace\n</text>"));
        // Text is at least 11 px.
        for size in svg.split("font-size=\"").skip(1) {
            let px: f64 = size.split('"').next().unwrap().parse().unwrap();
            assert!(px >= 11.0, "font-size {px}");
            assert!(
                !size.split('"').next().unwrap().contains("0000"),
                "untidy font-size {size}"
            );
        }
        // Merged land: the two halves become one polygon with the lake cut out.
        let land_fills = svg.matches("fill=\"#F6F3E6\" points=").count();
        assert_eq!(land_fills, 1, "land halves are merged into one outline");
    }

    #[test]
    fn deterministic() {
        let (airspace, land, zone) = sample();
        let input = MapInput {
            airspace: &airspace,
            land: &land,
            zones: vec![zone],
            edge_load: Some(vec![1.0, 2.0, 3.0, 0.0, 7.5]),
        };
        let a = render_map(&input, &MapOptions::default()).unwrap();
        let b = render_map(&input.clone(), &MapOptions::default()).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn load_legend_only_with_load() {
        let (airspace, land, _) = sample();
        let opts = MapOptions {
            load_label: "Flights per corridor".into(),
            ..MapOptions::default()
        };
        let mut input = MapInput {
            airspace: &airspace,
            land: &land,
            zones: vec![],
            edge_load: None,
        };
        let plain = render_map(&input, &opts).unwrap();
        assert!(!plain.contains("Flights per corridor"));
        assert!(plain.contains(">\nCorridor\n</text>"));
        input.edge_load = Some(vec![10.0, 20.0, 30.0, 0.0, 40.0]);
        let loaded = render_map(&input, &opts).unwrap();
        assert!(loaded.contains(">\nFlights per corridor\n</text>"));
        // Ticks at 0, half and max.
        for tick in ["0", "20", "40"] {
            assert!(
                loaded.contains(&format!(">\n{tick}\n</text>")),
                "tick {tick}"
            );
        }
        // The busiest corridor is drawn last and thickest.
        assert!(loaded.contains("stroke-width=\"6\""));
    }

    #[test]
    fn empty_zones_no_land_no_title() {
        let (airspace, _, _) = sample();
        let opts = MapOptions {
            title: String::new(),
            label_stations: false,
            ..MapOptions::default()
        };
        let svg = render_map(&MapInput::new(&airspace), &opts).unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(!svg.contains("No-fly zone"));
        assert!(!svg.contains(">\nS001\n</text>"));
        assert!(!svg.contains("font-weight=\"bold\" opacity=\"1\" fill=\"#1B2A41\">\n\n"));
    }

    #[test]
    fn closed_nodes_are_ringed() {
        let (airspace, land, mut zone) = sample();
        zone.closed_nodes = vec![NodeId(1)];
        let input = MapInput {
            airspace: &airspace,
            land: &land,
            zones: vec![zone],
            edge_load: None,
        };
        let svg = render_map(&input, &MapOptions::default()).unwrap();
        assert!(svg.contains(">\nClosed node\n</text>"));
        assert!(svg.contains("r=\"10\" opacity=\"1\" fill=\"none\" stroke=\"#D62728\""));
    }

    #[test]
    fn bad_input_is_an_error() {
        let (airspace, land, mut zone) = sample();
        let mut input = MapInput {
            airspace: &airspace,
            land: &land,
            zones: vec![],
            edge_load: Some(vec![1.0]),
        };
        assert!(matches!(
            render_map(&input, &MapOptions::default()),
            Err(RenderError::Input(_))
        ));
        input.edge_load = Some(vec![1.0, 1.0, f64::NAN, 1.0, 1.0]);
        assert!(matches!(
            render_map(&input, &MapOptions::default()),
            Err(RenderError::Input(_))
        ));
        input.edge_load = None;
        zone.closed_edges = vec![EdgeId(99)];
        input.zones = vec![zone];
        let err = render_map(&input, &MapOptions::default()).unwrap_err();
        assert!(err.to_string().contains("edge#99"), "{err}");
        let narrow = MapOptions {
            width_px: 10,
            ..MapOptions::default()
        };
        assert!(render_map(&MapInput::new(&airspace), &narrow).is_err());
        let nothing = Airspace::new(vec![], vec![]).unwrap();
        assert_eq!(
            render_map(&MapInput::new(&nothing), &MapOptions::default()),
            Err(RenderError::Empty)
        );
    }

    #[test]
    fn single_node_gets_a_map() {
        let airspace =
            Airspace::new(vec![node("S1", NodeKind::Station, 103.8, 1.3)], vec![]).unwrap();
        let svg = render_map(&MapInput::new(&airspace), &MapOptions::default()).unwrap();
        assert!(svg.contains(">\nS1\n</text>"));
    }

    #[test]
    fn tall_airspaces_keep_a_page_shape() {
        let airspace = Airspace::new(
            vec![
                node("S1", NodeKind::Station, 103.8, 1.0),
                node("S2", NodeKind::Station, 103.8, 2.0),
            ],
            vec![edge(0, 1)],
        )
        .unwrap();
        let svg = render_map(&MapInput::new(&airspace), &MapOptions::default()).unwrap();
        let height: f64 = svg
            .split("height=\"")
            .nth(1)
            .and_then(|h| h.split('"').next())
            .unwrap()
            .parse()
            .unwrap();
        assert!(height < 1_800.0 / 0.75 + 300.0, "height {height}");
    }

    #[test]
    fn circles_become_polygons() {
        let p = circle_polygon(LonLat::new(103.8, 1.3), 1_000.0, 36);
        assert_eq!(p.exterior().0.len(), 37);
        let c = p.exterior().0[0];
        let d = LonLat::new(103.8, 1.3).geodesic_distance_m(LonLat::new(c.x, c.y));
        assert!((d - 1_000.0).abs() < 1e-6, "{d}");
    }
}
