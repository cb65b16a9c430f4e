//! The viewer's tests in headless Chromium: the browser client itself (`cdp_selftest`), the
//! page `muse simulate` writes (`page`), what it tells the user (`truth`) and the live page of
//! `muse serve` (`live`). Each is skipped with a notice when Chromium is not installed, unless
//! `CI` is set.

#[path = "../support/mod.rs"]
mod support;

mod cdp_selftest;
mod live;
mod page;
mod truth;
