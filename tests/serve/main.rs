//! The tests that run the real `muse serve` binary: its store's promises across SIGKILL and
//! damage (`store`), concurrent clients through repeated SIGKILLs (`crash`, `zones_crash`),
//! its HTTP limits on the binary (`http`) and `muse verify` of what it planned (`verify`).

/// What this area's tests share (tests/support): `muse serve` on a loopback port, scratch
/// folders.
#[path = "../support"]
mod support {
    mod serve;
    pub use serve::{scratch_dir, start};
}

mod crash;
mod http;
mod store;
mod verify;
mod zones_crash;
