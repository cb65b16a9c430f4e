//! The plot's axes: value ranges, tick placement and labels, linear and logarithmic.

use super::{PlotOptions, Series};
use crate::RenderError;
use crate::ticks::{PLOT, fmt_tick, value_decimals};

/// Wanted distance between y ticks and between computed x ticks.
const Y_TICK_SPACING: f64 = 55.0;
/// Least distance between y ticks.
const Y_TICK_MIN_SPACING: f64 = 36.0;
const X_TICK_SPACING: f64 = 90.0;
/// Up to this many distinct x values, the x ticks are the data's x values.
const MAX_DATA_TICKS: usize = 12;

/// An axis: the value range spanned by the frame and the labelled ticks.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Axis {
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) ticks: Vec<Tick>,
    /// Unlabelled short ticks (the log axis's intermediate multiples).
    pub(super) minor: Vec<f64>,
    /// Whether positions are proportional to the logarithm of the value.
    log: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) struct Tick {
    pub(super) value: f64,
    pub(super) label: String,
}

impl Axis {
    /// Where `v` falls between `lo` (0) and `hi` (1).
    pub(super) fn frac(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
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
pub(super) fn y_axis(
    series: &[Series],
    opts: &PlotOptions,
    plot_h: f64,
    s: f64,
) -> Result<Axis, RenderError> {
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
    let coarse = PLOT.at_least((hi - lo) / target.floor());
    let limits = |step: f64| {
        let first = (lo / step + 1e-9).floor();
        let last = (hi / step - 1e-9).ceil();
        (first, last)
    };
    let step = [PLOT.below(coarse), coarse]
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
    let decimals = PLOT.decimals(step * scale);
    let ticks = PLOT
        .multiples(lo, hi, step)
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
pub(super) fn x_axis(series: &[Series], plot_w: f64, s: f64) -> Result<Axis, RenderError> {
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
        let step = PLOT.at_least((hi - lo) / intervals);
        let decimals = PLOT.decimals(step);
        PLOT.multiples(lo, hi, step)
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
pub(super) fn log_x_axis(series: &[Series], plot_w: f64, s: f64) -> Result<Axis, RenderError> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::fixtures::{options, point, scaling, text_nodes};
    use crate::plot::render_line_plot;

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
}
