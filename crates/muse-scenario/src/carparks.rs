//! HDB car parks from the embedded `hdb_carpark_information.csv` (data.gov.sg).

use muse_model::Svy21;

use crate::ScenarioError;
use crate::data::{HDB_CARPARK_CSV, HDB_CARPARK_CSV_NAME};

/// The `car_park_type` of the car parks stations are chosen from.
pub const MULTI_STOREY: &str = "MULTI-STOREY CAR PARK";

/// One row of the HDB car park list.
#[derive(Clone, Debug, PartialEq)]
pub struct CarPark {
    /// `car_park_no`, e.g. `ACM` (unique in the file).
    pub number: String,
    /// `address`, e.g. `BLK 98A ALJUNIED CRESCENT`.
    pub address: String,
    /// `car_park_type`, e.g. `MULTI-STOREY CAR PARK`.
    pub car_park_type: String,
    /// `x_coord`, `y_coord`: position on the SVY21 grid (EPSG:3414), metres.
    pub svy21: Svy21,
}

impl CarPark {
    /// The station name used in the scenario: number and address, e.g.
    /// `ACM BLK 98A ALJUNIED CRESCENT`.
    pub fn station_name(&self) -> String {
        format!("{} {}", self.number, self.address)
    }
}

/// Every row of the embedded car park list, in file order (sorted by car park number).
///
/// ```
/// let all = muse_scenario::carparks::car_parks().unwrap();
/// assert_eq!(all.len(), 2_257);
/// assert_eq!(all[1].number, "ACM");
/// ```
pub fn car_parks() -> Result<Vec<CarPark>, ScenarioError> {
    parse_car_parks(HDB_CARPARK_CSV, HDB_CARPARK_CSV_NAME)
}

/// The rows of type [`MULTI-STOREY CAR PARK`](MULTI_STOREY) (1,115 of them), in file order:
/// the candidates for stations.
pub fn multi_storey_car_parks() -> Result<Vec<CarPark>, ScenarioError> {
    Ok(car_parks()?
        .into_iter()
        .filter(|c| c.car_park_type == MULTI_STOREY)
        .collect())
}

/// Parses the data.gov.sg "HDB Carpark Information" CSV (header row with at least
/// `car_park_no`, `address`, `x_coord`, `y_coord`, `car_park_type`).
pub fn parse_car_parks(text: &str, file: &str) -> Result<Vec<CarPark>, ScenarioError> {
    let err = |line: u64, message: String| ScenarioError::Data {
        file: file.to_owned(),
        line,
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(text.as_bytes());
    let headers = reader.headers().map_err(|e| err(1, e.to_string()))?.clone();
    let column = |name: &str| {
        headers
            .iter()
            .position(|h| h.trim() == name)
            .ok_or_else(|| err(1, format!("missing column `{name}`")))
    };
    let (no, address, x, y, kind) = (
        column("car_park_no")?,
        column("address")?,
        column("x_coord")?,
        column("y_coord")?,
        column("car_park_type")?,
    );
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, csv::Position::line);
            err(line, e.to_string())
        })?;
        let line = record.position().map_or(0, csv::Position::line);
        let field = |i: usize| record.get(i).unwrap_or("").trim();
        let coord = |i: usize, name: &str| {
            field(i)
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| err(line, format!("`{name}` = `{}` is not a number", field(i))))
        };
        out.push(CarPark {
            number: field(no).to_owned(),
            address: field(address).to_owned(),
            car_park_type: field(kind).to_owned(),
            svy21: Svy21::new(coord(x, "x_coord")?, coord(y, "y_coord")?),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_match_the_provenance_notes() {
        let all = car_parks().unwrap();
        assert_eq!(all.len(), 2_257);
        let multi = multi_storey_car_parks().unwrap();
        assert_eq!(multi.len(), 1_115);
        let acm = all.iter().find(|c| c.number == "ACM").unwrap();
        assert_eq!(acm.station_name(), "ACM BLK 98A ALJUNIED CRESCENT");
        assert_eq!(acm.svy21, Svy21::new(33_758.414_3, 33_695.519_8));
    }

    #[test]
    fn bad_rows_name_the_line() {
        let text = "car_park_no,address,x_coord,y_coord,car_park_type\nA,X,1,2,T\nB,Y,oops,2,T\n";
        let err = parse_car_parks(text, "cp.csv").unwrap_err();
        assert_eq!(
            err.to_string(),
            "cp.csv: line 3: `x_coord` = `oops` is not a number"
        );
        let err = parse_car_parks("a,b\n", "cp.csv").unwrap_err();
        assert!(
            err.to_string().contains("missing column `car_park_no`"),
            "{err}"
        );
    }
}
