//! `--vary edge-rule`: exclusive corridors against a same-direction headway.

use muse_model::{EdgeRule, FlightParams};

use super::lever::{Base, Lever, LeverError, with_params};
use crate::experiment::sweep::variant::Variant;

/// `exclusive` against `headway` edges; the headway is the one given, or the base node
/// separation.
pub struct EdgeRules;

impl Lever for EdgeRules {
    fn name(&self) -> &'static str {
        "edge-rule"
    }

    fn help(&self) -> &'static str {
        "`exclusive` versus `headway` edges (headway = the node separation unless given)"
    }

    fn apply(
        &self,
        base: &Base<'_>,
        current: &Variant,
        _: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let h = match base.params.edge_rule {
            EdgeRule::Headway(h) => h,
            EdgeRule::Exclusive => base.params.node_separation,
        };
        Ok(vec![
            (
                "exclusive".to_owned(),
                with_params(
                    current,
                    FlightParams {
                        edge_rule: EdgeRule::Exclusive,
                        ..current.params
                    },
                ),
            ),
            (
                format!("headway {:.0} s", h.as_secs_f64()),
                with_params(
                    current,
                    FlightParams {
                        edge_rule: EdgeRule::Headway(h),
                        ..current.params
                    },
                ),
            ),
        ])
    }
}
