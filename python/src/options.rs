//! Keyword arguments as the model's parameters: the flight model
//! (docs/reference.md#flight-model-and-separation, #multi-leg-trips) by the members of a summary's
//! `parameters` (`speed_kmh`, `max_flight_min`, …), and the layers
//! (docs/reference.md#layered-airspace) by the command line's option names (`layers`,
//! `heading_rule`, …).

use muse_formats::layer_params::{LayerField, LayerParams};
use muse_formats::params::{Field, ParamsRecord};
use muse_formats::ranges::{BASE_ALTITUDE_M, CLIMB_MPS, LAYER_SPACING_M, LAYERS, Number, Range};
use muse_model::{FlightParams, HeadingRule, Layers};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
use serde_json::Value;

use crate::error;

/// The layering keywords: the command line's option names.
const LAYER_KEYS: [&str; 5] = LayerField::NAMES;

/// The flight-parameter keywords: the members of a summary's `parameters`.
const FLIGHT_KEYS: [&str; 11] = Field::NAMES;

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
    let mut layers = LayerParams::default();
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let json = to_json(&key, &value)?;
            if LAYER_KEYS.contains(&key.as_str()) {
                set_layer(&mut layers, &key, &json)?;
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
    let layers = layers.to_layers().map_err(error)?;
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

/// Sets the layering keyword `key` to `value`, within its range.
fn set_layer(layers: &mut LayerParams, key: &str, value: &Value) -> PyResult<()> {
    let number = |range: Range<f64>| {
        let bad = |problem: String| error(format!("{key} {value}: {problem}"));
        let x = value
            .as_f64()
            .ok_or_else(|| bad(range.check(f64::NAN).unwrap_err()))?;
        range.check(x).map_err(bad)
    };
    match key {
        "layers" => {
            layers.count = value
                .as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| LAYERS.check(0).unwrap_err())
                .and_then(|n| LAYERS.check(n))
                .map_err(|problem| error(format!("layers {value}: {problem}")))?;
        }
        "base_altitude_m" => layers.base_altitude_m = number(BASE_ALTITUDE_M)?,
        "layer_spacing_m" => layers.spacing_m = number(LAYER_SPACING_M)?,
        "climb_mps" => layers.climb_mps = number(CLIMB_MPS)?,
        _ => {
            layers.heading_rule = value.as_str().and_then(HeadingRule::parse).ok_or_else(|| {
                error(format!(
                    "heading_rule: must be \"none\" or \"sectors\", not {value}"
                ))
            })?;
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
