//! Latency statistics: exact percentiles from the sorted samples (nearest rank), no
//! histogram and no interpolation.

use std::time::Duration;

use serde::Serialize;

/// A quantile as an exact fraction in parts per 100,000 (`50_000` is the median, `99_900`
/// the 99.9th percentile), so that ranks are computed in integers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Quantile(pub u32);

impl Quantile {
    /// The median.
    pub const P50: Quantile = Quantile(50_000);
    /// The 90th percentile.
    pub const P90: Quantile = Quantile(90_000);
    /// The 99th percentile.
    pub const P99: Quantile = Quantile(99_000);
    /// The 99.9th percentile.
    pub const P99_9: Quantile = Quantile(99_900);
}

/// The nearest-rank percentile of `sorted` (ascending): the smallest sample such that at
/// least the fraction `q` of the samples are at most it, i.e. the sample of rank
/// `ceil(q · n)` (at least 1). `None` for no samples.
///
/// ```
/// use muse_load::stats::{Quantile, percentile};
/// let s: Vec<u64> = (1..=1000).collect();
/// assert_eq!(percentile(&s, Quantile::P50), Some(500));
/// assert_eq!(percentile(&s, Quantile::P99_9), Some(999));
/// assert_eq!(percentile(&s, Quantile(100_000)), Some(1000));
/// assert_eq!(percentile(&[], Quantile::P50), None);
/// ```
pub fn percentile(sorted: &[u64], q: Quantile) -> Option<u64> {
    let n = sorted.len() as u64;
    if n == 0 {
        return None;
    }
    let q = u64::from(q.0.min(100_000));
    let rank = (n * q).div_ceil(100_000).max(1);
    Some(sorted[(rank - 1) as usize])
}

/// A latency distribution in milliseconds: count, mean, min, p50 / p90 / p99 / p99.9 and max,
/// each an actual sample (nearest rank) except the mean. All zero for no samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Latency {
    /// Number of samples.
    pub count: u64,
    /// Mean, ms.
    pub mean_ms: f64,
    /// Smallest sample, ms.
    pub min_ms: f64,
    /// Median, ms.
    pub p50_ms: f64,
    /// 90th percentile, ms.
    pub p90_ms: f64,
    /// 99th percentile, ms.
    pub p99_ms: f64,
    /// 99.9th percentile, ms.
    pub p99_9_ms: f64,
    /// Largest sample, ms.
    pub max_ms: f64,
}

impl Latency {
    /// The distribution of `samples` (nanoseconds); sorts them in place.
    ///
    /// ```
    /// use muse_load::stats::Latency;
    /// let mut ns = vec![3_000_000, 1_000_000, 2_000_000];
    /// let l = Latency::from_nanos(&mut ns);
    /// assert_eq!((l.count, l.p50_ms, l.max_ms, l.mean_ms), (3, 2.0, 3.0, 2.0));
    /// ```
    pub fn from_nanos(samples: &mut [u64]) -> Self {
        samples.sort_unstable();
        let ms = |q: Quantile| percentile(samples, q).map_or(0.0, |ns| ns as f64 / 1e6);
        let sum: u128 = samples.iter().map(|&s| u128::from(s)).sum();
        Latency {
            count: samples.len() as u64,
            mean_ms: if samples.is_empty() {
                0.0
            } else {
                sum as f64 / samples.len() as f64 / 1e6
            },
            min_ms: samples.first().map_or(0.0, |&ns| ns as f64 / 1e6),
            p50_ms: ms(Quantile::P50),
            p90_ms: ms(Quantile::P90),
            p99_ms: ms(Quantile::P99),
            p99_9_ms: ms(Quantile::P99_9),
            max_ms: samples.last().map_or(0.0, |&ns| ns as f64 / 1e6),
        }
    }

    /// One line: `p50 1.21 ms, p90 2.03 ms, p99 5.10 ms, p99.9 9.80 ms, max 12.0 ms`.
    pub fn line(&self) -> String {
        format!(
            "p50 {}, p90 {}, p99 {}, p99.9 {}, max {}",
            ms(self.p50_ms),
            ms(self.p90_ms),
            ms(self.p99_ms),
            ms(self.p99_9_ms),
            ms(self.max_ms)
        )
    }
}

/// A duration in milliseconds with three significant figures (`0.412 ms`, `12.3 ms`,
/// `1530 ms`).
pub fn ms(v: f64) -> String {
    if v < 1.0 {
        format!("{v:.3} ms")
    } else if v < 10.0 {
        format!("{v:.2} ms")
    } else if v < 100.0 {
        format!("{v:.1} ms")
    } else {
        format!("{v:.0} ms")
    }
}

/// Nanoseconds in `d`, saturating.
pub fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_on_small_sets() {
        let one = [7];
        for q in [Quantile::P50, Quantile::P90, Quantile::P99, Quantile::P99_9] {
            assert_eq!(percentile(&one, q), Some(7));
        }
        let ten: Vec<u64> = (1..=10).collect();
        assert_eq!(percentile(&ten, Quantile::P50), Some(5));
        assert_eq!(percentile(&ten, Quantile::P90), Some(9));
        // ceil(0.99 · 10) = 10: the largest.
        assert_eq!(percentile(&ten, Quantile::P99), Some(10));
        assert_eq!(percentile(&ten, Quantile(0)), Some(1), "rank is at least 1");
        assert_eq!(
            percentile(&ten, Quantile(200_000)),
            Some(10),
            "clamped to the max"
        );
    }

    #[test]
    fn ranks_are_exact_where_floating_point_would_round() {
        // 0.999 · 1000 is 998.999… in binary floating point; in integers it is 999.
        let s: Vec<u64> = (1..=1000).collect();
        assert_eq!(percentile(&s, Quantile::P99_9), Some(999));
        assert_eq!(percentile(&s, Quantile::P99), Some(990));
        assert_eq!(percentile(&s, Quantile::P90), Some(900));
        // One more sample: rank ceil(0.999 · 1001) = ceil(999.999) = 1000.
        let s: Vec<u64> = (1..=1001).collect();
        assert_eq!(percentile(&s, Quantile::P99_9), Some(1000));
        let s: Vec<u64> = (1..=1002).collect();
        assert_eq!(percentile(&s, Quantile::P99_9), Some(1001));
        assert_eq!(percentile(&s, Quantile::P50), Some(501));
    }

    #[test]
    fn latency_summary_sorts_and_converts() {
        // 1..=100 ms, shuffled.
        let mut ns: Vec<u64> = (1..=100u64).rev().map(|m| m * 1_000_000).collect();
        ns.swap(3, 70);
        let l = Latency::from_nanos(&mut ns);
        assert_eq!(l.count, 100);
        assert!((l.mean_ms - 50.5).abs() < 1e-9);
        assert_eq!(
            (l.min_ms, l.p50_ms, l.p90_ms, l.p99_ms, l.p99_9_ms, l.max_ms),
            (1.0, 50.0, 90.0, 99.0, 100.0, 100.0)
        );
        assert_eq!(Latency::from_nanos(&mut []), Latency::default());
        assert_eq!(
            l.line(),
            "p50 50.0 ms, p90 90.0 ms, p99 99.0 ms, p99.9 100 ms, max 100 ms"
        );
    }

    #[test]
    fn millisecond_formatting() {
        assert_eq!(ms(0.4123), "0.412 ms");
        assert_eq!(ms(1.5), "1.50 ms");
        assert_eq!(ms(12.34), "12.3 ms");
        assert_eq!(ms(1530.4), "1530 ms");
    }
}
