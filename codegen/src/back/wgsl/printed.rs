//! What printing one variant gives: its WGSL, the source map, and whether it needs 64-bit
//! integers.

use super::source_map::SourceMap;

/// One printed variant.
#[derive(Debug)]
pub struct Printed {
    /// The WGSL text.
    pub text: String,
    /// Where each range of the text came from.
    pub map: SourceMap,
    /// The text uses a 64-bit type (`u64`, `i64`, `atomic<u64>`) or literal: it needs naga's
    /// `SHADER_INT64` (and, for its atomics, `SHADER_INT64_ATOMIC_MIN_MAX`). Set by the
    /// printer whenever it prints a 64-bit type or literal, so it is exact for the text:
    /// every 64-bit value of a WGSL module starts at such a type (a declaration, parameter,
    /// struct member, conversion) or literal.
    pub int64: bool,
}
