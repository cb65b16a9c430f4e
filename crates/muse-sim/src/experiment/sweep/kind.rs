//! The paper's sweep as a [`Kind`]: its cases are scenario variants, each run plans a day
//! against the variant's zones with its flight parameters on its airspace (flat or layered),
//! first come, first served or as one batch (`--vary planner`).

use muse_airspace::closures::{ClosureError, Closures, resolve};
use muse_model::Airspace;
use muse_planner::Planner;

use super::airspaces::Airspaces;
use super::record::{Approach, RunRecord, approach_columns, columns, layer_columns};
use super::report::{approach_metrics, layer_metrics, plots, summary, table};
use super::variant::Variant;
use crate::day::{Planning, plan_sorted};
use crate::demand::DemandError;
use crate::experiment::grid::Grid;
use crate::experiment::kind::{Day, Kind};
use crate::experiment::report::{Column, Group, Plot, SummarySpec};

/// Errors of a sweep.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A variant's zones could not be resolved.
    #[error("variant `{variant}`: {source}")]
    Zones {
        /// Variant name.
        variant: String,
        /// Cause.
        source: ClosureError,
    },
    /// Demand could not be generated.
    #[error(transparent)]
    Demand(#[from] DemandError),
}

/// The paper's experiment: the same days planned in each scenario variant.
pub struct Sweep<'a> {
    airspaces: &'a Airspaces,
    variants: Vec<Variant>,
    /// Each variant's planner and zone closures, prepared once.
    prepared: Vec<(Planner<'a>, Closures)>,
    booked: Option<String>,
}

impl std::fmt::Debug for Sweep<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Sweep")
            .field("variants", &self.variants)
            .finish_non_exhaustive()
    }
}

impl<'a> Sweep<'a> {
    /// The sweep of `variants` (at least one) over `grid`, each on its airspace of
    /// `airspaces` (flat, or layered as the variant says), its zones resolved over the grid's
    /// range; `booked` says how requests are booked, for plot footnotes (`None`: at
    /// departure).
    pub fn new(
        airspaces: &'a Airspaces,
        grid: &Grid,
        variants: Vec<Variant>,
        booked: Option<String>,
    ) -> Result<Self, SweepError> {
        let mut prepared = Vec::with_capacity(variants.len());
        for v in &variants {
            let (from, to) = grid.closure_range(&v.params);
            let airspace = airspaces.of(&v.layers);
            let closures =
                resolve(airspace, &v.zones, from, to).map_err(|source| SweepError::Zones {
                    variant: v.name.clone(),
                    source,
                })?;
            prepared.push((Planner::new(airspace, v.params), closures));
        }
        Ok(Sweep {
            airspaces,
            variants,
            prepared,
            booked,
        })
    }

    /// The variants, in run order.
    pub fn variants(&self) -> &[Variant] {
        &self.variants
    }

    /// Whether some variant flies a layered airspace (then the runs have layer columns).
    fn layered(&self) -> bool {
        self.variants.iter().any(|v| v.layers.is_layered())
    }

    /// Whether the sweep compares separations (some variant keeps metric separation, or the
    /// variants' node separations differ): then each run says how close its flights come.
    fn compares_separation(&self) -> bool {
        let taus = |v: &Variant| v.params.node_separation;
        self.variants.iter().any(|v| v.params.separation.is_on())
            || self
                .variants
                .first()
                .is_some_and(|first| self.variants.iter().any(|v| taus(v) != taus(first)))
    }
}

impl Kind for Sweep<'_> {
    type Record = RunRecord;
    type Error = SweepError;

    fn cases(&self) -> Vec<String> {
        self.variants.iter().map(|v| v.name.clone()).collect()
    }

    fn identity(&self) -> String {
        format!("{:?}", self.variants)
    }

    fn shared_demand(&self) -> Option<&Airspace> {
        Some(self.airspaces.flat())
    }

    fn run(&self, grid: &Grid, case: usize, day: &Day<'_>) -> Result<RunRecord, SweepError> {
        let (planner, closures) = &self.prepared[case];
        let (outcomes, wall) = match self.variants[case].planning {
            Planning::FirstComeFirstServed => plan_sorted(planner, closures, day.requests, |_| {}),
            Planning::Optimized(options) => {
                let out =
                    muse_optimize::optimize(planner, closures, day.requests, &options, |_| {});
                (out.outcomes, out.report.elapsed)
            }
        };
        let variant = &self.variants[case];
        let airspace = self.airspaces.of(&variant.layers);
        let mut record = RunRecord::of(
            &variant.name,
            (day.rep, day.seed, grid.booking_lead),
            day.requests,
            &outcomes,
            wall,
        )
        .with_layers(airspace, &outcomes);
        if self.compares_separation() {
            let vertical = variant.params.separation.vertical_in(airspace).m();
            record.approach = Some(Approach::of(airspace, day.requests, &outcomes, vertical));
        }
        Ok(record)
    }

    fn runs_file(&self) -> &'static str {
        "sweep.csv"
    }

    fn columns<'r>(&self, _: &'r [RunRecord]) -> Vec<Column<'r, RunRecord>> {
        let mut all = columns();
        if self.layered() {
            all.extend(layer_columns());
        }
        if self.compares_separation() {
            all.extend(approach_columns());
        }
        all
    }

    fn summary(&self) -> Option<SummarySpec<RunRecord>> {
        let mut spec = summary();
        if self.layered() {
            spec.metrics.extend(layer_metrics());
        }
        if self.compares_separation() {
            spec.metrics.extend(approach_metrics());
        }
        Some(spec)
    }

    fn measured(&self, column: &str) -> bool {
        column.starts_with("planner_ms")
    }

    fn table(&self, _: &Grid, _: &[RunRecord], groups: &[Group<RunRecord>]) -> String {
        table(groups, self.layered(), self.compares_separation())
    }

    fn plots(&self, grid: &Grid, _: &[RunRecord], groups: &[Group<RunRecord>]) -> Vec<Plot> {
        plots(grid, &self.cases(), groups, self.booked.as_deref())
    }
}
