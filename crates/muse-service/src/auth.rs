//! Who is calling (docs/reference.md#the-planning-service ownership): bearer tokens from a TOML
//! file, each naming an operator and a role, and a request-rate limit per token.
//!
//! ```toml
//! [[tokens]]
//! token = "op-a-secret-7f3k2q9x"
//! operator = "alpha"
//! role = "operator"
//!
//! [[tokens]]
//! token = "caa-secret-m4v8n1z6"
//! operator = "caa"
//! role = "authority"
//! ```
//!
//! A token has at least [`MIN_TOKEN_LEN`] characters. The tokens can be replaced while the
//! service runs ([`Tokens::reload`]; `muse serve` rereads its file on `SIGHUP`): a token
//! removed from the file is refused from then on, an added one accepted.
//!
//! Without a tokens file the service is *open*: every caller is the operator `open` with the
//! authority role, and the service listens on loopback addresses only.

use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex, PoisonError, RwLock};
use std::time::Instant as WallInstant;

use serde::Deserialize;

/// The operator name every caller has in open mode.
pub const OPEN_OPERATOR: &str = "open";

/// Fewest characters a token may have.
pub const MIN_TOKEN_LEN: usize = 16;

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
    /// The file cannot be read. (The I/O error is part of the message, not a `source`: a
    /// chain would print it twice.)
    #[error("{file}: cannot read: {error}")]
    Io {
        /// The file.
        file: String,
        /// The error.
        error: std::io::Error,
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
///
/// A clone shares the tokens: a [`Tokens::reload`] through any clone is seen by all of them
/// (`muse serve` keeps one to reload on `SIGHUP`, the service another to check callers).
#[derive(Clone, Debug)]
pub enum Tokens {
    /// No tokens: everyone is the operator `open` (`OPEN_OPERATOR`) with the authority role.
    Open,
    /// Bearer tokens and whom they name.
    Known(KnownTokens),
}

/// Bearer tokens and whom they name, replaceable as a whole while in use (see [`Tokens`]).
#[derive(Clone)]
pub struct KnownTokens(Arc<RwLock<HashMap<String, Caller>>>);

impl std::fmt::Debug for KnownTokens {
    /// The number of tokens, never the tokens.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "KnownTokens({} token(s))", self.len())
    }
}

impl KnownTokens {
    fn map(&self) -> std::sync::RwLockReadGuard<'_, HashMap<String, Caller>> {
        self.0.read().unwrap_or_else(PoisonError::into_inner)
    }

    /// How many tokens there are.
    pub fn len(&self) -> usize {
        self.map().len()
    }

    /// Whether there are none (never, for tokens read from a file).
    pub fn is_empty(&self) -> bool {
        self.map().is_empty()
    }
}

impl Tokens {
    /// Reads a tokens file (see the module docs).
    pub fn read(path: &Path) -> Result<Tokens, TokensError> {
        Ok(Tokens::Known(KnownTokens(Arc::new(RwLock::new(read_map(
            path,
        )?)))))
    }

    /// Parses a tokens file's text.
    pub fn parse(text: &str, file: &str) -> Result<Tokens, TokensError> {
        Ok(Tokens::Known(KnownTokens(Arc::new(RwLock::new(
            parse_map(text, file)?,
        )))))
    }

    /// Rereads the tokens from `path` and replaces them (for this value and all its clones),
    /// returning how many there are now. If the file cannot be read or is not a valid tokens
    /// file, the tokens in use are kept and the error names the file. An open service has no
    /// tokens to replace: that is an error too.
    pub fn reload(&self, path: &Path) -> Result<usize, TokensError> {
        let Tokens::Known(known) = self else {
            return Err(TokensError::Invalid {
                file: path.display().to_string(),
                message: "the service is open (started without tokens): there are no tokens \
                          to replace"
                    .into(),
            });
        };
        let map = read_map(path)?;
        let n = map.len();
        *known.0.write().unwrap_or_else(PoisonError::into_inner) = map;
        Ok(n)
    }

    /// Whether the service is open (no tokens).
    pub fn is_open(&self) -> bool {
        matches!(self, Tokens::Open)
    }

    /// How many tokens there are (0 when open).
    pub fn len(&self) -> usize {
        match self {
            Tokens::Open => 0,
            Tokens::Known(known) => known.len(),
        }
    }

    /// Whether there are no tokens (the service is open).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The caller an `Authorization` header value names, if any.
    pub(crate) fn caller(&self, authorization: Option<&str>) -> Option<(String, Caller)> {
        match self {
            Tokens::Open => Some((
                OPEN_OPERATOR.to_owned(),
                Caller {
                    operator: OPEN_OPERATOR.to_owned(),
                    role: Role::Authority,
                },
            )),
            Tokens::Known(known) => {
                let token = authorization?.strip_prefix("Bearer ")?.trim();
                known
                    .map()
                    .get(token)
                    .map(|c| (token.to_owned(), c.clone()))
            }
        }
    }
}

fn read_map(path: &Path) -> Result<HashMap<String, Caller>, TokensError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|error| TokensError::Io {
        file: file.clone(),
        error,
    })?;
    parse_map(&text, &file)
}

fn parse_map(text: &str, file: &str) -> Result<HashMap<String, Caller>, TokensError> {
    let invalid = |message: String| TokensError::Invalid {
        file: file.to_owned(),
        message,
    };
    let parsed: TokensFile = toml::from_str(text).map_err(|e| invalid(e.to_string()))?;
    let mut map = HashMap::new();
    for (i, t) in parsed.tokens.into_iter().enumerate() {
        let at = if t.operator.is_empty() {
            format!("tokens[{i}]")
        } else {
            format!("tokens[{i}] (operator `{}`)", t.operator)
        };
        let chars = t.token.chars().count();
        if chars < MIN_TOKEN_LEN {
            return Err(invalid(format!(
                "{at}: field `token`: too short ({chars} characters; at least {MIN_TOKEN_LEN})"
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
    Ok(map)
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
        self.check_at(key, WallInstant::now())
    }

    /// [`RateLimiter::check`] at the instant `now`.
    fn check_at(&self, key: &str, now: WallInstant) -> Result<(), f64> {
        if self.rate <= 0.0 {
            return Ok(());
        }
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

    const ONE: &str =
        "[[tokens]]\ntoken = \"abcdefgh-12345678\"\noperator = \"a\"\nrole = \"operator\"\n";

    #[test]
    fn tokens_file_errors_are_named() {
        let e = Tokens::parse("[[tokens]]\ntoken = \"abcdefgh-12345678\"\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.toml: ") && e.contains("missing field `operator`"),
            "{e}"
        );
        let e = Tokens::parse(
            "[[tokens]]\ntoken = \"abcdefgh-12345678\"\noperator = \"a\"\nrole = \"king\"\n",
            "t.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("unknown variant `king`"), "{e}");
        let t = Tokens::parse(ONE, "t.toml").unwrap();
        assert_eq!(
            t.caller(Some("Bearer abcdefgh-12345678"))
                .unwrap()
                .1
                .operator,
            "a"
        );
        assert!(t.caller(Some("Bearer nope")).is_none());
        assert!(t.caller(None).is_none());
        assert!(!format!("{t:?}").contains("abcdefgh"), "Debug hides tokens");
    }

    #[test]
    fn short_tokens_are_refused_by_entry() {
        let text = format!(
            "{ONE}\n[[tokens]]\ntoken = \"fifteen-chars-x\"\noperator = \"b\"\nrole = \"operator\"\n"
        );
        let e = Tokens::parse(&text, "t.toml").unwrap_err().to_string();
        assert_eq!(
            e,
            "t.toml: tokens[1] (operator `b`): field `token`: too short (15 characters; at least 16)"
        );
        // Characters, not bytes.
        let text =
            "[[tokens]]\ntoken = \"ééééééééééééééé\"\noperator = \"b\"\nrole = \"operator\"\n";
        assert!(Tokens::parse(text, "t.toml").is_err());
    }

    #[test]
    fn a_reload_is_seen_by_every_clone_and_a_bad_file_changes_nothing() {
        let dir = std::env::temp_dir().join(format!("muse-auth-reload-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("tokens.toml");
        std::fs::write(&path, ONE).unwrap();
        let held = Tokens::read(&path).unwrap();
        let service = held.clone();
        std::fs::write(
            &path,
            "[[tokens]]\ntoken = \"zyxwvuts-87654321\"\noperator = \"z\"\nrole = \"authority\"\n",
        )
        .unwrap();
        assert_eq!(held.reload(&path).unwrap(), 1);
        assert!(service.caller(Some("Bearer abcdefgh-12345678")).is_none());
        assert_eq!(
            service
                .caller(Some("Bearer zyxwvuts-87654321"))
                .unwrap()
                .1
                .role,
            Role::Authority
        );
        std::fs::write(&path, "[[tokens]]\ntoken = 1\n").unwrap();
        let e = held.reload(&path).unwrap_err().to_string();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        assert!(service.caller(Some("Bearer zyxwvuts-87654321")).is_some());
        assert!(Tokens::Open.reload(&path).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn rate_limit_refills() {
        // Instants given, not read: a slow machine cannot refill the bucket in between.
        let r = RateLimiter::new(1_000.0, 2.0);
        let t = WallInstant::now();
        assert!(r.check_at("k", t).is_ok());
        assert!(r.check_at("k", t).is_ok());
        assert!(r.check_at("k", t).is_err());
        assert!(r.check_at("other", t).is_ok());
        assert!(
            r.check_at("k", t + std::time::Duration::from_millis(5))
                .is_ok()
        );
    }
}
