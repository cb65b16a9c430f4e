//! The requests CSV (docs/reference.md#requests): header `id,origin,destination,departure`,
//! optionally followed by `submitted`.
//!
//! - `departure` (the earliest take-off) is an RFC 3339 timestamp with an offset, or a bare
//!   local clock time `HH:MM[:SS[.mmm]]` on the scenario's date in the scenario's offset.
//! - `submitted` (optional column) is when the request reaches the planner: a booking made
//!   ahead of departure, in the same syntax. It may not be later than the departure. Without
//!   the column, or in a row whose `submitted` cell is empty, the request is submitted at its
//!   departure (the paper). Requests are planned in order of `(submitted, id)`.
//!
//! The header names exactly these columns: the four required ones and, optionally,
//! `submitted`. They may come in any order; a missing required column, a column named twice,
//! an unnamed column or any other column is an error on line 1 naming the column. Origin and
//! destination must be distinct stations of the airspace; ids must be unique and follow the
//! service's rule ([`muse_model::request::ID_RULE`]). Every error
//! names the file, the line (the header is line 1) and the field.
//!
//! [`write_requests`] writes the four required columns, and the `submitted` column only when
//! some request was submitted before its departure, so files without bookings ahead are
//! written exactly as before the column existed.
//!
//! **Demand from customers** (docs/reference.md#airspace-from-pads, `muse demand --customers`) adds
//! the columns `origin_customer` and `destination_customer` (both or neither): the ids of the
//! customers a request joins. With them a request may be **unserved**: an empty `origin` or
//! `destination` (no pad within the last mile of that customer), or the same pad for both (both
//! customers on one pad). [`read_demand`] returns such requests apart ([`Demand::unserved`]);
//! [`read_requests`] refuses them. [`write_demand`] writes such files.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use muse_model::request::{ID_RULE, PLANNED, PLANNED_RULE, valid_id};
use muse_model::time::{TimeError, parse_clock};
use muse_model::{Airspace, Instant, NodeId, Request, UtcOffset};

use crate::day::LocalDay;
use crate::error::{InputError, Location};
use crate::table::Table;

/// The required columns, in the order [`write_requests`] writes them.
const COLUMNS: [&str; 4] = ["id", "origin", "destination", "departure"];

/// The optional column: when the request reaches the planner.
const SUBMITTED: &str = "submitted";

/// The optional columns of demand from customers, both or neither.
const CUSTOMERS: [&str; 2] = ["origin_customer", "destination_customer"];

/// What the header must be, for messages.
const HEADER: &str = "id,origin,destination,departure, optionally followed by submitted, and \
                      by origin_customer,destination_customer";

/// The position of every column in a header: the required ones in [`COLUMNS`] order, then
/// `submitted` and the customers' if present.
struct Header {
    required: [usize; 4],
    submitted: Option<usize>,
    customers: Option<[usize; 2]>,
}

impl Header {
    /// Checks that the header names exactly the required columns and optionally `submitted`,
    /// each once, in any order.
    fn parse(headers: &csv::StringRecord, file: &str) -> Result<Header, InputError> {
        let at_header = |field: Option<&str>, message: String| {
            InputError::new(file, Location::Line(1), field, message)
        };
        let mut required = [None; 4];
        let mut submitted = None;
        let mut customers = [None; 2];
        for (i, name) in headers.iter().enumerate() {
            let slot = match COLUMNS.iter().position(|c| *c == name) {
                Some(k) => &mut required[k],
                None if name == SUBMITTED => &mut submitted,
                None if name == CUSTOMERS[0] => &mut customers[0],
                None if name == CUSTOMERS[1] => &mut customers[1],
                None if name.is_empty() => {
                    return Err(at_header(
                        None,
                        format!(
                            "column {} has no name (a stray comma?); the header must be {HEADER}",
                            i + 1
                        ),
                    ));
                }
                None => {
                    return Err(at_header(
                        Some(name),
                        format!("unknown column; the header must be {HEADER}"),
                    ));
                }
            };
            if let Some(first) = slot.replace(i) {
                return Err(at_header(
                    Some(name),
                    format!(
                        "the column is named twice (columns {} and {})",
                        first + 1,
                        i + 1
                    ),
                ));
            }
        }
        let mut cols = [0usize; 4];
        for ((slot, found), name) in cols.iter_mut().zip(required).zip(COLUMNS) {
            *slot = found.ok_or_else(|| {
                at_header(
                    Some(name),
                    format!("missing column (the header must be {HEADER})"),
                )
            })?;
        }
        let customers = match customers {
            [Some(o), Some(d)] => Some([o, d]),
            [None, None] => None,
            [o, _] => {
                let (given, missing) = if o.is_some() {
                    (CUSTOMERS[0], CUSTOMERS[1])
                } else {
                    (CUSTOMERS[1], CUSTOMERS[0])
                };
                return Err(at_header(
                    Some(missing),
                    format!("missing column: `{given}` is given, and the two come together"),
                ));
            }
        };
        Ok(Header {
            required: cols,
            submitted,
            customers,
        })
    }
}

/// Requests read from a file of demand from customers: those to plan, and those unserved.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Demand {
    /// The requests to plan, in file order.
    pub requests: Vec<Request>,
    /// The unserved requests (docs/reference.md#airspace-from-pads), in file order: never planned.
    pub unserved: Vec<UnservedRequest>,
    /// With the customer columns: every row, served or not, in file order (what
    /// [`write_demand`] writes back).
    pub rows: Option<Vec<DemandRow>>,
}

/// A request of demand from customers that no drone can fly (docs/reference.md#airspace-from-pads,
/// reason `unserved`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnservedRequest {
    /// Request id.
    pub id: String,
    /// The sender's pad, if one is in reach.
    pub origin: Option<NodeId>,
    /// The receiver's pad, if one is in reach (the same as `origin` when both customers share
    /// a pad).
    pub destination: Option<NodeId>,
    /// Requested departure.
    pub departure: Instant,
    /// When it was submitted.
    pub submitted: Instant,
}

/// Reads requests from CSV text, in file order; `file` names the source in error messages. A
/// file with no request (its header alone) is an error.
/// A file of demand from customers may hold unserved requests: they are refused here (see
/// [`read_demand`]).
///
/// ```
/// use muse_formats::{day::LocalDay, requests::read_requests};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}}]}"#, "a").unwrap();
/// let day = LocalDay { date: jiff::civil::date(2026, 1, 5), offset: muse_model::UtcOffset::SINGAPORE };
/// let csv = "id,origin,destination,departure,submitted\n\
///            r1,A,B,08:15,07:00\n\
///            r2,B,A,2026-01-05T08:20:00.000+08:00,\n";
/// let reqs = read_requests(csv, "r.csv", &air, day).unwrap();
/// assert_eq!(reqs[1].departure - reqs[0].departure, muse_model::Millis::from_mins(5));
/// assert_eq!(reqs[0].departure - reqs[0].submitted, muse_model::Millis::from_mins(75));
/// assert_eq!(reqs[1].submitted, reqs[1].departure); // an empty cell: at departure
/// ```
pub fn read_requests(
    text: &str,
    file: &str,
    airspace: &Airspace,
    day: LocalDay,
) -> Result<Vec<Request>, InputError> {
    Ok(read(text, file, airspace, day, false)?.requests)
}

/// Reads requests as [`read_requests`] does, and a file of demand from customers's unserved
/// requests apart.
///
/// ```
/// use muse_formats::{day::LocalDay, requests::read_demand};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}}]}"#, "a").unwrap();
/// let day = LocalDay { date: jiff::civil::date(2026, 1, 5), offset: muse_model::UtcOffset::SINGAPORE };
/// let csv = "id,origin,destination,departure,origin_customer,destination_customer\n\
///            r1,A,B,08:15,c1,c2\n\
///            r2,,B,08:20,c7,c2\n\
///            r3,A,A,08:25,c1,c3\n";
/// let demand = read_demand(csv, "r.csv", &air, day).unwrap();
/// assert_eq!(demand.requests.len(), 1);
/// let unserved: Vec<&str> = demand.unserved.iter().map(|u| u.id.as_str()).collect();
/// assert_eq!(unserved, ["r2", "r3"]);
/// ```
pub fn read_demand(
    text: &str,
    file: &str,
    airspace: &Airspace,
    day: LocalDay,
) -> Result<Demand, InputError> {
    read(text, file, airspace, day, true)
}

/// Reads a file of requests, unserved ones apart when `allow_unserved`, else refused.
fn read(
    text: &str,
    file: &str,
    airspace: &Airspace,
    day: LocalDay,
    allow_unserved: bool,
) -> Result<Demand, InputError> {
    let mut table = Table::new(text, file)?;
    let header = Header::parse(table.headers(), file)?;
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Demand::default();
    let mut rows = Vec::new();
    for row in table.rows() {
        let (record, line) = row?;
        let err = |field: &str, msg: String| {
            InputError::new(file, Location::Line(line), Some(field), msg)
        };
        let r = read_row(&record, &header, airspace, day).map_err(|(f, m)| err(f, m))?;
        if let Some(prev) = seen.insert(r.id.clone(), line) {
            return Err(err(
                "id",
                format!("duplicate request id `{}` (first on line {prev})", r.id),
            ));
        }
        match (r.origin, r.destination) {
            (Some(origin), Some(destination)) if origin != destination => {
                out.requests.push(Request {
                    id: r.id.clone(),
                    origin,
                    destination,
                    departure: r.departure,
                    submitted: r.submitted,
                });
            }
            (origin, _) if !allow_unserved => {
                return Err(err(
                    if origin.is_none() {
                        "origin"
                    } else {
                        "destination"
                    },
                    "an unserved request (demand from customers: no pad in reach, or both \
                     customers on one pad); `muse plan` and `muse simulate` count such \
                     requests apart"
                        .into(),
                ));
            }
            (origin, destination) => out.unserved.push(UnservedRequest {
                id: r.id.clone(),
                origin,
                destination,
                departure: r.departure,
                submitted: r.submitted,
            }),
        }
        rows.push(r);
    }
    if rows.is_empty() {
        return Err(InputError::new(
            file,
            Location::Whole,
            None,
            "no requests: the file has its header and no row; give at least one request",
        ));
    }
    out.rows = header.customers.map(|_| rows);
    Ok(out)
}

/// One row's cells, checked (duplicate ids aside); else the field to blame and why. Without
/// the customer columns the pads must be given and differ, and the customers are empty.
fn read_row(
    record: &csv::StringRecord,
    header: &Header,
    airspace: &Airspace,
    day: LocalDay,
) -> Result<DemandRow, (&'static str, String)> {
    let col = header.required;
    let get = |i: usize| record.get(col[i]).unwrap_or("");
    let id = get(0);
    if id.is_empty() {
        return Err(("id", "missing".into()));
    }
    if !valid_id(id) {
        return Err((
            "id",
            format!("{id:?} is not a valid id: an id is {ID_RULE} (the service's rule too)"),
        ));
    }
    let mut customers = [String::new(), String::new()];
    if let Some(cols) = header.customers {
        for ((c, name), slot) in cols.iter().zip(CUSTOMERS).zip(&mut customers) {
            let cell = record.get(*c).unwrap_or("");
            if cell.is_empty() {
                return Err((name, "missing".into()));
            }
            if !valid_id(cell) {
                return Err((
                    name,
                    format!("{cell:?} is not a valid customer id: an id is {ID_RULE}"),
                ));
            }
            cell.clone_into(slot);
        }
    }
    // With customers, an empty pad cell is a customer with no pad in reach.
    let may_lack_pad = header.customers.is_some();
    let station = |i: usize| -> Result<Option<NodeId>, (&'static str, String)> {
        let name = get(i);
        if name.is_empty() {
            return if may_lack_pad {
                Ok(None)
            } else {
                Err((COLUMNS[i], "missing".into()))
            };
        }
        let n = airspace
            .node_id(name)
            .ok_or_else(|| (COLUMNS[i], format!("unknown node id `{name}`")))?;
        if !airspace.is_station(n) {
            return Err((COLUMNS[i], format!("`{name}` is a waypoint, not a station")));
        }
        Ok(Some(n))
    };
    let origin = station(1)?;
    let destination = station(2)?;
    if origin == destination && !may_lack_pad {
        return Err((
            "destination",
            format!("origin and destination are both `{}`", get(1)),
        ));
    }
    let departure = parse_planned(get(3), day).map_err(|m| ("departure", m))?;
    let submitted = match header.submitted.and_then(|i| record.get(i)) {
        None | Some("") => departure,
        Some(text) => {
            let submitted = parse_planned(text, day).map_err(|m| (SUBMITTED, m))?;
            if submitted > departure {
                return Err((
                    SUBMITTED,
                    format!(
                        "`{text}` is later than the departure `{}`; a request is submitted at \
                         or before its departure",
                        get(3)
                    ),
                ));
            }
            submitted
        }
    };
    Ok(DemandRow {
        id: id.to_owned(),
        origin,
        destination,
        departure,
        submitted,
        customers,
    })
}

/// Reads a requests CSV file.
pub fn read_requests_file(
    path: &Path,
    airspace: &Airspace,
    day: LocalDay,
) -> Result<Vec<Request>, InputError> {
    read_requests(
        &crate::read_to_string(path)?,
        &path.display().to_string(),
        airspace,
        day,
    )
}

/// Reads a requests CSV file, a file of demand from customers's unserved requests apart.
pub fn read_demand_file(
    path: &Path,
    airspace: &Airspace,
    day: LocalDay,
) -> Result<Demand, InputError> {
    read_demand(
        &crate::read_to_string(path)?,
        &path.display().to_string(),
        airspace,
        day,
    )
}

/// Writes requests as CSV with RFC 3339 times in `offset`: the columns
/// `id,origin,destination,departure`, and `submitted` after them only when some request was
/// submitted before its departure (then every row gives its submission instant).
///
/// ```
/// use muse_model::{Instant, NodeId, Request, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}}]}"#, "a").unwrap();
/// let mut r = Request { id: "r1".into(), origin: NodeId(0), destination: NodeId(1), departure: Instant(0), submitted: Instant(0) };
/// let csv = muse_formats::requests::write_requests(std::slice::from_ref(&r), &air, UtcOffset::SINGAPORE);
/// assert_eq!(csv, "id,origin,destination,departure\nr1,A,B,1970-01-01T08:00:00.000+08:00\n");
/// r.submitted = Instant(-60_000);
/// let csv = muse_formats::requests::write_requests(&[r], &air, UtcOffset::SINGAPORE);
/// assert_eq!(csv, "id,origin,destination,departure,submitted\n\
///                  r1,A,B,1970-01-01T08:00:00.000+08:00,1970-01-01T07:59:00.000+08:00\n");
/// ```
pub fn write_requests(requests: &[Request], airspace: &Airspace, offset: UtcOffset) -> String {
    let with_submitted = requests.iter().any(|r| r.submitted != r.departure);
    let mut out = COLUMNS.join(",");
    if with_submitted {
        let _ = write!(out, ",{SUBMITTED}");
    }
    out.push('\n');
    for r in requests {
        let _ = write!(
            out,
            "{},{},{},{}",
            csv_field(&r.id),
            csv_field(&airspace.node(r.origin).id),
            csv_field(&airspace.node(r.destination).id),
            r.departure.to_rfc3339(offset)
        );
        if with_submitted {
            let _ = write!(out, ",{}", r.submitted.to_rfc3339(offset));
        }
        out.push('\n');
    }
    out
}

/// One row of a file of demand from customers: a request between two customers, with each
/// customer's pad if one is in reach ([`write_demand`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DemandRow {
    /// Request id.
    pub id: String,
    /// The sender's pad, if any.
    pub origin: Option<NodeId>,
    /// The receiver's pad, if any.
    pub destination: Option<NodeId>,
    /// Requested departure.
    pub departure: Instant,
    /// When it is submitted.
    pub submitted: Instant,
    /// The sender's and the receiver's customer ids.
    pub customers: [String; 2],
}

/// Writes a file of demand from customers: as [`write_requests`], followed by the columns
/// `origin_customer,destination_customer`; a pad cell is empty when no pad is in reach.
///
/// ```
/// use muse_formats::requests::{write_demand, DemandRow};
/// use muse_model::{Instant, NodeId, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}}]}"#, "a").unwrap();
/// let row = DemandRow {
///     id: "r1".into(), origin: None, destination: Some(NodeId(1)), departure: Instant(0),
///     submitted: Instant(0), customers: ["c7".into(), "c2".into()],
/// };
/// assert_eq!(
///     write_demand(&[row], &air, UtcOffset::SINGAPORE),
///     "id,origin,destination,departure,origin_customer,destination_customer\n\
///      r1,,B,1970-01-01T08:00:00.000+08:00,c7,c2\n"
/// );
/// ```
pub fn write_demand(rows: &[DemandRow], airspace: &Airspace, offset: UtcOffset) -> String {
    let with_submitted = rows.iter().any(|r| r.submitted != r.departure);
    let mut out = COLUMNS.join(",");
    if with_submitted {
        let _ = write!(out, ",{SUBMITTED}");
    }
    let _ = writeln!(out, ",{}", CUSTOMERS.join(","));
    let pad = |n: Option<NodeId>| n.map_or_else(String::new, |n| csv_field(&airspace.node(n).id));
    for r in rows {
        let _ = write!(
            out,
            "{},{},{},{}",
            csv_field(&r.id),
            pad(r.origin),
            pad(r.destination),
            r.departure.to_rfc3339(offset)
        );
        if with_submitted {
            let _ = write!(out, ",{}", r.submitted.to_rfc3339(offset));
        }
        let _ = writeln!(
            out,
            ",{},{}",
            csv_field(&r.customers[0]),
            csv_field(&r.customers[1])
        );
    }
    out
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) || s.trim() != s {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// A `departure` or `submitted` cell ([`parse_time`]) that MUSE plans: an instant outside
/// [`PLANNED`] is refused, the time named as written.
fn parse_planned(text: &str, day: LocalDay) -> Result<Instant, String> {
    let t = parse_time(text, day)?;
    if PLANNED.contains(&t) {
        Ok(t)
    } else {
        Err(format!(
            "`{text}` is outside the years MUSE plans: {PLANNED_RULE}"
        ))
    }
}

/// A `departure` or `submitted` cell: RFC 3339 with an offset, or a local clock time of `day`.
fn parse_time(text: &str, day: LocalDay) -> Result<Instant, String> {
    if text.is_empty() {
        return Err("missing".into());
    }
    if text.contains('T') || text.contains('t') || text.contains('-') && text.len() > 10 {
        return Instant::parse_rfc3339(text).map_err(|e| e.to_string());
    }
    let tod = parse_clock(text).map_err(|e| match e {
        TimeError::LeapSecond(_) => e.to_string(),
        _ => format!(
            "`{text}` is neither an RFC 3339 timestamp with offset nor a local time HH:MM[:SS]"
        ),
    })?;
    Ok(Instant::at_local(day.date, tod, day.offset))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airspace_geojson::read_airspace;

    fn air() -> Airspace {
        let p = |id: &str, kind: &str, lon: f64| {
            format!(
                r#"{{"type": "Feature", "geometry": {{"type": "Point", "coordinates": [{lon}, 1.3]}}, "properties": {{"id": "{id}", "kind": "{kind}"}}}}"#
            )
        };
        read_airspace(
            &format!(
                r#"{{"type": "FeatureCollection", "features": [{}, {}, {}]}}"#,
                p("A", "station", 103.8),
                p("B", "station", 103.81),
                p("W", "waypoint", 103.82)
            ),
            "a",
        )
        .unwrap()
    }

    const DAY: LocalDay = LocalDay {
        date: jiff::civil::date(2026, 1, 5),
        offset: UtcOffset::SINGAPORE,
    };

    fn err(body: &str) -> String {
        read_requests(
            &format!("id,origin,destination,departure\n{body}"),
            "r.csv",
            &air(),
            DAY,
        )
        .unwrap_err()
        .to_string()
    }

    #[test]
    fn local_and_rfc3339_departures_agree() {
        let reqs = read_requests(
            "departure,destination,origin,id\n08:15:00,B,A,r1\n2026-01-05T00:15:00Z,A,B,r2\n",
            "r.csv",
            &air(),
            DAY,
        )
        .unwrap();
        assert_eq!(reqs[0].departure, reqs[1].departure);
        assert_eq!(
            reqs[0].departure.to_rfc3339(UtcOffset::SINGAPORE),
            "2026-01-05T08:15:00.000+08:00"
        );
        assert!(reqs.iter().all(|r| r.submitted == r.departure));
        let text = write_requests(&reqs, &air(), UtcOffset::SINGAPORE);
        assert!(
            text.starts_with("id,origin,destination,departure\n"),
            "{text}"
        );
        assert_eq!(read_requests(&text, "w.csv", &air(), DAY).unwrap(), reqs);
    }

    fn read(text: &str) -> Result<Vec<Request>, String> {
        read_requests(text, "r.csv", &air(), DAY).map_err(|e| e.to_string())
    }

    #[test]
    fn submitted_column_local_rfc3339_empty_and_any_order() {
        let reqs = read(
            "id,origin,destination,departure,submitted\n\
             r1,A,B,08:15,07:45:30\n\
             r2,B,A,08:15,2026-01-04T23:00:00Z\n\
             r3,A,B,08:15,\n\
             r4,A,B,08:15,08:15\n",
        )
        .unwrap();
        let dep = reqs[0].departure;
        let lead: Vec<i64> = reqs.iter().map(|r| (dep - r.submitted).0).collect();
        assert_eq!(lead, [1_770_000, 4_500_000, 0, 0]);
        assert!(reqs.iter().all(|r| r.departure == dep));
        // Columns in any order, `submitted` included.
        let moved =
            read("submitted,departure,id,destination,origin\n07:45:30,08:15,r1,B,A\n").unwrap();
        assert_eq!(moved[0], reqs[0]);
    }

    #[test]
    fn writes_submitted_only_when_some_request_is_booked_ahead() {
        let reqs =
            read("id,origin,destination,departure,submitted\nr1,A,B,08:15,07:00\nr2,B,A,09:00,\n")
                .unwrap();
        let text = write_requests(&reqs, &air(), UtcOffset::SINGAPORE);
        assert_eq!(
            text,
            "id,origin,destination,departure,submitted\n\
             r1,A,B,2026-01-05T08:15:00.000+08:00,2026-01-05T07:00:00.000+08:00\n\
             r2,B,A,2026-01-05T09:00:00.000+08:00,2026-01-05T09:00:00.000+08:00\n"
        );
        assert_eq!(read(&text).unwrap(), reqs);
        // All at departure: the column is left out, whatever the input had.
        let at_departure =
            read("id,origin,destination,departure,submitted\nr1,A,B,08:15,08:15\n").unwrap();
        assert_eq!(
            write_requests(&at_departure, &air(), UtcOffset::SINGAPORE),
            "id,origin,destination,departure\nr1,A,B,2026-01-05T08:15:00.000+08:00\n"
        );
        assert_eq!(
            write_requests(&[], &air(), UtcOffset::SINGAPORE),
            "id,origin,destination,departure\n"
        );
    }

    #[test]
    fn submitted_errors_name_file_line_and_field() {
        let bad = |body: &str| {
            read(&format!(
                "id,origin,destination,departure,submitted\n{body}"
            ))
            .unwrap_err()
        };
        assert_eq!(
            bad("r1,A,B,08:00,07:00\nr2,A,B,08:00,08:00:01\n"),
            "r.csv: line 3: field `submitted`: `08:00:01` is later than the departure `08:00`; \
             a request is submitted at or before its departure"
        );
        assert!(
            bad("r1,A,B,08:00,8 pm\n")
                .starts_with("r.csv: line 2: field `submitted`: `8 pm` is neither"),
        );
        assert!(bad("r1,A,B,08:00,2026-01-05T07:00:00\n").starts_with(
            "r.csv: line 2: field `submitted`: `2026-01-05T07:00:00` is not an RFC 3339"
        ));
        // The departure is checked first.
        assert_eq!(
            bad("r1,A,B,,07:00\n"),
            "r.csv: line 2: field `departure`: missing"
        );
        assert!(bad("r1,A,B,08:00\n").starts_with("r.csv: line 2: malformed CSV record"));
    }

    #[test]
    fn header_errors_name_the_column() {
        let header = |h: &str| read(&format!("{h}\nr1,A,B,08:00,x\n")).unwrap_err();
        let must = "the header must be id,origin,destination,departure, optionally followed by \
                    submitted, and by origin_customer,destination_customer";
        assert_eq!(
            header("id,origin,destination,departure,note"),
            format!("r.csv: line 1: field `note`: unknown column; {must}")
        );
        assert_eq!(
            header("id,origin,destination,departure,Submitted"),
            format!("r.csv: line 1: field `Submitted`: unknown column; {must}")
        );
        assert_eq!(
            header("id,origin,destination,departure,"),
            format!("r.csv: line 1: column 5 has no name (a stray comma?); {must}")
        );
        assert_eq!(
            header("id,origin,destination,departure,departure"),
            "r.csv: line 1: field `departure`: the column is named twice (columns 4 and 5)"
        );
        assert_eq!(
            header("id,origin,destination,submitted,submitted"),
            "r.csv: line 1: field `submitted`: the column is named twice (columns 4 and 5)"
        );
        assert_eq!(
            header("id,origin,destination,submitted"),
            format!("r.csv: line 1: field `departure`: missing column ({must})")
        );
        // Header errors come before any row is read.
        assert_eq!(
            read("id,origin,destination,departure,extra\n").unwrap_err(),
            format!("r.csv: line 1: field `extra`: unknown column; {must}")
        );
    }

    #[test]
    fn errors_name_file_line_and_field() {
        assert_eq!(
            err(""),
            "r.csv: no requests: the file has its header and no row; give at least one request"
        );
        assert_eq!(
            err("r1,A,B,08:00\nr2,A,Q,08:00\n"),
            "r.csv: line 3: field `destination`: unknown node id `Q`"
        );
        assert_eq!(
            err("r1,A,A,08:00\n"),
            "r.csv: line 2: field `destination`: origin and destination are both `A`"
        );
        assert_eq!(
            err("r1,W,B,08:00\n"),
            "r.csv: line 2: field `origin`: `W` is a waypoint, not a station"
        );
        assert!(
            err("r1,A,B,8 o'clock\n")
                .starts_with("r.csv: line 2: field `departure`: `8 o'clock` is neither")
        );
        assert!(err("r1,A,B,2026-01-05T08:15:00\n").starts_with(
            "r.csv: line 2: field `departure`: `2026-01-05T08:15:00` is not an RFC 3339"
        ));
        assert_eq!(
            err("r1,A,B,2026-06-30T23:59:60+00:00\n"),
            "r.csv: line 2: field `departure`: `2026-06-30T23:59:60+00:00` is a leap second \
             (second 60): leap seconds are not accepted, since MUSE time (like Unix time) has 60 \
             seconds in every minute; give :59 or the next minute's :00"
        );
        assert!(err("r1,A,B,23:59:60\n").starts_with(
            "r.csv: line 2: field `departure`: `23:59:60` is a leap second (second 60): leap \
             seconds are not accepted"
        ));
        assert!(
            read("id,origin,destination,departure,submitted\nr1,A,B,23:59:59,23:59:60.5\n")
                .unwrap_err()
                .starts_with(
                    "r.csv: line 2: field `submitted`: `23:59:60.5` is a leap second (second 60)"
                )
        );
        // A valid timestamp far ahead is read exactly, and planned up to the year 8999 (UTC);
        // one beyond 64-bit milliseconds is out of range.
        let far = read_requests(
            "id,origin,destination,departure\nr1,A,B,9000-01-01T07:59:59.999+08:00\n",
            "r.csv",
            &air(),
            DAY,
        )
        .unwrap();
        assert_eq!(
            far[0].departure.to_rfc3339(UtcOffset::SINGAPORE),
            "9000-01-01T07:59:59.999+08:00"
        );
        assert_eq!(
            err("r1,A,B,9999-12-31T23:59:59.999+08:00\n"),
            "r.csv: line 2: field `departure`: `9999-12-31T23:59:59.999+08:00` is outside the \
             years MUSE plans: from 1000-01-01T00:00:00Z up to 9000-01-01T00:00:00Z (the years \
             1000 to 8999, UTC)"
        );
        assert!(err("r1,A,B,+999999999-01-01T00:00:00Z\n").starts_with(
            "r.csv: line 2: field `departure`: `+999999999-01-01T00:00:00Z` is out of the range \
             MUSE represents"
        ));
        assert_eq!(
            err("r1,A,B,08:00\nr1,B,A,09:00\n"),
            "r.csv: line 3: field `id`: duplicate request id `r1` (first on line 2)"
        );
        assert_eq!(err(",A,B,08:00\n"), "r.csv: line 2: field `id`: missing");
        // Ids follow the service's rule: what the API refuses, the file refuses too.
        for (row, shown) in [
            ("\"a,b\",A,B,08:00", r#""a,b""#),
            ("\"say \"\"hi\"\"\",A,B,08:00", r#""say \"hi\"""#),
            ("caf\u{e9},A,B,08:00", "\"caf\u{e9}\""),
            ("a#2,A,B,08:00", r#""a#2""#),
        ] {
            assert_eq!(
                err(&format!("r1,A,B,08:00\n{row}\n")),
                format!(
                    "r.csv: line 3: field `id`: {shown} is not a valid id: an id is 1 to 128 \
                     characters among the ASCII letters and digits and `._~:-` (the service's \
                     rule too)"
                ),
                "{row}"
            );
        }
        assert!(err(&format!("{},A,B,08:00\n", "x".repeat(129))).contains("is not a valid id"));
        assert!(
            read(&format!(
                "id,origin,destination,departure\n{},A,B,08:00\n",
                "x".repeat(128)
            ))
            .is_ok()
        );
        assert_eq!(
            err("r1,,B,08:00\n"),
            "r.csv: line 2: field `origin`: missing"
        );
        assert!(err("r1,A,B\n").starts_with("r.csv: line 2: malformed CSV record"));
        let missing = read_requests("id,origin,departure\n", "r.csv", &air(), DAY).unwrap_err();
        assert_eq!(
            missing.to_string(),
            "r.csv: line 1: field `destination`: missing column (the header must be id,origin,destination,departure, optionally followed by submitted, and by origin_customer,destination_customer)"
        );
    }

    #[test]
    fn customer_columns_carry_unserved_requests_apart() {
        let text = "id,origin,destination,departure,destination_customer,origin_customer\n\
                    r1,A,B,08:00,c2,c1\n\
                    r2,,B,08:01,c2,c9\n\
                    r3,A,,08:02,c8,c1\n\
                    r4,B,B,08:03,c3,c4\n";
        let demand = read_demand(text, "d.csv", &air(), DAY).unwrap();
        assert_eq!(demand.requests.len(), 1);
        let pads: Vec<_> = demand
            .unserved
            .iter()
            .map(|u| (u.id.as_str(), u.origin, u.destination))
            .collect();
        assert_eq!(
            pads,
            [
                ("r2", None, Some(NodeId(1))),
                ("r3", Some(NodeId(0)), None),
                ("r4", Some(NodeId(1)), Some(NodeId(1)))
            ]
        );
        // Plain reading refuses them, naming the line and the pad.
        assert_eq!(
            read_requests(text, "d.csv", &air(), DAY)
                .unwrap_err()
                .to_string(),
            "d.csv: line 3: field `origin`: an unserved request (demand from customers: no pad \
             in reach, or both customers on one pad); `muse plan` and `muse simulate` count \
             such requests apart"
        );
        let e = |t: &str| {
            read_demand(t, "d.csv", &air(), DAY)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            e("id,origin,destination,departure,origin_customer\nr1,A,B,08:00,c1\n"),
            "d.csv: line 1: field `destination_customer`: missing column: `origin_customer` \
             is given, and the two come together"
        );
        assert_eq!(
            e(
                "id,origin,destination,departure,origin_customer,destination_customer\n\
               r1,A,B,08:00,c1,\n"
            ),
            "d.csv: line 2: field `destination_customer`: missing"
        );
        assert!(
            e(
                "id,origin,destination,departure,origin_customer,destination_customer\n\
               r1,A,B,08:00,c 1,c2\n"
            )
            .starts_with("d.csv: line 2: field `origin_customer`: \"c 1\" is not a valid")
        );
        // Without the customer columns an empty pad is still missing.
        assert_eq!(
            e("id,origin,destination,departure\nr1,,B,08:00\n"),
            "d.csv: line 2: field `origin`: missing"
        );
    }

    #[test]
    fn demand_files_read_back() {
        let rows = [
            DemandRow {
                id: "r1".into(),
                origin: Some(NodeId(0)),
                destination: Some(NodeId(1)),
                departure: Instant(3_600_000),
                submitted: Instant(3_000_000),
                customers: ["c1".into(), "c2".into()],
            },
            DemandRow {
                id: "r2".into(),
                origin: None,
                destination: Some(NodeId(0)),
                departure: Instant(3_700_000),
                submitted: Instant(3_700_000),
                customers: ["c3".into(), "c1".into()],
            },
        ];
        let text = write_demand(&rows, &air(), UtcOffset::SINGAPORE);
        let demand = read_demand(&text, "d.csv", &air(), DAY).unwrap();
        assert_eq!(demand.requests[0].submitted, Instant(3_000_000));
        assert_eq!(demand.unserved[0].destination, Some(NodeId(0)));
        assert_eq!(demand.unserved[0].departure, Instant(3_700_000));
    }
}
