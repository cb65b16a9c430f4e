//! The legend strip under the map: the symbols drawn, each zone by name, and the load
//! colour ramp when corridors are coloured by load.

use muse_model::NodeKind;
use plotters::element::{Circle, DashedPathElement, PathElement, Rectangle};
use plotters::style::Color;
use plotters::style::text_anchor::{HPos, VPos};

use super::{
    MARGIN_LEFT, MARGIN_RIGHT, MapInput, MapOptions, STATION_R, TICK_PX, WAYPOINT_R, load_top,
};
use crate::style::{EDGE, INK, MARKED, MUTED, WAYPOINT, ZONE, ramp, text, text_width};
use crate::ticks::fmt_num;
use crate::{Area, RenderError, drawing_err};

const LEGEND_ROW: f64 = 34.0;
const LEGEND_PX: f64 = 16.0;

/// The legend strip under the map.
pub(super) struct Legend {
    rows: Vec<Vec<LegendItem>>,
    load: Option<(f64, String)>,
    x0: f64,
}

enum LegendItem {
    Station,
    Marked(String),
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
            LegendItem::Marked(s) | LegendItem::Zone(s) => s,
        }
    }

    fn width(&self) -> f64 {
        40.0 + text_width(self.label(), LEGEND_PX, false) + 28.0
    }
}

impl Legend {
    pub(super) fn new(input: &MapInput<'_>, opts: &MapOptions, width: f64) -> Legend {
        let a = input.airspace;
        let mut items = vec![LegendItem::Station];
        if !input.marked.is_empty() {
            items.push(LegendItem::Marked(input.marked_label.clone()));
        }
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
        let load = input
            .edge_load
            .as_ref()
            .map(|l| (load_top(l, opts), opts.load_label.clone()));
        Legend {
            rows,
            load,
            x0: MARGIN_LEFT,
        }
    }

    pub(super) fn height(&self) -> f64 {
        LEGEND_ROW * self.rows.len() as f64
            + if self.load.is_some() {
                LEGEND_ROW + 22.0
            } else {
                0.0
            }
    }

    pub(super) fn draw(&self, root: &Area<'_>, top: f64) -> Result<(), RenderError> {
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
                    LegendItem::Marked(_) => {
                        root.draw(&Circle::new((xi + 14, yi), STATION_R + 2, MARKED.filled()))
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
