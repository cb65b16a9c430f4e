//! Growth exponents: power laws fitted by least squares on log–log axes — per graph, total
//! planner time against requests (1 means linear in demand); per demand level, time per
//! request against the number of nodes.

use super::record::CaseResult;

/// A power law `y = coefficient · x^exponent` fitted by least squares on `ln y` against
/// `ln x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerFit {
    /// The slope on log–log axes: the growth exponent.
    pub exponent: f64,
    /// `exp` of the intercept.
    pub coefficient: f64,
    /// Coefficient of determination of the log–log fit (1 when it is exact).
    pub r_squared: f64,
    /// Points fitted.
    pub points: usize,
}

/// Fits `y = c · x^k` to `points` by ordinary least squares on `(ln x, ln y)`.
///
/// `None` when there are fewer than two distinct `x`, or some value is not finite and
/// positive (a logarithm is needed).
///
/// ```
/// use muse_sim::experiment::bench::fit_power_law;
/// let pts: Vec<(f64, f64)> = [1e4, 1e5, 1e6].iter().map(|&n| (n, 2e-6 * n)).collect();
/// let fit = fit_power_law(&pts).unwrap();
/// assert!((fit.exponent - 1.0).abs() < 1e-12); // linear
/// assert!((fit.coefficient - 2e-6).abs() < 1e-15);
/// ```
pub fn fit_power_law(points: &[(f64, f64)]) -> Option<PowerFit> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if points.len() < 2 || !points.iter().all(|&(x, y)| ok(x) && ok(y)) {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = logs.iter().map(|p| (p.1 - my) * (p.1 - my)).sum();
    // All x equal (to rounding): no slope.
    if sxx <= 1e-24 * n {
        return None;
    }
    let exponent = sxy / sxx;
    let intercept = my - exponent * mx;
    let residual: f64 = logs
        .iter()
        .map(|p| {
            let e = p.1 - (intercept + exponent * p.0);
            e * e
        })
        .sum();
    let r_squared = if syy <= 1e-24 * n {
        1.0
    } else {
        (1.0 - residual / syy).clamp(0.0, 1.0)
    };
    Some(PowerFit {
        exponent,
        coefficient: intercept.exp(),
        r_squared,
        points: logs.len(),
    })
}

/// The growth exponents of a benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct Exponents {
    /// Per graph (in order of first appearance): total planner time against requests.
    pub by_graph: Vec<(String, Option<PowerFit>)>,
    /// Per demand level (ascending): time per request against the number of nodes.
    pub by_requests: Vec<(usize, Option<PowerFit>)>,
}

impl Exponents {
    /// The fits of `results`.
    pub fn of(results: &[CaseResult]) -> Self {
        let mut graphs: Vec<&str> = Vec::new();
        let mut levels: Vec<usize> = Vec::new();
        for r in results {
            if !graphs.contains(&r.graph.as_str()) {
                graphs.push(&r.graph);
            }
            if !levels.contains(&r.requests) {
                levels.push(r.requests);
            }
        }
        levels.sort_unstable();
        let by_graph = graphs
            .into_iter()
            .map(|g| {
                let pts: Vec<(f64, f64)> = results
                    .iter()
                    .filter(|r| r.graph == g)
                    .map(|r| (r.requests as f64, r.planner_s))
                    .collect();
                (g.to_owned(), fit_power_law(&pts))
            })
            .collect();
        let by_requests = levels
            .into_iter()
            .map(|n| {
                let pts: Vec<(f64, f64)> = results
                    .iter()
                    .filter(|r| r.requests == n)
                    .map(|r| (r.nodes as f64, r.us_per_request()))
                    .collect();
                (n, fit_power_law(&pts))
            })
            .collect();
        Exponents {
            by_graph,
            by_requests,
        }
    }

    /// The fit of total planner time against requests for `graph`.
    pub fn for_graph(&self, graph: &str) -> Option<PowerFit> {
        self.by_graph
            .iter()
            .find(|(g, _)| g == graph)
            .and_then(|(_, f)| *f)
    }

    /// The fit of time per request against nodes for `requests`.
    pub fn for_requests(&self, requests: usize) -> Option<PowerFit> {
        self.by_requests
            .iter()
            .find(|(n, _)| *n == requests)
            .and_then(|(_, f)| *f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * b.abs().max(1.0)
    }

    #[test]
    fn fit_is_exact_on_power_laws() {
        for (c, k) in [
            (2e-6_f64, 1.0_f64),
            (3.5, 1.5),
            (0.7, -0.5),
            (42.0, 0.0),
            (1e-3, 2.25),
        ] {
            for xs in [
                vec![1e4_f64, 1e5, 1e6],
                vec![77.0, 1_100.0, 10_000.0],
                vec![200.0, 400.0],
                vec![1.0, 2.0, 3.0, 5.0, 8.0, 13.0],
            ] {
                let pts: Vec<(f64, f64)> = xs.iter().map(|&x| (x, c * x.powf(k))).collect();
                let fit = fit_power_law(&pts).unwrap();
                assert!(close(fit.exponent, k), "{c} x^{k} on {xs:?}: {fit:?}");
                assert!(close(fit.coefficient, c), "{c} x^{k} on {xs:?}: {fit:?}");
                assert!(close(fit.r_squared, 1.0), "{fit:?}");
                assert_eq!(fit.points, xs.len());
            }
        }
    }

    #[test]
    fn fit_of_noisy_points_is_the_least_squares_slope() {
        // ln-space points (0, 0), (1, 1), (2, 3): slope 1.5, intercept -1/6.
        let e = std::f64::consts::E;
        let fit = fit_power_law(&[(1.0, 1.0), (e, e), (e * e, e.powi(3))]).unwrap();
        assert!(close(fit.exponent, 1.5), "{fit:?}");
        assert!(close(fit.coefficient, (-1.0f64 / 6.0).exp()), "{fit:?}");
        // Residuals 1/6, -1/3, 1/6: SSres = 1/6, SStot = 14/3.
        assert!(
            close(fit.r_squared, 1.0 - (1.0 / 6.0) / (14.0 / 3.0)),
            "{fit:?}"
        );
    }

    #[test]
    fn fit_needs_two_sizes_and_positive_values() {
        assert_eq!(fit_power_law(&[]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0), (10.0, 2.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0), (20.0, 0.0)]), None);
        assert_eq!(fit_power_law(&[(0.0, 1.0), (20.0, 1.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, f64::NAN), (20.0, 1.0)]), None);
        assert_eq!(fit_power_law(&[(10.0, 1.0), (f64::INFINITY, 1.0)]), None);
    }
}
