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

/// The first pair of `variant`'s group-`group` bindings given overlapping ranges of one buffer
/// where the shader may write one of them, as an error.
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
            if (writable(first) || writable(second)) && a.buffer == b.buffer && overlap(a, b) {
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

/// Whether two ranges of one buffer share a byte (a range without a size runs to the end).
fn overlap(a: &wgpu::BufferBinding<'_>, b: &wgpu::BufferBinding<'_>) -> bool {
    let end = |r: &wgpu::BufferBinding<'_>| {
        r.size
            .map_or(r.buffer.size(), |s| r.offset.saturating_add(s.get()))
    };
    a.offset < end(b) && b.offset < end(a)
}
