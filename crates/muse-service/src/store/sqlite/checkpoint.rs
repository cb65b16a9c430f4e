//! The WAL checkpointer: a thread with its own connection that copies committed pages from the
//! WAL into the database file now and then, so that the planner task's commits never wait for
//! it (`wal_autocheckpoint` is off on the writing connection).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use super::StoreError;

/// How often the WAL is checkpointed. Each pass syncs the WAL and the database file, and
/// copies every page changed since the last pass once, however often it changed: passes
/// further apart copy and sync less per answer (measured: a tenth of a second apart cost
/// several microseconds more per answer under closed-loop load than half a second), at the
/// price of a longer WAL (about 0.5 s of commits: a few MiB) for a restart to read.
const EVERY: Duration = Duration::from_millis(500);

/// The running checkpointer; stops when dropped.
#[derive(Debug)]
pub(super) struct Checkpointer {
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Checkpointer {
    pub(super) fn start(db: &Path) -> Result<Checkpointer, StoreError> {
        // Checkpointing writes to the database file: this connection is not read-only.
        let conn = rusqlite::Connection::open(db).map_err(|error| StoreError::Sql {
            what: format!("opening {} for checkpoints", db.display()),
            error,
        })?;
        conn.execute_batch("PRAGMA busy_timeout = 10000; PRAGMA synchronous = FULL;")
            .map_err(super::sql("setting up the checkpointer"))?;
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::Builder::new()
            .name("muse-checkpoint".into())
            .spawn(move || {
                while !flag.load(Ordering::Acquire) {
                    std::thread::park_timeout(EVERY);
                    // A failed checkpoint loses nothing (the WAL keeps the pages); the next
                    // one tries again.
                    let _ = conn.execute_batch("PRAGMA wal_checkpoint(PASSIVE);");
                }
            })
            .map_err(|error| StoreError::Io {
                what: "starting the checkpoint thread".into(),
                error,
            })?;
        Ok(Checkpointer {
            stop,
            thread: Some(thread),
        })
    }
}

impl Drop for Checkpointer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}
