//! Small multiples: several maps of one place side by side in one SVG, on one load scale —
//! e.g. a layered airspace's corridor load, one panel per layer
//! (docs/reference.md#layered-airspace).
//!
//! Each panel is a whole map ([`render_map`]) with its own title and legend, nested in the
//! page as an `<svg>` element at its place; the page adds a title above and the attribution
//! below, once.

use std::fmt::Write as _;

use super::{MARGIN_LEFT, MapInput, MapOptions, SMALL_PX, TITLE_BAND, render_map};
use crate::RenderError;
use crate::style::{INK, MUTED, PAPER};

/// One panel of [`render_map_panels`].
#[derive(Clone, Debug)]
pub struct MapPanel<'a> {
    /// What it draws.
    pub input: MapInput<'a>,
    /// Its title, e.g. `Layer 2 · 69.144 m`.
    pub title: String,
}

/// Narrowest panel, pixels (the narrowest map [`render_map`] draws).
const MIN_PANEL_PX: u32 = 400;
/// Title of the page, pixels.
const PAGE_TITLE_PX: f64 = 26.0;

/// Renders `panels` in rows of `columns`, each `opts.width_px / columns` wide, under
/// `opts.title`, every panel's corridors on one load scale (the busiest corridor of any
/// panel, or `opts.load_max`), `opts.attribution` once at the bottom. The output depends
/// only on the input.
///
/// ```
/// use muse_model::Airspace;
/// use muse_render::{MapInput, MapOptions, MapPanel, render_map_panels};
/// let air = Airspace::line(&[1_000.0]);
/// let panel = |load: f64, title: &str| {
///     let mut input = MapInput::new(&air);
///     input.edge_load = Some(vec![load]);
///     MapPanel { input, title: title.to_owned() }
/// };
/// let opts = MapOptions { width_px: 1_000, title: "Two layers".into(), ..MapOptions::default() };
/// let svg = render_map_panels(&[panel(3.0, "Layer 1"), panel(1.0, "Layer 2")], 2, &opts).unwrap();
/// assert!(svg.starts_with("<svg") && svg.matches("<svg").count() == 3);
/// assert!(svg.contains("Layer 2") && svg.contains("Two layers"));
/// ```
///
/// # Errors
/// No panel, no column, panels narrower than 400 px, or a panel [`render_map`] refuses.
pub fn render_map_panels(
    panels: &[MapPanel<'_>],
    columns: usize,
    opts: &MapOptions,
) -> Result<String, RenderError> {
    if panels.is_empty() || columns == 0 {
        return Err(RenderError::Input(
            "small multiples need a panel and a column".into(),
        ));
    }
    let panel_w = opts.width_px / u32::try_from(columns).unwrap_or(u32::MAX);
    if panel_w < MIN_PANEL_PX {
        return Err(RenderError::Input(format!(
            "{columns} columns of {} px: each panel must be at least {MIN_PANEL_PX} px wide",
            opts.width_px
        )));
    }
    let busiest = panels
        .iter()
        .filter_map(|p| p.input.edge_load.as_ref())
        .flatten()
        .copied()
        .fold(0.0, f64::max);
    let mut drawn = Vec::with_capacity(panels.len());
    for p in panels {
        let own = MapOptions {
            width_px: panel_w,
            title: p.title.clone(),
            attribution: String::new(),
            load_max: Some(opts.load_max.unwrap_or(busiest)),
            ..opts.clone()
        };
        let svg = render_map(&p.input, &own)?;
        let height = svg_height(&svg).ok_or_else(|| {
            RenderError::Drawing("a panel's SVG does not start with its size".into())
        })?;
        drawn.push((svg, height));
    }
    let top = if opts.title.is_empty() {
        0.0
    } else {
        TITLE_BAND
    };
    let rows: Vec<&[(String, u32)]> = drawn.chunks(columns).collect();
    let rows_h: u32 = rows
        .iter()
        .map(|r| r.iter().map(|(_, h)| *h).max().unwrap_or(0))
        .sum();
    let bottom = if opts.attribution.is_empty() {
        0.0
    } else {
        26.0
    };
    let width = panel_w * u32::try_from(columns).unwrap_or(u32::MAX);
    let height = (top + f64::from(rows_h) + bottom).round() as u32;
    let mut out = format!(
        "<svg width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" \
         xmlns=\"http://www.w3.org/2000/svg\">\n<rect x=\"0\" y=\"0\" width=\"{width}\" \
         height=\"{height}\" fill=\"{}\"/>\n",
        hex(PAPER)
    );
    if !opts.title.is_empty() {
        text(
            &mut out,
            (MARGIN_LEFT, top / 2.0),
            PAGE_TITLE_PX,
            true,
            INK,
            &opts.title,
        );
    }
    let mut y = top.round() as u32;
    for row in rows {
        for (k, (svg, _)) in row.iter().enumerate() {
            let x = panel_w * u32::try_from(k).unwrap_or(0);
            // The panel's own root element, placed: `<svg x=".." y=".." width=...`.
            let placed = svg.replacen("<svg ", &format!("<svg x=\"{x}\" y=\"{y}\" "), 1);
            out.push_str(placed.trim_end());
            out.push('\n');
        }
        y += row.iter().map(|(_, h)| *h).max().unwrap_or(0);
    }
    if !opts.attribution.is_empty() {
        text(
            &mut out,
            (MARGIN_LEFT, f64::from(height) - 13.0),
            SMALL_PX,
            false,
            MUTED,
            &opts.attribution,
        );
    }
    out.push_str("</svg>\n");
    Ok(out)
}

/// The `height` attribute of an SVG document's root element.
fn svg_height(svg: &str) -> Option<u32> {
    let root = &svg[..svg.find('>')?];
    let at = root.find(" height=\"")? + " height=\"".len();
    let end = root[at..].find('"')? + at;
    root[at..end].parse().ok()
}

/// Appends a `<text>` element at `(x, y)` (left, vertically centred), `px` high.
fn text(
    out: &mut String,
    (x, y): (f64, f64),
    px: f64,
    bold: bool,
    colour: plotters::style::RGBColor,
    content: &str,
) {
    let weight = if bold { " font-weight=\"bold\"" } else { "" };
    let _ = writeln!(
        out,
        "<text x=\"{x}\" y=\"{y}\" dominant-baseline=\"middle\" font-family=\"sans-serif\" \
         font-size=\"{px}\"{weight} fill=\"{}\">{}</text>",
        hex(colour),
        escape(content)
    );
}

/// `#rrggbb`.
fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// `s` as SVG text: `&`, `<`, `>` and `"` escaped.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use muse_model::Airspace;

    use super::*;

    fn panel<'a>(air: &'a Airspace, load: f64, title: &str) -> MapPanel<'a> {
        let mut input = MapInput::new(air);
        input.edge_load = Some(vec![load; air.edge_count()]);
        MapPanel {
            input,
            title: title.to_owned(),
        }
    }

    #[test]
    fn panels_share_one_scale_and_are_placed_in_rows() {
        let air = Airspace::line(&[1_000.0, 1_000.0]);
        let opts = MapOptions {
            width_px: 1_600,
            title: "Load <by> layer & more".into(),
            attribution: "Data: somebody".into(),
            ..MapOptions::default()
        };
        let panels: Vec<MapPanel<'_>> = (1..=3)
            .map(|k| panel(&air, f64::from(k), &format!("Layer {k}")))
            .collect();
        let svg = render_map_panels(&panels, 2, &opts).unwrap();
        assert_eq!(svg, render_map_panels(&panels, 2, &opts).unwrap());
        assert_eq!(svg.matches("<svg").count(), 4);
        assert!(svg.contains("Load &lt;by&gt; layer &amp; more"));
        assert_eq!(svg.matches("Data: somebody").count(), 1);
        // Two per row, 800 px each: the third starts a second row.
        let one = render_map(
            &panels[0].input,
            &MapOptions {
                width_px: 800,
                title: "Layer 1".into(),
                attribution: String::new(),
                load_max: Some(3.0),
                ..opts.clone()
            },
        )
        .unwrap();
        let h = svg_height(&one).unwrap();
        let top = TITLE_BAND.round() as u32;
        assert!(svg.contains(&format!("<svg x=\"0\" y=\"{top}\" ")));
        assert!(svg.contains(&format!("<svg x=\"800\" y=\"{top}\" ")));
        assert!(svg.contains(&format!("<svg x=\"0\" y=\"{}\" ", top + h)));
        // Every panel's legend runs to the busiest corridor of all: 3.
        let layer_1 = &svg[svg.find("Layer 1").unwrap()..svg.find("Layer 2").unwrap()];
        assert!(
            layer_1.contains(">\n3\n</text>"),
            "the shared top of the scale"
        );
        assert!(one.contains(">\n3\n</text>"));
    }

    #[test]
    fn bad_layouts_are_refused() {
        let air = Airspace::line(&[1_000.0]);
        let opts = MapOptions {
            width_px: 1_000,
            ..MapOptions::default()
        };
        let p = [panel(&air, 1.0, "one")];
        assert!(render_map_panels(&[], 1, &opts).is_err());
        assert!(render_map_panels(&p, 0, &opts).is_err());
        let e = render_map_panels(&p, 3, &opts).unwrap_err().to_string();
        assert_eq!(
            e,
            "invalid input: 3 columns of 1000 px: each panel must be at least 400 px wide"
        );
        let low = MapOptions {
            load_max: Some(0.5),
            ..opts
        };
        assert!(render_map_panels(&p, 1, &low).is_err());
    }
}
