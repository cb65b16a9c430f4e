//! The airspace map (the paper's Fig. 1): land, no-fly zones, corridors, stations.
//!
//! [`render_map`] checks the input, fits the projection and lays the page out; the drawing
//! is split by concept over `MapCtx` methods in the child modules: `layers` (land, zones,
//! corridors, stations), `labels` (zone and station labels), `furniture` (scale bar, north
//! arrow, frame with lon/lat ticks, title) and `legend`.

mod furniture;
mod labels;
mod layers;
mod legend;
mod panels;

use geo::BoundingRect;
use geo_types::Polygon;
use muse_model::{Airspace, EdgeId, NodeId};
use plotters::backend::SVGBackend;
use plotters::drawing::IntoDrawingArea;
use plotters::style::text_anchor::{HPos, VPos};

use self::layers::merge_land;
use self::legend::Legend;
pub use self::panels::{MapPanel, render_map_panels};
use crate::geom::{Extent, Projection, Rect};
use crate::style::{MUTED, PAPER, text};
use crate::{Area, RenderError, drawing_err};

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
    /// Stations to pick out (drawn larger, in an accent colour, with a legend entry named
    /// `marked_label`): e.g. the pads a siting added.
    pub marked: Vec<NodeId>,
    /// The legend entry of `marked`.
    pub marked_label: String,
}

impl<'a> MapInput<'a> {
    /// A map of `airspace` alone: no land, no zones, no load, nothing marked.
    pub fn new(airspace: &'a Airspace) -> Self {
        MapInput {
            airspace,
            land: &[],
            zones: Vec::new(),
            edge_load: None,
            marked: Vec::new(),
            marked_label: String::new(),
        }
    }
}

/// One no-fly zone on the map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ZoneLayer {
    /// Shown next to the zone and in the legend, e.g. `Downtown Core 10:00–12:00`.
    pub label: String,
    /// The zone's area in lon/lat degrees; a circle can be passed as a polygon (see
    /// [`muse_model::zone_area_polygons`] and [`muse_model::circle_polygon`]). May be empty
    /// for a zone that only lists elements.
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
    /// The load at the top of the colour scale; `None`: the busiest corridor's. Maps meant to
    /// be compared (the panels of [`render_map_panels`]) share one; it may not be below the
    /// busiest corridor's load.
    pub load_max: Option<f64>,
}

impl Default for MapOptions {
    fn default() -> Self {
        MapOptions {
            width_px: 1_800,
            title: "MUSE airspace".to_owned(),
            label_stations: true,
            load_label: "Corridor load".to_owned(),
            attribution: String::new(),
            load_max: None,
        }
    }
}

// Layout, in pixels.
const MARGIN_LEFT: f64 = 84.0;
const MARGIN_RIGHT: f64 = 28.0;
const TITLE_BAND: f64 = 64.0;
const TOP_NO_TITLE: f64 = 24.0;
const TICK_BAND: f64 = 36.0;
const TICK_PX: f64 = 14.0;
const SMALL_PX: f64 = 12.0;
const STATION_R: u32 = 5;
const WAYPOINT_R: u32 = 3;

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
    let land = merge_land(input.land);

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
    if let Some(n) = input.marked.iter().find(|n| n.index() >= a.node_count()) {
        return Err(RenderError::Input(format!(
            "marked node {n} does not exist"
        )));
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
        let busiest = load.iter().copied().fold(0.0, f64::max);
        if let Some(top) = opts.load_max
            && !(top.is_finite() && top >= busiest)
        {
            return Err(RenderError::Input(format!(
                "load_max {top} is below the busiest corridor's load {busiest}"
            )));
        }
    }
    Ok(())
}

/// The load at the top of the colour scale: [`MapOptions::load_max`], else the busiest
/// corridor's.
fn load_top(load: &[f64], opts: &MapOptions) -> f64 {
    opts.load_max
        .unwrap_or_else(|| load.iter().copied().fold(0.0, f64::max))
}

/// What the drawing methods share: the canvas, the input, the projection and the frame.
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo_types::polygon;
    use muse_model::testing::{airspace, edge, station, waypoint};

    /// Three stations and a waypoint on a square island, with a zone in the middle.
    fn sample() -> (Airspace, Vec<Polygon<f64>>, ZoneLayer) {
        let airspace = airspace(
            vec![
                station("S001", 103.70, 1.30),
                station("S002", 103.80, 1.35),
                station("S003", 103.90, 1.30),
                waypoint("W004", 103.80, 1.25),
            ],
            vec![
                edge(0, 1, 1_000.0),
                edge(1, 2, 1_000.0),
                edge(0, 3, 1_000.0),
                edge(3, 2, 1_000.0),
                edge(0, 2, 1_000.0),
            ],
        );
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
    fn marked_stations_stand_out_with_a_legend_entry() {
        let (airspace, land, _) = sample();
        let mut input = MapInput::new(&airspace);
        input.land = &land;
        let plain = render_map(&input, &MapOptions::default()).unwrap();
        input.marked = vec![NodeId(1)];
        input.marked_label = "Pads added".into();
        let svg = render_map(&input, &MapOptions::default()).unwrap();
        assert!(!plain.contains("#E87A00"));
        // The marked dot and its legend dot.
        assert_eq!(
            svg.matches("fill=\"#E87A00\"").count(),
            2,
            "one dot and one legend dot"
        );
        assert!(svg.contains(">\nPads added\n</text>"));
        input.marked = vec![NodeId(99)];
        assert!(render_map(&input, &MapOptions::default()).is_err());
    }

    #[test]
    fn svg_has_labels_zone_and_frame() {
        let (airspace, land, zone) = sample();
        let input = MapInput {
            airspace: &airspace,
            land: &land,
            zones: vec![zone],
            edge_load: None,
            marked: Vec::new(),
            marked_label: String::new(),
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
            marked: Vec::new(),
            marked_label: String::new(),
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
            marked: Vec::new(),
            marked_label: String::new(),
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
            marked: Vec::new(),
            marked_label: String::new(),
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
            marked: Vec::new(),
            marked_label: String::new(),
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
        let nothing = muse_model::testing::airspace(vec![], vec![]);
        assert_eq!(
            render_map(&MapInput::new(&nothing), &MapOptions::default()),
            Err(RenderError::Empty)
        );
    }

    #[test]
    fn single_node_gets_a_map() {
        let airspace = airspace(vec![station("S1", 103.8, 1.3)], vec![]);
        let svg = render_map(&MapInput::new(&airspace), &MapOptions::default()).unwrap();
        assert!(svg.contains(">\nS1\n</text>"));
    }

    #[test]
    fn tall_airspaces_keep_a_page_shape() {
        let airspace = airspace(
            vec![station("S1", 103.8, 1.0), station("S2", 103.8, 2.0)],
            vec![edge(0, 1, 1_000.0)],
        );
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
}
