//! Connecting to the PostgreSQL server, for the planner task, the handlers' reads and the
//! archiver alike.

use std::time::Duration;

use postgres::{Client, NoTls};

use crate::store::StoreError;

/// How long a connection may take to open.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(10);

/// Connects to the database at `url` (`label`: the URL without its password, for messages),
/// with the password in `PGPASSWORD` when the URL gives none, as PostgreSQL's own tools do.
pub(super) fn connect(url: &str, label: &str) -> Result<Client, StoreError> {
    let mut config: postgres::Config = url.parse().map_err(|error| StoreError::Postgres {
        what: format!("reading the URL {label}"),
        error,
    })?;
    config
        .connect_timeout(CONNECT_TIMEOUT)
        .application_name("muse serve");
    if config.get_password().is_none()
        && let Some(password) = std::env::var_os("PGPASSWORD")
    {
        config.password(password.as_encoded_bytes());
    }
    config.connect(NoTls).map_err(|error| StoreError::Postgres {
        what: format!("connecting to {label}"),
        error,
    })
}
