//! The leader's archiving thread (`muse serve --archive-after-days N`; see
//! `store::archive`): a pass at the start, then one every [`EVERY`], on a connection of its
//! own beside the writer's, until the planner task ends.

use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::Duration;

use crate::state::State;
use crate::store::Archiver;
use crate::store::archive::{Retention, pass};

/// How often a pass runs.
pub(super) const EVERY: Duration = Duration::from_mins(10);

/// Runs passes until `stop` is dropped. A pass that fails is said on standard error and
/// counted (`muse_archive_failures_total`); the next one tries again: the rows it did not
/// move stay in the hot tables, whole.
pub(super) fn run(
    state: &State,
    mut archiver: Box<dyn Archiver>,
    retention: &Retention,
    stop: &Receiver<()>,
) {
    loop {
        match pass(archiver.as_mut(), retention, state.clock.now()) {
            Ok(done) => state.metrics.count_archived(done.flights, done.events),
            Err(e) => {
                state.metrics.count_archive_failure();
                eprintln!(
                    "muse serve: archiving into {} failed: {e}; the next pass, in {} s, tries \
                     again",
                    retention.dir.display(),
                    EVERY.as_secs()
                );
            }
        }
        match stop.recv_timeout(EVERY) {
            Err(RecvTimeoutError::Timeout) => {}
            Ok(()) | Err(RecvTimeoutError::Disconnected) => return,
        }
    }
}
