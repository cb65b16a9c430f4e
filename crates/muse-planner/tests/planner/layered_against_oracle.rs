//! Layered airspace (docs/reference.md#layered-airspace): the planner against the oracle and the
//! verifier on random layered instances (2 to 4 layers, vertical links of whole units, with and
//! without the `sectors` heading rule, zones closing a band of layers or the whole sky), single
//! legs and multi-leg trips, batch and online. The oracle takes vertical links' times, one-way
//! corridors and zones per layer straight from the reference (`scenario::Instance::zones`,
//! `oracle::weight`, `oracle::ends`, `oracle::rule_of`).

use crate::scenario::multileg::multileg_instances;
use crate::scenario::{self, Instance, Shape, Tally, check_property, instances, layered};

/// Runs `cases` layered instances of `strategy` through `run`.
fn property_of(
    run: fn(&Instance) -> Result<Tally, String>,
    strategy: impl proptest::strategy::Strategy<Value = Instance>,
    path: &str,
    cases: u32,
    seed: u64,
) -> Tally {
    check_property(run, layered(strategy), path, cases, seed)
}

#[test]
fn layered_planner_matches_oracle() {
    let t = property_of(
        scenario::run,
        instances(Shape::MIXED),
        "layered batch",
        1_500,
        0x1a7e_0001,
    );
    assert!(
        t.planned > 3_000 && t.air_delayed > 300 && t.rejected.iter().all(|&r| r > 100),
        "{t:?}"
    );
}

#[test]
fn layered_online_matches_oracle_crowded() {
    let t = property_of(
        scenario::run_online,
        instances(Shape::CROWDED),
        "layered online",
        600,
        0x1a7e_0002,
    );
    assert!(t.planned > 1_000 && t.air_delayed > 200, "{t:?}");
}

#[test]
fn layered_multileg_matches_oracle() {
    let t = property_of(
        scenario::run,
        multileg_instances(Shape::MIXED),
        "layered multi-leg",
        600,
        0x1a7e_0003,
    );
    let [_, two, three, _] = t.legs;
    assert!(two > 20 && three > 2, "{t:?}");
}
