//! `muse`: the command-line interface.
fn main() {}
