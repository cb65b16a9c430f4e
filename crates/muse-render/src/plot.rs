//! Line plots with confidence bands (the paper's Figs. 2–4: the parameter sweep).

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use std::f64::consts::FRAC_1_SQRT_2;

use plotters::backend::SVGBackend;
use plotters::coord::Shift;
use plotters::drawing::{DrawingArea, IntoDrawingArea};
use plotters::element::{Circle, PathElement, Polygon, Rectangle};
use plotters::style::text_anchor::{HPos, VPos};
use plotters::style::{Color, FontTransform, RGBColor};

use crate::RenderError;
use crate::geom::Rect;
use crate::style::{INK, MUTED, PAPER, SERIES, exact_px, text, text_width};

/// One line of a plot: one scenario's results across the swept parameter.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Shown in the legend (there is no legend when there is only one series).
    pub name: String,
    /// The measurements, in any order: the line joins them in order of `x`.
    pub points: Vec<Point>,
}

/// One measurement: the mean over the runs at `x` and its 95 % confidence interval.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// The value of the swept parameter.
    pub x: f64,
    /// The mean of the measured quantity.
    pub mean: f64,
    /// The lower end of the confidence interval (at most `mean`).
    pub ci_low: f64,
    /// The upper end of the confidence interval (at least `mean`).
    pub ci_high: f64,
}

/// Titles, labels and size of a line plot.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotOptions {
    /// Bold title above the plot (none if empty).
    pub title: String,
    /// Caption under the x axis (none if empty).
    pub x_label: String,
    /// Caption along the y axis, read bottom to top (none if empty).
    pub y_label: String,
    /// Width of the SVG in pixels, 300..=20000. Text, strokes and margins are sized for
    /// 900 px and grow in proportion above that, so a wider plot shown 900 px wide looks
    /// the same.
    pub width_px: u32,
    /// Height of the SVG in pixels, 200..=20000.
    pub height_px: u32,
    /// Whether the y axis reaches zero (starts at it, or ends at it if all values are
    /// negative) instead of just enclosing the data.
    pub y_from_zero: bool,
    /// Whether y values are fractions to be labelled as percentages (`0.85` → `85%`).
    pub y_percent: bool,
    /// Whether the x axis is logarithmic, for x values spanning orders of magnitude (e.g.
    /// 10,000 to 1,000,000 requests). Labelled ticks are then at the powers of ten (at 1, 2
    /// and 5 × 10ⁿ when the data span less than a decade or two, or at the data's x values if
    /// even those are too few), with short unlabelled ticks at the other whole multiples.
    /// Every x must be positive.
    pub x_log: bool,
    /// Small print under the plot, e.g. `100 runs per point; 95% CI` (none if empty; `\n`
    /// starts a new line).
    pub footnote: String,
}

impl Default for PlotOptions {
    /// No text, 900 × 540 px, linear axes, y axis fitted to the data, plain numbers.
    fn default() -> Self {
        PlotOptions {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            width_px: 900,
            height_px: 540,
            y_from_zero: false,
            y_percent: false,
            x_log: false,
            footnote: String::new(),
        }
    }
}

// Layout at 900 px wide, in pixels; everything is scaled by `width / 900` above that.
const BASE_WIDTH: f64 = 900.0;
const PAD: f64 = 18.0;
const TITLE_PX: f64 = 21.0;
const LABEL_PX: f64 = 15.0;
const TICK_PX: f64 = 13.0;
const LEGEND_PX: f64 = 14.0;
const FOOT_PX: f64 = 12.0;
const TICK_LEN: f64 = 5.0;
const LEGEND_ROW: f64 = 24.0;
const LEGEND_SWATCH: f64 = 30.0;
/// Space after a legend item's (estimated) text.
const LEGEND_GAP: f64 = 18.0;
const MARKER_R: f64 = 4.5;
const MARKER_RIM: f64 = 1.5;
const LINE_W: f64 = 2.0;
/// Wanted distance between y ticks and between computed x ticks.
const Y_TICK_SPACING: f64 = 55.0;
/// Least distance between y ticks.
const Y_TICK_MIN_SPACING: f64 = 36.0;
const X_TICK_SPACING: f64 = 90.0;
/// Up to this many distinct x values, the x ticks are the data's x values.
const MAX_DATA_TICKS: usize = 12;
const MIN_PLOT_PX: f64 = 60.0;
/// Opacity of the confidence band.
const BAND_ALPHA: f64 = 0.16;
/// Grid line opacity (of [`INK`]).
const GRID_ALPHA: f64 = 0.10;

type Area<'b> = DrawingArea<SVGBackend<'b>, Shift>;

fn drawing_err<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError::Drawing(e.to_string())
}

/// Renders a line plot of `series` with their confidence intervals as an SVG document.
///
/// Each series is one line in its own colour (a colour-blind-safe palette) and marker, over
/// a translucent band spanning its confidence intervals (a series with a single point gets
/// an error bar instead). The y ticks are round numbers (1, 2 or 5 × 10ⁿ apart); the x ticks
/// are the data's x values when there are at most 12 distinct ones, round numbers
/// otherwise; a logarithmic x axis ([`PlotOptions::x_log`]) has them at the powers of ten.
/// The legend, above the plot, names the series; it is left out for a single
/// series.
///
/// Text is SVG `<text>` in the viewer's sans-serif font; no font files are read. The output
/// depends only on the input: the same input gives the same bytes.
///
/// Fails with [`RenderError::Input`] when there are no series, a series has no points, a
/// value is not finite, an interval does not contain its mean (`ci_low <= mean <= ci_high`),
/// or the size leaves no room for the plot.
///
/// ```
/// use muse_render::{render_line_plot, PlotOptions, Point, Series};
///
/// let point = |x, mean, half| Point { x, mean, ci_low: mean - half, ci_high: mean + half };
/// let series = vec![Series {
///     name: "Baseline".into(),
///     points: vec![point(10.0, 0.91, 0.02), point(20.0, 0.88, 0.03), point(40.0, 0.79, 0.04)],
/// }];
/// let opts = PlotOptions {
///     title: "Deliveries on time".into(),
///     x_label: "Drones".into(),
///     y_label: "On time".into(),
///     y_percent: true,
///     footnote: "100 runs per point; 95% CI".into(),
///     ..PlotOptions::default()
/// };
/// let svg = render_line_plot(&series, &opts).unwrap();
/// assert!(svg.starts_with("<svg"));
/// assert!(svg.contains(">\n80%\n</text>"));
/// ```
pub fn render_line_plot(series: &[Series], opts: &PlotOptions) -> Result<String, RenderError> {
    validate(series, opts)?;
    let (width, height) = (f64::from(opts.width_px), f64::from(opts.height_px));
    let s = (width / BASE_WIDTH).max(1.0);
    let size = |base: f64| exact_px(base * s);
    let fonts = Fonts {
        title: size(TITLE_PX),
        label: size(LABEL_PX),
        tick: size(TICK_PX),
        legend: size(LEGEND_PX),
        foot: size(FOOT_PX),
    };

    // Top to bottom: title, legend, plot, x tick labels, x label, footnote.
    let pad = PAD * s;
    let mut top = pad;
    let title_y = top;
    if !opts.title.is_empty() {
        top += fonts.title * 1.2 + 10.0 * s;
    }
    let legend = Legend::new(series, width - 2.0 * pad, s, fonts.legend);
    let legend_y = top;
    if !legend.rows.is_empty() {
        top += legend.height() + 4.0 * s;
    }
    let frame_y0 = top + fonts.tick;
    let foot_lines: Vec<&str> = if opts.footnote.is_empty() {
        Vec::new()
    } else {
        opts.footnote.lines().collect()
    };
    let mut bottom = height - pad;
    let foot_y = bottom - foot_lines.len() as f64 * fonts.foot * 1.3;
    if !foot_lines.is_empty() {
        bottom = foot_y - 8.0 * s;
    }
    let x_label_y = bottom;
    if !opts.x_label.is_empty() {
        bottom -= fonts.label * 1.2 + 6.0 * s;
    }
    let frame_y1 = bottom - fonts.tick * 1.2 - TICK_LEN * s - 4.0 * s;
    let plot_h = frame_y1 - frame_y0;
    if plot_h < MIN_PLOT_PX {
        return Err(too_small(opts));
    }

    // Left to right: y label, y tick labels, plot.
    let y_axis = y_axis(series, opts, plot_h, s)?;
    let y_label_x = pad + fonts.label * 0.6;
    let mut left = pad;
    if !opts.y_label.is_empty() {
        left += fonts.label * 1.2 + 10.0 * s;
    }
    let widest = y_axis
        .ticks
        .iter()
        .map(|t| text_width(&t.label, fonts.tick, false))
        .fold(0.0, f64::max);
    let frame_x0 = left + widest + (6.0 + TICK_LEN) * s;
    let frame_x1 = width - pad - 12.0 * s;
    if frame_x1 - frame_x0 < MIN_PLOT_PX {
        return Err(too_small(opts));
    }
    let x_axis = if opts.x_log { log_x_axis } else { x_axis }(series, frame_x1 - frame_x0, s)?;

    let plot = Plot {
        frame: Rect {
            x0: frame_x0,
            y0: frame_y0,
            x1: frame_x1,
            y1: frame_y1,
        },
        x: x_axis,
        y: y_axis,
        s,
        fonts,
    };

    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (opts.width_px, opts.height_px)).into_drawing_area();
        root.fill(&PAPER).map_err(drawing_err)?;
        plot.draw_grid_and_axes(&root)?;
        plot.draw_series(&root, series)?;
        plot.draw_axis_labels(&root, opts, x_label_y, y_label_x)?;
        if !opts.title.is_empty() {
            root.draw_text(
                &opts.title,
                &text(fonts.title, true, INK, HPos::Left, VPos::Top),
                px(pad, title_y),
            )
            .map_err(drawing_err)?;
        }
        legend.draw(&root, series, pad, legend_y)?;
        let foot_style = text(fonts.foot, false, MUTED, HPos::Left, VPos::Top);
        for (i, line) in foot_lines.iter().enumerate() {
            root.draw_text(
                line,
                &foot_style,
                px(pad, foot_y + i as f64 * fonts.foot * 1.3),
            )
            .map_err(drawing_err)?;
        }
        root.present().map_err(drawing_err)?;
    }
    Ok(svg)
}

fn too_small(opts: &PlotOptions) -> RenderError {
    RenderError::Input(format!(
        "a {} × {} px plot leaves no room for the plot area with these labels",
        opts.width_px, opts.height_px
    ))
}

fn validate(series: &[Series], opts: &PlotOptions) -> Result<(), RenderError> {
    let input = |msg: String| Err(RenderError::Input(msg));
    if !(300..=20_000).contains(&opts.width_px) {
        return input(format!(
            "plot width {} px is outside 300..=20000",
            opts.width_px
        ));
    }
    if !(200..=20_000).contains(&opts.height_px) {
        return input(format!(
            "plot height {} px is outside 200..=20000",
            opts.height_px
        ));
    }
    if series.is_empty() {
        return input("there are no series to plot".to_owned());
    }
    for line in series {
        let name = &line.name;
        if line.points.is_empty() {
            return input(format!("series `{name}` has no points"));
        }
        for (i, p) in line.points.iter().enumerate() {
            let values = [
                ("x", p.x),
                ("mean", p.mean),
                ("ci_low", p.ci_low),
                ("ci_high", p.ci_high),
            ];
            if let Some((what, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
                return input(format!(
                    "series `{name}`, point {i}: {what} = {v} is not finite"
                ));
            }
            if opts.x_log && p.x <= 0.0 {
                return input(format!(
                    "series `{name}`, point {i}: x = {} cannot be shown on a logarithmic x axis (it must be > 0)",
                    p.x
                ));
            }
            if p.ci_low > p.mean || p.mean > p.ci_high {
                return input(format!(
                    "series `{name}`, point {i}: the interval [{}, {}] does not contain the mean {}",
                    p.ci_low, p.ci_high, p.mean
                ));
            }
        }
    }
    Ok(())
}

/// Font sizes in pixels, after scaling.
#[derive(Clone, Copy)]
struct Fonts {
    title: f64,
    label: f64,
    tick: f64,
    legend: f64,
    foot: f64,
}

/// `(x, y)` rounded to whole pixels.
fn px(x: f64, y: f64) -> (i32, i32) {
    (x.round() as i32, y.round() as i32)
}

/// A pixel length of at least 1.
fn stroke(w: f64) -> u32 {
    (w.round() as u32).max(1)
}

/// An axis: the value range spanned by the frame and the labelled ticks.
#[derive(Clone, Debug, PartialEq)]
struct Axis {
    lo: f64,
    hi: f64,
    ticks: Vec<Tick>,
    /// Unlabelled short ticks (the log axis's intermediate multiples).
    minor: Vec<f64>,
    /// Whether positions are proportional to the logarithm of the value.
    log: bool,
}

#[derive(Clone, Debug, PartialEq)]
struct Tick {
    value: f64,
    label: String,
}

impl Axis {
    /// Where `v` falls between `lo` (0) and `hi` (1).
    fn frac(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

/// The smallest 1, 2 or 5 × 10ⁿ that is at least `raw` (1 for nonsense input).
fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let p = 10f64.powi(raw.log10().floor() as i32);
    let m = raw / p;
    let nice = if m <= 1.0 + 1e-9 {
        1.0
    } else if m <= 2.0 + 1e-9 {
        2.0
    } else if m <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    nice * p
}

/// The 1, 2 or 5 × 10ⁿ just below `step` (itself one of those).
fn smaller_nice_step(step: f64) -> f64 {
    let p = 10f64.powi(step.log10().floor() as i32);
    let m = (step / p).round();
    if m >= 5.0 {
        2.0 * p
    } else if m >= 2.0 {
        p
    } else {
        0.5 * p
    }
}

/// Decimals needed to write multiples of `step` (1, 2 or 5 × 10ⁿ) exactly.
fn step_decimals(step: f64) -> usize {
    ((-(step.log10() + 1e-9).floor()).max(0.0) as usize).min(12)
}

/// The fewest decimals (up to 6) that write every value in `values` exactly.
fn value_decimals(values: &[f64]) -> usize {
    (0..=6)
        .find(|&d| {
            let p = 10f64.powi(d);
            values
                .iter()
                .all(|v| ((v * p).round() / p - v).abs() <= 1e-9 * v.abs().max(1.0))
        })
        .map_or(6, |d| d as usize)
}

/// A tick label: `decimals` decimals, a true minus sign, thousands separated by commas
/// from 10,000 on.
fn fmt_tick(v: f64, decimals: usize) -> String {
    let digits = format!("{:.*}", decimals, v.abs());
    let negative = v < 0.0 && digits.chars().any(|c| ('1'..='9').contains(&c));
    let (int, frac) = digits.split_at(digits.find('.').unwrap_or(digits.len()));
    let int = if int.len() > 4 {
        let mut grouped = String::with_capacity(int.len() + int.len() / 3);
        for (i, c) in int.chars().enumerate() {
            if i > 0 && (int.len() - i) % 3 == 0 {
                grouped.push(',');
            }
            grouped.push(c);
        }
        grouped
    } else {
        int.to_owned()
    };
    format!("{}{int}{frac}", if negative { "\u{2212}" } else { "" })
}

/// Ticks at the multiples of `step` in `[lo, hi]` (with a little tolerance), from integer
/// indices so that they do not drift.
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).take(64).map(|i| i as f64 * step).collect()
}

/// A range that is never empty: a degenerate `[v, v]` is widened around `v` (to `[0, 1]`
/// for zero). Fails if the span is not a finite number.
fn widen(lo: f64, hi: f64) -> Result<(f64, f64), RenderError> {
    let span = hi - lo;
    if !span.is_finite() {
        return Err(RenderError::Input(format!(
            "the values span {lo} to {hi}, too wide to plot"
        )));
    }
    let m = lo.abs().max(hi.abs());
    if span > m * 1e-9 {
        Ok((lo, hi))
    } else if m == 0.0 {
        Ok((0.0, 1.0))
    } else {
        let mid = f64::midpoint(lo, hi);
        Ok((mid - m * 0.1, mid + m * 0.1))
    }
}

/// The y axis: round limits enclosing every interval (and zero if asked), 1-2-5 ticks about
/// [`Y_TICK_SPACING`] apart.
fn y_axis(series: &[Series], opts: &PlotOptions, plot_h: f64, s: f64) -> Result<Axis, RenderError> {
    let points = || series.iter().flat_map(|l| &l.points);
    let mut lo = points().map(|p| p.ci_low).fold(f64::INFINITY, f64::min);
    let mut hi = points()
        .map(|p| p.ci_high)
        .fold(f64::NEG_INFINITY, f64::max);
    if opts.y_from_zero {
        lo = lo.min(0.0);
        hi = hi.max(0.0);
    }
    let (lo, hi) = widen(lo, hi)?;
    // Of the two 1-2-5 steps around the wanted spacing, the one whose interval count (after
    // rounding the limits out) comes closest to the wanted count without crowding.
    let target = (plot_h / (Y_TICK_SPACING * s)).max(2.0);
    let most = (plot_h / (Y_TICK_MIN_SPACING * s)).floor().clamp(2.0, 12.0);
    let coarse = nice_step((hi - lo) / target.floor());
    let limits = |step: f64| {
        let first = (lo / step + 1e-9).floor();
        let last = (hi / step - 1e-9).ceil();
        (first, last)
    };
    let step = [smaller_nice_step(coarse), coarse]
        .into_iter()
        .filter(|&step| {
            let (first, last) = limits(step);
            last - first <= most
        })
        .min_by(|&a, &b| {
            let off = |step: f64| {
                let (first, last) = limits(step);
                (last - first - target).abs()
            };
            off(a).total_cmp(&off(b))
        })
        .unwrap_or(coarse);
    let (first, last) = limits(step);
    let (lo, hi) = (first * step, last * step);
    let (scale, unit) = if opts.y_percent {
        (100.0, "%")
    } else {
        (1.0, "")
    };
    let decimals = step_decimals(step * scale);
    let ticks = multiples(lo, hi, step)
        .into_iter()
        .map(|value| Tick {
            value,
            label: format!("{}{unit}", fmt_tick(value * scale, decimals)),
        })
        .collect();
    Ok(Axis {
        lo,
        hi,
        ticks,
        minor: Vec::new(),
        log: false,
    })
}

/// The distinct x values of all series, ascending.
fn distinct_xs(series: &[Series]) -> Vec<f64> {
    let mut xs: Vec<f64> = series
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.x))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    xs
}

/// The x axis: ticks at the data's x values when there are few, else 1-2-5 ticks about
/// [`X_TICK_SPACING`] apart; a margin on both sides keeps the end markers off the frame.
fn x_axis(series: &[Series], plot_w: f64, s: f64) -> Result<Axis, RenderError> {
    let xs = distinct_xs(series);
    let (lo, hi) = widen(xs[0], xs[xs.len() - 1])?;
    let margin = (hi - lo) * 0.04;
    let ticks: Vec<Tick> = if xs.len() <= MAX_DATA_TICKS {
        let decimals = value_decimals(&xs);
        xs.iter()
            .map(|&value| Tick {
                value,
                label: fmt_tick(value, decimals),
            })
            .collect()
    } else {
        let intervals = (plot_w / (X_TICK_SPACING * s)).floor().clamp(2.0, 10.0);
        let step = nice_step((hi - lo) / intervals);
        let decimals = step_decimals(step);
        multiples(lo, hi, step)
            .into_iter()
            .map(|value| Tick {
                value,
                label: fmt_tick(value, decimals),
            })
            .collect()
    };
    Ok(Axis {
        lo: lo - margin,
        hi: hi + margin,
        ticks,
        minor: Vec::new(),
        log: false,
    })
}

/// A logarithmic x axis (all x positive): labelled ticks at the powers of ten inside the
/// data's range; at 1, 2 and 5 × 10ⁿ when that gives fewer than three; at the data's x
/// values when that still gives fewer than two. Short unlabelled ticks mark the other whole
/// multiples of each power of ten when a decade is wide enough for them. A margin of 4% of
/// the logarithmic span on both sides keeps the end markers off the frame.
fn log_x_axis(series: &[Series], plot_w: f64, s: f64) -> Result<Axis, RenderError> {
    let xs = distinct_xs(series);
    let (min, max) = (xs[0], xs[xs.len() - 1]);
    // One value: half a decade either side.
    let (lo, hi) = if max / min > 1.0 + 1e-9 {
        (min.log10(), max.log10())
    } else {
        (min.log10() - 0.5, max.log10() + 0.5)
    };
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(RenderError::Input(format!(
            "the x values span {min} to {max}, too wide to plot"
        )));
    }
    let inside = |v: f64| {
        let l = v.log10();
        l >= lo - 1e-9 && l <= hi + 1e-9
    };
    let (first, last) = ((lo - 1e-9).floor() as i32, (hi + 1e-9).ceil() as i32);
    let decades: Vec<i32> = (first..=last).take(400).collect();
    let candidates = |mantissas: &[f64]| -> Vec<f64> {
        decades
            .iter()
            .flat_map(|&e| mantissas.iter().map(move |&m| m * 10f64.powi(e)))
            .filter(|&v| inside(v))
            .collect()
    };
    let decade_px = plot_w / (hi - lo).max(1e-9);
    let mut values = candidates(&[1.0]);
    if values.len() >= 3 {
        // Every `every`th power of ten, so that labels keep about `X_TICK_SPACING` apart.
        let every = (X_TICK_SPACING * s / decade_px).ceil().max(1.0) as i64;
        values.retain(|v| (v.log10().round() as i64).rem_euclid(every) == 0);
    } else {
        values = candidates(&[1.0, 2.0, 5.0]);
        if values.len() < 2 {
            values.clone_from(&xs);
        }
    }
    // Each label with its own decimals: 0.01, 0.1, 1, 10.
    let ticks = values
        .iter()
        .map(|&value| Tick {
            value,
            label: fmt_tick(value, value_decimals(&[value])),
        })
        .collect();
    // Minor ticks at 2..9 × 10ⁿ when a decade is at least ~60 px wide.
    let minor = if decade_px >= 60.0 * s {
        candidates(&[2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
            .into_iter()
            .filter(|v| !values.iter().any(|t| (t / v - 1.0).abs() < 1e-9))
            .collect()
    } else {
        Vec::new()
    };
    let margin = (hi - lo) * 0.04;
    Ok(Axis {
        lo: 10f64.powf(lo - margin),
        hi: 10f64.powf(hi + margin),
        ticks,
        minor,
        log: true,
    })
}

/// Marker shapes, one per series (in this order), so that series differ without colour.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Marker {
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
fn look(i: usize) -> (RGBColor, Marker) {
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
fn draw_marker(
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

/// The plot frame and its axes.
struct Plot {
    frame: Rect,
    x: Axis,
    y: Axis,
    s: f64,
    fonts: Fonts,
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
    fn draw_grid_and_axes(&self, root: &Area<'_>) -> Result<(), RenderError> {
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
    fn draw_series(&self, root: &Area<'_>, series: &[Series]) -> Result<(), RenderError> {
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
    fn draw_axis_labels(
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

/// The legend above the plot: one swatch (band, line and marker) and name per series,
/// flowed into rows.
struct Legend {
    /// Series indices per row; empty for a single series.
    rows: Vec<Vec<usize>>,
    /// Each series' item width.
    widths: Vec<f64>,
    s: f64,
    font: f64,
}

impl Legend {
    fn new(series: &[Series], usable: f64, s: f64, font: f64) -> Legend {
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

    fn height(&self) -> f64 {
        self.rows.len() as f64 * LEGEND_ROW * self.s
    }

    fn draw(
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

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f64, mean: f64, half: f64) -> Point {
        Point {
            x,
            mean,
            ci_low: mean - half,
            ci_high: mean + half,
        }
    }

    /// Three scenarios over five fleet sizes, as fractions.
    fn sweep() -> Vec<Series> {
        let scenario = |name: &str, base: f64, slope: f64| Series {
            name: name.into(),
            points: [10.0, 20.0, 50.0, 100.0, 200.0]
                .iter()
                .map(|&x| point(x, base - slope * x, 0.01 + x / 10_000.0))
                .collect(),
        };
        vec![
            scenario("Baseline", 0.97, 0.0006),
            scenario("Rush hour", 0.95, 0.0012),
            scenario("Airport closed", 0.93, 0.0020),
        ]
    }

    fn options() -> PlotOptions {
        PlotOptions {
            title: "On-time deliveries".into(),
            x_label: "Drones in the fleet".into(),
            y_label: "Delivered on time".into(),
            y_percent: true,
            footnote: "100 runs per point; 95% CI".into(),
            ..PlotOptions::default()
        }
    }

    fn text_nodes(svg: &str) -> Vec<&str> {
        svg.split("</text>")
            .filter_map(|t| t.rsplit_once(">\n").map(|(_, s)| s.trim_end_matches('\n')))
            .collect()
    }

    #[test]
    fn legend_labels_and_axes() {
        let svg = render_line_plot(&sweep(), &options()).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..80]);
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("width=\"900\"") && svg.contains("height=\"540\""));
        let texts = text_nodes(&svg);
        for label in [
            "Baseline",
            "Rush hour",
            "Airport closed",
            "On-time deliveries",
            "Drones in the fleet",
            "Delivered on time",
            "100 runs per point; 95% CI",
        ] {
            assert_eq!(
                texts.iter().filter(|t| **t == label).count(),
                1,
                "{label} in {texts:?}"
            );
        }
        // The y label runs up the left side.
        assert!(svg.contains("transform=\"rotate(270,"));
        // x ticks at the data's x values (all five fit at 900 px).
        for x in ["10", "20", "50", "100", "200"] {
            assert!(texts.contains(&x), "x tick {x} in {texts:?}");
        }
        // One line per series in its own colour, and a band each.
        for colour in &SERIES[..3] {
            let hex = format!("#{:02X}{:02X}{:02X}", colour.0, colour.1, colour.2);
            assert!(
                svg.contains(&format!(
                    "<polyline fill=\"none\" opacity=\"1\" stroke=\"{hex}\""
                )),
                "line {hex}"
            );
            assert!(
                svg.contains(&format!("<polygon opacity=\"0.16\" fill=\"{hex}\"")),
                "band {hex}"
            );
        }
        // Text is at least 11 px, with tidy sizes.
        for size in svg.split("font-size=\"").skip(1) {
            let size = size.split('"').next().unwrap();
            let v: f64 = size.parse().unwrap();
            assert!(v >= 11.0 && !size.contains("0000"), "font-size {size}");
        }
    }

    #[test]
    fn single_series_has_no_legend() {
        let one = vec![sweep().remove(0)];
        let svg = render_line_plot(&one, &options()).unwrap();
        assert!(!text_nodes(&svg).contains(&"Baseline"));
    }

    #[test]
    fn deterministic() {
        let a = render_line_plot(&sweep(), &options()).unwrap();
        let b = render_line_plot(&sweep().clone(), &options().clone()).unwrap();
        assert_eq!(a, b);
        // The order of the points does not matter either.
        let mut shuffled = sweep();
        for l in &mut shuffled {
            l.points.reverse();
        }
        assert_eq!(a, render_line_plot(&shuffled, &options()).unwrap());
    }

    #[test]
    fn percent_ticks() {
        let svg = render_line_plot(&sweep(), &options()).unwrap();
        let texts = text_nodes(&svg);
        let y_ticks: Vec<&str> = texts
            .iter()
            .copied()
            .filter(|t| t.ends_with('%') && t.len() <= 4)
            .collect();
        assert!(y_ticks.len() >= 4, "{y_ticks:?}");
        assert!(
            y_ticks.contains(&"80%") && y_ticks.contains(&"90%"),
            "{y_ticks:?}"
        );
        assert!(!texts.contains(&"0.8") && !texts.contains(&"0.9"));
        // From zero: the axis starts at 0%.
        let opts = PlotOptions {
            y_from_zero: true,
            ..options()
        };
        let svg = render_line_plot(&sweep(), &opts).unwrap();
        let texts = text_nodes(&svg);
        assert!(
            texts.contains(&"0%") && texts.contains(&"100%"),
            "{texts:?}"
        );
        // Plain numbers without the flag.
        let opts = PlotOptions {
            y_percent: false,
            ..options()
        };
        let svg = render_line_plot(&sweep(), &opts).unwrap();
        assert!(text_nodes(&svg).contains(&"0.8"));
    }

    #[test]
    fn nice_steps_and_labels() {
        #![allow(clippy::float_cmp)]
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(0.1), 0.1);
        assert_eq!(nice_step(1.5), 2.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(nice_step(2_000.0), 2_000.0);
        assert_eq!(nice_step(f64::NAN), 1.0);
        assert_eq!(smaller_nice_step(0.1), 0.05);
        assert_eq!(smaller_nice_step(0.2), 0.1);
        assert_eq!(smaller_nice_step(500.0), 200.0);
        assert_eq!(step_decimals(0.05), 2);
        assert_eq!(step_decimals(0.1), 1);
        assert_eq!(step_decimals(20.0), 0);
        assert_eq!(value_decimals(&[1.0, 2.5, 10.0]), 1);
        assert_eq!(value_decimals(&[0.125]), 3);
        assert_eq!(fmt_tick(-1.5, 1), "\u{2212}1.5");
        assert_eq!(fmt_tick(-0.0001, 1), "0.0");
        assert_eq!(fmt_tick(1_234.0, 0), "1234");
        assert_eq!(fmt_tick(12_345.0, 0), "12,345");
        assert_eq!(fmt_tick(1_234_567.25, 2), "1,234,567.25");
        assert_eq!(multiples(0.0, 1.0, 0.2).len(), 6);
    }

    #[test]
    fn y_ticks_are_one_two_five() {
        let opts = PlotOptions::default();
        for (lo, hi) in [
            (0.0, 1.0),
            (3.0, 97.0),
            (-12.0, 40.0),
            (0.31, 0.37),
            (1e6, 3e6),
        ] {
            let series = vec![Series {
                name: String::new(),
                points: vec![point(0.0, lo, 0.0), point(1.0, hi, 0.0)],
            }];
            let axis = y_axis(&series, &opts, 400.0, 1.0).unwrap();
            assert!(axis.lo <= lo && axis.hi >= hi, "{lo}..{hi}: {axis:?}");
            let steps: Vec<f64> = axis
                .ticks
                .windows(2)
                .map(|w| w[1].value - w[0].value)
                .collect();
            let step = steps[0];
            let mantissa = step / 10f64.powi(step.log10().floor() as i32);
            assert!(
                [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-6),
                "{lo}..{hi}: step {step}"
            );
            assert!((3..=11).contains(&axis.ticks.len()), "{axis:?}");
        }
    }

    #[test]
    fn many_x_values_get_round_ticks() {
        let series = vec![Series {
            name: "dense".into(),
            points: (0..30)
                .map(|i| point(f64::from(i) * 3.3, f64::from(i), 1.0))
                .collect(),
        }];
        let axis = x_axis(&series, 700.0, 1.0).unwrap();
        assert!(axis.ticks.len() <= 11, "{axis:?}");
        assert!(
            axis.ticks.iter().all(|t| !t.label.contains('.')),
            "{axis:?}"
        );
        assert!(render_line_plot(&series, &PlotOptions::default()).is_ok());
    }

    /// Time per request over three demand levels a decade apart, for three graphs.
    fn scaling() -> Vec<Series> {
        ["singapore-77", "singapore-all", "synthetic-10000"]
            .iter()
            .enumerate()
            .map(|(i, name)| Series {
                name: (*name).into(),
                points: [1e4, 1e5, 1e6]
                    .iter()
                    .map(|&x: &f64| point(x, (1.0 + i as f64) * x.powf(0.1), 0.0))
                    .collect(),
            })
            .collect()
    }

    #[test]
    fn log_x_axis_has_decade_ticks() {
        let series = scaling();
        let axis = log_x_axis(&series, 700.0, 1.0).unwrap();
        let labels: Vec<&str> = axis.ticks.iter().map(|t| t.label.as_str()).collect();
        assert_eq!(labels, ["10,000", "100,000", "1,000,000"]);
        // Decades are evenly spaced, with the same margin at both ends.
        let fracs: Vec<f64> = axis.ticks.iter().map(|t| axis.frac(t.value)).collect();
        assert!((fracs[1] - 0.5).abs() < 1e-12, "{fracs:?}");
        assert!((fracs[0] - (1.0 - fracs[2])).abs() < 1e-12, "{fracs:?}");
        assert!(fracs[0] > 0.0 && fracs[0] < 0.05, "{fracs:?}");
        // 2…9 × 10⁴ and 2…9 × 10⁵ as short unlabelled ticks.
        assert_eq!(axis.minor.len(), 16, "{:?}", axis.minor);
        assert!(
            (axis.frac(2e4) - axis.frac(1e4) - (axis.frac(2e5) - axis.frac(1e5))).abs() < 1e-12
        );

        let opts = PlotOptions {
            x_log: true,
            x_label: "Requests per day".into(),
            ..options()
        };
        let svg = render_line_plot(&series, &opts).unwrap();
        let texts = text_nodes(&svg);
        for label in ["10,000", "100,000", "1,000,000", "singapore-all"] {
            assert_eq!(
                texts.iter().filter(|t| **t == label).count(),
                1,
                "{label} in {texts:?}"
            );
        }
        // The same data on a linear axis is drawn differently.
        let linear = render_line_plot(
            &series,
            &PlotOptions {
                x_log: false,
                ..opts.clone()
            },
        );
        assert_ne!(svg, linear.unwrap());
        // Deterministic, whatever the order of the points.
        let mut shuffled = series.clone();
        shuffled[1].points.reverse();
        assert_eq!(svg, render_line_plot(&shuffled, &opts).unwrap());
    }

    #[test]
    fn log_x_axis_on_narrow_and_wide_ranges() {
        let at = |xs: &[f64]| {
            vec![Series {
                name: "s".into(),
                points: xs.iter().map(|&x| point(x, 1.0, 0.1)).collect(),
            }]
        };
        let labels = |xs: &[f64], w: f64| -> Vec<String> {
            let axis = log_x_axis(&at(xs), w, 1.0).unwrap();
            assert!(axis.lo < xs[0] && axis.hi > xs[xs.len() - 1], "{axis:?}");
            axis.ticks.into_iter().map(|t| t.label).collect()
        };
        // Less than a decade: 1-2-5 ticks, or the data's values when those are too few.
        assert_eq!(labels(&[150.0, 900.0], 700.0), ["200", "500"]);
        assert_eq!(labels(&[200.0, 400.0], 700.0), ["200", "400"]);
        assert_eq!(labels(&[1_000.0], 700.0), ["500", "1000", "2000"]);
        assert_eq!(
            labels(&[0.01, 1.0, 100.0], 700.0),
            ["0.01", "0.1", "1", "10", "100"]
        );
        // Fifteen decades on a narrow plot: every other or third power of ten.
        let wide = labels(&[1e-3, 1e12], 400.0);
        assert!((2..=6).contains(&wide.len()), "{wide:?}");
        let svg = render_line_plot(
            &at(&[1e-3, 1.0, 1e12]),
            &PlotOptions {
                x_log: true,
                ..PlotOptions::default()
            },
        );
        assert!(svg.is_ok());
        // Zero or negative x cannot be placed.
        for bad in [0.0, -5.0] {
            let opts = PlotOptions {
                x_log: true,
                ..PlotOptions::default()
            };
            match render_line_plot(&at(&[bad, 10.0]), &opts) {
                Err(RenderError::Input(msg)) => {
                    assert!(
                        msg.contains("logarithmic") && msg.contains("point 0"),
                        "{msg}"
                    );
                }
                other => panic!("expected an input error, got {other:?}"),
            }
            // Fine on a linear axis.
            assert!(render_line_plot(&at(&[bad, 10.0]), &PlotOptions::default()).is_ok());
        }
    }

    #[test]
    fn awkward_but_valid_input() {
        // One point (an error bar), all-equal values, negatives, big numbers, many series.
        let cases = vec![
            vec![Series {
                name: "one".into(),
                points: vec![point(5.0, 2.0, 0.5)],
            }],
            vec![Series {
                name: "flat".into(),
                points: vec![point(1.0, 0.0, 0.0), point(1.0, 0.0, 0.0)],
            }],
            vec![Series {
                name: "negative".into(),
                points: vec![point(-3.0, -40.0, 5.0), point(3.0, -10.0, 5.0)],
            }],
            vec![Series {
                name: "big".into(),
                points: vec![point(1e9, 1e12, 1e10), point(2e9, 3e12, 1e10)],
            }],
            (0..20)
                .map(|i| Series {
                    name: format!("scenario {i}"),
                    points: vec![
                        point(0.0, f64::from(i), 0.3),
                        point(1.0, f64::from(i) + 1.0, 0.3),
                    ],
                })
                .collect(),
        ];
        for series in cases {
            let svg = render_line_plot(&series, &PlotOptions::default()).unwrap();
            assert!(svg.starts_with("<svg"));
        }
        // Every series looks different.
        let looks: Vec<_> = (0..49).map(look).collect();
        for (i, a) in looks.iter().enumerate() {
            assert!(looks[..i].iter().all(|b| b != a), "series {i}");
        }
    }

    #[test]
    fn errors() {
        let opts = options();
        let err = |series: &[Series]| match render_line_plot(series, &opts) {
            Err(RenderError::Input(msg)) => msg,
            other => panic!("expected an input error, got {other:?}"),
        };
        assert!(err(&[]).contains("no series"));
        let mut series = sweep();
        series[1].points.clear();
        assert!(err(&series).contains("`Rush hour` has no points"));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for field in 0..4 {
                let mut series = sweep();
                let p = &mut series[2].points[3];
                *[&mut p.x, &mut p.mean, &mut p.ci_low, &mut p.ci_high][field] = bad;
                let msg = err(&series);
                assert!(
                    msg.contains("`Airport closed`, point 3") && msg.contains("not finite"),
                    "{msg}"
                );
            }
        }
        let mut series = sweep();
        series[0].points[0].ci_low = series[0].points[0].mean + 0.01;
        assert!(err(&series).contains("does not contain the mean"));
        let mut series = sweep();
        series[0].points[1].ci_high = series[0].points[1].mean - 0.01;
        assert!(err(&series).contains("does not contain the mean"));
        let mut series = sweep();
        series[0].points[1].mean = 1e308;
        series[0].points[1].ci_high = 1e308;
        series[0].points[0].ci_low = -1e308;
        series[0].points[0].mean = -1e308;
        assert!(err(&series).contains("too wide"));
        for (w, h) in [(100, 540), (900, 50), (300, 200)] {
            let small = PlotOptions {
                width_px: w,
                height_px: h,
                footnote: "a\nb\nc".into(),
                ..options()
            };
            assert!(
                matches!(
                    render_line_plot(&sweep(), &small),
                    Err(RenderError::Input(_))
                ),
                "{w} × {h}"
            );
        }
    }
}
