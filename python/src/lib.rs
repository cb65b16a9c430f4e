//! `muse._muse`: the extension module behind `import muse` (python/muse/__init__.py).
//!
//! It calls the same library functions as the command line — the same readers, the same
//! planner, the same summary and the same verifier — and hands back what the command line
//! writes to files (`plans.jsonl`, `summary.json`, `flights.csv`, `stays.csv`) as text, which
//! the Python layer turns into pandas `DataFrame`s and dicts. Every error is a
//! `muse.MuseError` (a `ValueError`) carrying the message the command line prints.
//!
//! - `airspace`: the `Airspace` class: a built-in scenario, a GeoJSON file, or built from
//!   pads (docs/reference.md#airspace-from-pads);
//! - `options`: keyword arguments as flight parameters and layers;
//! - `world`: an airspace with its zones and day, as the command line loads it;
//! - `day`: `plan` and `simulate`;
//! - `check`: `verify`.

// Python functions take their arguments as owned values (`PyRef`, `Vec`, `PathBuf`):
// that is how pyo3 extracts them.
#![allow(clippy::needless_pass_by_value)]

mod airspace;
mod check;
mod day;
mod options;
mod world;

use pyo3::prelude::*;

pyo3::create_exception!(
    _muse,
    MuseError,
    pyo3::exceptions::PyValueError,
    "An input MUSE refuses: the message names the input, line and field, as the command \
     line's does."
);

/// A `MuseError` carrying `message`.
fn error(message: impl std::fmt::Display) -> PyErr {
    MuseError::new_err(message.to_string())
}

/// The text of the file at `path` as the command line reads its inputs: a file that cannot be
/// read, or is not UTF-8, is a `MuseError` in the command line's words
/// (`PATH: cannot read: No such file or directory (os error 2)`), never an `OSError`.
#[pyfunction]
fn read_text(path: std::path::PathBuf) -> PyResult<String> {
    muse_formats::read_to_string(&path).map_err(error)
}

/// The module: the `Airspace` class, `plan`, `simulate`, `verify`, `read_text` and
/// `MuseError`.
#[pymodule]
fn _muse(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<airspace::Airspace>()?;
    m.add_function(wrap_pyfunction!(day::plan, m)?)?;
    m.add_function(wrap_pyfunction!(day::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(check::verify, m)?)?;
    m.add_function(wrap_pyfunction!(read_text, m)?)?;
    m.add("MuseError", m.py().get_type::<MuseError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
