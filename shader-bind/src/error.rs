//! Why a builder could not bind a variant's group.

use codegen::rt::Variant;

/// `module::variant`, for errors.
pub(crate) fn variant_name(variant: &Variant) -> String {
    format!("{}::{}", variant.module, variant.name())
}

/// Why a builder could not bind a variant's group.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BindError {
    /// The variant binds `binding`, and no resource was given for it.
    #[error(
        "bind group {group} of shader variant `{variant}` binds `{binding}` (binding {index}), \
         but the builder was given nothing for it"
    )]
    Missing {
        variant: String,
        group: u32,
        binding: &'static str,
        index: u32,
    },
    /// The resource given for `binding` does not fit it.
    #[error(
        "`{binding}` (group {group}, binding {index} of shader variant `{variant}`) needs \
         {expected}, but was given {given}"
    )]
    Mismatch {
        variant: String,
        group: u32,
        binding: &'static str,
        index: u32,
        expected: String,
        given: String,
    },
    /// The shader may write through `writable`, and `other` was given the same buffer: as a
    /// read binding (a usage conflict), or as a writable one over an overlapping range.
    #[error(
        "`{writable}` and `{other}` (group {group} of shader variant `{variant}`) were given \
         the same buffer, and the shader writes `{writable}`: give `{writable}` a buffer of its \
         own (two writable bindings may share one in ranges that do not overlap)"
    )]
    WritableAlias {
        variant: String,
        group: u32,
        writable: &'static str,
        other: &'static str,
    },
    /// The variant binds nothing in `group`.
    #[error("shader variant `{variant}` has no bind group {group}")]
    NoGroup { variant: String, group: u32 },
}
