//! The MUSE viewer: one self-contained HTML page that plays a day of deliveries.
//!
//! A [`Scene`] is everything the page draws — the land outline, corridors and stations, the
//! no-fly zones with their active windows and announcement instants, every flight's stays,
//! the requests that did not fly with their reasons, and the day's summary — as compact
//! JSON. [`page`] embeds it, with the page's own script and style (the front-end in this
//! crate's `web/` folder, built into the binary), into one HTML file that needs no network
//! at all: no tiles, no CDN, no fonts.
//!
//! The same page serves `muse serve`'s live view: [`live_page`] embeds the map layers only,
//! and the script fills in the flights from the service's API and its events stream.
//!
//! ```
//! use muse_model::{Airspace, UtcOffset, Instant};
//! use muse_view::{SceneInput, page, scene};
//! let airspace = Airspace::line(&[1_000.0]);
//! let input = SceneInput::new(&airspace, UtcOffset::SINGAPORE, (Instant(0), Instant(3_600_000)));
//! let html = page(&scene(&input).unwrap());
//! assert!(html.starts_with("<!doctype html>") && html.contains("museView"));
//! ```
#![cfg_attr(not(test), warn(unused_crate_dependencies))]

mod html;
mod scene;

pub use html::{live_page, page};
pub use scene::{
    Scene, SceneFlight, SceneInput, SceneNode, SceneReason, SceneUnflown, SceneZone, scene,
};

/// Why a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// A zone's schedule or area could not be resolved over the day.
    #[error("zone `{zone}`: {message}")]
    Zone {
        /// The zone's id.
        zone: String,
        /// What went wrong.
        message: String,
    },
    /// A flight's stays name a station that is not in the airspace.
    #[error("flight `{flight}`: {message}")]
    Flight {
        /// The request id.
        flight: String,
        /// What went wrong.
        message: String,
    },
}
