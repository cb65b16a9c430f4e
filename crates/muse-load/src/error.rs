//! Why a load run could not be made. (Failed requests *during* a run are not errors: they are
//! counted by kind in the report.)

/// Why a load run could not start or finish.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The options are inconsistent.
    #[error("{0}")]
    Config(String),
    /// No connection to the service.
    #[error(
        "cannot reach the MUSE service at {url}: {cause} (is `muse serve` running there? \
         see --url)"
    )]
    Unreachable {
        /// The base URL.
        url: String,
        /// What failed, with its causes.
        cause: String,
    },
    /// The service answered with an error status.
    #[error("{what}: the service answered {status}{}", detail(.message))]
    Http {
        /// The request, e.g. `GET /v1/airspace`.
        what: String,
        /// The HTTP status code.
        status: u16,
        /// The error message of the answer, if any.
        message: String,
    },
    /// The service's answer could not be understood.
    #[error("{what}: unexpected answer from the service: {message}")]
    BadAnswer {
        /// The request, e.g. `GET /healthz`.
        what: String,
        /// What is wrong with it.
        message: String,
    },
}

fn detail(message: &str) -> String {
    if message.is_empty() {
        String::new()
    } else {
        format!(": {message}")
    }
}

impl LoadError {
    /// A [`LoadError::BadAnswer`].
    pub fn bad_answer(what: impl Into<String>, message: impl std::fmt::Display) -> Self {
        LoadError::BadAnswer {
            what: what.into(),
            message: message.to_string(),
        }
    }
}
