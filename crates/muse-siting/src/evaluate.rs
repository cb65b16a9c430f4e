//! One pad set's deliveries: the airspace rebuilt from the pads, each seeded day's trips
//! mapped to their customers' serving pads and planned exactly, first come first served
//! (docs/reference.md#planning, #multi-leg-trips with battery swaps), from an empty schedule.

use muse_airspace::announced::KnownZones;
use muse_airspace::builder::build_airspace;
use muse_model::{Airspace, Node, NodeId};
use muse_planner::Planner;
use muse_sim::customers::trips::request_for;
use muse_sim::day::plan_sorted;
use muse_sim::stats::MeanCi;

use crate::{Siting, SitingError};

/// What one pad set delivers on each seeded day.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Evaluation {
    /// Requests planned (delivered), day by day.
    pub delivered: Vec<u32>,
    /// Requests served (both customers with a pad in reach, on different pads), day by day:
    /// the rest are `unserved`.
    pub served: Vec<u32>,
    /// Search effort, labels expanded, over all days.
    pub expanded: u64,
    /// Corridors of the rebuilt airspace.
    pub corridors: usize,
}

impl Evaluation {
    /// Mean delivered requests per day.
    pub fn mean_delivered(&self) -> f64 {
        self.delivered_ci().mean
    }

    /// Mean and 95% confidence interval of delivered requests per day.
    pub fn delivered_ci(&self) -> MeanCi {
        MeanCi::of(&as_f64(&self.delivered))
    }

    /// Mean and 95% confidence interval of served requests per day.
    pub fn served_ci(&self) -> MeanCi {
        MeanCi::of(&as_f64(&self.served))
    }

    /// The gain over `base` (same days): mean and 95% confidence interval of the day-by-day
    /// differences in delivered requests (a paired comparison: both planned the same trips).
    ///
    /// ```
    /// use muse_siting::Evaluation;
    /// let e = |d: Vec<u32>| Evaluation { served: d.clone(), delivered: d, expanded: 0, corridors: 0 };
    /// let gain = e(vec![12, 15, 11]).gain_over(&e(vec![10, 12, 10]));
    /// assert_eq!(gain.mean, 2.0);
    /// ```
    pub fn gain_over(&self, base: &Evaluation) -> MeanCi {
        let diff: Vec<f64> = self
            .delivered
            .iter()
            .zip(&base.delivered)
            .map(|(&a, &b)| f64::from(a) - f64::from(b))
            .collect();
        MeanCi::of(&diff)
    }
}

fn as_f64(xs: &[u32]) -> Vec<f64> {
    xs.iter().map(|&x| f64::from(x)).collect()
}

impl Siting {
    /// The pads of the set that adds candidates `added` (by candidate index, in order): the
    /// existing pads, then those candidates.
    pub fn pads(&self, added: &[usize]) -> Vec<Node> {
        let input = &self.input;
        input
            .existing
            .iter()
            .cloned()
            .chain(added.iter().map(|&c| input.candidates[c].clone()))
            .collect()
    }

    /// The airspace of the set that adds `added`, built by the rule of
    /// docs/reference.md#airspace-from-pads.
    ///
    /// # Errors
    /// The pads give no airspace (e.g. a pad inside an exclusion).
    pub fn airspace(&self, added: &[usize]) -> Result<Airspace, SitingError> {
        Ok(build_airspace(self.pads(added), &self.input.build)?)
    }

    /// Each customer's serving pad in the airspace of the set that adds `added`: the nearest
    /// pad of the set in reach (ties: the pad first in the airspace), as its node.
    pub fn serving(&self, added: &[usize]) -> Vec<Option<NodeId>> {
        let existing = self.input.existing.len();
        // Pad index → node of the rebuilt airspace, for the pads of the set.
        let mut node = vec![None; existing + self.input.candidates.len()];
        for (i, slot) in node.iter_mut().enumerate().take(existing) {
            *slot = Some(i);
        }
        for (j, &c) in added.iter().enumerate() {
            node[existing + c] = Some(existing + j);
        }
        self.reach
            .iter()
            .map(|near| {
                near.iter()
                    .filter_map(|&(pad, d)| node[pad].map(|n| (d, n)))
                    .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
                    .map(|(_, n)| NodeId(n as u32))
            })
            .collect()
    }

    /// Plans every seeded day on the airspace of the set that adds candidates `added` (by
    /// index, in order) and counts what is delivered.
    ///
    /// # Errors
    /// The pads give no airspace, or a zone cannot be resolved on it.
    pub fn evaluate(&self, added: &[usize]) -> Result<Evaluation, SitingError> {
        let airspace = self.airspace(added)?;
        let (from, to) = self.window;
        let zones = KnownZones::resolve(&airspace, &self.input.zones, from, to)?;
        let planner = Planner::new(&airspace, self.input.params);
        let serving = self.serving(added);
        let mut out = Evaluation {
            delivered: Vec::with_capacity(self.trips.len()),
            served: Vec::with_capacity(self.trips.len()),
            expanded: 0,
            corridors: airspace.edges().len(),
        };
        for day in &self.trips {
            let requests: Vec<_> = day
                .iter()
                .filter_map(|t| request_for(t, &serving).ok())
                .collect();
            let (outcomes, _) = plan_sorted(&planner, &zones.base, &requests, |_| {});
            out.served.push(requests.len() as u32);
            out.delivered
                .push(outcomes.iter().filter(|o| o.result.is_ok()).count() as u32);
            out.expanded += outcomes.iter().map(|o| o.expanded).sum::<u64>();
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use muse_model::LonLat;
    use muse_sim::customers::serving_pads;

    use crate::Siting;
    use crate::problem::example_input;

    #[test]
    fn serving_pads_are_those_of_the_rebuilt_airspace() {
        let siting = Siting::prepare(example_input()).unwrap();
        let customers: Vec<LonLat> = siting.input().customers.iter().map(|c| c.pos).collect();
        for added in [vec![], vec![0], vec![3, 1], vec![4, 2, 0, 1, 3]] {
            let air = siting.airspace(&added).unwrap();
            let expected: Vec<_> = serving_pads(&air, &customers, siting.input().last_mile_m)
                .into_iter()
                .map(|s| s.map(|s| s.pad))
                .collect();
            assert_eq!(siting.serving(&added), expected, "{added:?}");
        }
    }

    #[test]
    fn evaluations_are_reproducible_and_count_what_is_served() {
        let siting = Siting::prepare(example_input()).unwrap();
        let a = siting.evaluate(&[0, 2]).unwrap();
        assert_eq!(a, siting.evaluate(&[0, 2]).unwrap());
        assert_eq!(a.delivered.len(), 2);
        for (d, s) in a.delivered.iter().zip(&a.served) {
            assert!(d <= s && *s <= 300, "{d} of {s}");
        }
        // The centre candidate puts more customers in reach than the bare square.
        let base = siting.evaluate(&[]).unwrap();
        assert!(a.served_ci().mean > base.served_ci().mean);
    }
}
