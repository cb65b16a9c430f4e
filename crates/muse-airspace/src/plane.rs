//! The local metric plane an airspace is built in (docs/reference.md#airspace-from-pads): where the
//! Delaunay triangulation and the "join collinear nodes" angles are worked out.
//!
//! By default the UTM zone of the nodes' centroid (WGS84, north or south); `--crs` names
//! another by its EPSG code: 3414 (SVY21, Singapore's grid) or any WGS84 UTM zone (326zz,
//! 327zz). Before docs/reference.md#airspace-from-pads MUSE used an oblique stereographic
//! projection about the centroid, still available as [`Plane::Stereographic`].
//!
//! Whatever the plane, maps draw corridors and zones test them as straight lines in
//! longitude and latitude: [`check_extent`] keeps an airspace's nodes where that holds
//! (between 84° S and 84° N, within 60° of longitude, on one side of the ±180° meridian).
//!
//! ```
//! use muse_airspace::plane::Plane;
//! assert_eq!(Plane::parse("EPSG:3414").unwrap(), Plane::Epsg(3414));
//! assert_eq!(Plane::parse("utm").unwrap(), Plane::Utm);
//! assert_eq!(Plane::Epsg(32633).to_string(), "EPSG:32633");
//! assert!(Plane::parse("EPSG:4326").is_err());
//! ```

use std::fmt;

use muse_model::{LonLat, Node, SVY21_PROJ, WGS84_PROJ};
use proj4rs::proj::Proj;
use spade::Point2;

/// Mean Earth radius (IUGG), metres; the radius of the stereographic projection's sphere.
const EARTH_RADIUS_M: f64 = 6_371_008.8;

/// The furthest latitude, north or south, of an airspace's nodes ([`check_extent`]), degrees.
pub const MAX_LATITUDE_DEG: f64 = 84.0;

/// The widest span of longitude of an airspace's nodes ([`check_extent`]), degrees.
pub const MAX_LONGITUDE_SPAN_DEG: f64 = 60.0;

/// A local metric plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Plane {
    /// The WGS84 UTM zone of the nodes' centroid (zones of 6° from 180° W; north or south of
    /// the equator by the centroid's latitude; the Norway and Svalbard exceptions are not
    /// made).
    #[default]
    Utm,
    /// A coordinate reference system by its EPSG code: 3414 (SVY21) or a WGS84 UTM zone
    /// (32601–32660 north, 32701–32760 south).
    Epsg(u32),
    /// An oblique stereographic projection on a sphere of mean Earth radius, centred on the
    /// nodes' centroid: conformal, and the same wherever the nodes are.
    Stereographic,
}

/// Why a plane is refused, or a position cannot be projected onto it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlaneError {
    /// A name that is not a plane MUSE knows.
    #[error(
        "unknown CRS `{0}`: give `utm` (the UTM zone of the pads, the default), `EPSG:3414` \
         (SVY21), a WGS84 UTM zone as `EPSG:326zz` (north) or `EPSG:327zz` (south), or \
         `stereographic`"
    )]
    Unknown(String),
    /// The nodes do not fit in one hemisphere around their centroid.
    #[error("the nodes span more than a hemisphere; node `{0}` is 90° or more from their centroid")]
    TooSpread(String),
    /// A node beyond [`MAX_LATITUDE_DEG`] north or south.
    #[error(
        "node `{id}` is at latitude {lat}°: an airspace's nodes must lie between 84° S and 84° N \
         (nearer a pole, the straight lines in longitude and latitude that maps draw corridors \
         as, and zones test them by, stray far from the paths flown)"
    )]
    NearPole {
        /// The node's id.
        id: String,
        /// Its latitude.
        lat: f64,
    },
    /// Nodes on both sides of the ±180° meridian.
    #[error(
        "the nodes lie on both sides of the ±180° meridian (`{west}` at {west_lon}°, `{east}` \
         at {east_lon}°): maps draw corridors, and zones test them, as straight lines in \
         longitude and latitude, which cannot cross it; an airspace must lie on one side"
    )]
    AcrossAntimeridian {
        /// The node furthest west, by its longitude as written.
        west: String,
        /// Its longitude.
        west_lon: f64,
        /// The node furthest east.
        east: String,
        /// Its longitude.
        east_lon: f64,
    },
    /// Nodes spanning more than [`MAX_LONGITUDE_SPAN_DEG`] of longitude.
    #[error(
        "the nodes span {span}° of longitude (`{west}` at {west_lon}° to `{east}` at \
         {east_lon}°): they must lie within 60° (maps draw corridors, and zones test them, as \
         straight lines in longitude and latitude, far from the paths flown over such a width)"
    )]
    TooWide {
        /// The span, degrees.
        span: f64,
        /// The node furthest west.
        west: String,
        /// Its longitude.
        west_lon: f64,
        /// The node furthest east.
        east: String,
        /// Its longitude.
        east_lon: f64,
    },
    /// The projection library refused a position.
    #[error("node `{id}` at ({lon}, {lat}) cannot be projected to {plane}: {message}")]
    Projection {
        /// The node's id.
        id: String,
        /// Its longitude.
        lon: f64,
        /// Its latitude.
        lat: f64,
        /// The plane.
        plane: Plane,
        /// What the library said.
        message: String,
    },
}

impl Plane {
    /// The plane named `text`: `utm`, `stereographic`, or `EPSG:code` (case aside).
    ///
    /// # Errors
    /// A name or code MUSE does not know.
    pub fn parse(text: &str) -> Result<Plane, PlaneError> {
        let t = text.trim();
        let unknown = || PlaneError::Unknown(text.to_owned());
        match t.to_ascii_lowercase().as_str() {
            "utm" => return Ok(Plane::Utm),
            "stereographic" => return Ok(Plane::Stereographic),
            _ => {}
        }
        let code = t
            .get(..5)
            .filter(|p| p.eq_ignore_ascii_case("EPSG:"))
            .and_then(|_| t[5..].parse::<u32>().ok())
            .ok_or_else(unknown)?;
        let plane = Plane::Epsg(code);
        plane
            .proj_string(LonLat::new(0.0, 0.0))
            .ok_or_else(unknown)?;
        Ok(plane)
    }

    /// The proj string of this plane for nodes centred on `centre` (`None` for the
    /// stereographic plane and for an EPSG code MUSE does not know).
    fn proj_string(self, centre: LonLat) -> Option<String> {
        let utm = |zone: u32, south: bool| {
            format!(
                "+proj=utm +zone={zone}{} +ellps=WGS84 +datum=WGS84 +units=m +no_defs",
                if south { " +south" } else { "" }
            )
        };
        match self {
            Plane::Utm => {
                let zone = (((centre.lon + 180.0) / 6.0).floor() as i64).clamp(0, 59) + 1;
                Some(utm(u32::try_from(zone).ok()?, centre.lat < 0.0))
            }
            Plane::Epsg(3414) => Some(SVY21_PROJ.to_owned()),
            Plane::Epsg(code @ 32601..=32660) => Some(utm(code - 32600, false)),
            Plane::Epsg(code @ 32701..=32760) => Some(utm(code - 32700, true)),
            Plane::Epsg(_) | Plane::Stereographic => None,
        }
    }

    /// The positions of `nodes` in this plane, metres (x east, y north).
    ///
    /// # Errors
    /// Nodes beyond a hemisphere from their centroid, or a position the projection refuses.
    pub fn project(self, nodes: &[Node]) -> Result<Vec<Point2<f64>>, PlaneError> {
        let centre = centroid(nodes)?;
        let Some(proj) = self.proj_string(centre) else {
            return Ok(stereographic(nodes, centre));
        };
        let from = Proj::from_proj_string(WGS84_PROJ).expect("the WGS84 proj string is valid");
        let to = Proj::from_proj_string(&proj).expect("MUSE's proj strings are valid");
        nodes
            .iter()
            .map(|n| {
                let mut xy = (n.pos.lon.to_radians(), n.pos.lat.to_radians(), 0.0);
                proj4rs::transform::transform(&from, &to, &mut xy).map_err(|e| {
                    PlaneError::Projection {
                        id: n.id.clone(),
                        lon: n.pos.lon,
                        lat: n.pos.lat,
                        plane: self,
                        message: e.to_string(),
                    }
                })?;
                if xy.0.is_finite() && xy.1.is_finite() {
                    Ok(Point2::new(xy.0, xy.1))
                } else {
                    Err(PlaneError::Projection {
                        id: n.id.clone(),
                        lon: n.pos.lon,
                        lat: n.pos.lat,
                        plane: self,
                        message: "not a finite position".into(),
                    })
                }
            })
            .collect()
    }
}

impl fmt::Display for Plane {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Plane::Utm => f.write_str("utm"),
            Plane::Epsg(code) => write!(f, "EPSG:{code}"),
            Plane::Stereographic => f.write_str("stereographic"),
        }
    }
}

/// Checks that `nodes` lie where an airspace can be drawn and tested as MUSE does, corridors
/// and zones being straight lines in longitude and latitude: between [`MAX_LATITUDE_DEG`]
/// south and north (nearer a pole such lines stray far from the paths flown, and a pole may
/// lie inside the nodes' hull), within [`MAX_LONGITUDE_SPAN_DEG`] of longitude as written, and
/// so not on both sides of the ±180° meridian (a corridor across it would be drawn round the
/// world). Positions are assumed valid.
///
/// # Errors
/// The first node beyond the latitudes; nodes on both sides of ±180° (when they are nearer
/// across it than along it); nodes too far apart in longitude.
///
/// ```
/// use muse_airspace::plane::{PlaneError, check_extent};
/// use muse_model::{LonLat, Node, NodeKind};
/// let node = |id: &str, lon, lat| Node {
///     id: id.into(), kind: NodeKind::Station, name: String::new(), pos: LonLat::new(lon, lat),
/// };
/// assert!(check_extent(&[node("A", 16.37, 48.21), node("B", 16.40, 48.20)]).is_ok());
/// let fiji = [node("F1", 179.95, -17.0), node("F2", -179.95, -17.05)];
/// assert!(matches!(check_extent(&fiji), Err(PlaneError::AcrossAntimeridian { .. })));
/// assert!(matches!(check_extent(&[node("P", 0.0, 88.5)]), Err(PlaneError::NearPole { .. })));
/// ```
pub fn check_extent(nodes: &[Node]) -> Result<(), PlaneError> {
    if let Some(n) = nodes.iter().find(|n| n.pos.lat.abs() > MAX_LATITUDE_DEG) {
        return Err(PlaneError::NearPole {
            id: n.id.clone(),
            lat: n.pos.lat,
        });
    }
    let by_lon = |a: &&Node, b: &&Node| a.pos.lon.total_cmp(&b.pos.lon);
    let (Some(west), Some(east)) = (nodes.iter().min_by(by_lon), nodes.iter().max_by(by_lon))
    else {
        return Ok(());
    };
    let span = east.pos.lon - west.pos.lon;
    if span <= MAX_LONGITUDE_SPAN_DEG {
        return Ok(());
    }
    // Nearer across ±180° than along: the widest gap between neighbours in longitude is
    // inside the span, wider than the one across the meridian.
    let mut lons: Vec<f64> = nodes.iter().map(|n| n.pos.lon).collect();
    lons.sort_by(f64::total_cmp);
    let widest = lons.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    let (west, west_lon, east, east_lon) =
        (west.id.clone(), west.pos.lon, east.id.clone(), east.pos.lon);
    Err(if widest > 360.0 - span {
        PlaneError::AcrossAntimeridian {
            west,
            west_lon,
            east,
            east_lon,
        }
    } else {
        PlaneError::TooWide {
            span,
            west,
            west_lon,
            east,
            east_lon,
        }
    })
}

fn unit_vector(p: LonLat) -> [f64; 3] {
    let (lat, lon) = (p.lat.to_radians(), p.lon.to_radians());
    [lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()]
}

/// The nodes' centroid: the normalised mean of their unit vectors.
fn centroid(nodes: &[Node]) -> Result<LonLat, PlaneError> {
    let mut sum = [0.0_f64; 3];
    for n in nodes {
        let v = unit_vector(n.pos);
        for k in 0..3 {
            sum[k] += v[k];
        }
    }
    let norm = (sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]).sqrt();
    if nodes.is_empty() || norm < 1e-9 * nodes.len() as f64 {
        return Err(PlaneError::TooSpread(
            nodes.first().map_or_else(String::new, |n| n.id.clone()),
        ));
    }
    let lat = (sum[2] / norm).clamp(-1.0, 1.0).asin().to_degrees();
    let lon = sum[1].atan2(sum[0]).to_degrees();
    // Every node within a hemisphere of the centroid, whatever the plane.
    let c = unit_vector(LonLat::new(lon, lat));
    for n in nodes {
        let v = unit_vector(n.pos);
        if v[0] * c[0] + v[1] * c[1] + v[2] * c[2] <= 1e-9 {
            return Err(PlaneError::TooSpread(n.id.clone()));
        }
    }
    Ok(LonLat::new(lon, lat))
}

/// Oblique stereographic projection centred on `centre`, metres.
fn stereographic(nodes: &[Node], centre: LonLat) -> Vec<Point2<f64>> {
    let (lat0, lon0) = (centre.lat.to_radians(), centre.lon.to_radians());
    let (sin0, cos0) = lat0.sin_cos();
    nodes
        .iter()
        .map(|n| {
            let (lat, lon) = (n.pos.lat.to_radians(), n.pos.lon.to_radians());
            let (sin, cos) = lat.sin_cos();
            let (sin_dl, cos_dl) = (lon - lon0).sin_cos();
            // Cosine of the angular distance to the centre (positive: checked by `centroid`).
            let cos_c = sin0 * sin + cos0 * cos * cos_dl;
            let k = 2.0 * EARTH_RADIUS_M / (1.0 + cos_c);
            Point2::new(k * cos * sin_dl, k * (cos0 * sin - sin0 * cos * cos_dl))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use muse_model::NodeKind;

    fn node(id: &str, lon: f64, lat: f64) -> Node {
        Node {
            id: id.into(),
            kind: NodeKind::Station,
            name: String::new(),
            pos: LonLat::new(lon, lat),
        }
    }

    #[test]
    fn utm_picks_the_centroids_zone_and_hemisphere() {
        // Vienna, 16.4° E: zone 33 north; its central meridian is 15° E, false easting 500 km.
        let vienna = [node("A", 16.37, 48.21), node("B", 16.40, 48.20)];
        let p = Plane::Utm.project(&vienna).unwrap();
        let q = Plane::Epsg(32633).project(&vienna).unwrap();
        assert_eq!(p, q);
        assert!(p[0].x > 500_000.0 && p[0].x < 700_000.0, "{p:?}");
        assert!(p[0].y > 5_300_000.0 && p[0].y < 5_400_000.0, "{p:?}");
        // Sydney, 151.2° E, 33.9° S: zone 56 south (false northing 10,000 km).
        let sydney = [node("S", 151.21, -33.87), node("T", 151.25, -33.89)];
        let p = Plane::Utm.project(&sydney).unwrap();
        assert_eq!(p, Plane::Epsg(32756).project(&sydney).unwrap());
        assert!(p[0].y > 6_000_000.0 && p[0].y < 6_500_000.0, "{p:?}");
    }

    #[test]
    fn svy21_is_singapores_grid() {
        // The SVY21 origin (1°22′ N, 103°50′ E) is at 28,001.642 E, 38,744.572 N.
        let origin = [node("O", 103.0 + 50.0 / 60.0, 1.0 + 22.0 / 60.0)];
        let p = Plane::Epsg(3414).project(&origin).unwrap();
        assert!((p[0].x - 28_001.642).abs() < 1e-3 && (p[0].y - 38_744.572).abs() < 1e-3);
    }

    #[test]
    fn bad_names_and_spreads_are_refused() {
        for bad in [
            "EPSG:4326",
            "EPSG:32661",
            "EPSG:",
            "epsg:abc",
            "lambert",
            "",
        ] {
            let e = Plane::parse(bad).unwrap_err().to_string();
            assert!(
                e.contains("unknown CRS") && e.contains("EPSG:3414"),
                "{bad}: {e}"
            );
        }
        assert_eq!(Plane::parse(" epsg:32633 ").unwrap(), Plane::Epsg(32633));
        let opposite = [node("N", 0.0, 0.0), node("S", 180.0, 0.0)];
        assert!(matches!(
            Plane::Utm.project(&opposite),
            Err(PlaneError::TooSpread(_))
        ));
    }
}
