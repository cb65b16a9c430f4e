//! Metres per degree at a latitude on the WGS84 ellipsoid, and the local metric frame built
//! on them: the plane tangent to the ellipsoid at an origin, in metres east and north.
//!
//! - [`MetresPer`]: metres per radian ([`MetresPer::radian`]: the meridional radius of
//!   curvature `M` and the radius of the parallel `N cos φ`) and per degree
//!   ([`MetresPer::degree`]) of latitude and of longitude at a latitude; and the usual series
//!   approximation of the same quantity ([`MetresPer::degree_by_series`]), which the maps are
//!   drawn with.
//! - [`LocalFrame`]: an origin and its metres per degree: points to metres east and north
//!   ([`LocalFrame::to_xy`], or [`LocalFrame::to_xy_wrapped`] with longitudes taken modulo
//!   360° around the origin) and back ([`LocalFrame::to_lon_lat`]). Over a city (tens of
//!   kilometres near one latitude) its distances are within a few parts in 10⁵ of the geodesic
//!   ones (muse-export's tests check it).
//!
//! The arithmetic is fixed, operation by operation (every airspace, zone closure, export and
//! map made with it depends on the last bit): per degree is per radian times `π/180`, a
//! longitude difference times metres per degree is metres east, metres east over metres per
//! degree is a longitude difference.

use std::f64::consts::PI;

use crate::LonLat;

/// WGS84 semi-major axis, metres.
const WGS84_A: f64 = 6_378_137.0;
/// WGS84 flattening.
const WGS84_F: f64 = 1.0 / 298.257_223_563;

/// Metres per unit of angle at a latitude on WGS84: along a meridian, per unit of latitude
/// (`lat`), and along the parallel, per unit of longitude (`lon`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetresPer {
    /// Metres per unit of latitude.
    pub lat: f64,
    /// Metres per unit of longitude.
    pub lon: f64,
}

impl MetresPer {
    /// Metres per radian at latitude `lat_deg` (degrees): the ellipsoid's meridional radius of
    /// curvature `M = a(1 − e²)/w³` and the radius of the parallel `N cos φ = a cos φ / w`,
    /// with `w = √(1 − e² sin² φ)`.
    ///
    /// ```
    /// use muse_model::MetresPer;
    /// let equator = MetresPer::radian(0.0);
    /// assert_eq!(equator.lon, 6_378_137.0);
    /// assert!((equator.lat - 6_335_439.3).abs() < 0.1);
    /// ```
    pub fn radian(lat_deg: f64) -> MetresPer {
        let e2 = WGS84_F * (2.0 - WGS84_F);
        let (sin, cos) = lat_deg.to_radians().sin_cos();
        let w = (1.0 - e2 * sin * sin).sqrt();
        MetresPer {
            lat: WGS84_A * (1.0 - e2) / (w * w * w),
            lon: WGS84_A / w * cos,
        }
    }

    /// Metres per degree at latitude `lat_deg`: [`MetresPer::radian`] times `π/180`.
    ///
    /// ```
    /// use muse_model::MetresPer;
    /// let singapore = MetresPer::degree(1.3);
    /// assert!((singapore.lat - 110_574.8).abs() < 0.1);
    /// assert!((singapore.lon - 111_291.0).abs() < 0.1);
    /// ```
    pub fn degree(lat_deg: f64) -> MetresPer {
        let per_radian = MetresPer::radian(lat_deg);
        let radians_per_degree = PI / 180.0;
        MetresPer {
            lat: per_radian.lat * radians_per_degree,
            lon: per_radian.lon * radians_per_degree,
        }
    }

    /// Metres per degree at latitude `lat_deg` by the usual series expansion in multiples of
    /// the latitude (`111,132.954 − 559.822 cos 2φ + 1.175 cos 4φ` along a meridian,
    /// `111,412.84 cos φ − 93.5 cos 3φ` along the parallel): a different approximation of
    /// [`MetresPer::degree`], within about a metre per degree of it. The maps are drawn with
    /// it (their pixels depend on its last bits).
    ///
    /// ```
    /// use muse_model::MetresPer;
    /// let (series, exact) = (MetresPer::degree_by_series(45.0), MetresPer::degree(45.0));
    /// assert!((series.lat - exact.lat).abs() < 1.0 && (series.lon - exact.lon).abs() < 1.0);
    /// ```
    pub fn degree_by_series(lat_deg: f64) -> MetresPer {
        let phi = lat_deg.to_radians();
        MetresPer {
            lat: 111_132.954 - 559.822 * (2.0 * phi).cos() + 1.175 * (4.0 * phi).cos(),
            lon: 111_412.84 * phi.cos() - 93.5 * (3.0 * phi).cos(),
        }
    }
}

/// A local east/north frame in metres around an origin: the plane tangent to the WGS84
/// ellipsoid there, longitudes and latitudes scaled by the [metres per
/// degree](MetresPer::degree) at the origin's latitude (an equirectangular plane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    origin: LonLat,
    per_degree: MetresPer,
}

impl LocalFrame {
    /// The frame whose origin is `origin`.
    ///
    /// ```
    /// use muse_model::{LocalFrame, LonLat};
    /// let frame = LocalFrame::at(LonLat::new(103.8, 1.3));
    /// let (x, y) = frame.to_xy(LonLat::new(103.81, 1.3));
    /// assert!((x - 1_112.9).abs() < 0.1 && y == 0.0);
    /// ```
    pub fn at(origin: LonLat) -> LocalFrame {
        LocalFrame {
            origin,
            per_degree: MetresPer::degree(origin.lat),
        }
    }

    /// The frame at the centre of the bounding box of `points` (at longitude and latitude 0
    /// when there are none).
    ///
    /// ```
    /// use muse_model::{LocalFrame, LonLat};
    /// let frame = LocalFrame::around([LonLat::new(103.5, 1.25), LonLat::new(104.0, 1.5)]);
    /// assert_eq!(frame.origin(), LonLat::new(103.75, 1.375));
    /// ```
    pub fn around(points: impl IntoIterator<Item = LonLat>) -> LocalFrame {
        let mut bounds: Option<(LonLat, LonLat)> = None;
        for p in points {
            let (lo, hi) = bounds.get_or_insert((p, p));
            *lo = LonLat::new(lo.lon.min(p.lon), lo.lat.min(p.lat));
            *hi = LonLat::new(hi.lon.max(p.lon), hi.lat.max(p.lat));
        }
        let (lo, hi) = bounds.unwrap_or_default();
        LocalFrame::at(LonLat::new(
            f64::midpoint(lo.lon, hi.lon),
            f64::midpoint(lo.lat, hi.lat),
        ))
    }

    /// The origin.
    pub fn origin(&self) -> LonLat {
        self.origin
    }

    /// Metres per degree of latitude and of longitude at the origin.
    ///
    /// ```
    /// use muse_model::{LocalFrame, LonLat, MetresPer};
    /// let frame = LocalFrame::at(LonLat::new(103.8, 1.3));
    /// assert_eq!(frame.metres_per_degree(), MetresPer::degree(1.3));
    /// ```
    pub fn metres_per_degree(&self) -> MetresPer {
        self.per_degree
    }

    /// East and north of the origin, metres.
    ///
    /// ```
    /// use muse_model::{LocalFrame, LonLat};
    /// let frame = LocalFrame::at(LonLat::new(103.8, 1.3));
    /// let (x, y) = frame.to_xy(LonLat::new(103.8, 1.31));
    /// assert!(x == 0.0 && (y - 1_105.7).abs() < 0.1);
    /// ```
    pub fn to_xy(&self, p: LonLat) -> (f64, f64) {
        (
            (p.lon - self.origin.lon) * self.per_degree.lon,
            (p.lat - self.origin.lat) * self.per_degree.lat,
        )
    }

    /// East and north of the origin, metres, the longitude difference taken modulo 360° into
    /// `[−180°, 180°)`: a point just across the antimeridian from the origin is just east or
    /// west of it. The difference is rounded to the precision of numbers near 540°, so it may
    /// differ from [`LocalFrame::to_xy`]'s in its last bits.
    ///
    /// ```
    /// use muse_model::{LocalFrame, LonLat};
    /// let frame = LocalFrame::at(LonLat::new(179.99, 0.0));
    /// let (x, _) = frame.to_xy_wrapped(LonLat::new(-179.99, 0.0));
    /// assert!((x - 2_226.4).abs() < 0.1);
    /// ```
    pub fn to_xy_wrapped(&self, p: LonLat) -> (f64, f64) {
        let dlon = (p.lon - self.origin.lon + 540.0).rem_euclid(360.0) - 180.0;
        (
            dlon * self.per_degree.lon,
            (p.lat - self.origin.lat) * self.per_degree.lat,
        )
    }

    /// The point `x` metres east and `y` north of the origin (the inverse of
    /// [`LocalFrame::to_xy`]).
    ///
    /// ```
    /// use muse_model::{LocalFrame, LonLat};
    /// let frame = LocalFrame::at(LonLat::new(103.8, 1.3));
    /// let p = frame.to_lon_lat((1_000.0, -500.0));
    /// let (x, y) = frame.to_xy(p);
    /// assert!((x - 1_000.0).abs() < 1e-9 && (y + 500.0).abs() < 1e-9);
    /// ```
    pub fn to_lon_lat(&self, (x, y): (f64, f64)) -> LonLat {
        LonLat::new(
            self.origin.lon + x / self.per_degree.lon,
            self.origin.lat + y / self.per_degree.lat,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapping_changes_nothing_near_the_origin_but_rounding() {
        let frame = LocalFrame::at(LonLat::new(103.8, 1.3));
        let p = LonLat::new(103.85, 1.32);
        let (plain, wrapped) = (frame.to_xy(p), frame.to_xy_wrapped(p));
        assert_eq!(plain.1.to_bits(), wrapped.1.to_bits());
        assert!((plain.0 - wrapped.0).abs() < 1e-6);
    }

    #[test]
    fn per_degree_is_per_radian_times_pi_over_180() {
        for lat in [-89.0, -45.0, 0.0, 1.35, 30.0, 60.0, 89.9] {
            let (r, d) = (MetresPer::radian(lat), MetresPer::degree(lat));
            assert_eq!(d.lat.to_bits(), (r.lat * (PI / 180.0)).to_bits());
            assert_eq!(d.lon.to_bits(), (r.lon * (PI / 180.0)).to_bits());
            assert!(d.lon > 0.0 && d.lat > 110_000.0);
        }
    }
}
