//! The true optimum of a small batch (docs/reference.md#batch-planning's objective: most requests
//! planned, then least total delay), over every valid schedule, by conflict-based search (Sharon et
//! al., 2015) on the grid of whole seconds. Tests only: it shares nothing with the planner or the
//! optimiser but the airspace, the parameters and the objective's type.
//!
//! # Why whole seconds are exact
//!
//! The instances' data are whole seconds: traversal times, `tau`, `T_max`, `G_max` and the
//! departures. Take any valid schedule and fix its routes, which flight goes first at every
//! node and corridor both use, and its rejections. What remains is a system of difference
//! constraints on the schedule's times (`arrive <= depart`, `arrive' = depart + w`,
//! `arrive2 >= depart1 + tau`, `start2 >= start1 + w`, `take-off >= departure`,
//! `take-off <= departure + G_max`, `landing - take-off <= T_max`), and such a system, when
//! it has a solution, has a least one: every time as early as any solution has it, so no
//! landing later. Its every time is the longest chain of lower bounds from a departure,
//! a sum of whole seconds. So some optimal schedule has every time on whole seconds, and the
//! search over them finds the optimum.
//!
//! # The search
//!
//! Each request is an agent planned alone by [`grid::earliest`] (its earliest landing, or a
//! rejection if it has none) under the ranges forbidden to it. A search node is one set of
//! forbidden ranges with every agent's plan; its cost, `(rejections, total delay)` in that
//! order, is a bound on every schedule below it. Nodes are taken best cost first; a node with
//! no conflict is the optimum. Otherwise its earliest conflict is split into two children,
//! one forbidding each flight its range ([`conflict`] shows that no valid schedule is lost).
//! A rejection never conflicts, so the search always ends: at worst with every request
//! rejected.

pub mod conflict;
pub mod grid;

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashSet};

use muse_model::{Millis, Plan};
use muse_optimize::Objective;

use crate::instances::Instance;
use conflict::{Conflict, first_conflict};
use grid::{Agent, Forbid, Grid, GridPlan, earliest};

/// The optimum of an instance.
pub struct Optimum {
    /// Its objective.
    pub objective: Objective,
    /// Each request's plan, or `None` if rejected.
    pub plans: Vec<Option<Plan>>,
    /// Search nodes expanded.
    pub expanded: usize,
}

/// One node of the search.
struct Node {
    forbid: Vec<Vec<Forbid>>,
    plans: Vec<Option<GridPlan>>,
    cost: (usize, i64),
}

/// `(rejections, total delay in seconds)` of plans.
fn cost(agents: &[Agent], plans: &[Option<GridPlan>]) -> (usize, i64) {
    agents
        .iter()
        .zip(plans)
        .fold((0, 0), |(r, d), (a, p)| match p {
            None => (r + 1, d),
            Some(p) => (
                r,
                d + p.landing() - a.departure - a.free_flow.expect("planned"),
            ),
        })
}

/// What `forbid` forbids, as a value: per agent, the ranges of each node and of each
/// corridor direction merged where they overlap or touch, sorted.
fn canonical(forbid: &[Vec<Forbid>]) -> Vec<Vec<(usize, usize, i64, i64)>> {
    forbid
        .iter()
        .map(|ranges| {
            // (kind and place, direction, from, to): nodes as `2 n`, corridors `2 e + 1`.
            let mut keyed: Vec<(usize, usize, i64, i64)> = ranges
                .iter()
                .map(|f| match *f {
                    Forbid::Node { node, from, to } => (2 * node, 0, from, to),
                    Forbid::Start {
                        edge,
                        forward,
                        from,
                        to,
                    } => (2 * edge + 1, usize::from(forward), from, to),
                })
                .collect();
            keyed.sort_unstable();
            let mut merged: Vec<(usize, usize, i64, i64)> = Vec::new();
            for k in keyed {
                match merged.last_mut() {
                    Some(m) if (m.0, m.1) == (k.0, k.1) && k.2 <= m.3 + 1 => m.3 = m.3.max(k.3),
                    _ => merged.push(k),
                }
            }
            merged
        })
        .collect()
}

/// The first conflict of every pair of planned agents that conflict, earliest first.
fn conflicts(grid: &Grid, plans: &[Option<GridPlan>]) -> Vec<(usize, usize, Conflict)> {
    let mut all = Vec::new();
    for (i, a) in plans.iter().enumerate() {
        for (j, b) in plans.iter().enumerate().skip(i + 1) {
            if let (Some(a), Some(b)) = (a, b)
                && let Some(c) = first_conflict(grid, a, b)
            {
                all.push((i, j, c));
            }
        }
    }
    all.sort_by_key(|(i, j, c)| (c.at, *i, *j));
    all
}

/// The search's data.
struct Search<'a> {
    grid: &'a Grid,
    agents: &'a [Agent],
}

impl Search<'_> {
    /// The plan of `agent` under `forbid`, avoiding the other plans where it costs nothing.
    fn replan(
        &self,
        agent: usize,
        forbid: &[Forbid],
        plans: &[Option<GridPlan>],
    ) -> Option<GridPlan> {
        let others: Vec<&GridPlan> = plans
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != agent)
            .filter_map(|(_, p)| p.as_ref())
            .collect();
        earliest(self.grid, &self.agents[agent], forbid, &others)
    }

    /// The two children of `node` that split `conflict` (between `i` and `j`).
    fn children(&self, node: &Node, i: usize, j: usize, conflict: &Conflict) -> [Node; 2] {
        [(i, conflict.first), (j, conflict.second)].map(|(agent, range)| {
            let mut forbid = node.forbid.clone();
            forbid[agent].push(range);
            let mut plans = node.plans.clone();
            plans[agent] = self.replan(agent, &forbid[agent], &plans);
            Node {
                cost: cost(self.agents, &plans),
                forbid,
                plans,
            }
        })
    }

    /// The children to push for `node`, which has `found` conflicts: those of a cardinal
    /// conflict (both children cost more) if any, else of a semi-cardinal one, else of the
    /// earliest. Among the conflicts looked at, a child that costs no more and has fewer
    /// conflicts replaces its parent's plan instead (a bypass): then `None`, and the node is
    /// looked at again.
    fn split(&self, node: &mut Node, found: &[(usize, usize, Conflict)]) -> Option<[Node; 2]> {
        let mut best: Option<(usize, [Node; 2])> = None;
        for (i, j, c) in found.iter().take(8) {
            let kids = self.children(node, *i, *j, c);
            for (kid, agent) in kids.iter().zip([*i, *j]) {
                if kid.cost == node.cost && conflicts(self.grid, &kid.plans).len() < found.len() {
                    node.plans[agent].clone_from(&kid.plans[agent]);
                    return None;
                }
            }
            let rank = kids.iter().filter(|k| k.cost > node.cost).count();
            if best.as_ref().is_none_or(|(r, _)| rank > *r) {
                best = Some((rank, kids));
            }
            if rank == 2 {
                break;
            }
        }
        best.map(|(_, kids)| kids)
    }
}

/// The optimum of `inst`; if more than `cap` nodes would be expanded, `Err` with a bound: no
/// schedule is better than it (the cost of the next node to expand).
pub fn optimum(inst: &Instance, cap: usize) -> Result<Optimum, Objective> {
    let grid = Grid::new(&inst.airspace, &inst.params);
    let agents: Vec<Agent> = inst.requests.iter().map(|r| Agent::new(&grid, r)).collect();
    let search = Search {
        grid: &grid,
        agents: &agents,
    };
    let mut plans: Vec<Option<GridPlan>> = vec![None; agents.len()];
    for a in 0..agents.len() {
        plans[a] = search.replan(a, &[], &plans);
    }
    let root = Node {
        forbid: vec![Vec::new(); agents.len()],
        cost: cost(&agents, &plans),
        plans,
    };
    // Best cost first; among equals the newest (deepest) first.
    let mut open = BinaryHeap::new();
    let mut nodes = vec![root];
    open.push((Reverse(nodes[0].cost), 0_usize));
    let mut expanded = 0;
    let mut seen = HashSet::new();
    let objective = |(rejected, delay): (usize, i64)| Objective {
        planned: agents.len() - rejected,
        delay: Millis(delay * 1_000),
    };
    while let Some((_, k)) = open.pop() {
        expanded += 1;
        if expanded > cap {
            return Err(objective(nodes[k].cost));
        }
        let kids = loop {
            let found = conflicts(&grid, &nodes[k].plans);
            if found.is_empty() {
                let node = &nodes[k];
                return Ok(Optimum {
                    objective: objective(node.cost),
                    plans: node
                        .plans
                        .iter()
                        .map(|p| p.as_ref().map(GridPlan::to_plan))
                        .collect(),
                    expanded,
                });
            }
            if let Some(kids) = search.split(&mut nodes[k], &found) {
                break kids;
            }
        };
        for kid in kids {
            // Two orders of the same splits forbid the same: look at such a node once.
            if seen.insert(canonical(&kid.forbid)) {
                open.push((Reverse(kid.cost), nodes.len()));
                nodes.push(kid);
            }
        }
    }
    unreachable!("a schedule with every request rejected has no conflict")
}
