//! The planner's test binary: the exhaustive oracle (`oracle`) and the random instances it
//! judges (`scenario`); the planner against the oracle on single-leg (`against_oracle`) and
//! multi-leg (`multileg_against_oracle`) trips, on layered airspace (`layered_against_oracle`),
//! cancellation (`schedule_remove`) and minimal instances
//! that once failed (`regressions`).

mod oracle;
mod scenario;

mod against_oracle;
mod layered_against_oracle;
mod multileg_against_oracle;
mod regressions;
mod schedule_remove;
mod separation_against_oracle;
