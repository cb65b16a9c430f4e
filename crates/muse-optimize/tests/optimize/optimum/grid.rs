//! One request on the grid of whole seconds: its earliest landing that keeps out of a set of
//! forbidden ranges, by a search over `(node, second)` in time order. It shares nothing with
//! the planner but the airspace and the parameters.

use muse_model::{Airspace, EdgeRule, FlightParams, Instant, Millis, NodeId, Plan, Request, Stay};

/// The instance in whole seconds.
pub struct Grid {
    /// Per node: `(neighbour, edge, forward)`.
    adjacent: Vec<Vec<(usize, usize, bool)>>,
    /// Traversal time of each edge.
    pub w: Vec<i64>,
    /// Node separation `tau`.
    pub tau: i64,
    /// Same-direction headway, under the `headway` edge rule.
    pub headway: Option<i64>,
    /// Maximum ground delay.
    gmax: i64,
    /// Maximum airborne time.
    tmax: i64,
}

/// Whole seconds of `t`, which must be whole.
fn secs(t: Millis, what: &str) -> i64 {
    assert_eq!(t.0 % 1_000, 0, "{what} is not whole seconds: {t:?}");
    t.0 / 1_000
}

impl Grid {
    /// The grid of an instance; every time must be whole seconds and `tau` at least one.
    pub fn new(airspace: &Airspace, params: &FlightParams) -> Self {
        assert!(params.battery_swap.is_none(), "single legs only");
        let mut adjacent = vec![Vec::new(); airspace.node_count()];
        for (e, edge) in airspace.edges().iter().enumerate() {
            adjacent[edge.from.index()].push((edge.to.index(), e, true));
            adjacent[edge.to.index()].push((edge.from.index(), e, false));
        }
        let w = airspace
            .traversal_times(params.speed)
            .into_iter()
            .map(|t| secs(t, "a traversal time"))
            .collect();
        let tau = secs(params.node_separation, "tau");
        assert!(tau >= 1, "the conflict ranges need tau >= 1 s");
        Grid {
            adjacent,
            w,
            tau,
            headway: match params.edge_rule {
                EdgeRule::Exclusive => None,
                EdgeRule::Headway(h) => Some(secs(h, "the headway")),
            },
            gmax: secs(params.max_ground_delay, "G_max"),
            tmax: secs(params.max_flight, "T_max"),
        }
    }

    /// The free-flow time from `a` to `b` (Dijkstra on the traversal times), if any.
    pub fn free_flow(&self, a: usize, b: usize) -> Option<i64> {
        let mut dist = vec![i64::MAX; self.adjacent.len()];
        let mut done = vec![false; self.adjacent.len()];
        dist[a] = 0;
        while let Some(v) = (0..dist.len())
            .filter(|&v| !done[v] && dist[v] < i64::MAX)
            .min_by_key(|&v| dist[v])
        {
            done[v] = true;
            for &(u, e, _) in &self.adjacent[v] {
                dist[u] = dist[u].min(dist[v] + self.w[e]);
            }
        }
        (dist[b] < i64::MAX).then_some(dist[b])
    }
}

/// One request in whole seconds.
#[derive(Clone, Copy, Debug)]
pub struct Agent {
    pub origin: usize,
    pub destination: usize,
    pub departure: i64,
    /// Free-flow time; `None` when the trip cannot be flown within the battery.
    pub free_flow: Option<i64>,
}

impl Agent {
    /// The agent of `request`.
    pub fn new(grid: &Grid, request: &Request) -> Self {
        let (origin, destination) = (request.origin.index(), request.destination.index());
        let free_flow = grid
            .free_flow(origin, destination)
            .filter(|&f| f <= grid.tmax);
        Agent {
            origin,
            destination,
            departure: secs(Millis(request.departure.0), "a departure"),
            free_flow,
        }
    }
}

/// A range of whole seconds an agent must keep out of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Forbid {
    /// Not at `node` at any second of `[from, to]`.
    Node { node: usize, from: i64, to: i64 },
    /// No traversal of `edge` in direction `forward` starting at a second of `[from, to]`.
    Start {
        edge: usize,
        forward: bool,
        from: i64,
        to: i64,
    },
}

/// A stay on the grid, with the edge flown to reach it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridStay {
    pub node: usize,
    pub arrive: i64,
    pub depart: i64,
    /// `(edge, forward)` flown to get here; `None` for the first stay.
    pub via: Option<(usize, bool)>,
}

/// A plan on the grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GridPlan {
    pub stays: Vec<GridStay>,
}

impl GridPlan {
    /// Landing second.
    pub fn landing(&self) -> i64 {
        self.stays.last().expect("a plan has stays").arrive
    }

    /// Every traversal: `(edge, forward, start)`.
    pub fn traversals(&self) -> impl Iterator<Item = (usize, bool, i64)> + '_ {
        self.stays.windows(2).map(|p| {
            let (e, f) = p[1].via.expect("every stay but the first is flown to");
            (e, f, p[0].depart)
        })
    }

    /// The plan in milliseconds.
    pub fn to_plan(&self) -> Plan {
        let at = |s: i64| Instant(s * 1_000);
        Plan {
            path: self
                .stays
                .iter()
                .map(|s| Stay {
                    node: NodeId(u32::try_from(s.node).expect("small")),
                    arrive: at(s.arrive),
                    depart: at(s.depart),
                })
                .collect(),
        }
    }
}

/// How a state was reached.
#[derive(Clone, Copy)]
enum Step {
    TakeOff,
    Wait,
    Fly {
        from: usize,
        edge: usize,
        forward: bool,
    },
}

/// The earliest landing of `agent` that keeps out of `forbid`, or `None` if it has none;
/// among the earliest, one with few clashes with `others` (the other agents' plans), which
/// makes the search above find fewer conflicts (a "conflict avoidance table").
///
/// States are `(node, second)`: at the node at that second, valued by the latest take-off
/// that reaches them (a later take-off is never worse: only the battery links a plan's past
/// to its future), then by fewest clashes. All moves go forward in time, so the states of a
/// second are final when it is reached.
pub fn earliest(
    grid: &Grid,
    agent: &Agent,
    forbid: &[Forbid],
    others: &[&GridPlan],
) -> Option<GridPlan> {
    agent.free_flow?;
    let (dep, n) = (agent.departure, grid.adjacent.len());
    let span = usize::try_from(grid.gmax + grid.tmax).expect("positive") + 1;
    let clashes = Clashes::new(grid, dep, span, others);
    let at_ok = |v: usize, t: i64| {
        !forbid.iter().any(
            |f| matches!(*f, Forbid::Node { node, from, to } if node == v && from <= t && t <= to),
        )
    };
    let start_ok = |e: usize, fwd: bool, t: i64| {
        !forbid.iter().any(|f| {
            matches!(*f, Forbid::Start { edge, forward, from, to }
                if edge == e && forward == fwd && from <= t && t <= to)
        })
    };
    let index = |v: usize, t: usize| v * span + t;
    // Per state: (take-off, clashes so far).
    let mut value: Vec<Option<(i64, u32)>> = vec![None; n * span];
    let mut how = vec![Step::TakeOff; n * span];
    let mut reach =
        |v: usize, t: usize, val: (i64, u32), step: Step, value: &mut [Option<(i64, u32)>]| {
            let better = |o: (i64, u32)| o.0 < val.0 || (o.0 == val.0 && o.1 > val.1);
            if value[index(v, t)].is_none_or(better) {
                value[index(v, t)] = Some(val);
                how[index(v, t)] = step;
                true
            } else {
                false
            }
        };
    for g in 0..=grid.gmax {
        if at_ok(agent.origin, dep + g) {
            let t = usize::try_from(g).expect("small");
            let val = (g, clashes.at(agent.origin, t));
            reach(agent.origin, t, val, Step::TakeOff, &mut value);
        }
    }
    // The earliest landing, with its clashes.
    let mut goal: Option<(usize, u32)> = None;
    for t in 0..span {
        if goal.is_some_and(|(g, _)| t >= g) {
            break;
        }
        let now = i64::try_from(t).expect("small");
        for v in 0..n {
            let Some((off, clash)) = value[index(v, t)] else {
                continue;
            };
            if t + 1 < span && now + 1 - off <= grid.tmax && at_ok(v, dep + now + 1) {
                let val = (off, clash + clashes.at(v, t + 1));
                reach(v, t + 1, val, Step::Wait, &mut value);
            }
            for &(u, e, forward) in &grid.adjacent[v] {
                let arrive = now + grid.w[e];
                if arrive - off > grid.tmax
                    || !start_ok(e, forward, dep + now)
                    || !at_ok(u, dep + arrive)
                {
                    continue;
                }
                let ta = usize::try_from(arrive).expect("small");
                let fly = Step::Fly {
                    from: v,
                    edge: e,
                    forward,
                };
                let total = clash + clashes.start(e, forward, t) + clashes.at(u, ta);
                let reached = reach(u, ta, (off, total), fly, &mut value);
                if u == agent.destination
                    && reached
                    && goal.is_none_or(|(g, c)| ta < g || (ta == g && total < c))
                {
                    goal = Some((ta, total));
                }
            }
        }
    }
    let (landing, _) = goal?;
    Some(trace(grid, agent, &how, span, landing))
}

/// The plan that lands at `landing` (relative second), read back from the steps.
fn trace(grid: &Grid, agent: &Agent, how: &[Step], span: usize, landing: usize) -> GridPlan {
    let dep = agent.departure;
    let secs = |t: usize| dep + i64::try_from(t).expect("small");
    let mut stays = vec![GridStay {
        node: agent.destination,
        arrive: secs(landing),
        depart: secs(landing),
        via: None,
    }];
    let (mut v, mut t) = (agent.destination, landing);
    // The landing stay was reached by flying; find that step, then walk back.
    loop {
        match how[v * span + t] {
            Step::TakeOff => break,
            Step::Wait => t -= 1,
            Step::Fly {
                from,
                edge,
                forward,
            } => {
                let start = t - usize::try_from(grid.w[edge]).expect("small");
                stays.last_mut().expect("a stay").via = Some((edge, forward));
                stays.push(GridStay {
                    node: from,
                    arrive: 0,
                    depart: secs(start),
                    via: None,
                });
                (v, t) = (from, start);
            }
        }
        stays.last_mut().expect("a stay").arrive = secs(t);
    }
    stays.reverse();
    GridPlan { stays }
}

/// How many of the other agents' stays and traversals each grid step would conflict with.
struct Clashes {
    span: usize,
    /// Per `(node, second)`: other stays within `tau`.
    nodes: Vec<u32>,
    /// Per `(edge, direction, second)`: other traversals a start then would conflict with.
    starts: Vec<u32>,
}

impl Clashes {
    /// The table for seconds `dep ..dep + span` against `others`.
    fn new(grid: &Grid, dep: i64, span: usize, others: &[&GridPlan]) -> Self {
        let n = grid.adjacent.len();
        let mut c = Clashes {
            span,
            nodes: vec![0; n * span],
            starts: vec![0; grid.w.len() * 2 * span],
        };
        let len = i64::try_from(span).expect("small");
        // Seconds `(lo, hi)` exclusive, relative to `dep`, clamped to the window.
        let window = |lo: i64, hi: i64| {
            let from = usize::try_from((lo - dep + 1).max(0)).expect("clamped");
            let to = usize::try_from((hi - dep).clamp(0, len)).expect("clamped");
            from..to.max(from)
        };
        for plan in others {
            for s in &plan.stays {
                for t in window(s.arrive - grid.tau, s.depart + grid.tau) {
                    c.nodes[s.node * span + t] += 1;
                }
            }
            for (e, f, s) in plan.traversals() {
                for forward in [true, false] {
                    let g = match grid.headway {
                        Some(h) if forward == f => h,
                        _ => grid.w[e],
                    };
                    let row = (e * 2 + usize::from(forward)) * span;
                    for t in window(s - g, s + g) {
                        c.starts[row + t] += 1;
                    }
                }
            }
        }
        c
    }

    /// Clashes of being at `v` at relative second `t`.
    fn at(&self, v: usize, t: usize) -> u32 {
        self.nodes[v * self.span + t]
    }

    /// Clashes of starting `e` in direction `forward` at relative second `t`.
    fn start(&self, e: usize, forward: bool, t: usize) -> u32 {
        self.starts[(e * 2 + usize::from(forward)) * self.span + t]
    }
}
