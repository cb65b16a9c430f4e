//! Line plots with confidence bands (the paper's Figs. 2–4: the parameter sweep).
//!
//! [`render_line_plot`] lays the page out (title, legend, plot, labels, footnote) and draws
//! it from its parts: `axis` places the ticks, `frame` draws the plot, `markers` and
//! `legend` tell the series apart.

mod axis;
mod frame;
mod legend;
mod markers;

use plotters::backend::SVGBackend;
use plotters::drawing::IntoDrawingArea;
use plotters::style::text_anchor::{HPos, VPos};

use self::axis::{log_x_axis, x_axis, y_axis};
use self::frame::Plot;
use self::legend::Legend;
use crate::geom::Rect;
use crate::style::{INK, MUTED, PAPER, exact_px, text, text_width};
use crate::{RenderError, drawing_err};

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
/// Length of a tick mark.
const TICK_LEN: f64 = 5.0;
/// Width of a series' line.
const LINE_W: f64 = 2.0;
const MIN_PLOT_PX: f64 = 60.0;
/// Opacity of the confidence band.
const BAND_ALPHA: f64 = 0.16;

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

/// Series, options and SVG helpers shared by the plot tests.
#[cfg(test)]
mod fixtures {
    use super::{PlotOptions, Point, Series};

    pub(super) fn point(x: f64, mean: f64, half: f64) -> Point {
        Point {
            x,
            mean,
            ci_low: mean - half,
            ci_high: mean + half,
        }
    }

    /// Three scenarios over five fleet sizes, as fractions.
    pub(super) fn sweep() -> Vec<Series> {
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

    pub(super) fn options() -> PlotOptions {
        PlotOptions {
            title: "On-time deliveries".into(),
            x_label: "Drones in the fleet".into(),
            y_label: "Delivered on time".into(),
            y_percent: true,
            footnote: "100 runs per point; 95% CI".into(),
            ..PlotOptions::default()
        }
    }

    pub(super) fn text_nodes(svg: &str) -> Vec<&str> {
        svg.split("</text>")
            .filter_map(|t| t.rsplit_once(">\n").map(|(_, s)| s.trim_end_matches('\n')))
            .collect()
    }

    /// Time per request over three demand levels a decade apart, for three graphs.
    pub(super) fn scaling() -> Vec<Series> {
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
}

#[cfg(test)]
mod tests {
    use super::fixtures::{options, point, sweep, text_nodes};
    use super::markers::look;
    use super::*;
    use crate::style::SERIES;

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
