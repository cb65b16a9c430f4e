//! The one tick rule of the plots and the map: round steps, their multiples, the decimals
//! their labels need, and number formats.
//!
//! A [`TickRule`] is the ladder of round steps (1, 2, 5 × 10ⁿ for the plots; 1, 2, 2.5,
//! 5 × 10ⁿ for the map's graticule and scale bar) and how much floating-point slack a
//! comparison allows. The plots pick the smallest step at least as wide as wanted
//! ([`TickRule::at_least`]), the map the widest step at most as wide ([`TickRule::at_most`]).

/// A ladder of round steps and the tolerance of its comparisons.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TickRule {
    /// The mantissas of a step within a decade, ascending, starting at 1 and below 10.
    rungs: &'static [f64],
    /// How far a value may miss a rung (in mantissa units), a multiple (in steps) or a power
    /// of ten (in its logarithm) and still count as on it, so that rounding error in a
    /// computed span costs neither a rung nor an end tick. The map compares exactly.
    slack: f64,
}

/// The plots' axes: 1, 2 and 5 × 10ⁿ, with a slack of 10⁻⁹.
pub(crate) const PLOT: TickRule = TickRule {
    rungs: &[1.0, 2.0, 5.0],
    slack: 1e-9,
};

/// The map's graticule and scale bar: 1, 2, 2.5 and 5 × 10ⁿ, compared exactly.
pub(crate) const MAP: TickRule = TickRule {
    rungs: &[1.0, 2.0, 2.5, 5.0],
    slack: 0.0,
};

/// At most this many multiples are returned (a cap against nonsense input).
const MAX_MULTIPLES: usize = 64;

/// Most decimals a step is written with.
const MAX_DECIMALS: usize = 12;

/// 10 to the power of `e`'s whole part (`e` is a floored logarithm).
fn pow10(e: f64) -> f64 {
    10f64.powi(e as i32)
}

impl TickRule {
    /// The smallest step on the ladder that is at least `raw` (1 for nonsense input).
    pub(crate) fn at_least(self, raw: f64) -> f64 {
        if !(raw.is_finite() && raw > 0.0) {
            return 1.0;
        }
        let p = pow10(raw.log10().floor());
        let m = raw / p;
        let nice = self
            .rungs
            .iter()
            .copied()
            .find(|&r| m <= r + self.slack)
            .unwrap_or(10.0);
        nice * p
    }

    /// The largest step on the ladder that is at most `raw` (1 for nonsense input).
    pub(crate) fn at_most(self, raw: f64) -> f64 {
        if !(raw.is_finite() && raw > 0.0) {
            return 1.0;
        }
        let p = pow10(raw.log10().floor());
        let m = raw / p;
        let nice = self
            .rungs
            .iter()
            .rev()
            .copied()
            .find(|&r| m >= r - self.slack)
            .unwrap_or(self.rungs[0]);
        nice * p
    }

    /// The step on the ladder just below `step` (itself on the ladder).
    pub(crate) fn below(self, step: f64) -> f64 {
        let p = pow10(step.log10().floor());
        // The mantissa rounded to a whole number picks the rung (a 2.5 rounds to 3).
        let m = (step / p).round();
        match self.rungs.iter().rposition(|&r| m >= r) {
            Some(i) if i > 0 => self.rungs[i - 1] * p,
            _ => self.rungs[self.rungs.len() - 1] / 10.0 * p,
        }
    }

    /// The multiples of `step` in `[lo, hi]` (within the slack, in steps), from integer
    /// indices so that they do not drift; at most 64.
    pub(crate) fn multiples(self, lo: f64, hi: f64, step: f64) -> Vec<f64> {
        let first = (lo / step - self.slack).ceil() as i64;
        let last = (hi / step + self.slack).floor() as i64;
        (first..=last)
            .take(MAX_MULTIPLES)
            .map(|i| i as f64 * step)
            .collect()
    }

    /// Decimals needed to write the multiples of `step` (a step on the ladder) exactly: one
    /// more than the decade's for a mantissa of 2.5; at most 12 (a map's graticule step is
    /// never below 0.001°: its extent spans at least 0.02°).
    pub(crate) fn decimals(self, step: f64) -> usize {
        let e = (step.log10() + self.slack).floor();
        let m = step / pow10(e);
        let whole = (-e).max(0.0) as usize;
        let half = usize::from((m - m.round()).abs() > 1e-9);
        (whole + half).min(MAX_DECIMALS)
    }
}

/// The fewest decimals (up to 6) that write every value in `values` exactly.
pub(crate) fn value_decimals(values: &[f64]) -> usize {
    (0..=6)
        .find(|&d| {
            let p = 10f64.powi(d);
            values
                .iter()
                .all(|v| ((v * p).round() / p - v).abs() <= 1e-9 * v.abs().max(1.0))
        })
        .map_or(6, |d| d as usize)
}

/// A plot tick label: `decimals` decimals, a true minus sign, thousands separated by commas
/// from 10,000 on.
pub(crate) fn fmt_tick(v: f64, decimals: usize) -> String {
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

/// A number for a map legend or scale bar: at most three significant decimals, no trailing
/// zeros.
pub(crate) fn fmt_num(v: f64) -> String {
    let s = if v.abs() >= 100.0 {
        format!("{v:.0}")
    } else if v.abs() >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    };
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::float_cmp)]
    use super::*;

    #[test]
    fn nice_steps_and_labels() {
        assert_eq!(PLOT.at_least(0.3), 0.5);
        assert_eq!(PLOT.at_least(0.1), 0.1);
        assert_eq!(PLOT.at_least(1.5), 2.0);
        assert_eq!(PLOT.at_least(7.0), 10.0);
        assert_eq!(PLOT.at_least(2_000.0), 2_000.0);
        assert_eq!(PLOT.at_least(f64::NAN), 1.0);
        assert_eq!(PLOT.below(0.1), 0.05);
        assert_eq!(PLOT.below(0.2), 0.1);
        assert_eq!(PLOT.below(500.0), 200.0);
        assert_eq!(PLOT.decimals(0.05), 2);
        assert_eq!(PLOT.decimals(0.1), 1);
        assert_eq!(PLOT.decimals(20.0), 0);
        assert_eq!(value_decimals(&[1.0, 2.5, 10.0]), 1);
        assert_eq!(value_decimals(&[0.125]), 3);
        assert_eq!(fmt_tick(-1.5, 1), "\u{2212}1.5");
        assert_eq!(fmt_tick(-0.0001, 1), "0.0");
        assert_eq!(fmt_tick(1_234.0, 0), "1234");
        assert_eq!(fmt_tick(12_345.0, 0), "12,345");
        assert_eq!(fmt_tick(1_234_567.25, 2), "1,234,567.25");
        assert_eq!(PLOT.multiples(0.0, 1.0, 0.2).len(), 6);
    }

    #[test]
    fn map_steps_round_down_and_count_the_half() {
        assert_eq!(MAP.at_most(7.3), 5.0);
        assert_eq!(MAP.at_most(3.0), 2.5);
        assert_eq!(MAP.at_most(2.4), 2.0);
        assert_eq!(MAP.at_most(0.019), 0.01);
        assert_eq!(MAP.at_most(f64::INFINITY), 1.0);
        assert_eq!(MAP.below(0.025), 0.02);
        assert_eq!(MAP.below(0.05), 0.025);
        assert_eq!(MAP.decimals(0.025), 3);
        assert_eq!(MAP.decimals(0.05), 2);
        assert_eq!(MAP.decimals(2.5), 1);
        assert_eq!(MAP.decimals(20.0), 0);
        assert_eq!(MAP.multiples(1.05, 1.35, 0.1).len(), 3);
    }

    #[test]
    fn plot_slack_keeps_rounded_spans_on_the_ladder() {
        // A span that came out a hair over a rung stays on it; the map's exact rule moves
        // to the next rung down instead.
        assert_eq!(PLOT.at_least(0.2 + 1e-12), 0.2);
        assert_eq!(MAP.at_most(0.2 - 1e-12), 0.1);
        // An end a hair outside the range still gets its tick on a plot (0.3 / 0.1 is
        // 2.9999999999999996).
        assert_eq!(PLOT.multiples(0.1, 0.3, 0.1).len(), 3);
        assert_eq!(MAP.multiples(0.1, 0.3, 0.1), [0.1, 0.2]);
        assert_eq!(PLOT.multiples(0.0, 1.0 - 1e-12, 0.5).len(), 3);
        assert_eq!(MAP.multiples(0.0, 1.0 - 1e-12, 0.5).len(), 2);
    }

    #[test]
    fn numbers() {
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(2.5), "2.5");
        assert_eq!(fmt_num(12.25), "12.2");
        assert_eq!(fmt_num(1234.4), "1234");
    }
}
