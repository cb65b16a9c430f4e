//! The service's tests on a real server on an ephemeral loopback port: the API (`api`), the
//! HTTP limits (`http_limits`) and the conversion of an earlier version's log (`import`);
//! and the throwaway PostgreSQL the replicated store's tests start (`throwaway_pg`).

mod api;
mod damage;
mod http_limits;
mod import;
mod throwaway_pg;
