//! The legend above the plot.

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use plotters::element::{PathElement, Rectangle};
use plotters::style::Color;
use plotters::style::text_anchor::{HPos, VPos};

use super::markers::{draw_marker, look};
use super::{BAND_ALPHA, LINE_W, Series, px, stroke};
use crate::style::{INK, text, text_width};
use crate::{Area, RenderError, drawing_err};

/// Height of a legend row, pixels at 900 px wide.
const LEGEND_ROW: f64 = 24.0;
/// Width of an item's swatch (band, line and marker).
const LEGEND_SWATCH: f64 = 30.0;
/// Space after a legend item's (estimated) text.
const LEGEND_GAP: f64 = 18.0;

/// The legend above the plot: one swatch (band, line and marker) and name per series,
/// flowed into rows.
pub(super) struct Legend {
    /// Series indices per row; empty for a single series.
    pub(super) rows: Vec<Vec<usize>>,
    /// Each series' item width.
    widths: Vec<f64>,
    s: f64,
    font: f64,
}

impl Legend {
    pub(super) fn new(series: &[Series], usable: f64, s: f64, font: f64) -> Legend {
        let widths: Vec<f64> = series
            .iter()
            .map(|l| (LEGEND_SWATCH + 8.0 + LEGEND_GAP) * s + text_width(&l.name, font, false))
            .collect();
        let mut rows: Vec<Vec<usize>> = Vec::new();
        if series.len() > 1 {
            let mut used = f64::INFINITY;
            for (i, w) in widths.iter().enumerate() {
                if used + w - LEGEND_GAP * s > usable {
                    rows.push(Vec::new());
                    used = 0.0;
                }
                used += w;
                if let Some(row) = rows.last_mut() {
                    row.push(i);
                }
            }
        }
        Legend {
            rows,
            widths,
            s,
            font,
        }
    }

    pub(super) fn height(&self) -> f64 {
        self.rows.len() as f64 * LEGEND_ROW * self.s
    }

    pub(super) fn draw(
        &self,
        root: &Area<'_>,
        series: &[Series],
        x0: f64,
        top: f64,
    ) -> Result<(), RenderError> {
        let s = self.s;
        let style = text(self.font, false, INK, HPos::Left, VPos::Center);
        let half_band = (5.0 * s).round() as i32;
        for (r, row) in self.rows.iter().enumerate() {
            let y = top + (r as f64 + 0.5) * LEGEND_ROW * s;
            let mut x = x0;
            for &i in row {
                let (colour, marker) = look(i);
                let (a, yi) = px(x, y);
                let b = px(x + LEGEND_SWATCH * s, y).0;
                root.draw(&Rectangle::new(
                    [(a, yi - half_band), (b, yi + half_band)],
                    colour.mix(BAND_ALPHA).filled(),
                ))
                .map_err(drawing_err)?;
                root.draw(&PathElement::new(
                    [(a, yi), (b, yi)],
                    colour.stroke_width(stroke(LINE_W * s)),
                ))
                .map_err(drawing_err)?;
                draw_marker(
                    root,
                    marker,
                    colour,
                    (f64::from(a + b) / 2.0, f64::from(yi)),
                    s,
                )?;
                root.draw_text(
                    &series[i].name,
                    &style,
                    px(x + (LEGEND_SWATCH + 8.0) * s, y),
                )
                .map_err(drawing_err)?;
                x += self.widths[i];
            }
        }
        Ok(())
    }
}
