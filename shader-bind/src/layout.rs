//! Bind-group layout entries from the DSL's reflected bindings: what a pipeline's layouts are
//! built from, and what [`crate::Resources::build`] checks resources against.

use codegen::rt::{
    BindingKind, SampleType, StorageAccess, StorageFormat, Variant, ViewDimension, Visibility,
};

/// The layout entries of bind group `group` of `variant`, in binding order.
pub fn bind_group_layout_entries(variant: &Variant, group: u32) -> Vec<wgpu::BindGroupLayoutEntry> {
    variant
        .group(group)
        .map(|b| wgpu::BindGroupLayoutEntry {
            binding: b.binding,
            visibility: stages(b.visibility),
            ty: binding_type(b.kind),
            count: None,
        })
        .collect()
}

fn stages(v: Visibility) -> wgpu::ShaderStages {
    let mut s = wgpu::ShaderStages::NONE;
    s.set(wgpu::ShaderStages::COMPUTE, v.compute);
    s.set(wgpu::ShaderStages::VERTEX, v.vertex);
    s.set(wgpu::ShaderStages::FRAGMENT, v.fragment);
    s
}

pub(crate) fn binding_type(kind: BindingKind) -> wgpu::BindingType {
    match kind {
        BindingKind::Uniform { min_size } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(min_size),
        },
        BindingKind::Storage {
            read_only,
            min_size,
        } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(min_size),
        },
        BindingKind::Texture {
            sample_type,
            view_dimension,
            multisampled,
        } => wgpu::BindingType::Texture {
            sample_type: match sample_type {
                SampleType::Float { filterable } => wgpu::TextureSampleType::Float { filterable },
                SampleType::Depth => wgpu::TextureSampleType::Depth,
                SampleType::Uint => wgpu::TextureSampleType::Uint,
                SampleType::Sint => wgpu::TextureSampleType::Sint,
            },
            view_dimension: view_dimension_of(view_dimension),
            multisampled,
        },
        BindingKind::StorageTexture {
            format,
            access,
            view_dimension,
        } => wgpu::BindingType::StorageTexture {
            access: match access {
                StorageAccess::ReadOnly => wgpu::StorageTextureAccess::ReadOnly,
                StorageAccess::WriteOnly => wgpu::StorageTextureAccess::WriteOnly,
                StorageAccess::ReadWrite => wgpu::StorageTextureAccess::ReadWrite,
            },
            format: storage_format(format),
            view_dimension: view_dimension_of(view_dimension),
        },
        BindingKind::Sampler { comparison: true } => {
            wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison)
        }
        BindingKind::Sampler { comparison: false } => {
            wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering)
        }
    }
}

fn view_dimension_of(d: ViewDimension) -> wgpu::TextureViewDimension {
    match d {
        ViewDimension::D2 => wgpu::TextureViewDimension::D2,
        ViewDimension::D2Array => wgpu::TextureViewDimension::D2Array,
    }
}

/// The wgpu format of a DSL storage-texture format.
pub fn storage_format(f: StorageFormat) -> wgpu::TextureFormat {
    use wgpu::TextureFormat as T;
    match f {
        StorageFormat::Rgba8Unorm => T::Rgba8Unorm,
        StorageFormat::Rgba8Snorm => T::Rgba8Snorm,
        StorageFormat::Rgba8Uint => T::Rgba8Uint,
        StorageFormat::Rgba8Sint => T::Rgba8Sint,
        StorageFormat::Rgba16Uint => T::Rgba16Uint,
        StorageFormat::Rgba16Sint => T::Rgba16Sint,
        StorageFormat::Rgba16Float => T::Rgba16Float,
        StorageFormat::R32Uint => T::R32Uint,
        StorageFormat::R32Sint => T::R32Sint,
        StorageFormat::R32Float => T::R32Float,
        StorageFormat::Rg32Uint => T::Rg32Uint,
        StorageFormat::Rg32Sint => T::Rg32Sint,
        StorageFormat::Rg32Float => T::Rg32Float,
        StorageFormat::Rgba32Uint => T::Rgba32Uint,
        StorageFormat::Rgba32Sint => T::Rgba32Sint,
        StorageFormat::Rgba32Float => T::Rgba32Float,
        StorageFormat::Bgra8Unorm => T::Bgra8Unorm,
    }
}
