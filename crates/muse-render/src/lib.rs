//! muse-render
