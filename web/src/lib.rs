//! The renderer in a browser: the courtyard demo page on WebGPU.
//!
//! [`showcase`] builds what the page shows (the courtyard, its lights, shadows, decals and
//! particles, an orbit camera) the same way on every target; the browser test renders it
//! natively on lavapipe as the reference for the page's frame. On `wasm32` the crate also
//! exports the page's API to JavaScript (`WebDemo`, through wasm-bindgen), which
//! `cargo xtask web` builds and serves with `web/index.html`.

pub mod showcase;

#[cfg(target_arch = "wasm32")]
mod page;
