//! Screen geometry: the map projection, polygon rings in pixels, and greedy label placement.

// Screen geometry reads best with x, y, w, h, r.
#![allow(clippy::many_single_char_names)]

use geo::Simplify;
use geo_types::{Coord, LineString, Polygon};
use muse_model::MetresPer;

/// Equirectangular projection with the longitude axis scaled by the ratio of metres per
/// degree at the mean latitude (≈ cos φ), so that distances look right on a small map. The
/// metres per degree are [`MetresPer::degree_by_series`], the maps' approximation.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Projection {
    /// West edge of the extent, degrees.
    pub lon0: f64,
    /// North edge of the extent, degrees.
    pub lat1: f64,
    /// Pixels per degree of longitude.
    pub kx: f64,
    /// Pixels per degree of latitude.
    pub ky: f64,
    /// Pixel x of `lon0`.
    pub x0: f64,
    /// Pixel y of `lat1`.
    pub y0: f64,
    /// Pixels per kilometre (both axes).
    pub px_per_km: f64,
}

/// A lon/lat box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Extent {
    pub lon0: f64,
    pub lon1: f64,
    pub lat0: f64,
    pub lat1: f64,
}

impl Extent {
    /// The smallest box holding all `points` (`None` if there are none).
    pub fn of(points: impl IntoIterator<Item = (f64, f64)>) -> Option<Extent> {
        let mut e: Option<Extent> = None;
        for (lon, lat) in points {
            if !(lon.is_finite() && lat.is_finite()) {
                continue;
            }
            e = Some(match e {
                None => Extent {
                    lon0: lon,
                    lon1: lon,
                    lat0: lat,
                    lat1: lat,
                },
                Some(b) => Extent {
                    lon0: b.lon0.min(lon),
                    lon1: b.lon1.max(lon),
                    lat0: b.lat0.min(lat),
                    lat1: b.lat1.max(lat),
                },
            });
        }
        e
    }

    /// Grows the box by `frac` of its size on each side, and to at least `min_deg` wide and
    /// tall (so that a single point still gets a map around it).
    pub fn padded(self, frac: f64, min_deg: f64) -> Extent {
        let grow = |lo: f64, hi: f64| {
            let pad = ((hi - lo) * frac).max((min_deg - (hi - lo)) / 2.0).max(0.0);
            (lo - pad, hi + pad)
        };
        let (lon0, lon1) = grow(self.lon0, self.lon1);
        let (lat0, lat1) = grow(self.lat0, self.lat1);
        Extent {
            lon0,
            lon1,
            lat0: lat0.max(-89.9),
            lat1: lat1.min(89.9),
        }
    }

    /// Widens the box east–west, about its centre, until width over height is at least
    /// `min_aspect`, so that a tall, narrow airspace still gives a page-shaped map.
    pub fn with_min_aspect(self, min_aspect: f64) -> Extent {
        let aspect = self.aspect();
        if aspect >= min_aspect || !aspect.is_finite() || aspect <= 0.0 {
            return self;
        }
        let half = (self.lon1 - self.lon0) * min_aspect / aspect / 2.0;
        let mid = f64::midpoint(self.lon0, self.lon1);
        Extent {
            lon0: mid - half,
            lon1: mid + half,
            ..self
        }
    }

    /// Width over height once projected (metres over metres).
    pub fn aspect(self) -> f64 {
        let m = MetresPer::degree_by_series(self.mid_lat());
        ((self.lon1 - self.lon0) * m.lon) / ((self.lat1 - self.lat0) * m.lat)
    }

    pub fn mid_lat(self) -> f64 {
        f64::midpoint(self.lat0, self.lat1)
    }
}

impl Projection {
    /// Maps `extent` onto a box `width_px` wide whose top-left corner is at (`x0`, `y0`).
    pub fn fit(extent: Extent, x0: f64, y0: f64, width_px: f64) -> Projection {
        let m = MetresPer::degree_by_series(extent.mid_lat());
        let kx = width_px / (extent.lon1 - extent.lon0);
        let ky = kx * m.lat / m.lon;
        Projection {
            lon0: extent.lon0,
            lat1: extent.lat1,
            kx,
            ky,
            x0,
            y0,
            px_per_km: ky * 1_000.0 / m.lat,
        }
    }

    /// Pixel position of a lon/lat, unrounded.
    #[inline]
    pub fn xy(&self, lon: f64, lat: f64) -> (f64, f64) {
        (
            self.x0 + (lon - self.lon0) * self.kx,
            self.y0 + (self.lat1 - lat) * self.ky,
        )
    }

    /// Pixel position of a lon/lat, rounded to the pixel grid.
    #[inline]
    pub fn px(&self, lon: f64, lat: f64) -> (i32, i32) {
        let (x, y) = self.xy(lon, lat);
        (x.round() as i32, y.round() as i32)
    }

    /// A ring in pixels: projected, simplified to `tolerance_px`, rounded, with consecutive
    /// duplicates and the closing point removed.
    pub fn ring(&self, ring: &LineString<f64>, tolerance_px: f64) -> Vec<(i32, i32)> {
        let projected: LineString<f64> = ring
            .coords()
            .map(|c| {
                let (x, y) = self.xy(c.x, c.y);
                Coord { x, y }
            })
            .collect();
        let simplified = if tolerance_px > 0.0 {
            projected.simplify(tolerance_px)
        } else {
            projected
        };
        let mut out: Vec<(i32, i32)> = Vec::with_capacity(simplified.0.len());
        for c in simplified.coords() {
            let p = (c.x.round() as i32, c.y.round() as i32);
            if out.last() != Some(&p) {
                out.push(p);
            }
        }
        if out.len() > 1 && out.first() == out.last() {
            out.pop();
        }
        out
    }

    /// A polygon in pixels as one ring that a plain polygon fill draws with its holes empty:
    /// each hole is joined to the exterior by a zero-width bridge and wound the other way, so
    /// the winding number inside a hole is zero (holds for both SVG fill rules).
    pub fn keyhole(&self, polygon: &Polygon<f64>, tolerance_px: f64) -> Vec<(i32, i32)> {
        let exterior = self.ring(polygon.exterior(), tolerance_px);
        if exterior.len() < 3 {
            return Vec::new();
        }
        let ext_sign = signed_area2(&exterior).signum();
        let mut out = exterior.clone();
        let start = exterior[0];
        for hole in polygon.interiors() {
            let mut h = self.ring(hole, tolerance_px);
            if h.len() < 3 {
                continue;
            }
            if signed_area2(&h).signum() == ext_sign {
                h.reverse();
            }
            out.push(start);
            let first = h[0];
            out.extend(h);
            out.push(first);
        }
        if out.len() > exterior.len() {
            out.push(start);
        }
        out
    }
}

/// Twice the signed area of a pixel ring (shoelace formula, exact in integers).
fn signed_area2(ring: &[(i32, i32)]) -> i64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (x1, y1) = ring[i];
            let (x2, y2) = ring[(i + 1) % n];
            i64::from(x1) * i64::from(y2) - i64::from(x2) * i64::from(y1)
        })
        .sum()
}

/// An axis-aligned box in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    pub fn new(x0: f64, y0: f64, w: f64, h: f64) -> Rect {
        Rect {
            x0,
            y0,
            x1: x0 + w,
            y1: y0 + h,
        }
    }

    /// A square of half-size `r` around a point.
    pub fn around(x: f64, y: f64, r: f64) -> Rect {
        Rect {
            x0: x - r,
            y0: y - r,
            x1: x + r,
            y1: y + r,
        }
    }

    /// The box grown by `d` on every side.
    pub fn inflate(&self, d: f64) -> Rect {
        Rect {
            x0: self.x0 - d,
            y0: self.y0 - d,
            x1: self.x1 + d,
            y1: self.y1 + d,
        }
    }

    pub fn overlap_area(&self, o: &Rect) -> f64 {
        let w = self.x1.min(o.x1) - self.x0.max(o.x0);
        let h = self.y1.min(o.y1) - self.y0.max(o.y0);
        if w > 0.0 && h > 0.0 { w * h } else { 0.0 }
    }

    pub fn contains(&self, o: &Rect) -> bool {
        o.x0 >= self.x0 && o.x1 <= self.x1 && o.y0 >= self.y0 && o.y1 <= self.y1
    }

    /// Whether the segment `a`–`b` passes through the box (Liang–Barsky clipping).
    pub fn hits_segment(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let mut t0: f64 = 0.0;
        let mut t1: f64 = 1.0;
        for (p, q) in [
            (-dx, a.0 - self.x0),
            (dx, self.x1 - a.0),
            (-dy, a.1 - self.y0),
            (dy, self.y1 - a.1),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
                if t0 > t1 {
                    return false;
                }
            }
        }
        true
    }
}

/// Minimum gap between two labels, pixels.
const LABEL_GAP: f64 = 3.0;

/// Greedy label placement: each label takes the cheapest of its candidate boxes, where
/// overlapping earlier labels or node dots costs a lot and crossing an edge a little.
/// Deterministic: candidates are tried in the order given, ties keep the first.
pub(crate) struct LabelPlacer {
    frame: Rect,
    placed: Vec<Rect>,
    dots: Vec<Rect>,
    segments: Vec<((f64, f64), (f64, f64))>,
}

impl LabelPlacer {
    pub fn new(frame: Rect, dots: Vec<Rect>, segments: Vec<((f64, f64), (f64, f64))>) -> Self {
        LabelPlacer {
            frame,
            placed: Vec::new(),
            dots,
            segments,
        }
    }

    /// Reserves a box (a legend inset, a label placed by other means).
    pub fn reserve(&mut self, r: Rect) {
        self.placed.push(r);
    }

    /// The cost of putting a label at `r`; `own_dot` is the dot the label belongs to.
    fn cost(&self, r: &Rect, own_dot: Option<usize>) -> f64 {
        if !self.frame.contains(r) {
            return f64::INFINITY;
        }
        // Labels keep a small gap between them, so that neighbours do not read as one.
        let padded = r.inflate(LABEL_GAP);
        let labels: f64 = self.placed.iter().map(|p| p.overlap_area(&padded)).sum();
        let dots: f64 = self
            .dots
            .iter()
            .enumerate()
            .filter(|(i, _)| Some(*i) != own_dot)
            .map(|(_, d)| d.overlap_area(r))
            .sum();
        let crossings = self
            .segments
            .iter()
            .filter(|(a, b)| r.hits_segment(*a, *b))
            .count();
        100.0 * labels + 100.0 * dots + 40.0 * crossings as f64
    }

    /// Places one label at the cheapest candidate, reserves it, and returns its index
    /// (`None` if no candidate fits inside the frame).
    pub fn place(&mut self, candidates: &[Rect], own_dot: Option<usize>) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (i, r) in candidates.iter().enumerate() {
            // A small preference for earlier candidates keeps placements regular.
            let c = self.cost(r, own_dot) + i as f64;
            if c.is_finite() && best.is_none_or(|(_, bc)| c < bc) {
                best = Some((i, c));
            }
        }
        let (i, _) = best?;
        self.placed.push(candidates[i]);
        Some(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo_types::polygon;

    #[test]
    fn projection_keeps_distances_square() {
        let e = Extent {
            lon0: 103.6,
            lon1: 104.0,
            lat0: 1.2,
            lat1: 1.5,
        };
        let p = Projection::fit(e, 10.0, 20.0, 1_000.0);
        assert_eq!(p.px(103.6, 1.5), (10, 20));
        let (x, _) = p.xy(104.0, 1.5);
        assert!((x - 1_010.0).abs() < 1e-9);
        // 0.01° of latitude and of longitude near the equator are both ≈ 1.1 km.
        let (a, b) = (p.xy(103.8, 1.3), p.xy(103.81, 1.31));
        let (dx_km, dy_km) = ((b.0 - a.0) / p.px_per_km, (a.1 - b.1) / p.px_per_km);
        assert!((dx_km - 1.1132).abs() < 0.002, "{dx_km}");
        assert!((dy_km - 1.1058).abs() < 0.002, "{dy_km}");
    }

    #[test]
    fn keyhole_reverses_holes() {
        let e = Extent {
            lon0: 0.0,
            lon1: 10.0,
            lat0: 0.0,
            lat1: 10.0,
        };
        let p = Projection::fit(e, 0.0, 0.0, 100.0);
        let poly = polygon!(
            exterior: [(x: 0.0, y: 0.0), (x: 10.0, y: 0.0), (x: 10.0, y: 10.0), (x: 0.0, y: 10.0)],
            interiors: [[(x: 2.0, y: 2.0), (x: 4.0, y: 2.0), (x: 4.0, y: 4.0), (x: 2.0, y: 4.0)]],
        );
        let ring = p.keyhole(&poly, 0.0);
        // 4 exterior + bridge + 4 hole + closing hole point + bridge back.
        assert_eq!(ring.len(), 4 + 1 + 4 + 1 + 1);
        // Net area = outer − hole.
        let area = signed_area2(&ring).abs();
        let outer = signed_area2(&ring[..4]).abs();
        let hole = signed_area2(&ring[5..9]).abs();
        assert_eq!(area, outer - hole);
    }

    #[test]
    fn rect_segment_hits() {
        let r = Rect::new(0.0, 0.0, 10.0, 10.0);
        assert!(r.hits_segment((-5.0, 5.0), (15.0, 5.0)));
        assert!(r.hits_segment((5.0, 5.0), (6.0, 6.0)));
        assert!(!r.hits_segment((-5.0, -5.0), (-1.0, 20.0)));
        assert!(!r.hits_segment((11.0, 0.0), (20.0, 10.0)));
    }

    #[test]
    fn placer_avoids_overlaps() {
        let frame = Rect::new(0.0, 0.0, 100.0, 100.0);
        let mut placer = LabelPlacer::new(frame, vec![], vec![]);
        let a = Rect::new(10.0, 10.0, 20.0, 10.0);
        let b = Rect::new(40.0, 10.0, 20.0, 10.0);
        assert_eq!(placer.place(&[a, b], None), Some(0));
        assert_eq!(placer.place(&[a, b], None), Some(1));
        let outside = Rect::new(95.0, 10.0, 20.0, 10.0);
        assert_eq!(placer.place(&[outside], None), None);
    }
}
