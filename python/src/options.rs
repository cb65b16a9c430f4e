//! Keyword arguments as the model's parameters: the flight model (SPEC §3, §12) by the
//! members of a summary's `parameters` (`speed_kmh`, `max_flight_min`, …), and the layers
//! (SPEC §13) by the command line's option names (`layers`, `heading_rule`, …).

use muse_formats::params::{Field, ParamsRecord};
use muse_formats::ranges::{BASE_ALTITUDE_M, CLIMB_MPS, LAYER_SPACING_M, LAYERS, Number, Range};
use muse_model::{FlightParams, HeadingRule, Layers, Metres};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
use serde_json::Value;

use crate::error;

/// The layering keywords and what each sets.
const LAYER_KEYS: [&str; 5] = [
    "layers",
    "base_altitude_m",
    "layer_spacing_m",
    "climb_mps",
    "heading_rule",
];

/// The flight-parameter keywords: the members of a summary's `parameters`.
const FLIGHT_KEYS: [&str; 9] = Field::NAMES;

/// The parameters a call's keywords give.
pub struct Options {
    /// The flight parameters.
    pub params: FlightParams,
    /// The layering.
    pub layers: Layers,
}

/// Reads `kwargs`: flight parameters over the paper's defaults, and layers.
///
/// # Errors
/// An unknown keyword, a value of the wrong type, or a value out of range, named by its
/// keyword.
pub fn options(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Options> {
    let mut record =
        serde_json::to_value(ParamsRecord::from(&FlightParams::default())).map_err(error)?;
    let mut layers = Layers::default();
    let mut climb_mps = f64::from(layers.climb_mm_per_s) / 1e3;
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let json = to_json(&key, &value)?;
            if LAYER_KEYS.contains(&key.as_str()) {
                set_layer(&mut layers, &mut climb_mps, &key, &json)?;
            } else if FLIGHT_KEYS.contains(&key.as_str()) {
                record[key.as_str()] = json;
            } else {
                return Err(error(format!(
                    "unknown parameter `{key}`: the flight parameters are {}; the layers' {}",
                    FLIGHT_KEYS.join(", "),
                    LAYER_KEYS.join(", ")
                )));
            }
        }
    }
    let record: ParamsRecord = serde_json::from_value(record).map_err(error)?;
    record.check_ranges().map_err(error)?;
    let params = record.to_params().map_err(error)?;
    let mm = climb_mps * 1_000.0;
    if (mm - mm.round()).abs() > 1e-6 {
        return Err(error(format!(
            "climb_mps {climb_mps}: give whole millimetres per second (at most 3 decimals)"
        )));
    }
    layers.climb_mm_per_s = mm.round() as u32;
    layers
        .validate()
        .map_err(|e| error(format!("layers: {e}")))?;
    Ok(Options { params, layers })
}

/// The argument `key` (`count`, `seed`) as a number in `range`, read as the command line
/// reads its option (from the value's text), refused in the same words:
/// `count 0: must be a whole number of requests from 1 to 10000000`. A negative or huge
/// integer, a float or a bool is a `MuseError` too, never an `OverflowError` or a
/// `TypeError`.
///
/// # Errors
/// A value outside `range`, or not a whole number.
pub fn whole<T: Number>(key: &str, value: &Bound<'_, PyAny>, range: Range<T>) -> PyResult<T> {
    let text = value.str()?.to_string();
    range
        .parse(&text)
        .map_err(|problem| error(format!("{key} {text}: {problem}")))
}

/// Sets the layering keyword `key` to `value`.
fn set_layer(layers: &mut Layers, climb_mps: &mut f64, key: &str, value: &Value) -> PyResult<()> {
    let number = |range: Range<f64>| {
        let bad = |problem: String| error(format!("{key} {value}: {problem}"));
        let x = value
            .as_f64()
            .ok_or_else(|| bad(range.check(f64::NAN).unwrap_err()))?;
        range.check(x).map_err(bad)
    };
    let metres = |m: f64| Metres::from_m(m).map_err(|e| error(format!("{key} {m}: {e}")));
    match key {
        "layers" => {
            layers.count = value
                .as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| LAYERS.check(0).unwrap_err())
                .and_then(|n| LAYERS.check(n))
                .map_err(|problem| error(format!("layers {value}: {problem}")))?;
        }
        "base_altitude_m" => layers.base = metres(number(BASE_ALTITUDE_M)?)?,
        "layer_spacing_m" => layers.spacing = metres(number(LAYER_SPACING_M)?)?,
        "climb_mps" => *climb_mps = number(CLIMB_MPS)?,
        _ => {
            layers.heading_rule = match value.as_str() {
                Some("none") => HeadingRule::None,
                Some("sectors") => HeadingRule::Sectors,
                _ => {
                    return Err(error(format!(
                        "heading_rule: must be \"none\" or \"sectors\", not {value}"
                    )));
                }
            };
        }
    }
    Ok(())
}

/// A keyword's value as JSON: `None`, a bool, an integer, a float or a string.
fn to_json(key: &str, value: &Bound<'_, PyAny>) -> PyResult<Value> {
    if value.is_none() {
        Ok(Value::Null)
    } else if value.is_instance_of::<PyBool>() {
        Ok(Value::Bool(value.extract()?))
    } else if value.is_instance_of::<PyInt>() {
        let n: i64 = value
            .extract()
            .map_err(|_| error(format!("{key}: {value} is too large")))?;
        Ok(Value::from(n))
    } else if value.is_instance_of::<PyFloat>() {
        let x: f64 = value.extract()?;
        serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| error(format!("{key}: {x} is not a finite number")))
    } else if value.is_instance_of::<PyString>() {
        Ok(Value::String(value.extract()?))
    } else {
        Err(error(format!(
            "{key}: expected a number or a string, not {}",
            value.get_type().name()?
        )))
    }
}
