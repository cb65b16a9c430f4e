//! The viewer's tests in headless Chromium: the browser client itself (`cdp_selftest`), the
//! page `muse simulate` writes (`page`), what it tells the user (`truth`), a layered day
//! (`layers`) and the live page of `muse serve` (`live`). Each is skipped with a notice when Chromium is not installed, unless
//! `CI` is set.

/// What this area's tests share (tests/support): `muse serve` on a loopback port, scratch
/// folders; [`cdp`](support::cdp) is the small client of CDP (Chrome's debugging protocol) that drives
/// Chromium; [`viewer`](support::viewer) what the tests of `view.html` share.
#[path = "../support"]
mod support {
    pub mod cdp;
    mod serve;
    pub mod viewer;
    pub use serve::{scratch_dir, start};
}

mod cdp_selftest;
mod layers;
mod live;
mod page;
mod truth;
