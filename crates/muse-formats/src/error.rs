//! The one error type of the readers: where in which file, which field, and what is wrong.

use std::fmt;

/// Where in a file an error is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// The file as a whole (unreadable, not JSON, wrong top-level shape).
    Whole,
    /// A 1-based line of a text file (CSV: the header is line 1).
    Line(usize),
    /// A 0-based feature of a GeoJSON / JSON list, with its id if it has one.
    Feature {
        /// Index in the list.
        index: usize,
        /// The feature's id, when known.
        id: Option<String>,
    },
}

/// A bad input: file, location, field and message.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct InputError {
    /// The file's name as given by the caller (usually its path).
    pub file: String,
    /// Where in the file.
    pub location: Location,
    /// The field (column, property or JSON key), when one is to blame.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl InputError {
    /// A new error.
    pub fn new(
        file: impl Into<String>,
        location: Location,
        field: Option<&str>,
        message: impl Into<String>,
    ) -> Self {
        InputError {
            file: file.into(),
            location,
            field: field.map(str::to_owned),
            message: message.into(),
        }
    }
}

impl fmt::Display for InputError {
    /// For example ``r.csv: line 3: field `departure`: message`` or
    /// ``a.geojson: feature 5 (`S001`): field `length_m`: message``.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        match &self.location {
            Location::Whole => {}
            Location::Line(n) => write!(f, ": line {n}")?,
            Location::Feature {
                index,
                id: Some(id),
            } => write!(f, ": feature {index} (`{id}`)")?,
            Location::Feature { index, id: None } => write!(f, ": feature {index}")?,
        }
        if let Some(field) = &self.field {
            write!(f, ": field `{field}`")?;
        }
        write!(f, ": {}", self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_location_and_field() {
        let e = InputError::new("r.csv", Location::Line(3), Some("departure"), "bad time");
        assert_eq!(e.to_string(), "r.csv: line 3: field `departure`: bad time");
        let e = InputError::new(
            "a.geojson",
            Location::Feature {
                index: 5,
                id: Some("S001".into()),
            },
            Some("length_m"),
            "must be > 0",
        );
        assert_eq!(
            e.to_string(),
            "a.geojson: feature 5 (`S001`): field `length_m`: must be > 0"
        );
    }
}
