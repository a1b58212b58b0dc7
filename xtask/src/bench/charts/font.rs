//! The charts' font: DejaVu Sans, embedded in the binary (`xtask/assets/fonts`, with its licence)
//! and rasterised by plotters' pure-Rust `ab_glyph` backend. No system font is read, so a chart
//! has the same pixels on every machine, and a machine without fonts draws it too.

use std::sync::OnceLock;

use anyhow::Result;
use plotters::style::FontStyle;

/// The family name the embedded font is registered under (plotters' default family).
pub(crate) const FONT: &str = "sans-serif";

/// DejaVu Sans 2.37 (Bitstream Vera licence: `xtask/assets/fonts/LICENSE-DejaVu.txt`).
pub(crate) const FONT_TTF: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/fonts/DejaVuSans.ttf"
));

/// Registers the embedded font for plotters under [`FONT`], once per process.
pub(crate) fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    let registered = REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_TTF)
            .map_err(|_| "the embedded chart font (DejaVu Sans) is not a valid font".to_owned())
    });
    registered.clone().map_err(anyhow::Error::msg)
}
