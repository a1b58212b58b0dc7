//! A crate exporting one shader DSL library (`shared::tint`), so that the compile-fail suite
//! can name a library such a crate lacks.

/// The crate's libraries.
pub mod shared {
    /// One helper function, as a library other crates could use.
    #[shader_dsl::library]
    pub mod tint {
        pub fn tinted(c: Vec3) -> Vec3 {
            c * 0.5
        }
    }
}
