//! The closest approach of two straight constant-pace pieces, exactly: the least horizontal
//! distance between them over the instants both are flying them and are closer than `V`
//! vertically.
//!
//! On the instants both pieces share, the difference of the positions is linear in time, so
//! the squared horizontal distance is a quadratic and the vertical distance the absolute value
//! of a linear function: the instants closer than `V` vertically are one open interval, and
//! the quadratic's least value on it is at its vertex or at an end.

use super::track::Piece;

/// The closest approach of `one` and `other` within `[lo, hi]` (seconds) under the vertical
/// separation `vertical`: the horizontal distance and the instant; `None` if no instant of
/// the window has both flying closer than `vertical` vertically.
#[must_use]
pub fn closest(one: &Piece, other: &Piece, lo: f64, hi: f64, vertical: f64) -> Option<(f64, f64)> {
    let lo = lo.max(one.t0).max(other.t0);
    let hi = hi.min(one.t1).min(other.t1);
    if lo > hi {
        return None;
    }
    let (p, q) = (one.at(lo), other.at(lo));
    let (vp, vq) = (one.velocity(), other.velocity());
    let d0 = [0, 1, 2].map(|i| p[i] - q[i]);
    let dv = [0, 1, 2].map(|i| vp[i] - vq[i]);
    // Instants (after `lo`) closer than `vertical` vertically: |d0z + dvz·s| < vertical.
    let (mut from, mut to) = (0.0_f64, hi - lo);
    if dv[2] == 0.0 {
        if d0[2].abs() >= vertical {
            return None;
        }
    } else {
        let (s1, s2) = ((-vertical - d0[2]) / dv[2], (vertical - d0[2]) / dv[2]);
        let (enter, leave) = (s1.min(s2), s1.max(s2));
        let mut open = false;
        if enter >= from {
            from = enter;
            open = true;
        }
        if leave <= to {
            to = leave;
            open = true;
        }
        // An open end makes a single instant empty.
        if from > to || (open && from >= to) {
            return None;
        }
    }
    // The least of |d0 + dv·s| horizontally over [from, to].
    let speed2 = dv[0] * dv[0] + dv[1] * dv[1];
    let at = if speed2 == 0.0 {
        from
    } else {
        (-(d0[0] * dv[0] + d0[1] * dv[1]) / speed2).clamp(from, to)
    };
    let (dx, dy) = (d0[0] + dv[0] * at, d0[1] + dv[1] * at);
    Some((dx.hypot(dy), lo + at))
}

#[cfg(test)]
#[allow(clippy::many_single_char_names)]
mod tests {
    use super::*;
    use muse_model::NodeId;

    fn piece(flight: u32, t0: f64, t1: f64, p0: [f64; 3], p1: [f64; 3]) -> Piece {
        Piece {
            flight,
            t0,
            t1,
            p0,
            p1,
            from: NodeId(0),
            to: NodeId(0),
        }
    }

    /// The least horizontal distance by dense sampling (the oracle of these tests).
    fn sampled(a: &Piece, b: &Piece, v: f64) -> Option<f64> {
        let (lo, hi) = (a.t0.max(b.t0), a.t1.min(b.t1));
        if lo > hi {
            return None;
        }
        let mut best: Option<f64> = None;
        for k in 0..=200_000 {
            let t = lo + (hi - lo) * f64::from(k) / 200_000.0;
            let (p, q) = (a.at(t), b.at(t));
            if (p[2] - q[2]).abs() < v {
                let d = (p[0] - q[0]).hypot(p[1] - q[1]);
                best = Some(best.map_or(d, |b: f64| b.min(d)));
            }
        }
        best
    }

    #[test]
    fn a_crossing_at_right_angles() {
        // One flies east through the origin at t = 10 s, the other north through it at 12 s,
        // both at 10 m/s: closest at t = 11 s, 10·√2 m apart.
        let a = piece(0, 0.0, 20.0, [-100.0, 0.0, 60.0], [100.0, 0.0, 60.0]);
        let b = piece(1, 0.0, 20.0, [0.0, -120.0, 60.0], [0.0, 80.0, 60.0]);
        let (d, t) = closest(&a, &b, f64::NEG_INFINITY, f64::INFINITY, 9.144).unwrap();
        assert!((d - 200f64.sqrt()).abs() < 1e-9, "{d}");
        assert!((t - 11.0).abs() < 1e-9, "{t}");
        // A layer apart (9.144 m, equal to V): never too close.
        let c = piece(1, 0.0, 20.0, [0.0, -120.0, 69.144], [0.0, 80.0, 69.144]);
        assert_eq!(
            closest(&a, &c, f64::NEG_INFINITY, f64::INFINITY, 9.144),
            None
        );
    }

    #[test]
    fn a_climb_is_close_only_while_within_v() {
        // A hover at 60 m above the origin; another climbs above a point 5 m away, from 60 m
        // to 69.144 m over 1.829 s: within 9.144 m vertically until it reaches the top.
        let hover = piece(0, 0.0, 10.0, [0.0, 0.0, 60.0], [0.0, 0.0, 60.0]);
        let climb = piece(1, 2.0, 3.829, [5.0, 0.0, 60.0], [5.0, 0.0, 69.144]);
        let (d, t) = closest(&hover, &climb, f64::NEG_INFINITY, f64::INFINITY, 9.144).unwrap();
        assert!(
            (d - 5.0).abs() < 1e-12 && (2.0..3.829).contains(&t),
            "{d} {t}"
        );
        assert_eq!(closest(&hover, &climb, 3.829, 10.0, 9.144), None);
    }

    #[test]
    fn agrees_with_sampling_on_random_pieces() {
        let mut x = 0x39_0001_u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..300 {
            let mut p = || {
                let t0 = next() * 20.0;
                let t1 = t0 + 1.0 + next() * 20.0;
                let z = |r: f64| 60.0 + (r * 3.0).floor() * 9.144;
                [
                    t0,
                    t1,
                    next() * 200.0 - 100.0,
                    next() * 200.0 - 100.0,
                    z(next()),
                    next() * 200.0 - 100.0,
                    next() * 200.0 - 100.0,
                    z(next()),
                ]
            };
            let (r, s) = (p(), p());
            let a = piece(0, r[0], r[1], [r[2], r[3], r[4]], [r[5], r[6], r[7]]);
            let b = piece(1, s[0], s[1], [s[2], s[3], s[4]], [s[5], s[6], s[7]]);
            let exact = closest(&a, &b, f64::NEG_INFINITY, f64::INFINITY, 9.144).map(|c| c.0);
            let dense = sampled(&a, &b, 9.144);
            match (exact, dense) {
                (Some(e), Some(d)) => assert!(e <= d + 1e-9 && d - e < 0.2, "case {case}: {e} {d}"),
                // Sampling can miss a window narrower than its step.
                (None | Some(_), None) => {}
                (None, Some(d)) => panic!("case {case}: sampling finds {d}, exact none"),
            }
        }
    }
}
