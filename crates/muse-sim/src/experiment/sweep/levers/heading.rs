//! `--vary heading-rule`: no heading rule against `sectors` (docs/reference.md#layered-airspace:
//! layer `k` of `L` flown only on bearings in `[(k−1)·360/L, k·360/L)`). With one layer the two are
//! the same airspace, so only `none` is run.

use muse_model::{HeadingRule, Layers};

use super::lever::{Base, Lever, LeverError};
use crate::experiment::sweep::variant::Variant;

/// `none` and `sectors`.
pub struct HeadingRules;

impl Lever for HeadingRules {
    fn name(&self) -> &'static str {
        "heading-rule"
    }

    fn help(&self) -> &'static str {
        "No heading rule against `sectors`, one sector of bearings per layer (with --vary layers)"
    }

    fn apply(
        &self,
        _: &Base<'_>,
        current: &Variant,
        _: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let with = |rule: HeadingRule| Variant {
            layers: Layers {
                heading_rule: rule,
                ..current.layers
            },
            ..current.clone()
        };
        let mut out = vec![("none".to_owned(), with(HeadingRule::None))];
        if current.layers.is_layered() {
            out.push(("sectors".to_owned(), with(HeadingRule::Sectors)));
        }
        Ok(out)
    }
}
