//! Who is calling (SPEC §10 ownership): bearer tokens from a TOML file, each naming an
//! operator and a role, and a request-rate limit per token.
//!
//! ```toml
//! [[tokens]]
//! token = "op-a-secret"
//! operator = "alpha"
//! role = "operator"
//!
//! [[tokens]]
//! token = "caa-secret"
//! operator = "caa"
//! role = "authority"
//! ```
//!
//! Without a tokens file the service is *open*: every caller is the operator `open` with the
//! authority role, and the service listens on loopback addresses only.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Mutex;
use std::time::Instant as WallInstant;

use serde::Deserialize;

/// The operator name every caller has in open mode.
pub const OPEN_OPERATOR: &str = "open";

/// What a caller may do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Plans, reads and cancels its own flights.
    Operator,
    /// Also reads every operator's flights and events, and announces and withdraws zones.
    Authority,
}

/// An authenticated caller.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Caller {
    /// The operator it acts for.
    pub operator: String,
    /// Its role.
    pub role: Role,
}

impl Caller {
    /// Whether the caller may read `operator`'s flights.
    pub fn may_read(&self, operator: &str) -> bool {
        self.role == Role::Authority || self.operator == operator
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TokensFile {
    tokens: Vec<TokenEntry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TokenEntry {
    token: String,
    operator: String,
    role: Role,
}

/// Errors reading a tokens file.
#[derive(Debug, thiserror::Error)]
pub enum TokensError {
    /// The file cannot be read.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The error.
        source: std::io::Error,
    },
    /// The file is not a valid tokens file.
    #[error("{file}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// What is wrong (with line and column for TOML errors).
        message: String,
    },
}

/// The callers the service knows.
#[derive(Debug)]
pub enum Tokens {
    /// No tokens: everyone is [`OPEN_OPERATOR`] with the authority role.
    Open,
    /// Bearer tokens and whom they name.
    Known(HashMap<String, Caller>),
}

impl Tokens {
    /// Reads a tokens file (see the module docs).
    pub fn read(path: &Path) -> Result<Tokens, TokensError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| TokensError::Io {
            file: file.clone(),
            source,
        })?;
        Tokens::parse(&text, &file)
    }

    /// Parses a tokens file's text.
    pub fn parse(text: &str, file: &str) -> Result<Tokens, TokensError> {
        let invalid = |message: String| TokensError::Invalid {
            file: file.to_owned(),
            message,
        };
        let parsed: TokensFile = toml::from_str(text).map_err(|e| invalid(e.to_string()))?;
        let mut map = HashMap::new();
        for (i, t) in parsed.tokens.into_iter().enumerate() {
            let at = format!("tokens[{i}]");
            if t.token.len() < 8 {
                return Err(invalid(format!(
                    "{at}: field `token`: too short (at least 8 characters)"
                )));
            }
            if t.operator.is_empty() {
                return Err(invalid(format!("{at}: field `operator`: empty")));
            }
            let caller = Caller {
                operator: t.operator,
                role: t.role,
            };
            if map.insert(t.token, caller).is_some() {
                return Err(invalid(format!("{at}: field `token`: used twice")));
            }
        }
        if map.is_empty() {
            return Err(invalid("no [[tokens]] entry".into()));
        }
        Ok(Tokens::Known(map))
    }

    /// Whether the service is open (no tokens).
    pub fn is_open(&self) -> bool {
        matches!(self, Tokens::Open)
    }

    /// The caller an `Authorization` header value names, if any.
    pub fn caller(&self, authorization: Option<&str>) -> Option<(String, Caller)> {
        match self {
            Tokens::Open => Some((
                OPEN_OPERATOR.to_owned(),
                Caller {
                    operator: OPEN_OPERATOR.to_owned(),
                    role: Role::Authority,
                },
            )),
            Tokens::Known(map) => {
                let token = authorization?.strip_prefix("Bearer ")?.trim();
                map.get(token).map(|c| (token.to_owned(), c.clone()))
            }
        }
    }
}

/// A token-bucket limit on requests per token: `rate` per second on average, bursts of up to
/// `burst`.
#[derive(Debug)]
pub struct RateLimiter {
    rate: f64,
    burst: f64,
    buckets: Mutex<HashMap<String, (f64, WallInstant)>>,
}

impl RateLimiter {
    /// A limiter allowing `rate` requests per second per token, bursts of `burst`.
    /// A `rate` of 0 disables the limit.
    pub fn new(rate: f64, burst: f64) -> Self {
        RateLimiter {
            rate,
            burst: burst.max(1.0),
            buckets: Mutex::new(HashMap::new()),
        }
    }

    /// Takes one request from `key`'s bucket; `Err(seconds)` to wait if it is empty.
    pub fn check(&self, key: &str) -> Result<(), f64> {
        if self.rate <= 0.0 {
            return Ok(());
        }
        let now = WallInstant::now();
        let mut buckets = self
            .buckets
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let (level, at) = buckets.entry(key.to_owned()).or_insert((self.burst, now));
        *level = (*level + now.duration_since(*at).as_secs_f64() * self.rate).min(self.burst);
        *at = now;
        if *level >= 1.0 {
            *level -= 1.0;
            Ok(())
        } else {
            Err((1.0 - *level) / self.rate)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_file_errors_are_named() {
        let e = Tokens::parse("[[tokens]]\ntoken = \"abcdefgh\"\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.toml: ") && e.contains("missing field `operator`"),
            "{e}"
        );
        let e = Tokens::parse(
            "[[tokens]]\ntoken = \"abcdefgh\"\noperator = \"a\"\nrole = \"king\"\n",
            "t.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("unknown variant `king`"), "{e}");
        let t = Tokens::parse(
            "[[tokens]]\ntoken = \"abcdefgh\"\noperator = \"a\"\nrole = \"operator\"\n",
            "t.toml",
        )
        .unwrap();
        assert_eq!(t.caller(Some("Bearer abcdefgh")).unwrap().1.operator, "a");
        assert!(t.caller(Some("Bearer nope")).is_none());
        assert!(t.caller(None).is_none());
    }

    #[test]
    fn rate_limit_refills() {
        let r = RateLimiter::new(1_000.0, 2.0);
        assert!(r.check("k").is_ok());
        assert!(r.check("k").is_ok());
        assert!(r.check("k").is_err());
        assert!(r.check("other").is_ok());
        std::thread::sleep(std::time::Duration::from_millis(5));
        assert!(r.check("k").is_ok());
    }
}
