//! `muse`: the command-line interface of MUSE.
//!
//! A thin layer over the library crates: it parses arguments, loads files or the embedded
//! Singapore default, calls the libraries and prints or writes their results.
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    match cli::run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
