//! Which movements come too close in metres, and when (docs/reference.md#metric-separation):
//! the geometry the planner keeps metric separation with, worked out once per pair of
//! movements of an airspace.
//!
//! A movement is a straight flight at constant pace ([`Motion`]): a corridor traversal at a
//! layer, a climb between layers above a node, or a stay (a motion of no length). Two drones
//! on movements `A` and `B`, `B` starting `δ` seconds after `A`, come closer than `D` when at
//! some instant both are on their movements, less than `D` apart horizontally and less than
//! `V` vertically. In `(t, τ)`, each drone's own time on its movement, that set is the
//! intersection of a box, the preimage of a disk under an affine map and a slab, all convex:
//! so the offsets `δ = t − τ` at which the two conflict form one open interval ([`offsets`]).
//! Against a stay at a node, what matters is when a movement is near the node
//! ([`near_window`]): a stay `[a, d]` and a movement starting at `s` conflict when that window,
//! moved to `s`, meets `[a, d]`.
//!
//! ```
//! use muse_airspace::conflicts::{Motion, offsets};
//! // One drone leaves a node eastwards, another arrives at it from a corridor 90° away, both
//! // at 10 m/s over 100 s. Arriving less than 2.83 s (20 m / (10 m/s · sin 45°)) after the
//! // departure, they come closer than 20 m; arriving before it, the two motions share no
//! // instant (the stay at the node between is a movement of its own).
//! let east = Motion::between([0.0, 0.0, 60.0], [1000.0, 0.0, 60.0], 100.0);
//! let from_north = Motion::between([0.0, 1000.0, 60.0], [0.0, 0.0, 60.0], 100.0);
//! let (lo, hi) = offsets(&east, &from_north, 20.0, 9.144).unwrap();
//! // `from_north` reaches the node 100 s after it starts, at δ + 100.
//! assert!((lo + 100.0).abs() < 1e-5 && (hi - (-100.0 + 2.828_427)).abs() < 1e-5);
//! ```

mod relation;

pub use relation::{Link, Movement, Relation};

/// A straight flight at constant pace: from `from` to `to` (metres east, north, up) over
/// `duration` seconds (zero: an instant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Where it begins.
    pub from: [f64; 3],
    /// Where it ends.
    pub to: [f64; 3],
    /// How long it takes, seconds.
    pub duration: f64,
}

impl Motion {
    /// The motion from `from` to `to` over `duration` seconds.
    #[must_use]
    pub fn between(from: [f64; 3], to: [f64; 3], duration: f64) -> Motion {
        Motion { from, to, duration }
    }

    /// Its velocity, metres per second (zero for an instant or a stay).
    fn velocity(&self) -> [f64; 3] {
        if self.duration <= 0.0 {
            return [0.0; 3];
        }
        [0, 1, 2].map(|i| (self.to[i] - self.from[i]) / self.duration)
    }
}

/// The least horizontal distance between `a` and `b` started `delta` seconds after `a`, over
/// the instants both are on their motions and within `vertical` of each other vertically;
/// `None` if there is no such instant.
#[must_use]
pub fn approach(a: &Motion, b: &Motion, delta: f64, vertical: f64) -> Option<f64> {
    // In `a`'s time t: both on their motions for t in [max(0, δ), min(wa, δ + wb)].
    let (t0, t1) = (delta.max(0.0), a.duration.min(delta + b.duration));
    if t0 > t1 {
        return None;
    }
    let (va, vb) = (a.velocity(), b.velocity());
    // Difference of positions at t: a.from − b.from + vb·δ + (va − vb)·t.
    let gap = [0, 1, 2].map(|i| a.from[i] - b.from[i] + vb[i] * delta);
    let drift = [0, 1, 2].map(|i| va[i] - vb[i]);
    let (lo, hi) = within_vertical(gap[2], drift[2], vertical, t0, t1)?;
    let speed2 = drift[0] * drift[0] + drift[1] * drift[1];
    let at = if speed2 == 0.0 {
        lo
    } else {
        (-(gap[0] * drift[0] + gap[1] * drift[1]) / speed2).clamp(lo, hi)
    };
    Some((gap[0] + drift[0] * at).hypot(gap[1] + drift[1] * at))
}

/// The times in `[lo, hi]` at which two drones whose difference in altitude is
/// `gap + drift·t` are within `vertical` of each other: an interval, open at an end the
/// vertical bound sets (equality is separation); `None` if there is no such time.
fn within_vertical(gap: f64, drift: f64, vertical: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if drift == 0.0 {
        return (gap.abs() < vertical).then_some((lo, hi));
    }
    let (s1, s2) = ((-vertical - gap) / drift, (vertical - gap) / drift);
    let (enter, leave) = (s1.min(s2), s1.max(s2));
    let open = enter >= lo || leave <= hi;
    let (lo, hi) = (lo.max(enter), hi.min(leave));
    let some = if open { lo < hi } else { lo <= hi };
    some.then_some((lo, hi))
}

/// Whether `a` and `b`, `b` started `delta` seconds after `a`, come closer than `distance`
/// horizontally while within `vertical` vertically.
fn conflict(a: &Motion, b: &Motion, delta: f64, distance: f64, vertical: f64) -> bool {
    approach(a, b, delta, vertical).is_some_and(|d| d < distance)
}

/// The open interval of offsets `δ` (seconds; `b` starting `δ` after `a`) at which `a` and `b`
/// come closer than `distance` horizontally while within `vertical` vertically, its ends
/// found to a microsecond (each end a little outside the exact one, never inside); `None` if
/// they never do.
#[must_use]
pub fn offsets(a: &Motion, b: &Motion, distance: f64, vertical: f64) -> Option<(f64, f64)> {
    let inside = deepest(a, b, vertical).filter(|&(_, d)| d < distance)?.0;
    let edge = |mut ok: f64, mut out: f64| {
        // `ok` conflicts, `out` does not: halve until within a microsecond.
        while (ok - out).abs() > 1e-7 {
            let mid = 0.5 * (ok + out);
            if conflict(a, b, mid, distance, vertical) {
                ok = mid;
            } else {
                out = mid;
            }
        }
        out
    };
    // Outside the offsets at which the two are ever on their motions together, no conflict.
    let (first, last) = (-b.duration - 1.0, a.duration + 1.0);
    Some((edge(inside, first), edge(inside, last)))
}

/// The offset at which `a` and `b` come closest (within `vertical`), and that distance: the
/// least of [`approach`] over the offsets, found by golden-section search on the convex
/// function it is (the least distance of two straight motions against their offset), from a
/// scan that brackets it.
fn deepest(a: &Motion, b: &Motion, vertical: f64) -> Option<(f64, f64)> {
    let (first, last) = (-b.duration, a.duration);
    let f = |delta: f64| approach(a, b, delta, vertical).unwrap_or(f64::INFINITY);
    // A scan first: where they are never within `vertical`, the function is infinite, so the
    // search starts from the best sampled offset.
    let steps = 256;
    let mut best = (first, f(first));
    for k in 1..=steps {
        let delta = first + (last - first) * f64::from(k) / f64::from(steps);
        let d = f(delta);
        if d < best.1 {
            best = (delta, d);
        }
    }
    if !best.1.is_finite() {
        return None;
    }
    let width = (last - first) / f64::from(steps);
    let (mut lo, mut hi) = (best.0 - width, best.0 + width);
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    while hi - lo > 1e-9 {
        let (x1, x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
        if f(x1) <= f(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    let mid = 0.5 * (lo + hi);
    let at = if f(mid) <= best.1 { mid } else { best.0 };
    Some((at, f(at)))
}

/// The open window of times after `b` starts (seconds) during which `b` is closer than
/// `distance` horizontally to `point` and within `vertical` of it vertically; `None` if it
/// never is.
#[must_use]
pub fn near_window(
    point: [f64; 3],
    b: &Motion,
    distance: f64,
    vertical: f64,
) -> Option<(f64, f64)> {
    // The times `t` at which the distance is under `distance`: an interval (convex in t).
    let pace = b.velocity();
    let gap = [0, 1, 2].map(|i| b.from[i] - point[i]);
    let (lo, hi) = within_vertical(gap[2], pace[2], vertical, 0.0, b.duration)?;
    let speed2 = pace[0] * pace[0] + pace[1] * pace[1];
    let r2 = distance * distance;
    if speed2 == 0.0 {
        return (gap[0] * gap[0] + gap[1] * gap[1] < r2).then_some((lo, hi));
    }
    // |c + v t|² < r² ⟺ speed2 t² + 2 (c·v) t + |c|² − r² < 0.
    let p = gap[0] * pace[0] + gap[1] * pace[1];
    let q = gap[0] * gap[0] + gap[1] * gap[1] - r2;
    let disc = p * p - speed2 * q;
    if disc <= 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let (enter, leave) = ((-p - root) / speed2, (-p + root) / speed2);
    let (lo, hi) = (lo.max(enter), hi.min(leave));
    (lo < hi).then_some((lo, hi))
}

#[cfg(test)]
mod tests;
