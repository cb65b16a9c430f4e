//! Marker shapes: one per series, so that series differ without colour.

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use std::f64::consts::FRAC_1_SQRT_2;

use plotters::element::{Circle, Polygon};
use plotters::style::{Color, RGBColor};

use super::{px, stroke};
use crate::style::{PAPER, SERIES};
use crate::{Area, RenderError, drawing_err};

/// A marker's nominal radius, pixels at 900 px wide.
pub(super) const MARKER_R: f64 = 4.5;
/// The white rim around a marker, pixels at 900 px wide.
const MARKER_RIM: f64 = 1.5;

/// Marker shapes, one per series (in this order), so that series differ without colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
    Plus,
    Cross,
}

const MARKERS: [Marker; 7] = [
    Marker::Circle,
    Marker::Square,
    Marker::TriangleUp,
    Marker::Diamond,
    Marker::TriangleDown,
    Marker::Plus,
    Marker::Cross,
];

/// The colour and marker of the `i`th series. Both cycle through seven, shifted against
/// each other after every full cycle, so the first 49 series all differ.
pub(super) fn look(i: usize) -> (RGBColor, Marker) {
    (
        SERIES[i % SERIES.len()],
        MARKERS[(i + i / SERIES.len()) % MARKERS.len()],
    )
}

/// The outline of a (non-circle) marker of nominal radius `r` around the origin, grown by
/// `grow` pixels on every side. Sizes are chosen so that the shapes have similar areas.
fn marker_outline(m: Marker, r: f64, grow: f64) -> Vec<(f64, f64)> {
    let tri = |sign: f64| {
        // The circumradius grows twice as fast as the inradius.
        let big = 1.45 * r + 2.0 * grow;
        let (dx, dy) = (big * 0.866, big * 0.5);
        vec![(0.0, -sign * big), (dx, sign * dy), (-dx, sign * dy)]
    };
    let plus = || {
        let (a, l) = (0.45 * r + grow, 1.25 * r + grow);
        vec![
            (-a, -l),
            (a, -l),
            (a, -a),
            (l, -a),
            (l, a),
            (a, a),
            (a, l),
            (-a, l),
            (-a, a),
            (-l, a),
            (-l, -a),
            (-a, -a),
        ]
    };
    match m {
        Marker::Circle => Vec::new(),
        Marker::Square => {
            let h = 0.9 * r + grow;
            vec![(-h, -h), (h, -h), (h, h), (-h, h)]
        }
        Marker::Diamond => {
            let h = 1.25 * r + grow * std::f64::consts::SQRT_2;
            vec![(0.0, -h), (h, 0.0), (0.0, h), (-h, 0.0)]
        }
        Marker::TriangleUp => tri(1.0),
        Marker::TriangleDown => tri(-1.0),
        Marker::Plus => plus(),
        Marker::Cross => plus()
            .into_iter()
            .map(|(x, y)| ((x - y) * FRAC_1_SQRT_2, (x + y) * FRAC_1_SQRT_2))
            .collect(),
    }
}

/// A marker at `(x, y)` with a white rim, so that it stands out on lines and bands.
pub(super) fn draw_marker(
    root: &Area<'_>,
    m: Marker,
    colour: RGBColor,
    (x, y): (f64, f64),
    s: f64,
) -> Result<(), RenderError> {
    let (r, rim) = (MARKER_R * s, MARKER_RIM * s);
    let c = px(x, y);
    if m == Marker::Circle {
        root.draw(&Circle::new(c, stroke(r + rim), PAPER.filled()))
            .map_err(drawing_err)?;
        root.draw(&Circle::new(c, stroke(r), colour.filled()))
            .map_err(drawing_err)?;
        return Ok(());
    }
    for (grow, fill) in [(rim, PAPER), (0.0, colour)] {
        let pts: Vec<(i32, i32)> = marker_outline(m, r, grow)
            .into_iter()
            .map(|(dx, dy)| (c.0 + dx.round() as i32, c.1 + dy.round() as i32))
            .collect();
        root.draw(&Polygon::new(pts, fill.filled()))
            .map_err(drawing_err)?;
    }
    Ok(())
}
