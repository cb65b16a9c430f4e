//! The conflict geometry against brute force: dense sampling of both drones' positions.

#![allow(clippy::many_single_char_names)]

use super::*;

/// A small random generator (xorshift), seeded.
struct Draw(u64);

impl Draw {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A corridor traversal, a stay or a climb near the origin, at 10 m/s or so.
    fn motion(&mut self) -> Motion {
        let p = [
            self.unit() * 200.0 - 100.0,
            self.unit() * 200.0 - 100.0,
            60.0,
        ];
        match (self.unit() * 3.0) as u32 {
            0 => Motion::between(p, p, 1.0 + self.unit() * 30.0),
            1 => Motion::between(p, [p[0], p[1], 69.144], 1.829),
            _ => {
                let q = [
                    self.unit() * 200.0 - 100.0,
                    self.unit() * 200.0 - 100.0,
                    60.0,
                ];
                let length = (q[0] - p[0]).hypot(q[1] - p[1]);
                Motion::between(p, q, (length / 10.0).max(0.5))
            }
        }
    }
}

/// The least horizontal distance (within `vertical`) by sampling both motions' common time.
fn sampled(a: &Motion, b: &Motion, delta: f64, vertical: f64) -> Option<f64> {
    let (t0, t1) = (delta.max(0.0), a.duration.min(delta + b.duration));
    if t0 > t1 {
        return None;
    }
    let at = |m: &Motion, t: f64| {
        let f = if m.duration > 0.0 {
            t / m.duration
        } else {
            0.0
        };
        [0, 1, 2].map(|i| m.from[i] + (m.to[i] - m.from[i]) * f)
    };
    let mut best: Option<f64> = None;
    for k in 0..=4_000 {
        let t = t0 + (t1 - t0) * f64::from(k) / 4_000.0;
        let (p, q) = (at(a, t), at(b, t - delta));
        if (p[2] - q[2]).abs() < vertical {
            let d = (p[0] - q[0]).hypot(p[1] - q[1]);
            best = Some(best.map_or(d, |b: f64| b.min(d)));
        }
    }
    best
}

#[test]
fn approach_agrees_with_sampling() {
    let mut draw = Draw(0x39_2001);
    for case in 0..400 {
        let (a, b) = (draw.motion(), draw.motion());
        let delta = draw.unit() * (a.duration + b.duration) - b.duration;
        let exact = approach(&a, &b, delta, 9.144);
        match (exact, sampled(&a, &b, delta, 9.144)) {
            (Some(e), Some(s)) => assert!(e <= s + 1e-9 && s - e < 0.05, "case {case}: {e} {s}"),
            (None | Some(_), None) => {}
            (None, Some(s)) => panic!("case {case}: sampling finds {s}, exact none"),
        }
    }
}

#[test]
fn offsets_hold_every_conflicting_offset_and_no_other() {
    let mut draw = Draw(0x39_2002);
    let mut found = 0;
    for case in 0..300 {
        let (a, b) = (draw.motion(), draw.motion());
        let got = offsets(&a, &b, 30.0, 9.144);
        // Offsets on a fine grid: conflicting ones lie inside; ones well inside conflict.
        let steps = 600;
        for k in 0..=steps {
            let delta = -b.duration - 1.0
                + (a.duration + b.duration + 2.0) * f64::from(k) / f64::from(steps);
            let hit = approach(&a, &b, delta, 9.144).is_some_and(|d| d < 30.0);
            match got {
                Some((lo, hi)) => {
                    if hit {
                        assert!(
                            lo < delta && delta < hi,
                            "case {case}: {delta} outside ({lo}, {hi})"
                        );
                    } else {
                        assert!(
                            delta <= lo + 1e-6 || delta >= hi - 1e-6,
                            "case {case}: {delta} inside ({lo}, {hi}) but no conflict"
                        );
                    }
                }
                None => assert!(!hit, "case {case}: {delta} conflicts, offsets none"),
            }
        }
        found += usize::from(got.is_some());
    }
    assert!(
        found > 50,
        "only {found} conflicting pairs: the test checks too little"
    );
}

#[test]
fn a_departure_and_an_arrival_at_a_sharp_corner() {
    // Two corridors leaving the origin 6.6° apart, 1 km long, 120 s at 30 km/h: a departure
    // along one and an arrival along the other stay 30 m apart only if more than
    // 30 / (8.333 · sin 3.3°) = 62.5 s separate them at the node.
    let theta = 6.6_f64.to_radians();
    let out = Motion::between([0.0, 0.0, 60.0], [1000.0, 0.0, 60.0], 120.0);
    let back = Motion::between(
        [1000.0 * theta.cos(), 1000.0 * theta.sin(), 60.0],
        [0.0, 0.0, 60.0],
        120.0,
    );
    let (lo, hi) = offsets(&out, &back, 30.0, 9.144).unwrap();
    let v = 1000.0 / 120.0;
    let g = 30.0 / (v * (theta / 2.0).sin());
    // The arrival (at δ + 120) less than g after the departure (at 0) conflicts; an arrival
    // before the departure shares no instant with it on these two motions (the stay at the
    // node between is another movement).
    assert!((hi - (g - 120.0)).abs() < 1e-4, "{hi} {}", g - 120.0);
    assert!((lo + 120.0).abs() < 1e-6, "{lo}");
}

#[test]
fn a_stay_and_a_pass() {
    // A drone passing 20 m from a hovering one at 10 m/s: within 30 m for 2·√(30² − 20²)/10 s
    // around its closest point, reached 50 s after it starts.
    let pass = Motion::between([-500.0, 20.0, 60.0], [500.0, 20.0, 60.0], 100.0);
    let (lo, hi) = near_window([0.0, 0.0, 60.0], &pass, 30.0, 9.144).unwrap();
    let half = (30.0_f64 * 30.0 - 20.0 * 20.0).sqrt() / 10.0;
    assert!((lo - (50.0 - half)).abs() < 1e-9 && (hi - (50.0 + half)).abs() < 1e-9);
    // A layer up: never.
    assert_eq!(near_window([0.0, 0.0, 69.144], &pass, 30.0, 9.144), None);
}
