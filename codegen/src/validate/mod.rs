//! Validation of each variant's WGSL with naga: parse with naga's WGSL front end, validate with
//! all flags and only the capabilities the variant needs (what it declares, and the 64-bit
//! integer ones exactly when the printer wrote a 64-bit type), and map naga's errors (byte
//! ranges of the WGSL) back through the source map to the user's Rust span, naming the variant.
//!
//! Must not change the WGSL; a variant that fails here is a compile error.

use crate::back::wgsl::SourceMap;
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use proc_macro2::Span;

/// A validated naga module.
#[derive(Debug)]
pub struct Validated {
    /// naga's IR of the WGSL.
    pub module: naga::Module,
    /// Validation info (needed by the SPIR-V writer).
    pub info: ModuleInfo,
}

/// Capabilities every WebGPU device has (core WGSL features naga gates behind a capability:
/// `@builtin(sample_index)` and per-sample interpolation; `pack2x16float` and
/// `unpack2x16float`, which wgpu grants with the downlevel flag `SHADER_F16_IN_F32` that every
/// Vulkan, Metal, D3D12 and WebGPU device has).
pub const BASELINE: Capabilities =
    Capabilities::MULTISAMPLED_SHADING.union(Capabilities::SHADER_FLOAT16_IN_FLOAT32);

/// The capabilities of 64-bit integers: `u64` values and their atomic `min`/`max` on storage
/// buffers without a returned value (wgpu `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`).
pub const INT64: Capabilities =
    Capabilities::SHADER_INT64.union(Capabilities::SHADER_INT64_ATOMIC_MIN_MAX);

/// Capabilities a variant is validated with: the baseline plus exactly what it needs.
/// `subgroup` is what the variant declares (`requires(subgroup = ..)`); `int64` is whether its
/// WGSL uses a 64-bit type or literal ([`crate::back::wgsl::Printed::int64`]), so a variant
/// without one is validated without [`INT64`].
pub fn capabilities(subgroup: bool, int64: bool) -> Capabilities {
    let mut caps = BASELINE;
    if subgroup {
        caps |= Capabilities::SUBGROUP;
    }
    if int64 {
        caps |= INT64;
    }
    caps
}

fn error_at(
    map: &SourceMap,
    fallback: Span,
    variant: &str,
    wgsl: &str,
    what: &str,
    ranges: &[std::ops::Range<usize>],
    detail: &str,
) -> syn::Error {
    let span = ranges
        .iter()
        .find_map(|r| map.lookup(r.clone()))
        .unwrap_or(fallback);
    let snippet = ranges
        .first()
        .map(|r| {
            let line_start = wgsl[..r.start.min(wgsl.len())]
                .rfind('\n')
                .map_or(0, |i| i + 1);
            let line_end = wgsl[r.start.min(wgsl.len())..]
                .find('\n')
                .map_or(wgsl.len(), |i| r.start + i);
            format!(
                "\n  in generated WGSL: `{}`",
                wgsl[line_start..line_end].trim()
            )
        })
        .unwrap_or_default();
    syn::Error::new(
        span,
        format!("naga {what} failed for variant `{variant}`: {detail}{snippet}"),
    )
}

/// Parses and validates one variant with [`capabilities`]`(subgroup, int64)`.
pub fn validate(
    wgsl: &str,
    map: &SourceMap,
    subgroup: bool,
    int64: bool,
    variant: &str,
    fallback: Span,
    fn_span: &dyn Fn(&str) -> Option<Span>,
) -> syn::Result<Validated> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| {
        let ranges: Vec<_> = e.labels().filter_map(|(s, _)| s.to_range()).collect();
        let labels: Vec<_> = e
            .labels()
            .map(|(_, l)| l.to_string())
            .filter(|l| !l.is_empty())
            .collect();
        let detail = if labels.is_empty() {
            e.message().to_string()
        } else {
            format!("{} ({})", e.message(), labels.join("; "))
        };
        error_at(
            map,
            fallback,
            variant,
            wgsl,
            "WGSL parsing",
            &ranges,
            &detail,
        )
    })?;
    let mut validator = Validator::new(ValidationFlags::all(), capabilities(subgroup, int64));
    let info = validator.validate(&module).map_err(|e| {
        let ranges: Vec<_> = e.spans().filter_map(|(s, _)| s.to_range()).collect();
        let mut detail = e.as_inner().to_string();
        let mut source: Option<&dyn std::error::Error> = std::error::Error::source(e.as_inner());
        while let Some(s) = source {
            detail.push_str(": ");
            detail.push_str(&s.to_string());
            source = s.source();
        }
        // Errors without a location still name their function or entry point.
        let fallback = match e.as_inner() {
            naga::valid::ValidationError::EntryPoint { name, .. }
            | naga::valid::ValidationError::Function { name, .. } => {
                fn_span(name).unwrap_or(fallback)
            }
            _ => fallback,
        };
        error_at(map, fallback, variant, wgsl, "validation", &ranges, &detail)
    })?;
    Ok(Validated { module, info })
}
