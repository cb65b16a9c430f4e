//! Customers files (docs/reference.md#airspace-from-pads, demand from points): where deliveries
//! start and end, as a CSV with the columns `id,lon,lat` and optionally `weight` (any order, other
//! columns ignored).
//!
//! A customer's id follows the requests' rule ([`ID_RULE`]), so that it can stand in a
//! requests file; its weight, the relative chance of being drawn as an end of a request, is
//! a finite number above 0 (1 when the column or the cell is empty). Refused, naming the line
//! and field: a missing or invalid id, the same id twice, a position that is not a number or
//! is outside WGS84, a weight that is not a number above 0; and a file with fewer than two
//! customers (a request joins two).
//!
//! ```
//! use muse_formats::customers::read_customers;
//! let csv = "id,lon,lat,weight\nc1,103.85,1.29,2\nc2,103.86,1.30,\n";
//! let customers = read_customers(csv, "c.csv").unwrap();
//! assert_eq!((customers[0].weight, customers[1].weight), (2.0, 1.0));
//! let e = read_customers("id,lon,lat,weight\nc1,103.85,1.29,0\nc2,103.86,1.30,1\n", "c.csv");
//! assert_eq!(e.unwrap_err().to_string(), "c.csv: line 2: field `weight`: `0` is not a weight: give a number above 0");
//! ```

use std::collections::HashMap;
use std::path::Path;

use muse_model::LonLat;
use muse_model::request::{ID_RULE, valid_id};

use crate::error::{InputError, Location};
use crate::table::{Table, number};

/// The fewest customers a demand is drawn from (a request joins two).
pub const MIN_CUSTOMERS: usize = 2;

/// One customer: a point where deliveries start and end.
#[derive(Clone, Debug, PartialEq)]
pub struct Customer {
    /// Its id.
    pub id: String,
    /// Where it is.
    pub pos: LonLat,
    /// Its relative chance of being drawn as an end of a request (above 0).
    pub weight: f64,
}

/// Reads a customers CSV's text; `file` names it in errors.
///
/// # Errors
/// The first bad line, or too few customers (see the [module documentation](self)).
pub fn read_customers(text: &str, file: &str) -> Result<Vec<Customer>, InputError> {
    let mut table = Table::new(text, file)?;
    let required = table.required(
        ["id", "lon", "lat"],
        "a customers CSV has the columns id, lon, lat and optionally weight",
    )?;
    let weight_col = table.column("weight");
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for row in table.rows() {
        let (record, line) = row?;
        let c = customer(&record, required, weight_col)
            .map_err(|(field, m)| InputError::new(file, Location::Line(line), Some(field), m))?;
        if let Some(first) = seen.insert(c.id.clone(), line) {
            return Err(InputError::new(
                file,
                Location::Line(line),
                Some("id"),
                format!("duplicate customer id `{}` (first on line {first})", c.id),
            ));
        }
        out.push(c);
    }
    if out.len() < MIN_CUSTOMERS {
        return Err(InputError::new(
            file,
            Location::Whole,
            None,
            format!(
                "{} customer{}: a demand needs at least {MIN_CUSTOMERS}",
                out.len(),
                if out.len() == 1 { "" } else { "s" }
            ),
        ));
    }
    Ok(out)
}

/// One customer from its record: the columns of `id, lon, lat` and of the weight, if any;
/// else the field to blame and why.
fn customer(
    record: &csv::StringRecord,
    [id_col, lon_col, lat_col]: [usize; 3],
    weight_col: Option<usize>,
) -> Result<Customer, (&'static str, String)> {
    let get = |i: usize| record.get(i).unwrap_or("");
    let id = get(id_col);
    if id.is_empty() {
        return Err(("id", "missing".into()));
    }
    if !valid_id(id) {
        return Err((
            "id",
            format!("{id:?} is not a valid id: an id is {ID_RULE}"),
        ));
    }
    let number = |i: usize, field: &'static str, lo: f64, hi: f64| {
        let v = number(get(i)).map_err(|m| (field, m))?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err((field, format!("{v} is outside {lo} to {hi}")))
        }
    };
    let lon = number(lon_col, "lon", -180.0, 180.0)?;
    let lat = number(lat_col, "lat", -90.0, 90.0)?;
    let weight = match weight_col.map(get) {
        None | Some("") => 1.0,
        Some(text) => text
            .parse::<f64>()
            .ok()
            .filter(|w| w.is_finite() && *w > 0.0)
            .ok_or_else(|| {
                (
                    "weight",
                    format!("`{text}` is not a weight: give a number above 0"),
                )
            })?,
    };
    Ok(Customer {
        id: id.to_owned(),
        pos: LonLat::new(lon, lat),
        weight,
    })
}

/// Reads a customers file.
///
/// # Errors
/// An unreadable file, or as [`read_customers`].
pub fn read_customers_file(path: &Path) -> Result<Vec<Customer>, InputError> {
    read_customers(&crate::read_to_string(path)?, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bad_customer_is_named_by_line_and_field() {
        let err = |text: &str| read_customers(text, "c").unwrap_err().to_string();
        let cases = [
            (
                "id,lon\nA,1\n",
                "c: line 1: field `lat`: the header has no `lat` column: a customers CSV has the columns id, lon, lat and optionally weight",
            ),
            (
                "id,lon,lat\n,1,1\nB,2,2\n",
                "c: line 2: field `id`: missing",
            ),
            (
                "id,lon,lat\nA,1,1\nA,2,2\n",
                "c: line 3: field `id`: duplicate customer id `A` (first on line 2)",
            ),
            (
                "id,lon,lat\nA,1,1\nB,x,2\n",
                "c: line 3: field `lon`: `x` is not a number",
            ),
            (
                "id,lon,lat\nA,1,1\nB,2,95\n",
                "c: line 3: field `lat`: 95 is outside -90 to 90",
            ),
            (
                "id,lon,lat,weight\nA,1,1,-1\nB,2,2,1\n",
                "c: line 2: field `weight`: `-1` is not a weight: give a number above 0",
            ),
            (
                "id,lon,lat,weight\nA,1,1,inf\nB,2,2,1\n",
                "c: line 2: field `weight`: `inf` is not a weight: give a number above 0",
            ),
            (
                "id,lon,lat\nA,1,1\n",
                "c: 1 customer: a demand needs at least 2",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(err(text), want, "{text}");
        }
        assert!(
            err("id,lon,lat\na b,1,1\nB,2,2\n")
                .starts_with("c: line 2: field `id`: \"a b\" is not a valid id")
        );
    }

    #[test]
    fn columns_in_any_order_and_weights_default_to_one() {
        let c = read_customers("lat,id,lon,extra\n1.3,A,103.8,x\n1.31,B,103.81,y\n", "c").unwrap();
        assert_eq!(c[1].id, "B");
        assert_eq!(
            (c[1].pos.lon, c[1].pos.lat, c[1].weight),
            (103.81, 1.31, 1.0)
        );
    }
}
