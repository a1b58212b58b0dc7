//! Typed bind-group builders: for every bind group a module or library declares, a struct
//! `Group<N>` with a field per binding the module (or library) declares itself, named as the
//! `static` in lower case and typed by its kind, plus, in a module, a field per used library
//! that declares bindings in the group, holding that library's own `Group<N>` (a library's
//! builders hold its own bindings only). Its
//! `bind_group` builds the `wgpu::BindGroup` through `::shader_bind`, which numbers the
//! resources from the variant's reflection and checks each against its binding.

use crate::Compiled;
use crate::ir::{Global, Space, Ty};
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};

/// The groups where `globals` declare bindings, ascending.
pub(crate) fn declared_groups<'a>(globals: impl Iterator<Item = &'a Global>) -> Vec<u32> {
    let mut groups: Vec<u32> = globals.filter_map(|g| g.binding.map(|b| b.0)).collect();
    groups.sort_unstable();
    groups.dedup();
    groups
}

/// The module's (or library's) own resource statics: not merged in from a library.
fn own_bindings(c: &Compiled) -> impl Iterator<Item = &Global> {
    c.module
        .globals
        .iter()
        .filter(|g| !g.from_library && g.binding.is_some())
}

/// The libraries whose parts a builder of `c` holds: every library a module reaches; none for
/// a library, whose builders hold its own bindings only (a module lists each library it
/// reaches once, so a library used through another is not bound twice).
fn parts(c: &Compiled) -> impl Iterator<Item = &crate::pipeline::LinkedLibrary> {
    c.libraries.iter().filter(|_| !c.module.library)
}

/// A field name for a DSL name: lower case, raw where it is a Rust keyword.
fn field_ident(name: &str) -> Ident {
    let lower = name.to_lowercase();
    if syn::parse_str::<Ident>(&lower).is_ok() {
        Ident::new(&lower, Span::call_site())
    } else {
        Ident::new_raw(&lower, Span::call_site())
    }
}

/// The field type of a binding, and how its kind reads in the field's documentation.
fn field_type(g: &Global) -> (TokenStream, &'static str) {
    let w = quote!(::shader_bind::wgpu);
    let (ty, what) = match (&g.space, &g.ty) {
        (Space::Uniform, _) => (quote!(#w::BufferBinding<'a>), "uniform buffer"),
        (Space::Storage { .. }, _) => (quote!(#w::BufferBinding<'a>), "storage buffer"),
        (_, Ty::Sampler { comparison: true }) => (quote!(&'a #w::Sampler), "comparison sampler"),
        (_, Ty::Sampler { .. }) => (quote!(&'a #w::Sampler), "sampler"),
        (_, Ty::StorageTexture(..)) => (quote!(&'a #w::TextureView), "storage texture view"),
        _ => (quote!(&'a #w::TextureView), "sampled texture view"),
    };
    if g.when.is_some() {
        (quote!(::core::option::Option<#ty>), what)
    } else {
        (ty, what)
    }
}

/// Where the generated builders take the resource of the static `name` in `c`, as Rust reads
/// it: `Group0.camera` for the module's (or library's) own binding, `Group0.shadow_atlas.shadow_views`
/// for a binding a reached library declares; `None` for a static without a binding.
pub fn builder_field(c: &Compiled, name: &str) -> Option<String> {
    let g = c.module.globals.iter().find(|g| g.name == name)?;
    let group = g.binding?.0;
    let field = field_ident(name);
    if !g.from_library {
        return Some(format!("Group{group}.{field}"));
    }
    let lib = parts(c).find(|l| l.bindings.iter().any(|b| b == name))?;
    let part = &lib.path.segments.last()?.ident;
    Some(format!("Group{group}.{part}.{field}"))
}

/// The `Group<N>` builders of `c` (the libraries' parts included in a module's), or a
/// `compile_error!` where a host item or two fields would take the same name.
pub(crate) fn builders(c: &Compiled) -> TokenStream {
    let own: Vec<&Global> = own_bindings(c).collect();
    let mut groups = declared_groups(own.iter().copied());
    groups.extend(parts(c).flat_map(|l| l.groups.iter().copied()));
    groups.sort_unstable();
    groups.dedup();
    let mut out = TokenStream::new();
    for group in groups {
        let name = format!("Group{group}");
        if let Some(s) = c.module.structs.iter().find(|s| s.name == name) {
            let msg = format!(
                "`{name}` is the name of the generated builder of bind group {group}; rename this struct"
            );
            return syn::Error::new(s.span, msg).to_compile_error();
        }
        let fields: Vec<&Global> = own
            .iter()
            .copied()
            .filter(|g| g.binding.is_some_and(|b| b.0 == group))
            .collect();
        match builder(c, group, &fields) {
            Ok(tokens) => out.extend(tokens),
            Err(e) => return e.to_compile_error(),
        }
    }
    out
}

fn builder(c: &Compiled, group: u32, fields: &[&Global]) -> syn::Result<TokenStream> {
    let ty = format_ident!("Group{group}");
    let mut names: Vec<String> = vec![];
    let mut decls = vec![];
    let mut collects = vec![];
    for g in fields {
        let field = field_ident(&g.name);
        let (field_ty, what) = field_type(g);
        let index = g.binding.map_or(0, |b| b.1);
        let when = if g.when.is_some() {
            " Only some variants bind it (`#[when(..)]`): `None` where none is given."
        } else {
            ""
        };
        let doc = format!("`{}`: binding {index}, a {what}.{when}", g.name);
        decls.push(quote!(#[doc = #doc] pub #field: #field_ty,));
        let dsl = &g.name;
        collects.push(if g.when.is_some() {
            quote!(out.push(#dsl, ::core::clone::Clone::clone(&self.#field).map(::shader_bind::Resource::from));)
        } else {
            quote!(out.push(#dsl, ::core::option::Option::Some(::shader_bind::Resource::from(::core::clone::Clone::clone(&self.#field))));)
        });
        names.push(field.to_string());
    }
    for lib in parts(c).filter(|l| l.groups.contains(&group)) {
        let Some(last) = lib.path.segments.last() else {
            continue;
        };
        let field = last.ident.clone();
        if names.contains(&field.to_string()) {
            return Err(syn::Error::new(
                last.ident.span(),
                format!(
                    "bind group {group}'s builder would have two fields named `{field}`: a binding and this library's part; rename one"
                ),
            ));
        }
        names.push(field.to_string());
        let path = &lib.path;
        let doc = format!("The bindings library `{field}` declares in group {group}.");
        decls.push(quote!(#[doc = #doc] pub #field: #path::#ty<'a>,));
        collects.push(quote!(::shader_bind::GroupResources::collect(&self.#field, out);));
    }
    let doc = format!(
        "The resources of bind group {group}, by binding name: `bind_group` numbers them from a variant's reflection."
    );
    Ok(quote! {
        #[doc = #doc]
        #[derive(Debug, Clone)]
        pub struct #ty<'a> {
            #(#decls)*
        }

        impl<'a> ::shader_bind::GroupResources<'a> for #ty<'a> {
            fn collect(&self, out: &mut ::shader_bind::Resources<'a>) {
                #(#collects)*
            }
        }

        impl<'a> #ty<'a> {
            /// The bind group's index.
            pub const GROUP: u32 = #group;

            /// Builds this group of `variant` on `layout` (made from the same variant), each
            /// binding the variant has numbered from its reflection and checked against what
            /// is given; resources the variant does not bind are left out.
            pub fn bind_group(
                &self,
                device: &::shader_bind::wgpu::Device,
                layout: &::shader_bind::wgpu::BindGroupLayout,
                variant: &::codegen::rt::Variant,
                label: &str,
            ) -> ::core::result::Result<::shader_bind::wgpu::BindGroup, ::shader_bind::BindError> {
                ::shader_bind::Resources::of(self).build(device, layout, variant, #group, label)
            }
        }
    })
}
