//! Which pairs of operational intents intersect in 4-D: some volume of one and some volume of
//! the other share a point of space at a shared instant.
//!
//! Two volumes intersect when all three hold:
//!
//! - **time**: their windows, taken half-open `[time_start, time_end)`, overlap:
//!   `s1 < e2 && s2 < e1`. A volume that ends at the instant another begins does not meet it:
//!   that is docs/reference.md#flight-model-and-separation's exclusive edge rule, which lets a
//!   drone enter a corridor at the very millisecond the previous one leaves it (`s2 >= f1`), and
//!   docs/reference.md#no-fly-zones's zone windows `[start, end)`. Closed windows would count every
//!   such back-to-back pair, which MUSE separates by construction, as a conflict.
//! - **altitude**: their bands, closed, overlap: `lo1 <= hi2 && lo2 <= hi1`.
//! - **space**: their outlines, closed, share a point (touching counts): circles whose centres
//!   are at most `r1 + r2` apart, a circle whose centre is at most `r` from a polygon
//!   (0 inside), or polygons that intersect. Outlines are compared in one local metric frame
//!   ([`LocalFrame`]) around all the volumes.
//!
//! Volumes are swept in order of start time, each compared only with those still open, so a
//! day of thousands of flights takes a fraction of a second.

use std::collections::HashSet;

use geo::{Coord, Distance, Euclidean, Intersects, LineString, Point, Polygon};
use muse_model::{Instant, LocalFrame, LonLat};

use super::model::{OperationalIntent, Volume4D};

/// The result of [`intersecting_pairs`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pairs {
    /// Pairs of intents that intersect in 4-D.
    pub intersecting: u64,
    /// All pairs of intents: `n (n − 1) / 2`.
    pub pairs: u64,
    /// Intents.
    pub intents: usize,
    /// Volumes of all intents.
    pub volumes: usize,
}

/// Why intents cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntersectError {
    /// A time that is not RFC 3339.
    #[error("intent {intent}, volume {volume}: time `{text}` is not RFC 3339")]
    Time {
        /// Index of the intent.
        intent: usize,
        /// Index of the volume in it.
        volume: usize,
        /// The text.
        text: String,
    },
    /// A volume whose end is not after its start.
    #[error("intent {intent}, volume {volume}: it ends before it starts")]
    Backwards {
        /// Index of the intent.
        intent: usize,
        /// Index of the volume in it.
        volume: usize,
    },
    /// A volume without exactly one outline, or an outline of no area.
    #[error("intent {intent}, volume {volume}: {problem}")]
    Outline {
        /// Index of the intent.
        intent: usize,
        /// Index of the volume in it.
        volume: usize,
        /// What is wrong.
        problem: &'static str,
    },
}

/// An outline in the local frame.
#[derive(Clone, Debug)]
enum Shape {
    Circle { center: Point<f64>, radius: f64 },
    Polygon(Polygon<f64>),
}

/// A volume ready to compare.
#[derive(Clone, Debug)]
struct Slab {
    intent: u32,
    start: Instant,
    end: Instant,
    lower: f64,
    upper: f64,
    /// Bounding box: west, south, east, north.
    bbox: [f64; 4],
    shape: Shape,
}

/// Counts the pairs of `intents` whose volumes intersect in 4-D (see the module's rule).
///
/// ```
/// use muse_export::f3548::intersect::intersecting_pairs;
/// use muse_export::f3548::{Flight, Options, operational_intents};
/// use muse_model::{Airspace, Instant, NodeId, Plan, Stay};
/// let air = Airspace::line(&[1_000.0]); // A — B
/// let stay = |n, a, d| Stay { node: NodeId(n), arrive: Instant(a), depart: Instant(d) };
/// // A to B in 120 s; the next drone enters the corridor as the first leaves it.
/// let first = Plan { path: vec![stay(0, 0, 0), stay(1, 120_000, 120_000)] };
/// let second = Plan { path: vec![stay(0, 120_000, 120_000), stay(1, 240_000, 240_000)] };
/// let flights = [Flight { request: "a", plan: &first }, Flight { request: "b", plan: &second }];
/// let entries = operational_intents(&air, &flights, &Options::default()).unwrap();
/// let intents: Vec<_> = entries.into_iter().map(|e| e.operational_intent).collect();
/// let pairs = intersecting_pairs(&intents).unwrap();
/// assert_eq!((pairs.intersecting, pairs.pairs, pairs.volumes), (0, 1, 2));
/// ```
///
/// # Errors
/// A volume whose times do not read or do not move forward, or whose outline is missing,
/// doubled or empty ([`IntersectError`]).
pub fn intersecting_pairs(intents: &[OperationalIntent]) -> Result<Pairs, IntersectError> {
    let frame = LocalFrame::around(intents.iter().flat_map(|oi| {
        oi.details.volumes.iter().flat_map(|v| {
            let circle = v.volume.outline_circle.iter().map(|c| c.center);
            let polygon = v.volume.outline_polygon.iter().flat_map(|p| &p.vertices);
            circle
                .chain(polygon.copied())
                .map(|p| LonLat::new(p.lng, p.lat))
        })
    }));
    let mut slabs = Vec::new();
    for (i, oi) in intents.iter().enumerate() {
        for (j, v) in oi.details.volumes.iter().enumerate() {
            slabs.push(slab(&frame, i, j, v)?);
        }
    }
    slabs.sort_by_key(|s| s.start);
    let mut open: Vec<usize> = Vec::new();
    let mut found: HashSet<(u32, u32)> = HashSet::new();
    for (k, s) in slabs.iter().enumerate() {
        open.retain(|&o| slabs[o].end > s.start);
        for &o in &open {
            let other = &slabs[o];
            if other.intent == s.intent {
                continue;
            }
            let pair = (other.intent.min(s.intent), other.intent.max(s.intent));
            if !found.contains(&pair) && meet(other, s) {
                found.insert(pair);
            }
        }
        open.push(k);
    }
    let n = intents.len() as u64;
    Ok(Pairs {
        intersecting: found.len() as u64,
        pairs: n * n.saturating_sub(1) / 2,
        intents: intents.len(),
        volumes: slabs.len(),
    })
}

/// Whether two volumes open at the same instant also share altitude and space.
fn meet(a: &Slab, b: &Slab) -> bool {
    if a.lower > b.upper || b.lower > a.upper {
        return false;
    }
    let [aw, a_s, ae, an] = a.bbox;
    let [bw, b_s, be, bn] = b.bbox;
    if aw > be || bw > ae || a_s > bn || b_s > an {
        return false;
    }
    match (&a.shape, &b.shape) {
        (
            Shape::Circle {
                center: c1,
                radius: r1,
            },
            Shape::Circle {
                center: c2,
                radius: r2,
            },
        ) => Euclidean.distance(*c1, *c2) <= r1 + r2,
        (Shape::Circle { center, radius }, Shape::Polygon(p))
        | (Shape::Polygon(p), Shape::Circle { center, radius }) => {
            Euclidean.distance(center, p) <= *radius
        }
        (Shape::Polygon(p), Shape::Polygon(q)) => p.intersects(q),
    }
}

/// Volume `volume` of intent `intent` in the frame.
fn slab(
    frame: &LocalFrame,
    intent: usize,
    volume: usize,
    v4: &Volume4D,
) -> Result<Slab, IntersectError> {
    let time = |text: &str| {
        Instant::parse_rfc3339(text).map_err(|_| IntersectError::Time {
            intent,
            volume,
            text: text.to_owned(),
        })
    };
    let (start, end) = (time(&v4.time_start.value)?, time(&v4.time_end.value)?);
    if end <= start {
        return Err(IntersectError::Backwards { intent, volume });
    }
    let outline = |problem| IntersectError::Outline {
        intent,
        volume,
        problem,
    };
    let xy = |p: &super::model::LatLngPoint| frame.to_xy(LonLat::new(p.lng, p.lat));
    let (shape, bbox) = match (&v4.volume.outline_circle, &v4.volume.outline_polygon) {
        (Some(c), None) => {
            let (east, north) = xy(&c.center);
            let radius = c.radius.value;
            if radius.is_nan() || radius <= 0.0 {
                return Err(outline("a circle's radius must be positive"));
            }
            let shape = Shape::Circle {
                center: Point::new(east, north),
                radius,
            };
            let bbox = [east - radius, north - radius, east + radius, north + radius];
            (shape, bbox)
        }
        (None, Some(polygon)) if polygon.vertices.len() >= 3 => {
            let ring: Vec<Coord<f64>> = polygon
                .vertices
                .iter()
                .map(|point| {
                    let (x, y) = xy(point);
                    Coord { x, y }
                })
                .collect();
            let fold = |f: fn(f64, f64) -> f64, pick: fn(&Coord<f64>) -> f64, init: f64| {
                ring.iter().map(pick).fold(init, f)
            };
            let bbox = [
                fold(f64::min, |c| c.x, f64::INFINITY),
                fold(f64::min, |c| c.y, f64::INFINITY),
                fold(f64::max, |c| c.x, f64::NEG_INFINITY),
                fold(f64::max, |c| c.y, f64::NEG_INFINITY),
            ];
            (
                Shape::Polygon(Polygon::new(LineString::new(ring), vec![])),
                bbox,
            )
        }
        (None, Some(_)) => return Err(outline("a polygon needs at least 3 vertices")),
        _ => return Err(outline("a volume needs exactly one outline")),
    };
    Ok(Slab {
        intent: u32::try_from(intent).unwrap_or(u32::MAX),
        start,
        end,
        lower: v4.volume.altitude_lower.value,
        upper: v4.volume.altitude_upper.value,
        bbox,
        shape,
    })
}

#[cfg(test)]
mod tests;
