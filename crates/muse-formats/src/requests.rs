//! The requests CSV (SPEC §5): header `id,origin,destination,departure`.
//!
//! `departure` is an RFC 3339 timestamp with an offset, or a bare local clock time
//! `HH:MM[:SS[.mmm]]` on the scenario's date in the scenario's offset. Origin and destination
//! must be distinct stations of the airspace; ids must be unique. Columns may come in any
//! order; other columns are allowed and ignored. Every error names the file, the line (the
//! header is line 1) and the field.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use jiff::civil::Date;
use muse_model::time::parse_clock;
use muse_model::{Airspace, Instant, NodeId, Request, UtcOffset};

use crate::error::{InputError, Location};

/// The date and offset that give meaning to bare local clock times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocalDay {
    /// The scenario date.
    pub date: Date,
    /// The scenario's UTC offset.
    pub offset: UtcOffset,
}

const COLUMNS: [&str; 4] = ["id", "origin", "destination", "departure"];

/// Reads requests from CSV text, in file order; `file` names the source in error messages.
///
/// ```
/// use muse_formats::requests::{read_requests, LocalDay};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}}]}"#, "a").unwrap();
/// let day = LocalDay { date: jiff::civil::date(2026, 1, 5), offset: muse_model::UtcOffset::SINGAPORE };
/// let csv = "id,origin,destination,departure\nr1,A,B,08:15\nr2,B,A,2026-01-05T08:20:00.000+08:00\n";
/// let reqs = read_requests(csv, "r.csv", &air, day).unwrap();
/// assert_eq!(reqs[1].departure - reqs[0].departure, muse_model::Millis::from_mins(5));
/// ```
pub fn read_requests(
    text: &str,
    file: &str,
    airspace: &Airspace,
    day: LocalDay,
) -> Result<Vec<Request>, InputError> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| {
            InputError::new(
                file,
                Location::Line(1),
                None,
                format!("cannot read the header: {e}"),
            )
        })?
        .clone();
    let mut col = [0usize; 4];
    for (slot, name) in col.iter_mut().zip(COLUMNS) {
        *slot = headers.iter().position(|h| h == name).ok_or_else(|| {
            InputError::new(
                file,
                Location::Line(1),
                Some(name),
                format!(
                    "missing column (the header must have {})",
                    COLUMNS.join(",")
                ),
            )
        })?;
    }
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            InputError::new(
                file,
                Location::Line(line),
                None,
                format!("malformed CSV record: {e}"),
            )
        })?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        let err = |field: &str, msg: String| {
            InputError::new(file, Location::Line(line), Some(field), msg)
        };
        let get = |i: usize| record.get(col[i]).unwrap_or("");
        let id = get(0);
        if id.is_empty() {
            return Err(err("id", "missing".into()));
        }
        if let Some(prev) = seen.insert(id.to_owned(), line) {
            return Err(err(
                "id",
                format!("duplicate request id `{id}` (first on line {prev})"),
            ));
        }
        let station = |i: usize| -> Result<NodeId, InputError> {
            let name = get(i);
            if name.is_empty() {
                return Err(err(COLUMNS[i], "missing".into()));
            }
            let n = airspace
                .node_id(name)
                .ok_or_else(|| err(COLUMNS[i], format!("unknown node id `{name}`")))?;
            if !airspace.is_station(n) {
                return Err(err(
                    COLUMNS[i],
                    format!("`{name}` is a waypoint, not a station"),
                ));
            }
            Ok(n)
        };
        let origin = station(1)?;
        let destination = station(2)?;
        if origin == destination {
            return Err(err(
                "destination",
                format!("origin and destination are both `{}`", get(1)),
            ));
        }
        let departure = parse_departure(get(3), day).map_err(|m| err("departure", m))?;
        out.push(Request {
            id: id.to_owned(),
            origin,
            destination,
            departure,
            submitted: departure,
        });
    }
    Ok(out)
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

/// Writes requests as CSV with RFC 3339 departures in `offset`.
///
/// ```
/// use muse_model::{Instant, NodeId, Request, UtcOffset};
/// # let air = muse_formats::airspace_geojson::read_airspace(r#"{"type": "FeatureCollection", "features": [
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.8, 1.3]}, "properties": {"id": "A", "kind": "station"}},
/// #  {"type": "Feature", "geometry": {"type": "Point", "coordinates": [103.81, 1.3]}, "properties": {"id": "B", "kind": "station"}}]}"#, "a").unwrap();
/// let r = Request { id: "r1".into(), origin: NodeId(0), destination: NodeId(1), departure: Instant(0), submitted: Instant(0) };
/// let csv = muse_formats::requests::write_requests(&[r], &air, UtcOffset::SINGAPORE);
/// assert_eq!(csv, "id,origin,destination,departure\nr1,A,B,1970-01-01T08:00:00.000+08:00\n");
/// ```
pub fn write_requests(requests: &[Request], airspace: &Airspace, offset: UtcOffset) -> String {
    let mut out = String::from("id,origin,destination,departure\n");
    for r in requests {
        let _ = writeln!(
            out,
            "{},{},{},{}",
            csv_field(&r.id),
            csv_field(&airspace.node(r.origin).id),
            csv_field(&airspace.node(r.destination).id),
            r.departure.to_rfc3339(offset)
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

fn parse_departure(text: &str, day: LocalDay) -> Result<Instant, String> {
    if text.is_empty() {
        return Err("missing".into());
    }
    if text.contains('T') || text.contains('t') || text.contains('-') && text.len() > 10 {
        return Instant::parse_rfc3339(text).map_err(|e| e.to_string());
    }
    let tod = parse_clock(text).map_err(|_| {
        format!("`{text}` is neither an RFC 3339 timestamp with offset nor a local time HH:MM[:SS]")
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
            "departure,destination,origin,id,note\n08:15:00,B,A,r1,x\n2026-01-05T00:15:00Z,A,B,r2,y\n",
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
        let text = write_requests(&reqs, &air(), UtcOffset::SINGAPORE);
        assert_eq!(read_requests(&text, "w.csv", &air(), DAY).unwrap(), reqs);
    }

    #[test]
    fn errors_name_file_line_and_field() {
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
            err("r1,A,B,08:00\nr1,B,A,09:00\n"),
            "r.csv: line 3: field `id`: duplicate request id `r1` (first on line 2)"
        );
        assert_eq!(err(",A,B,08:00\n"), "r.csv: line 2: field `id`: missing");
        assert_eq!(
            err("r1,,B,08:00\n"),
            "r.csv: line 2: field `origin`: missing"
        );
        assert!(err("r1,A,B\n").starts_with("r.csv: line 2: malformed CSV record"));
        let missing = read_requests("id,origin,departure\n", "r.csv", &air(), DAY).unwrap_err();
        assert_eq!(
            missing.to_string(),
            "r.csv: line 1: field `destination`: missing column (the header must have id,origin,destination,departure)"
        );
    }
}
