//! A sample of durations summarized: mean, median, 95th percentile and maximum.

use muse_model::Millis;
use serde::Serialize;

/// Mean, median, 95th percentile and maximum of a sample, in seconds. Percentiles use the
/// nearest-rank definition on the sorted sample (the median of an even sample is the lower of
/// the two middle values), so each figure is a value that occurred. All zero for an empty
/// sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Distribution {
    /// Arithmetic mean.
    pub mean: f64,
    /// Median (nearest rank).
    pub median: f64,
    /// 95th percentile (nearest rank).
    pub p95: f64,
    /// Maximum.
    pub max: f64,
}

impl Distribution {
    /// Statistics of durations.
    ///
    /// ```
    /// use muse_model::Millis;
    /// let d = muse_sim::metrics::Distribution::of(&[Millis(1_000), Millis(3_000), Millis(2_000)]);
    /// assert_eq!((d.mean, d.median, d.p95, d.max), (2.0, 2.0, 3.0, 3.0));
    /// ```
    pub fn of(sample: &[Millis]) -> Self {
        if sample.is_empty() {
            return Distribution::default();
        }
        let mut v: Vec<i64> = sample.iter().map(|m| m.0).collect();
        v.sort_unstable();
        let rank = |p: f64| {
            let k = (p * v.len() as f64).ceil() as usize;
            Millis(v[k.clamp(1, v.len()) - 1]).as_secs_f64()
        };
        let sum: i128 = v.iter().map(|&x| i128::from(x)).sum();
        Distribution {
            mean: round_ms(sum as f64 / v.len() as f64 / 1_000.0),
            median: rank(0.5),
            p95: rank(0.95),
            max: Millis(v[v.len() - 1]).as_secs_f64(),
        }
    }
}

fn round_ms(secs: f64) -> f64 {
    (secs * 1e6).round() / 1e6
}
