//! Where a test's `muse serve` keeps its store: a scratch folder or a database on the
//! throwaway PostgreSQL (the tests that run on both).

use std::path::PathBuf;

use super::serve::{Server, scratch_dir, start_with};

/// Where a test's `muse serve` keeps its store: a scratch folder (`--data`), or a database of
/// its own on the throwaway PostgreSQL the test process shares (`--store`).
#[derive(Clone, Debug)]
pub enum StoreArg {
    /// `--data DIR`.
    Folder(PathBuf),
    /// `--store URL`.
    Postgres(String),
}

impl StoreArg {
    /// A fresh store named `name` of the kind `postgres` says; `None` where PostgreSQL is not
    /// installed (the test is skipped, saying so; a failure under CI).
    pub fn fresh(name: &str, postgres: bool) -> Option<StoreArg> {
        if postgres {
            let pg = super::throwaway_pg::Throwaway::shared()?;
            Some(StoreArg::Postgres(pg.database(name)))
        } else {
            Some(StoreArg::Folder(scratch_dir(name)))
        }
    }

    /// The options that name it.
    pub fn args(&self) -> Vec<String> {
        match self {
            StoreArg::Folder(dir) => vec!["--data".into(), dir.display().to_string()],
            StoreArg::Postgres(url) => vec!["--store".into(), url.clone()],
        }
    }

    /// Removes a scratch folder (a database stays until the cluster is removed).
    pub fn remove(&self) {
        if let StoreArg::Folder(dir) = self {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// Starts `muse serve --listen 127.0.0.1:0` on `store` with `extra` arguments.
pub fn start_on(store: &StoreArg, extra: &[&str]) -> Server {
    let named = store.args();
    let named: Vec<&str> = named.iter().map(String::as_str).collect();
    start_with(&[extra, &named].concat())
}
