//! Plane geometry for the volumes, in the local metric frame ([`LocalFrame`]) around the
//! airspace: points back to rounded degrees, and the outline of a corridor buffered by a
//! distance.

use muse_model::LocalFrame;

use super::model::LatLngPoint;

/// Vertices of each rounded end of a corridor outline (16 in all).
pub const CAP_VERTICES: usize = 8;

/// Degrees are written to 9 decimals (about 0.1 mm): enough for the 1 cm the standard
/// resolves, and short, reproducible numbers.
const DEGREE_SCALE: f64 = 1e9;

/// The point `x` metres east and `y` north of the origin of `frame`, its degrees rounded to 9
/// decimals.
pub fn to_lat_lng(frame: &LocalFrame, xy: (f64, f64)) -> LatLngPoint {
    let p = frame.to_lon_lat(xy);
    LatLngPoint {
        lat: round_degrees(p.lat),
        lng: round_degrees(p.lon),
    }
}

/// `degrees` rounded to 9 decimals.
pub fn round_degrees(degrees: f64) -> f64 {
    (degrees * DEGREE_SCALE).round() / DEGREE_SCALE
}

/// The outline of the segment `a`–`b` buffered by `r` (all metres in one frame): the set of
/// points within `r` of the segment (a stadium), as a polygon that contains it. Its straight
/// sides are the stadium's, at `r` from the segment; each rounded end is replaced by
/// [`CAP_VERTICES`] vertices on lines tangent to the half circle, so the polygon reaches `r`
/// beyond each end along the segment's axis and at most `r / cos(90° / CAP_VERTICES)`
/// (+2 %) elsewhere. Vertices run clockwise, none repeated. `None` when `a` and `b`
/// coincide (the outline is then a circle) or `r` is not positive.
pub fn corridor_outline(a: (f64, f64), b: (f64, f64), r: f64) -> Option<Vec<(f64, f64)>> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let length = dx.hypot(dy);
    if length <= 0.0 || r.is_nan() || r <= 0.0 {
        return None;
    }
    let d = (dx / length, dy / length);
    let left = (-d.1, d.0);
    let half_step = std::f64::consts::FRAC_PI_2 / CAP_VERTICES as f64;
    let reach = r / half_step.cos();
    let mut vertices = Vec::with_capacity(2 * CAP_VERTICES);
    // The end at `b` faces `d`, the end at `a` faces `−d`; each cap sweeps from its left
    // side, through its axis, to its right side.
    for (end, u, n) in [(b, d, left), (a, (-d.0, -d.1), (-left.0, -left.1))] {
        for k in 0..CAP_VERTICES {
            let alpha = std::f64::consts::FRAC_PI_2 - (2 * k + 1) as f64 * half_step;
            let (sin, cos) = alpha.sin_cos();
            vertices.push((
                end.0 + reach * (cos * u.0 + sin * n.0),
                end.1 + reach * (cos * u.1 + sin * n.1),
            ));
        }
    }
    Some(vertices)
}

#[cfg(test)]
mod tests {
    use muse_model::LonLat;

    use super::*;

    /// Distance from `p` to the segment `a`–`b`.
    fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
    }

    #[test]
    fn the_outline_lies_between_the_buffer_and_two_percent_beyond() {
        let (start, end, r) = ((0.0, 0.0), (300.0, 400.0), 10.0);
        let outline = corridor_outline(start, end, r).unwrap();
        assert_eq!(outline.len(), 16);
        let reach = r / (std::f64::consts::PI / 16.0).cos();
        for &v in &outline {
            let d = to_segment(v, start, end);
            assert!(d > r && (d - reach).abs() < 1e-9, "{v:?} at {d}");
        }
        // The edges between the vertices come no nearer than r: the midpoint of every
        // edge is at least r from the segment (tangent points are exactly at r).
        for i in 0..outline.len() {
            let (this, next) = (outline[i], outline[(i + 1) % outline.len()]);
            let mid = (f64::midpoint(this.0, next.0), f64::midpoint(this.1, next.1));
            assert!(to_segment(mid, start, end) >= r - 1e-9);
        }
        // Beyond `b` along the axis, the outline reaches exactly r: the edge between the
        // two middle vertices of the cap is tangent there.
        let (left, right) = (outline[3], outline[4]);
        let tip = (
            f64::midpoint(left.0, right.0),
            f64::midpoint(left.1, right.1),
        );
        assert!((tip.0 - 306.0).abs() < 1e-9 && (tip.1 - 408.0).abs() < 1e-9);
    }

    #[test]
    fn the_outline_runs_clockwise() {
        let outline = corridor_outline((0.0, 0.0), (100.0, 0.0), 5.0).unwrap();
        let twice_area: f64 = (0..outline.len())
            .map(|i| {
                let (p, q) = (outline[i], outline[(i + 1) % outline.len()]);
                p.0 * q.1 - q.0 * p.1
            })
            .sum();
        assert!(twice_area < 0.0);
        // Its area is the stadium's, a little more.
        let stadium = 100.0 * 10.0 + std::f64::consts::PI * 25.0;
        assert!(-twice_area / 2.0 > stadium && -twice_area / 2.0 < stadium * 1.02);
    }

    #[test]
    fn no_outline_for_a_point_or_no_buffer() {
        assert_eq!(corridor_outline((1.0, 2.0), (1.0, 2.0), 5.0), None);
        assert_eq!(corridor_outline((0.0, 0.0), (1.0, 0.0), 0.0), None);
        assert_eq!(corridor_outline((0.0, 0.0), (1.0, 0.0), f64::NAN), None);
    }

    #[test]
    fn the_frame_round_trips_and_matches_the_geodesic() {
        let frame = LocalFrame::around([LonLat::new(103.6, 1.2), LonLat::new(104.0, 1.5)]);
        let p = LonLat::new(103.93, 1.41);
        let back = to_lat_lng(&frame, frame.to_xy(p));
        assert!((back.lat - p.lat).abs() < 1e-9 && (back.lng - p.lon).abs() < 1e-9);
        let q = LonLat::new(103.95, 1.43);
        let (a, b) = (frame.to_xy(p), frame.to_xy(q));
        let plane = (b.0 - a.0).hypot(b.1 - a.1);
        let geodesic = p.geodesic_distance_m(q);
        assert!(
            (plane - geodesic).abs() / geodesic < 1e-4,
            "{plane} vs {geodesic}"
        );
    }
}
