//! Coordinates: WGS84 longitude/latitude and SVY21 (EPSG:3414) plane coordinates.
//!
//! SVY21 is the Singapore national grid: a transverse Mercator on the WGS84 ellipsoid with
//! origin 1°22′ N, 103°50′ E, scale factor 1, false easting 28 001.642 m and false northing
//! 38 744.572 m. Conversions go through `proj4rs`.

use std::sync::LazyLock;

use geo::{Distance, Geodesic, Point};
use proj4rs::proj::Proj;

/// A WGS84 position in degrees (GeoJSON order: longitude first).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LonLat {
    /// Longitude, degrees east.
    pub lon: f64,
    /// Latitude, degrees north.
    pub lat: f64,
}

/// A position on the SVY21 grid (EPSG:3414), metres.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Svy21 {
    /// Easting, metres.
    pub easting: f64,
    /// Northing, metres.
    pub northing: f64,
}

/// Errors from coordinate conversion.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CoordError {
    /// The projection library refused the point.
    #[error("cannot convert ({0}, {1}) between SVY21 and WGS84: {2}")]
    Projection(f64, f64, String),
    /// A coordinate is not a finite number or out of range.
    #[error("({0}, {1}) is not a valid coordinate")]
    Invalid(f64, f64),
}

/// The proj string of EPSG:3414, built from the parameters in `data/SOURCES.md`.
pub const SVY21_PROJ: &str = "+proj=tmerc +lat_0=1.36666666666666667 +lon_0=103.833333333333333 \
     +k=1 +x_0=28001.642 +y_0=38744.572 +ellps=WGS84 +units=m +no_defs +type=crs";

/// The proj string of WGS84 longitude and latitude (EPSG:4326).
pub const WGS84_PROJ: &str = "+proj=longlat +ellps=WGS84 +datum=WGS84 +no_defs";

struct Projections {
    svy21: Proj,
    wgs84: Proj,
}

static PROJECTIONS: LazyLock<Projections> = LazyLock::new(|| Projections {
    svy21: Proj::from_proj_string(SVY21_PROJ).expect("the SVY21 proj string is valid"),
    wgs84: Proj::from_proj_string(WGS84_PROJ).expect("the WGS84 proj string is valid"),
});

impl LonLat {
    /// A position from longitude and latitude in degrees.
    pub const fn new(lon: f64, lat: f64) -> Self {
        LonLat { lon, lat }
    }

    /// Whether both values are finite and within ±180° / ±90°.
    pub fn is_valid(self) -> bool {
        self.lon.is_finite()
            && self.lat.is_finite()
            && (-180.0..=180.0).contains(&self.lon)
            && (-90.0..=90.0).contains(&self.lat)
    }

    /// Converts to SVY21.
    ///
    /// ```
    /// use muse_model::LonLat;
    /// let o = LonLat::new(103.0 + 50.0 / 60.0, 1.0 + 22.0 / 60.0).to_svy21().unwrap();
    /// assert!((o.easting - 28_001.642).abs() < 1e-3 && (o.northing - 38_744.572).abs() < 1e-3);
    /// ```
    pub fn to_svy21(self) -> Result<Svy21, CoordError> {
        if !self.is_valid() {
            return Err(CoordError::Invalid(self.lon, self.lat));
        }
        let p = &*PROJECTIONS;
        let mut xy = (self.lon.to_radians(), self.lat.to_radians(), 0.0);
        proj4rs::transform::transform(&p.wgs84, &p.svy21, &mut xy)
            .map_err(|e| CoordError::Projection(self.lon, self.lat, e.to_string()))?;
        Ok(Svy21 {
            easting: xy.0,
            northing: xy.1,
        })
    }

    /// Geodesic distance on the WGS84 ellipsoid, metres.
    ///
    /// ```
    /// use muse_model::LonLat;
    /// let d = LonLat::new(103.8, 1.3).geodesic_distance_m(LonLat::new(103.8, 1.31));
    /// assert!((d - 1_105.8).abs() < 1.0);
    /// ```
    pub fn geodesic_distance_m(self, other: LonLat) -> f64 {
        Geodesic.distance(
            Point::new(self.lon, self.lat),
            Point::new(other.lon, other.lat),
        )
    }
}

impl Svy21 {
    /// A grid position from easting and northing in metres.
    pub const fn new(easting: f64, northing: f64) -> Self {
        Svy21 { easting, northing }
    }

    /// Converts to WGS84.
    ///
    /// ```
    /// use muse_model::Svy21;
    /// let p = Svy21::new(28_001.642, 38_744.572).to_wgs84().unwrap();
    /// assert!((p.lat - (1.0 + 22.0 / 60.0)).abs() < 1e-9);
    /// assert!((p.lon - (103.0 + 50.0 / 60.0)).abs() < 1e-9);
    /// ```
    pub fn to_wgs84(self) -> Result<LonLat, CoordError> {
        if !self.easting.is_finite() || !self.northing.is_finite() {
            return Err(CoordError::Invalid(self.easting, self.northing));
        }
        let p = &*PROJECTIONS;
        let mut xy = (self.easting, self.northing, 0.0);
        proj4rs::transform::transform(&p.svy21, &p.wgs84, &mut xy)
            .map_err(|e| CoordError::Projection(self.easting, self.northing, e.to_string()))?;
        Ok(LonLat {
            lon: xy.0.to_degrees(),
            lat: xy.1.to_degrees(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference points for EPSG:3414, computed independently with PROJ 9.5.1 through pyproj
    /// 3.7.2 (`Transformer.from_crs("EPSG:4326", "EPSG:3414", always_xy=True)`, which uses the
    /// EPSG database's definition, not ours): the SVY21 origin, the corners of the HDB data's
    /// extent, a car park (ACM), the island's centre and two points beyond the island.
    const REFERENCE: &[(f64, f64, f64, f64)] = &[
        // (lon, lat, easting, northing)
        (
            103.833_333_333_333_33,
            1.366_666_666_666_666_7,
            28_001.642_0,
            38_744.572_0,
        ),
        (103.685_4, 1.270_6, 11_537.782_3, 28_122.484_7),
        (103.988_5, 1.456_6, 45_269.193_4, 48_689.540_2),
        (103.885_06, 1.321, 33_758.308_8, 33_695.045_4),
        (103.819_8, 1.352_1, 26_495.534_9, 37_133.868_5),
        (103.6, 1.16, 2_032.309_5, 15_893.513_7),
        (104.09, 1.47, 56_564.400_4, 50_172.292_0),
    ];

    #[test]
    fn svy21_matches_epsg_3414_to_a_tenth_of_a_metre() {
        for &(lon, lat, e, n) in REFERENCE {
            let grid = LonLat::new(lon, lat).to_svy21().unwrap();
            let dist = (grid.easting - e).hypot(grid.northing - n);
            assert!(dist < 0.1, "forward ({lon}, {lat}) off by {dist} m");
            let back = Svy21::new(e, n).to_wgs84().unwrap();
            let err_m = back.geodesic_distance_m(LonLat::new(lon, lat));
            assert!(err_m < 0.1, "inverse ({e}, {n}) off by {err_m} m");
        }
    }

    #[test]
    fn rejects_invalid_points() {
        assert!(LonLat::new(f64::NAN, 1.0).to_svy21().is_err());
        assert!(LonLat::new(200.0, 1.0).to_svy21().is_err());
        assert!(Svy21::new(f64::INFINITY, 0.0).to_wgs84().is_err());
    }
}
