//! Labels on the map: each zone's name beside its area, each station's id beside it, placed
//! where they cover the least.

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use geo::BoundingRect;
use muse_model::NodeId;
use plotters::element::Rectangle;
use plotters::style::Color;
use plotters::style::text_anchor::{HPos, VPos};

use super::{MapCtx, STATION_R, WAYPOINT_R};
use crate::geom::{LabelPlacer, Rect};
use crate::style::{INK, LAND, PAPER, ZONE, text, text_width};
use crate::{RenderError, drawing_err};

const LABEL_PX: f64 = 14.0;
const ZONE_LABEL_PX: f64 = 17.0;

impl MapCtx<'_, '_, '_> {
    /// Scale bar and north arrow first (labels avoid them), then zone and station labels.
    pub(super) fn draw_labels_and_insets(&self) -> Result<(), RenderError> {
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
}
