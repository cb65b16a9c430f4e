//! The map's furniture: a kilometre scale bar, a north arrow, the frame with its lon/lat
//! graticule and ticks, and the title with the airspace's counts.

use plotters::element::{PathElement, Polygon as PolygonElement, Rectangle};
use plotters::style::Color;
use plotters::style::text_anchor::{HPos, VPos};

use super::{MapCtx, TICK_PX, TITLE_BAND};
use crate::geom::{Extent, Rect};
use crate::style::{INK, MUTED, PAPER, text, text_width};
use crate::ticks::{MAP, fmt_num};
use crate::{RenderError, drawing_err};

const TITLE_PX: f64 = 28.0;
const SUBTITLE_PX: f64 = 16.0;

impl MapCtx<'_, '_, '_> {
    /// Draws a kilometre scale bar in the lower left of the frame; returns its box.
    pub(super) fn draw_scale_bar(&self) -> Result<Rect, RenderError> {
        let f = self.frame;
        let target_px = (f.x1 - f.x0) / 5.0;
        let km_per_px = 1.0 / self.proj.px_per_km;
        let km = MAP.at_most(target_px * km_per_px);
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
    pub(super) fn draw_north_arrow(&self) -> Result<Rect, RenderError> {
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
    pub(super) fn draw_frame_and_ticks(&self, extent: Extent) -> Result<(), RenderError> {
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
        let lon_step = MAP.at_most((extent.lon1 - extent.lon0) / 7.0);
        let lat_step = MAP.at_most((extent.lat1 - extent.lat0) / 6.0);
        let bottom = text(TICK_PX, false, MUTED, HPos::Center, VPos::Top);
        let left = text(TICK_PX, false, MUTED, HPos::Right, VPos::Center);
        let grid = INK.mix(0.10).stroke_width(1);
        let tick = MUTED.stroke_width(1);
        for lon in MAP.multiples(extent.lon0, extent.lon1, lon_step) {
            let (x, _) = self.proj.px(lon, extent.lat1);
            root.draw(&PathElement::new([(x, fy0), (x, fy1)], grid))
                .map_err(drawing_err)?;
            root.draw(&PathElement::new([(x, fy1), (x, fy1 + 6)], tick))
                .map_err(drawing_err)?;
            let hemi = if lon < 0.0 { 'W' } else { 'E' };
            let label = format!("{:.*}°{hemi}", MAP.decimals(lon_step), lon.abs());
            // Skip a label that would run off the page.
            let half = (text_width(&label, TICK_PX, false) / 2.0) as i32;
            if x - half >= 0 && x + half <= w {
                root.draw_text(&label, &bottom, (x, fy1 + 9))
                    .map_err(drawing_err)?;
            }
        }
        for lat in MAP.multiples(extent.lat0, extent.lat1, lat_step) {
            let (_, y) = self.proj.px(extent.lon0, lat);
            root.draw(&PathElement::new([(fx0, y), (fx1, y)], grid))
                .map_err(drawing_err)?;
            root.draw(&PathElement::new([(fx0 - 6, y), (fx0, y)], tick))
                .map_err(drawing_err)?;
            let hemi = if lat < 0.0 { 'S' } else { 'N' };
            let label = format!("{:.*}°{hemi}", MAP.decimals(lat_step), lat.abs());
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

    pub(super) fn draw_title(&self) -> Result<(), RenderError> {
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
