//! Bind groups built by binding name against a shader DSL variant's reflected layout.
//!
//! The shader DSL reflects every binding of every variant (`codegen::rt::Variant::bindings`:
//! name, group, binding number, kind). For every bind group a DSL module or library declares,
//! it also generates a *builder*: a struct with one field per binding, named as the `static` in
//! the DSL (lower case) and typed by its kind ([`wgpu::BufferBinding`] for uniform and storage
//! buffers, [`wgpu::TextureView`] for sampled and storage textures, [`wgpu::Sampler`] for
//! samplers), and one field per library of the module that declares bindings in that group,
//! holding that library's own builder. A library that owns a binding contract (a shadow atlas,
//! a set of light lists) thus exports its part, and every module that uses the library binds
//! those resources through the same part.
//!
//! The generated `bind_group` collects the fields into [`Resources`] and calls
//! [`Resources::build`], which numbers them from the variant's reflection, so no binding number
//! is written on the host. It checks what it can before wgpu does, with a typed
//! [`BindError`] naming the binding:
//! - every binding the variant has in the group must be given (a binding declared
//!   `#[when(..)]` is an `Option` field; resources the variant does not use are left out, so
//!   one builder serves every variant of a module);
//! - a buffer must have the usage its binding needs (`UNIFORM` or `STORAGE`) and at least the
//!   binding's minimum size;
//! - a texture must be multisampled exactly when the binding is, have a depth format for a depth
//!   binding, integer texels for an integer binding, float (or depth) texels for a float binding,
//!   the `STORAGE_BINDING` usage and the declared format for a storage texture;
//! - a sampler can only be given where a sampler is bound (the field's type);
//! - a buffer bound where the shader may write it is bound nowhere else in the group, but for
//!   another writable binding over a range that does not overlap (a read binding of the same
//!   buffer is a usage conflict for WebGPU and wgpu alike; overlapping writable ranges WebGPU
//!   refuses and native backends let race).
//!
//! [`driver_module`] gives a Vulkan driver a variant's own build-time SPIR-V, for the variants
//! whose SPIR-V wgpu would write invalidly (a `sample_mask` built-in).
//!
//! A crate that uses the DSL depends on this crate (the generated builders name
//! `::shader_bind`), and through it on wgpu.

mod check;
mod driver_spirv;
mod error;
mod layout;
mod resource;

pub use driver_spirv::driver_module;
pub use error::BindError;
pub use layout::{bind_group_layout_entries, storage_format};
pub use resource::{BoundResource, Resource};
pub use wgpu;

use codegen::rt::Variant;

/// A builder's resources by binding name (the DSL `static`'s name), as the generated
/// [`GroupResources::collect`] gathers them; a `None` is a `#[when(..)]` binding left empty.
#[derive(Debug, Default, Clone)]
pub struct Resources<'a> {
    named: Vec<(&'static str, Option<Resource<'a>>)>,
}

/// What a generated builder (or a library's part of one) gives to [`Resources`].
pub trait GroupResources<'a> {
    /// Adds every field's resource under its binding's DSL name, and every library part's.
    fn collect(&self, out: &mut Resources<'a>);
}

impl<'a> Resources<'a> {
    /// No resources yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The resources of `builder`.
    pub fn of(builder: &impl GroupResources<'a>) -> Self {
        let mut out = Self::new();
        builder.collect(&mut out);
        out
    }

    /// Adds the resource bound to the DSL `static` named `name` (`None`: not given).
    pub fn push(&mut self, name: &'static str, resource: Option<Resource<'a>>) {
        self.named.push((name, resource));
    }

    /// The resource given for the binding named `name`, if any.
    pub fn get(&self, name: &str) -> Option<&Resource<'a>> {
        self.named
            .iter()
            .find(|(n, _)| *n == name)
            .and_then(|(_, r)| r.as_ref())
    }

    /// Every resource given, owned, by binding name: what a bind group built from these
    /// resources holds, for a tool that reads it back after the GPU ran (a host replay of a
    /// kernel).
    pub fn snapshot(&self) -> Vec<(&'static str, BoundResource)> {
        self.named
            .iter()
            .filter_map(|(name, r)| r.as_ref().map(|r| (*name, BoundResource::from(r))))
            .collect()
    }

    /// The bind-group entries of group `group` of `variant`: every binding the variant has
    /// there, numbered from its reflection, each checked against what it was given.
    pub fn entries(
        &self,
        variant: &Variant,
        group: u32,
    ) -> Result<Vec<wgpu::BindGroupEntry<'a>>, BindError> {
        if variant.group(group).next().is_none() {
            return Err(BindError::NoGroup {
                variant: error::variant_name(variant),
                group,
            });
        }
        let entries = variant
            .group(group)
            .map(|binding| {
                let at = check::Site::new(variant, binding);
                let resource = self.get(binding.name).ok_or_else(|| at.missing())?;
                check::compatible(&at, binding.kind, resource)?;
                Ok(wgpu::BindGroupEntry {
                    binding: binding.binding,
                    resource: check::binding_resource(resource),
                })
            })
            .collect::<Result<Vec<_>, BindError>>()?;
        check::no_writable_alias(variant, group, |name| self.get(name))?;
        Ok(entries)
    }

    /// Builds bind group `group` of `variant` on `layout` (a layout made from the same
    /// variant's group, as `bind_group_layout_entries` makes it).
    pub fn build(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        variant: &Variant,
        group: u32,
        label: &str,
    ) -> Result<wgpu::BindGroup, BindError> {
        let entries = self.entries(variant, group)?;
        Ok(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &entries,
        }))
    }
}
