//! The plot itself: frame, grid, axes with their ticks and labels, and the series.

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use plotters::element::{PathElement, Polygon};
use plotters::style::text_anchor::{HPos, VPos};
use plotters::style::{Color, FontTransform};

use super::axis::Axis;
use super::markers::{MARKER_R, draw_marker, look};
use super::{BAND_ALPHA, Fonts, LINE_W, PlotOptions, Point, Series, TICK_LEN, px, stroke};
use crate::geom::Rect;
use crate::style::{INK, MUTED, text, text_width};
use crate::{Area, RenderError, drawing_err};

/// Grid line opacity (of [`INK`]).
const GRID_ALPHA: f64 = 0.10;

/// The plot frame and its axes.
pub(super) struct Plot {
    pub(super) frame: Rect,
    pub(super) x: Axis,
    pub(super) y: Axis,
    pub(super) s: f64,
    pub(super) fonts: Fonts,
}

impl Plot {
    /// Pixel position of a data point (unrounded).
    fn xy(&self, x: f64, y: f64) -> (f64, f64) {
        let f = self.frame;
        (
            f.x0 + self.x.frac(x) * (f.x1 - f.x0),
            f.y1 - self.y.frac(y) * (f.y1 - f.y0),
        )
    }

    /// Pixel position of a data point.
    fn px(&self, x: f64, y: f64) -> (i32, i32) {
        let (a, b) = self.xy(x, y);
        px(a, b)
    }

    /// Grid lines at the ticks, the left and bottom axes, tick marks and tick labels. Tick
    /// labels that would collide with the previous one are left out (the tick stays).
    pub(super) fn draw_grid_and_axes(&self, root: &Area<'_>) -> Result<(), RenderError> {
        let f = self.frame;
        let s = self.s;
        let grid = INK.mix(GRID_ALPHA).stroke_width(1);
        let axis = MUTED.stroke_width(1);
        let tick_len = TICK_LEN * s;
        let (x0, y0) = px(f.x0, f.y0);
        let (x1, y1) = px(f.x1, f.y1);
        for t in &self.y.ticks {
            let (_, y) = self.px(self.x.lo, t.value);
            // Zero, when the axis crosses it, is a reference line.
            let style = if t.value == 0.0 && self.y.lo < 0.0 {
                MUTED.mix(0.6).stroke_width(1)
            } else {
                grid
            };
            root.draw(&PathElement::new([(x0, y), (x1, y)], style))
                .map_err(drawing_err)?;
        }
        for t in &self.x.ticks {
            let (x, _) = self.px(t.value, self.y.lo);
            root.draw(&PathElement::new([(x, y0), (x, y1)], grid))
                .map_err(drawing_err)?;
        }
        root.draw(&PathElement::new([(x0, y0), (x0, y1), (x1, y1)], axis))
            .map_err(drawing_err)?;

        let left = text(self.fonts.tick, false, MUTED, HPos::Right, VPos::Center);
        for t in &self.y.ticks {
            let (_, y) = self.px(self.x.lo, t.value);
            let tx = f.x0 - tick_len;
            root.draw(&PathElement::new([(px(tx, 0.0).0, y), (x0, y)], axis))
                .map_err(drawing_err)?;
            root.draw_text(&t.label, &left, px(tx - 4.0 * s, f64::from(y)))
                .map_err(drawing_err)?;
        }
        let below = text(self.fonts.tick, false, MUTED, HPos::Center, VPos::Top);
        let ty = f.y1 + tick_len;
        for &v in &self.x.minor {
            let (x, _) = self.px(v, self.y.lo);
            root.draw(&PathElement::new(
                [(x, y1), (x, px(0.0, f.y1 + tick_len * 0.6).1)],
                axis,
            ))
            .map_err(drawing_err)?;
        }
        let mut free_from = f64::NEG_INFINITY;
        for t in &self.x.ticks {
            let (x, _) = self.px(t.value, self.y.lo);
            root.draw(&PathElement::new([(x, y1), (x, px(0.0, ty).1)], axis))
                .map_err(drawing_err)?;
            let half = text_width(&t.label, self.fonts.tick, false) / 2.0;
            if f64::from(x) - half >= free_from {
                root.draw_text(&t.label, &below, px(f64::from(x), ty + 4.0 * s))
                    .map_err(drawing_err)?;
                free_from = f64::from(x) + half + 6.0 * s;
            }
        }
        Ok(())
    }

    /// Bands (all series, so that no band covers a line), then lines, then markers.
    pub(super) fn draw_series(
        &self,
        root: &Area<'_>,
        series: &[Series],
    ) -> Result<(), RenderError> {
        let s = self.s;
        let sorted: Vec<Vec<Point>> = series
            .iter()
            .map(|l| {
                let mut pts = l.points.clone();
                pts.sort_by(|a, b| a.x.total_cmp(&b.x));
                pts
            })
            .collect();
        for (i, pts) in sorted.iter().enumerate() {
            let (colour, _) = look(i);
            if pts.len() > 1 {
                let band: Vec<(i32, i32)> = pts
                    .iter()
                    .map(|p| self.px(p.x, p.ci_high))
                    .chain(pts.iter().rev().map(|p| self.px(p.x, p.ci_low)))
                    .collect();
                root.draw(&Polygon::new(band, colour.mix(BAND_ALPHA).filled()))
                    .map_err(drawing_err)?;
            }
        }
        let line = stroke(LINE_W * s);
        for (i, pts) in sorted.iter().enumerate() {
            let (colour, _) = look(i);
            if let [p] = pts.as_slice() {
                // A lone point: an error bar with caps.
                let (x, lo) = self.px(p.x, p.ci_low);
                let (_, hi) = self.px(p.x, p.ci_high);
                let cap = (MARKER_R * 1.6 * s).round() as i32;
                for path in [
                    [(x, lo), (x, hi)],
                    [(x - cap, lo), (x + cap, lo)],
                    [(x - cap, hi), (x + cap, hi)],
                ] {
                    root.draw(&PathElement::new(path, colour.stroke_width(line)))
                        .map_err(drawing_err)?;
                }
            } else {
                let path: Vec<(i32, i32)> = pts.iter().map(|p| self.px(p.x, p.mean)).collect();
                root.draw(&PathElement::new(path, colour.stroke_width(line)))
                    .map_err(drawing_err)?;
            }
        }
        for (i, pts) in sorted.iter().enumerate() {
            let (colour, marker) = look(i);
            for p in pts {
                draw_marker(root, marker, colour, self.xy(p.x, p.mean), s)?;
            }
        }
        Ok(())
    }

    /// The x label centred under the tick labels, the y label centred along the axis.
    pub(super) fn draw_axis_labels(
        &self,
        root: &Area<'_>,
        opts: &PlotOptions,
        x_label_bottom: f64,
        y_label_x: f64,
    ) -> Result<(), RenderError> {
        let f = self.frame;
        if !opts.x_label.is_empty() {
            root.draw_text(
                &opts.x_label,
                &text(self.fonts.label, false, INK, HPos::Center, VPos::Bottom),
                px(f64::midpoint(f.x0, f.x1), x_label_bottom),
            )
            .map_err(drawing_err)?;
        }
        if !opts.y_label.is_empty() {
            root.draw_text(
                &opts.y_label,
                &text(self.fonts.label, false, INK, HPos::Center, VPos::Center)
                    .transform(FontTransform::Rotate270),
                px(y_label_x, f64::midpoint(f.y0, f.y1)),
            )
            .map_err(drawing_err)?;
        }
        Ok(())
    }
}
