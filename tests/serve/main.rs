//! The tests that run the real `muse serve` binary: its store's promises across SIGKILL and
//! damage (`store`), concurrent clients through repeated SIGKILLs (`crash`, `zones_crash`, each
//! on a data folder and on a PostgreSQL store),
//! its HTTP limits on the binary (`http`), `muse verify` of what it planned (`verify`), and three
//! services on one PostgreSQL store whose leader is killed again and again (`failover`).

/// What this area's tests share (tests/support): `muse serve` on a loopback port, scratch
/// folders, stores of both kinds, the throwaway PostgreSQL.
#[path = "../support"]
mod support {
    mod serve;
    mod stores;
    // Shared with the service crate's tests, which use the rest of it.
    #[allow(dead_code)]
    pub mod throwaway_pg;
    pub use serve::{Server, scratch_dir, start, start_with};
    pub use stores::{StoreArg, start_on};
}

mod crash;
mod failover;
mod http;
mod store;
mod verify;
mod zones_crash;
