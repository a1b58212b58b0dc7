//! What a printed variant may use, beyond its axis values.

/// Options of one printed variant.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// The variant may use subgroup operations (subgroup builtin parameters are kept).
    pub subgroup: bool,
}
