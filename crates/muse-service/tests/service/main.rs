//! The service's tests on a real server on an ephemeral loopback port: the API (`api`), the
//! HTTP limits (`http_limits`) and the conversion of an earlier version's log (`import`).

mod api;
mod damage;
mod http_limits;
mod import;
