//! The announcement-lead sweep as a [`Kind`]: its cases are the leads, then the zones known
//! from the start, then (optionally) never announced; each run replays a day in its case.

use muse_model::{Airspace, Millis, Zone};

use super::case::{LeadCase, LeadError};
use super::plots::plots;
use super::record::{LeadRecord, columns};
use super::report::{summary, table};
use super::world::{LeadWorld, ScenarioDay};
use crate::experiment::grid::Grid;
use crate::experiment::kind::{Day, Kind};
use crate::experiment::report::{Column, Group, Plot, SummarySpec};

/// What an announcement-lead sweep compares, besides its grid.
#[derive(Clone, Debug, PartialEq)]
pub struct LeadSpec {
    /// Leads, in the order runs are reported.
    pub leads: Vec<Millis>,
    /// Zones known from the start in every case.
    pub base_zones: Vec<Zone>,
    /// Zones to announce (their own announcement instants are replaced).
    pub announce: Vec<Zone>,
    /// The day on which each zone's first window is looked for.
    pub day: ScenarioDay,
    /// Whether to run the [`LeadCase::NoZone`] reference too.
    pub no_zone_reference: bool,
}

impl LeadSpec {
    /// The cases run: each lead, then [`LeadCase::Known`], then [`LeadCase::NoZone`] if asked.
    pub fn cases(&self) -> Vec<LeadCase> {
        let mut cases: Vec<LeadCase> = self
            .leads
            .iter()
            .map(|&lead| LeadCase::Announced { lead })
            .collect();
        cases.push(LeadCase::Known);
        if self.no_zone_reference {
            cases.push(LeadCase::NoZone);
        }
        cases
    }
}

/// The regulator's question: the same days planned with the zones announced at each lead,
/// known from the start, and never announced.
#[derive(Debug)]
pub struct Lead<'a> {
    spec: LeadSpec,
    cases: Vec<LeadCase>,
    world: LeadWorld<'a>,
    booked: String,
    zones: Vec<String>,
}

impl<'a> Lead<'a> {
    /// The sweep of `spec` on `airspace` over `grid`, its zones resolved once; `booked` says
    /// how requests are booked, for plot footnotes.
    ///
    /// Errors: a negative lead, and those of [`LeadWorld::new`].
    pub fn new(
        airspace: &'a Airspace,
        grid: &Grid,
        spec: LeadSpec,
        booked: String,
    ) -> Result<Self, LeadError> {
        if let Some(&lead) = spec.leads.iter().find(|l| **l < Millis::ZERO) {
            return Err(LeadError::NegativeLead(lead));
        }
        let world = LeadWorld::new(
            airspace,
            grid.params,
            &spec.base_zones,
            &spec.announce,
            spec.day,
            grid.closure_range(&grid.params),
        )?;
        let zones = world
            .first_windows()
            .map(|(id, t)| format!("{id} (first window {})", spec.day.clock(t)))
            .collect();
        Ok(Lead {
            cases: spec.cases(),
            spec,
            world,
            booked,
            zones,
        })
    }

    /// The cases, in run order.
    pub fn lead_cases(&self) -> &[LeadCase] {
        &self.cases
    }

    /// The zones announced, each with its first window's clock time, e.g.
    /// `SG-CBD-DOWNTOWN-CORE (first window 10:00)`.
    pub fn announced(&self) -> &[String] {
        &self.zones
    }
}

impl Kind for Lead<'_> {
    type Record = LeadRecord;
    type Error = LeadError;

    fn cases(&self) -> Vec<String> {
        self.cases.iter().map(|c| c.label()).collect()
    }

    fn identity(&self) -> String {
        format!("{:?}", self.spec)
    }

    fn shared_demand(&self) -> Option<&Airspace> {
        Some(self.world.airspace())
    }

    fn run(&self, grid: &Grid, case: usize, day: &Day<'_>) -> Result<LeadRecord, LeadError> {
        let case = self.cases[case];
        let run = self.world.run(case, day.requests)?;
        Ok(LeadRecord::of(
            case,
            day.rep,
            day.seed,
            grid.booking_lead,
            &run,
        ))
    }

    fn runs_file(&self) -> &'static str {
        "announce_lead.csv"
    }

    fn columns<'r>(&self, _: &'r [LeadRecord]) -> Vec<Column<'r, LeadRecord>> {
        columns()
    }

    fn summary(&self) -> Option<SummarySpec<LeadRecord>> {
        Some(summary())
    }

    fn measured(&self, column: &str) -> bool {
        column.starts_with("planner_ms")
    }

    fn table(&self, _: &Grid, _: &[LeadRecord], groups: &[Group<LeadRecord>]) -> String {
        table(groups)
    }

    fn plots(&self, grid: &Grid, _: &[LeadRecord], groups: &[Group<LeadRecord>]) -> Vec<Plot> {
        plots(grid, &self.spec.leads, groups, &self.booked, &self.zones)
    }
}
