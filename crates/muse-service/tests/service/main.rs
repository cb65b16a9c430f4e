//! The service's tests on a real server on an ephemeral loopback port: the API (`api`, each
//! test on both stores: a data folder and a PostgreSQL database), the HTTP limits
//! (`http_limits`), damage to the SQLite store (`damage`) and to the PostgreSQL store
//! (`pg_damage`), several services on one PostgreSQL store (`standby`), archiving (`archive`, on both stores), the conversion of an earlier version's log (`import`); and the throwaway
//! PostgreSQL the tests start (`throwaway_pg`).

mod api;
mod archive;
mod damage;
mod http_limits;
mod import;
mod pg_damage;
mod standby;
/// The throwaway PostgreSQL, shared with the binary's tests (tests/support).
#[path = "../../../../tests/support/throwaway_pg.rs"]
mod throwaway_pg;
