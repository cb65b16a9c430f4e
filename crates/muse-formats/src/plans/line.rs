//! One line of a plans file being read: the file and line to name in errors, and the airspace
//! its stations are resolved against. Its reading is in `read.rs`, its legs' checks in
//! `legs.rs`.

use muse_model::Airspace;

use crate::error::{InputError, Location};

/// Reads one line of a plans file, naming it in errors.
pub(super) struct LineReader<'a> {
    pub(super) file: &'a str,
    pub(super) line_no: usize,
    pub(super) airspace: &'a Airspace,
}

impl LineReader<'_> {
    /// An error at this line, in `field` if given.
    pub(super) fn err(&self, field: Option<&str>, msg: String) -> InputError {
        InputError::new(self.file, Location::Line(self.line_no), field, msg)
    }
}
