//! `--vary zones`: with and without the no-fly zones.

use super::lever::{Base, Lever, LeverError};
use crate::experiment::sweep::variant::Variant;

/// With and without the no-fly zones.
pub struct Zones;

impl Lever for Zones {
    fn name(&self) -> &'static str {
        "zones"
    }

    fn help(&self) -> &'static str {
        "With and without the no-fly zones"
    }

    fn apply(
        &self,
        base: &Base<'_>,
        current: &Variant,
        _: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        if base.zones.is_empty() {
            return Err(LeverError(
                "--vary zones needs zones (the embedded CBD zone, or --zones FILE)".to_owned(),
            ));
        }
        Ok(vec![
            (base.zone_label.to_owned(), current.clone()),
            (
                "no zone".to_owned(),
                Variant {
                    zones: Vec::new(),
                    ..current.clone()
                },
            ),
        ])
    }
}
