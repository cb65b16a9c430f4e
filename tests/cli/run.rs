//! Running `muse` as a user does, and reading what it says and writes.

use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

/// Runs `muse` with `args` in the current folder and waits for it.
pub fn muse(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(args)
        .output()
        .expect("muse runs")
}

/// Its standard output.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Its standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Its standard output and error, for assertion messages.
pub fn said(o: &Output) -> String {
    format!("{}{}", stdout(o), stderr(o))
}

/// A JSON file `muse` wrote.
pub fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
