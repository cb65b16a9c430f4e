//! The schedule's building block: sorted lists of barriers `(L, R)` (see the module docs of
//! [`super`]) and the one question asked of them, the slot of an instant over several lists.

use muse_model::{Instant, Millis};

use super::{FlightId, NodeSlot};
use crate::time::Unbounded;

/// One reservation: a stay `[start, end]`, an entry instant (`start == end`), or a zone
/// barrier already in `(L, R)` form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Occ {
    pub(super) start: Instant,
    pub(super) end: Instant,
    pub(super) flight: FlightId,
}

impl Occ {
    /// The order of a list, as plain integers (they compare fastest): by start, then end,
    /// then flight.
    #[inline]
    pub(super) fn order(&self) -> (i64, i64, FlightId) {
        (self.start.0, self.end.0, self.flight)
    }
}

/// A read-only view of a sorted list whose barriers are `(start + lo, end + hi)`.
///
/// `occ` may be a suffix of the list (see [`Book`]); `before` is then the last entry left
/// out, whose `R` is all the left-out entries can still answer (read only when needed: it is
/// usually a cache miss).
#[derive(Clone, Copy)]
pub(super) struct View<'a> {
    pub(super) occ: &'a [Occ],
    pub(super) lo: Millis,
    pub(super) hi: Millis,
    pub(super) before: Option<&'a Occ>,
}

impl View<'_> {
    /// A view of nothing.
    pub(super) const EMPTY: View<'static> = View {
        occ: &[],
        lo: Millis::ZERO,
        hi: Millis::ZERO,
        before: None,
    };

    #[inline]
    pub(super) fn l(self, o: &Occ) -> Instant {
        o.start + self.lo
    }

    #[inline]
    pub(super) fn r(self, o: &Occ) -> Instant {
        o.end + self.hi
    }

    /// The index of the first entry with `R > t`: every entry before it ends by `t`, and it
    /// has the smallest `L` of those after (both `L` and `R` are sorted).
    #[inline]
    pub(super) fn first_after(self, t: Instant) -> usize {
        self.occ.partition_point(|o| self.r(o) <= t)
    }

    /// Moves `i` (a `first_after` of an earlier, smaller `t`) to `first_after(t)`: a few
    /// linear steps, then a binary search for long jumps.
    #[inline]
    pub(super) fn advance(self, mut i: usize, t: Instant) -> usize {
        for _ in 0..8 {
            match self.occ.get(i) {
                Some(o) if self.r(o) <= t => i += 1,
                _ => return i,
            }
        }
        i + self.occ[i..].partition_point(|o| self.r(o) <= t)
    }

    /// `R` of the last entry before index `i` (`Instant::NEG_INF` if none).
    #[inline]
    pub(super) fn r_before(self, i: usize) -> Instant {
        match i.checked_sub(1) {
            Some(j) => self.r(&self.occ[j]),
            None => self.before.map_or(Instant::NEG_INF, |o| self.r(o)),
        }
    }
}

/// One reservation list with its *floor*: entries below `floor` have `R ≤ horizon` for every
/// view of the list, so no query at or after the schedule's horizon can be blocked or bounded
/// by them except through the last one's `R`. Searches skip them, which keeps every binary
/// search inside the short, cache-hot window of current traffic when requests are planned in
/// departure order; the entries stay, for removal and for memory accounting.
#[derive(Clone, Debug, Default)]
pub(super) struct Book {
    pub(super) occ: Vec<Occ>,
    pub(super) floor: usize,
}

impl Book {
    /// The view with widening `grow`, skipping the floor when `t` is at or after `horizon`.
    #[inline]
    pub(super) fn view(&self, grow: Millis, t: Instant, horizon: Instant) -> View<'_> {
        self.view_within(Millis(-grow.0), grow, t, horizon)
    }

    /// The view with barriers `(start + lo, end + hi)`, skipping the floor when `t` is at or
    /// after `horizon`.
    #[inline]
    pub(super) fn view_within(
        &self,
        lo: Millis,
        hi: Millis,
        t: Instant,
        horizon: Instant,
    ) -> View<'_> {
        if t >= horizon && self.floor > 0 {
            let (left_out, rest) = self.occ.split_at(self.floor);
            View {
                occ: rest,
                lo,
                hi,
                before: left_out.last(),
            }
        } else {
            View {
                occ: &self.occ,
                lo,
                hi,
                before: None,
            }
        }
    }

    /// Moves the floor past every entry whose widest barrier (`grow_max`) ends by `horizon`.
    pub(super) fn advance(&mut self, horizon: Instant, grow_max: Millis) {
        while self.floor < self.occ.len() && self.occ[self.floor].end + grow_max <= horizon {
            self.floor += 1;
        }
    }
}

/// Where `occ` is in a sorted list, if it is there.
pub(super) fn position(list: &[Occ], occ: Occ) -> Option<usize> {
    let i = insertion_point(list, occ);
    (list.get(i) == Some(&occ)).then_some(i)
}

/// The index of the first entry of the sorted `list` not before `occ` (where `occ` goes), as
/// `partition_point` gives it, found from the end: steps of 1, 2, 4, … back from the last
/// entry bracket it, then a binary search inside the bracket. A day is planned in time order,
/// so a new reservation goes among the last few entries of a list, which are in cache, and a
/// binary search over the whole list would touch its cold middle (a cache miss per step).
pub(super) fn insertion_point(list: &[Occ], occ: Occ) -> usize {
    let key = occ.order();
    let mut hi = list.len();
    let mut step = 1;
    while hi > 0 {
        let probe = hi.saturating_sub(step);
        if list[probe].order() < key {
            return probe + 1 + list[probe + 1..hi].partition_point(|o| o.order() < key);
        }
        hi = probe;
        step *= 2;
    }
    0
}

/// Zone windows `[start, end)` of one element as merged barriers `(start − 1 − before, end)`
/// (`before`: the traversal time on an edge, 0 at a node; see the module docs).
pub(super) fn barriers(windows: &[muse_airspace::closures::Window], before: Millis) -> Vec<Occ> {
    let mut v: Vec<(Instant, Instant)> = windows
        .iter()
        .filter(|win| win.start < win.end)
        .map(|win| (win.start, win.end))
        .collect();
    v.sort_unstable();
    let mut merged: Vec<(Instant, Instant)> = Vec::with_capacity(v.len());
    for (a, b) in v {
        match merged.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    merged
        .into_iter()
        .map(|(a, b)| Occ {
            start: a - Millis(1) - before,
            end: b,
            flight: FlightId(u64::MAX),
        })
        .collect()
}

/// The slot of instant `t` over several views: one binary search per view, then cursors
/// that only move forward while blocked stretches are skipped.
#[inline]
pub(super) fn slot<const N: usize>(views: &[View<'_>; N], t: Instant) -> NodeSlot {
    slot_of(views, &mut [0usize; N], t)
}

/// [`slot`] over `count` views made on demand by `view(k)` (the time rules' and those metric
/// separation adds, which are many and made from the relation as they are read): passes of
/// one binary search per view, until a pass no view blocks.
pub(super) fn slot_of_views<'a>(
    count: usize,
    view: impl Fn(usize) -> View<'a>,
    t: Instant,
) -> NodeSlot {
    let mut t = t;
    let mut blocked = false;
    loop {
        let mut lo = Instant::NEG_INF;
        let (mut hi, mut next) = (Instant::INF, Instant::INF);
        let mut moved = false;
        for k in 0..count {
            let list = view(k);
            // Most lists are all behind `t` or all ahead of it: no binary search then.
            let at = match (list.occ.first(), list.occ.last()) {
                (None, _) => 0,
                (_, Some(last)) if list.r(last) <= t => list.occ.len(),
                (Some(first), _) if list.r(first) > t => 0,
                _ => list.first_after(t),
            };
            match list.occ.get(at) {
                Some(o) if list.l(o) < t => {
                    t = list.r(o);
                    moved = true;
                }
                Some(o) if !moved => {
                    lo = lo.max(list.r_before(at));
                    let (l, r) = (list.l(o), list.r(o));
                    if l < hi {
                        (hi, next) = (l, r);
                    } else if l == hi {
                        next = next.max(r);
                    }
                }
                None if !moved => lo = lo.max(list.r_before(at)),
                _ => {}
            }
        }
        if !moved {
            return if blocked {
                NodeSlot::Blocked { next_free: t }
            } else {
                NodeSlot::Safe { lo, hi, next }
            };
        }
        blocked = true;
    }
}

/// [`slot`] with one cursor per view in `idx`.
#[inline]
fn slot_of<const N: usize>(views: &[View<'_>; N], idx: &mut [usize; N], t: Instant) -> NodeSlot {
    let mut t = t;
    for (i, v) in idx.iter_mut().zip(views) {
        *i = v.first_after(t);
    }
    let mut blocked = false;
    loop {
        // `t` is blocked by a view exactly when its first entry with `R > t` has `L < t`.
        let mut end: Option<Instant> = None;
        for (i, v) in idx.iter_mut().zip(views) {
            *i = v.advance(*i, t);
            if let Some(o) = v.occ.get(*i)
                && v.l(o) < t
            {
                end = Some(end.map_or(v.r(o), |e| e.max(v.r(o))));
            }
        }
        match end {
            Some(r) => {
                blocked = true;
                t = r;
            }
            None => break,
        }
    }
    if blocked {
        return NodeSlot::Blocked { next_free: t };
    }
    let mut lo = Instant::NEG_INF;
    let (mut hi, mut next) = (Instant::INF, Instant::INF);
    for (&i, v) in idx.iter().zip(views) {
        lo = lo.max(v.r_before(i));
        if let Some(o) = v.occ.get(i) {
            let (l, r) = (v.l(o), v.r(o));
            if l < hi {
                (hi, next) = (l, r);
            } else if l == hi {
                next = next.max(r);
            }
        }
    }
    NodeSlot::Safe { lo, hi, next }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn occ(start: i64, end: i64, flight: u64) -> Occ {
        Occ {
            start: Instant(start),
            end: Instant(start + end),
            flight: FlightId(flight),
        }
    }

    proptest! {
        /// From the end or over the whole list, the same place: every key, present or not,
        /// on lists with repeated starts.
        #[test]
        fn insertion_point_is_partition_point(
            mut list in prop::collection::vec((0i64..50, 0i64..5, 0u64..4), 0..200),
            key in (0i64..55, 0i64..5, 0u64..4),
        ) {
            list.sort_unstable();
            let list: Vec<Occ> = list.into_iter().map(|(s, e, f)| occ(s, e, f)).collect();
            let key = occ(key.0, key.1, key.2);
            let whole = list.partition_point(|o| o.order() < key.order());
            prop_assert_eq!(insertion_point(&list, key), whole);
        }
    }

    #[test]
    fn insertion_point_of_empty_and_ends() {
        assert_eq!(insertion_point(&[], occ(1, 0, 0)), 0);
        let list = [occ(1, 0, 0), occ(2, 0, 0), occ(3, 0, 0)];
        assert_eq!(insertion_point(&list, occ(0, 0, 0)), 0);
        assert_eq!(insertion_point(&list, occ(2, 0, 0)), 1);
        assert_eq!(insertion_point(&list, occ(9, 0, 0)), 3);
    }
}
