//! Outputs being written, removed when the run is interrupted: on SIGINT (Ctrl-C) or SIGTERM,
//! every temporary folder or file of the run (`.NAME.partial-PID`) is removed and the process
//! exits with 128 + the signal's number (130, 143), as a shell reports a run a signal ended.
//!
//! The signals are listened for from the first temporary output on ([`guard`]), by a thread of
//! its own; until then they end the process as usual (nothing of the run is on disk yet).
//! Putting a folder in place ([`finish`]) is never cut in two: a signal arriving meanwhile is
//! acted on once the folder is in place.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard, Once, PoisonError};

/// The temporary outputs of the run, to remove if it is interrupted.
static TEMPORARY: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Set once an interruption is being acted on.
static STOPPING: AtomicBool = AtomicBool::new(false);

/// Starts the listening thread once.
static LISTENING: Once = Once::new();

fn temporary() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARY.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Registers `path`, a temporary output about to be made, to be removed if the run is
/// interrupted; the first call starts listening for SIGINT and SIGTERM.
pub(super) fn guard(path: &Path) {
    LISTENING.call_once(|| {
        // Without the listener (it could not start), a signal ends the run as it did before:
        // its temporary outputs stay, for the next run into the same place to remove.
        let _ = listen();
    });
    temporary().push(path.to_owned());
}

/// Forgets `path`: it was removed, or put in place.
pub(super) fn release(path: &Path) {
    temporary().retain(|p| p != path);
}

/// Runs `f`, which puts the temporary output `path` in place, with interruptions held off;
/// forgets `path` if `f` succeeds.
pub(super) fn finish<T>(path: &Path, f: impl FnOnce() -> anyhow::Result<T>) -> anyhow::Result<T> {
    let mut list = temporary();
    let done = f();
    if done.is_ok() {
        list.retain(|p| p != path);
    }
    done
}

/// Waits for the process to end if an interruption is being acted on: an error the removal
/// of the run's outputs caused (a file written into a folder just removed) is not reported.
pub fn hold_if_interrupted() {
    if STOPPING.load(Ordering::SeqCst) {
        // The listening thread holds the list until it ends the process.
        let _list = temporary();
    }
}

/// Listens for SIGINT and SIGTERM on a thread of its own: each is registered before this
/// returns, so no signal is missed once the first temporary output exists.
#[cfg(unix)]
fn listen() -> std::io::Result<()> {
    use tokio::signal::unix::{SignalKind, signal};
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    let (mut interrupt, mut terminate) = {
        let _entered = runtime.enter();
        (
            signal(SignalKind::interrupt())?,
            signal(SignalKind::terminate())?,
        )
    };
    std::thread::Builder::new()
        .name("muse-interrupt".into())
        .spawn(move || {
            let (name, code) = runtime.block_on(async {
                tokio::select! {
                    _ = interrupt.recv() => ("SIGINT", 130),
                    _ = terminate.recv() => ("SIGTERM", 143),
                }
            });
            stop(name, code)
        })?;
    Ok(())
}

#[cfg(not(unix))]
fn listen() -> std::io::Result<()> {
    Ok(())
}

/// Removes the run's temporary outputs and ends the process with `code`, holding the list
/// until the end so that nothing is added or put in place meanwhile.
fn stop(signal: &str, code: i32) -> ! {
    let list = temporary();
    STOPPING.store(true, Ordering::SeqCst);
    for path in list.iter() {
        remove(path);
    }
    eprintln!("interrupted by {signal}: the run's unfinished outputs are removed");
    std::process::exit(code)
}

/// Removes a temporary folder or file; a folder the run is still writing into is removed again
/// until it is gone.
fn remove(path: &Path) {
    for _ in 0..10 {
        let gone = match std::fs::symlink_metadata(path) {
            Ok(m) if m.is_dir() => std::fs::remove_dir_all(path),
            Ok(_) => std::fs::remove_file(path),
            Err(e) => Err(e),
        };
        match gone {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {}
            _ => return,
        }
    }
}
