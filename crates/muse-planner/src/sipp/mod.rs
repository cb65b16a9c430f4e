//! Exact safe-interval A* (SIPP) with hovering, a battery limit, ground delay and battery
//! swaps at stations (multi-leg trips, docs/reference.md#multi-leg-trips).
//!
//! # States and labels
//!
//! A *state* is a node together with one of its safe intervals `[lo, hi]` (a maximal run of
//! instants at which the node is free, from
//! [`Schedule::node_slot`](crate::schedule::Schedule::node_slot)). A drone in a state may
//! hover anywhere inside the interval, so arriving earlier is never worse — *for the same
//! take-off time*. With a battery limit and ground delay, a later take-off can matter more
//! than an earlier arrival, so a state keeps every label that is not dominated.
//!
//! A *label* is a family of equivalent partial plans `{(a + x, t₀ + x) : 0 ≤ x ≤ σ}`:
//! arrival `a + x` with take-off `t₀ + x`. Sliding `x` means taking off later by `x` and
//! flying the same timing shifted, which ground delay makes possible near the origin. A point
//! label has `σ = 0`. Label `S` dominates label `N` in the same state when `N` arrives no
//! earlier, has been airborne no shorter, and cannot take off later:
//! `a_N ≥ a_S`, `a_N − t₀_N ≥ a_S − t₀_S` and `t₀_N + σ_N ≤ t₀_S + σ_S`. With `G_max = 0`
//! every label is a point with the requested take-off, and this is the classic SIPP rule
//! "keep the earliest arrival per state".
//!
//! # Successors
//!
//! From a label at node `u` (interval `[lo_u, hi_u]`) along edge `e` to `v` (traversal `w`),
//! the drone enters `e` at some `s` with `a ≤ s ≤ hi_u` (it hovers at `u` until then) at
//! which entry is allowed
//! ([`Schedule::edge_free_run`](crate::schedule::Schedule::edge_free_run)), arriving at
//! `s + w` inside a safe interval `J` of `v`. For departure `s`, the best member is the one that arrives at `u`
//! last, no later than `s`: take-off `t₀ + min(σ, s − a)`. So for each run of allowed entries
//! that lands in `J`, the successors are one slope-1 label (no hovering, later take-off) while
//! `s < a + σ`, and one point label for the first allowed `s ≥ a + σ`; later entries landing
//! in the same `J` are dominated. Every label is pruned by the battery: time airborne so far
//! plus the free-flow time still to fly must not exceed `T_max`.
//!
//! # Multi-leg trips
//!
//! With battery swaps a label also carries the first take-off of the trip, `f₀ + min(x, ρ)`
//! for member `x` (in the first leg `ρ = σ` and the first take-off is the leg's take-off), and
//! the legs begun. At a station other than the destination a drone may land: a *ground label*
//! free to take off from `a + x + S` with first take-off `f₀ + x` (`x ≤ ρ`; later landings
//! add nothing). Waiting on the ground is unlimited, so a take-off from the ground is a label
//! whose slack runs to the end of the station's safe interval; the ground label then moves on
//! to the next safe interval. The first leg may not land at the trip's origin (a leg joins two
//! different stations; landing back would only lift the ground-delay bound). The dominance
//! rule gains two conditions: no more legs, and a first take-off no earlier for every member
//! (`label.rs`).
//!
//! # Files
//!
//! `problem.rs` holds what a search is asked (start, goal, heuristic, swaps, deadline);
//! `label.rs` the labels, their named constructors (a search's first labels, and each kind of
//! successor), their priority and their dominance; `scratch.rs` the search's reusable memory
//! (labels, states, queue); `search.rs` the loop, as a small struct whose steps are named
//! (`seed`, `settle`, `expand`, `split_off_later_members`), and the plan's reconstruction;
//! `expand.rs` the successors (`fly`, `land`, `take_off`).
//!
//! A label with a long slack (a take-off from the ground, or a wide ground-delay window) would
//! generate a successor for every free run of every corridor up to the end of its interval,
//! most of them never needed. Its members beyond half a battery are queued apart as a
//! *continuation* that expands only when its turn comes; it shares the state's dominance with
//! the label it came from.
//!
//! # Order and optimality
//!
//! Labels are expanded in order of `(a + h(v, a − t₀), −f₀, legs)` where `h` is the exact
//! remaining time on the empty graph: the free-flow time to the destination, or with swaps
//! the time of the best chain of legs given what the current leg has flown
//! ([`crate::heuristic::swaps`]). Both are exact costs of a relaxation, hence consistent: the
//! key never decreases along a successor, and where its first part stays equal the first
//! take-off does not move (sliding a member later costs as much in arrival as it gains in
//! take-off). So the first label popped at the destination lands earliest, among the earliest
//! landings it has the latest first take-off, and among those the fewest legs — exactly the
//! docs/reference.md#planning (and #multi-leg-trips) objective.

mod expand;
mod label;
mod problem;
mod scratch;
mod search;

pub(crate) use problem::{Goal, Problem, Remaining, Start, Swaps};
pub use scratch::Scratch;
pub(crate) use search::search;
