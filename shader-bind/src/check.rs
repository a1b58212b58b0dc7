//! Whether a resource fits a reflected binding, checked before wgpu sees it so that the error
//! names the binding as the DSL declares it.

use codegen::rt::{Binding, BindingKind, SampleType, Variant};

use crate::error::{BindError, variant_name};
use crate::resource::Resource;

/// Where a check happens: the binding and its variant, named only when an error is made (the
/// checks run for every binding of every bind group a frame builds).
pub(crate) struct Site<'v> {
    variant: &'v Variant,
    binding: &'static Binding,
}

impl<'v> Site<'v> {
    pub(crate) fn new(variant: &'v Variant, binding: &'static Binding) -> Self {
        Self { variant, binding }
    }

    pub(crate) fn missing(&self) -> BindError {
        BindError::Missing {
            variant: variant_name(self.variant),
            group: self.binding.group,
            binding: self.binding.name,
            index: self.binding.binding,
        }
    }

    fn mismatch(&self, expected: impl Into<String>, given: impl Into<String>) -> BindError {
        BindError::Mismatch {
            variant: variant_name(self.variant),
            group: self.binding.group,
            binding: self.binding.name,
            index: self.binding.binding,
            expected: expected.into(),
            given: given.into(),
        }
    }
}

/// The wgpu resource of `r`.
pub(crate) fn binding_resource<'a>(r: &Resource<'a>) -> wgpu::BindingResource<'a> {
    match r {
        Resource::Buffer(b) => wgpu::BindingResource::Buffer(b.clone()),
        Resource::Texture(v) => wgpu::BindingResource::TextureView(v),
        Resource::Sampler(s) => wgpu::BindingResource::Sampler(s),
    }
}

/// `Ok` when `r` fits a binding of `kind`.
pub(crate) fn compatible(
    at: &Site<'_>,
    kind: BindingKind,
    r: &Resource<'_>,
) -> Result<(), BindError> {
    match (kind, r) {
        (BindingKind::Uniform { min_size }, Resource::Buffer(b)) => buffer(
            at,
            b,
            wgpu::BufferUsages::UNIFORM,
            "a uniform buffer",
            min_size,
        ),
        (BindingKind::Storage { min_size, .. }, Resource::Buffer(b)) => buffer(
            at,
            b,
            wgpu::BufferUsages::STORAGE,
            "a storage buffer",
            min_size,
        ),
        (
            BindingKind::Texture {
                sample_type,
                multisampled,
                ..
            },
            Resource::Texture(view),
        ) => sampled(at, view.texture(), sample_type, multisampled),
        (BindingKind::StorageTexture { format, .. }, Resource::Texture(view)) => {
            let texture = view.texture();
            let wanted = crate::layout::storage_format(format);
            if !texture
                .usage()
                .contains(wgpu::TextureUsages::STORAGE_BINDING)
            {
                return Err(at.mismatch(
                    "a texture with the STORAGE_BINDING usage",
                    format!("one with {:?}", texture.usage()),
                ));
            }
            if texture.format() != wanted {
                return Err(at.mismatch(
                    format!("a {wanted:?} storage texture"),
                    format!("a {:?} texture", texture.format()),
                ));
            }
            Ok(())
        }
        (BindingKind::Sampler { .. }, Resource::Sampler(_)) => Ok(()),
        (kind, r) => Err(at.mismatch(kind_name(kind), resource_name(r))),
    }
}

fn buffer(
    at: &Site<'_>,
    b: &wgpu::BufferBinding<'_>,
    usage: wgpu::BufferUsages,
    what: &str,
    min_size: u64,
) -> Result<(), BindError> {
    if !b.buffer.usage().contains(usage) {
        return Err(at.mismatch(
            format!("{what} (usage {usage:?})"),
            format!("a buffer with usage {:?}", b.buffer.usage()),
        ));
    }
    let size = b.size.map_or_else(
        || b.buffer.size().saturating_sub(b.offset),
        std::num::NonZero::get,
    );
    if size < min_size {
        return Err(at.mismatch(
            format!("{what} of at least {min_size} bytes"),
            format!("{size} bytes"),
        ));
    }
    Ok(())
}

fn sampled(
    at: &Site<'_>,
    texture: &wgpu::Texture,
    sample_type: SampleType,
    multisampled: bool,
) -> Result<(), BindError> {
    let samples = texture.sample_count();
    if (samples > 1) != multisampled {
        let wanted = if multisampled {
            "a multisampled texture"
        } else {
            "a single-sampled texture"
        };
        return Err(at.mismatch(wanted, format!("one of {samples} samples")));
    }
    let format = texture.format();
    let texels = if format.has_depth_aspect() {
        Texels::Depth
    } else {
        match format.sample_type(None, None) {
            Some(wgpu::TextureSampleType::Uint) => Texels::Uint,
            Some(wgpu::TextureSampleType::Sint) => Texels::Sint,
            _ => Texels::Float,
        }
    };
    let fits = match sample_type {
        // A depth texture may also be read as unfilterable floats.
        SampleType::Float { filterable } => {
            texels == Texels::Float || (texels == Texels::Depth && !filterable)
        }
        SampleType::Depth => texels == Texels::Depth,
        SampleType::Uint => texels == Texels::Uint,
        SampleType::Sint => texels == Texels::Sint,
    };
    if fits {
        Ok(())
    } else {
        Err(at.mismatch(
            format!("a texture of {sample_type:?} texels"),
            format!("a {format:?} texture"),
        ))
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Texels {
    Float,
    Depth,
    Uint,
    Sint,
}

fn kind_name(kind: BindingKind) -> &'static str {
    match kind {
        BindingKind::Uniform { .. } => "a uniform buffer",
        BindingKind::Storage { .. } => "a storage buffer",
        BindingKind::Texture { .. } => "a sampled texture",
        BindingKind::StorageTexture { .. } => "a storage texture",
        BindingKind::Sampler { .. } => "a sampler",
    }
}

fn resource_name(r: &Resource<'_>) -> &'static str {
    match r {
        Resource::Buffer(_) => "a buffer",
        Resource::Texture(_) => "a texture view",
        Resource::Sampler(_) => "a sampler",
    }
}

/// The first pair of `variant`'s group-`group` bindings that may not share their buffer, as an
/// error: a binding the shader may write and any other binding of the same buffer (a usage
/// conflict, for WebGPU and wgpu alike), except a second writable binding whose range does not
/// overlap it (WebGPU refuses overlapping writable ranges; native backends let them race).
pub(crate) fn no_writable_alias<'a>(
    variant: &Variant,
    group: u32,
    given: impl Fn(&str) -> Option<&'a Resource<'a>>,
) -> Result<(), BindError> {
    let buffers: Vec<(&Binding, &wgpu::BufferBinding<'a>)> = variant
        .group(group)
        .filter_map(|b| match given(b.name) {
            Some(Resource::Buffer(range)) => Some((b, range)),
            _ => None,
        })
        .collect();
    let writable = |b: &Binding| {
        matches!(
            b.kind,
            BindingKind::Storage {
                read_only: false,
                ..
            }
        )
    };
    for (i, (first, a)) in buffers.iter().enumerate() {
        for (second, b) in &buffers[i + 1..] {
            let conflict = match (writable(first), writable(second)) {
                (false, false) => false,
                (true, true) => overlap(byte_range(a), byte_range(b)),
                _ => true,
            };
            if conflict && a.buffer == b.buffer {
                let (writable, other) = if writable(first) {
                    (first.name, second.name)
                } else {
                    (second.name, first.name)
                };
                return Err(BindError::WritableAlias {
                    variant: variant_name(variant),
                    group,
                    writable,
                    other,
                });
            }
        }
    }
    Ok(())
}

/// The bytes `[start, end)` a binding covers (one without a size runs to the buffer's end).
fn byte_range(r: &wgpu::BufferBinding<'_>) -> (u64, u64) {
    let end = r
        .size
        .map_or(r.buffer.size(), |s| r.offset.saturating_add(s.get()));
    (r.offset, end)
}

/// Whether two byte ranges `[start, end)` share a byte.
fn overlap(a: (u64, u64), b: (u64, u64)) -> bool {
    a.0 < b.1 && b.0 < a.1
}

#[cfg(test)]
mod tests {
    use super::overlap;

    #[test]
    fn ranges_overlap_when_they_share_a_byte() {
        assert!(overlap((0, 16), (15, 32)));
        assert!(overlap((8, 9), (0, 16)));
        assert!(!overlap((0, 16), (16, 32)));
        assert!(!overlap((16, 32), (0, 16)));
        assert!(!overlap((0, 0), (0, 16)));
    }
}
