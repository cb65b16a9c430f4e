//! The first conflict between two plans on the grid, and the two ranges that split it.
//!
//! Both rules of docs/reference.md#flight-model-and-separation come down to two times closer than
//! some gap `g`: stays at one node conflict when some second `x` of one and `y` of the other have
//! `|x − y| < tau` (with `tau >= 1 s`); traversals of one edge when their starts have `|s1 − s2| <
//! w` (either direction under `exclusive`, opposite directions under `headway`) or `< h` (same
//! direction under `headway`). For such a pair `(x, y)`, every `x'` in `[x, y + g − 1]` and `y'` in
//! `[y, x + g − 1]` still have `|x' − y'| <= g − 1`: so no valid schedule has the one flight in its
//! range and the other in its own, and forbidding either range (one branch each) loses no valid
//! schedule, while each branch rules out the current pair.

use super::grid::{Forbid, Grid, GridPlan};

/// Two flights' plans conflict: what to forbid to the first, and to the second.
#[derive(Debug)]
pub struct Conflict {
    /// When (the earlier of the two times): conflicts are split earliest first.
    pub at: i64,
    pub first: Forbid,
    pub second: Forbid,
}

/// The earliest conflict between plans `one` and `other`, if any.
pub fn first_conflict(grid: &Grid, one: &GridPlan, other: &GridPlan) -> Option<Conflict> {
    let mut found: Option<Conflict> = None;
    let mut keep = |c: Conflict| {
        if found.as_ref().is_none_or(|f| c.at < f.at) {
            found = Some(c);
        }
    };
    for s1 in &one.stays {
        for s2 in other.stays.iter().filter(|s2| s2.node == s1.node) {
            if s2.arrive < s1.depart + grid.tau && s1.arrive < s2.depart + grid.tau {
                // The closest seconds of the two stays.
                let (x, y) = if s1.arrive <= s2.arrive {
                    (s1.depart.min(s2.arrive), s2.arrive)
                } else {
                    (s1.arrive, s2.depart.min(s1.arrive))
                };
                let g = grid.tau;
                let node = s1.node;
                keep(Conflict {
                    at: x.min(y),
                    first: Forbid::Node {
                        node,
                        from: x,
                        to: y + g - 1,
                    },
                    second: Forbid::Node {
                        node,
                        from: y,
                        to: x + g - 1,
                    },
                });
            }
        }
    }
    for (e1, f1, x) in one.traversals() {
        for (_, f2, y) in other.traversals().filter(|t| t.0 == e1) {
            let g = match grid.headway {
                Some(h) if f1 == f2 => h,
                _ => grid.w[e1],
            };
            if (x - y).abs() < g {
                keep(Conflict {
                    at: x.min(y),
                    first: Forbid::Start {
                        edge: e1,
                        forward: f1,
                        from: x,
                        to: y + g - 1,
                    },
                    second: Forbid::Start {
                        edge: e1,
                        forward: f2,
                        from: y,
                        to: x + g - 1,
                    },
                });
            }
        }
    }
    found
}
