//! The typed variant key (one enum per numeric axis, `bool` for boolean axes) and the static
//! variant table with its key → variant lookup.

use crate::Compiled;
use crate::ir::{Lit, Scalar};
use crate::reflect::{BindingInfo, EntryPointInfo};
use crate::rt::{BindingKind, SampleType, StorageAccess, ViewDimension};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

fn camel(s: &str) -> String {
    s.split('_')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let mut c = p.chars();
            c.next()
                .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        })
        .collect()
}

fn value_variant(label: &str, v: &Lit) -> Ident {
    match v {
        Lit::Int(i, _) if *i < 0 => format_ident!("{}", format!("{}M{}", camel(label), -i)),
        Lit::Int(i, _) => format_ident!("{}", format!("{}{}", camel(label), i)),
        _ => unreachable!("numeric axis"),
    }
}

pub(super) fn key_types(c: &Compiled) -> TokenStream {
    let m = &c.module;
    let mut out = TokenStream::new();
    let mut fields = vec![];
    let mut index_terms = vec![];
    let mut stride = 1usize;
    let mut strides = vec![0; m.axes.len()];
    for (i, a) in m.axes.iter().enumerate().rev() {
        strides[i] = stride;
        stride *= a.values.len();
    }
    for (i, a) in m.axes.iter().enumerate() {
        let field = Ident::new(&a.name, Span::call_site());
        let st = Literal::usize_unsuffixed(strides[i]);
        if a.ty == Scalar::Bool {
            fields.push(quote!(pub #field: bool));
            let f_idx = a.values.iter().position(|v| *v == Lit::Bool(false));
            let t_idx = a.values.iter().position(|v| *v == Lit::Bool(true));
            let fi = Literal::usize_unsuffixed(f_idx.unwrap_or(0));
            let ti = Literal::usize_unsuffixed(t_idx.unwrap_or(0));
            index_terms.push(quote!((if self.#field { #ti } else { #fi }) * #st));
            continue;
        }
        let ename = format_ident!("{}", camel(&a.name));
        let variants: Vec<Ident> = a
            .values
            .iter()
            .map(|v| value_variant(&a.label, v))
            .collect();
        let ty = if a.ty == Scalar::U32 {
            quote!(u32)
        } else {
            quote!(i32)
        };
        let vals: Vec<Literal> = a
            .values
            .iter()
            .map(|v| match v {
                Lit::Int(i, Scalar::U32) => Literal::u32_unsuffixed(*i as u32),
                Lit::Int(i, _) => Literal::i32_unsuffixed(*i as i32),
                _ => unreachable!("numeric axis"),
            })
            .collect();
        let n = Literal::usize_unsuffixed(variants.len());
        let doc = format!("Values of the `{}` axis.", a.name);
        out.extend(quote! {
            #[doc = #doc]
            #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
            pub enum #ename { #(#variants),* }
            impl #ename {
                /// Every value, in declaration order.
                pub const ALL: [#ename; #n] = [#(#ename::#variants),*];
                /// The axis value.
                pub const fn value(self) -> #ty { match self { #(#ename::#variants => #vals),* } }
                /// The enum value for an axis value, if it is one of the declared values.
                pub const fn from_value(v: #ty) -> Option<Self> { match v { #(#vals => Some(#ename::#variants),)* _ => None } }
            }
        });
        fields.push(quote!(pub #field: #ename));
        index_terms.push(quote!((self.#field as usize) * #st));
    }
    let total = c.keys.len();
    let key_inits: Vec<TokenStream> = c
        .keys
        .iter()
        .map(|k| {
            let inits = m.axes.iter().zip(&k.env.values).map(|(a, v)| {
                let field = Ident::new(&a.name, Span::call_site());
                match v {
                    Lit::Bool(b) => quote!(#field: #b),
                    v => {
                        let ename = format_ident!("{}", camel(&a.name));
                        let var = value_variant(&a.label, v);
                        quote!(#field: #ename::#var)
                    }
                }
            });
            quote!(VariantKey { #(#inits),* })
        })
        .collect();
    let valid: Vec<&TokenStream> = key_inits
        .iter()
        .zip(&c.key_variant)
        .filter(|(_, v)| v.is_some())
        .map(|(k, _)| k)
        .collect();
    let names: Vec<&str> = c.keys.iter().map(|k| k.name.as_str()).collect();
    let map: Vec<Literal> = c
        .key_variant
        .iter()
        .map(|v| Literal::usize_unsuffixed(v.unwrap_or(usize::MAX)))
        .collect();
    let total_lit = Literal::usize_unsuffixed(total);
    let index = if index_terms.is_empty() {
        quote!(0)
    } else {
        quote!(#(#index_terms)+*)
    };
    let lookup = if c.key_variant.iter().all(Option::is_some) {
        quote! {
            /// The variant for a key.
            pub fn variant(key: VariantKey) -> &'static ::codegen::rt::Variant {
                &VARIANTS[KEY_VARIANT[key.index()]]
            }
        }
    } else {
        let module = m.name.as_str();
        quote! {
            /// The variant for a key, or an error for keys removed by `exclude(..)`.
            pub fn variant(key: VariantKey) -> ::core::result::Result<&'static ::codegen::rt::Variant, ::codegen::rt::ExcludedVariant> {
                match KEY_VARIANT[key.index()] {
                    usize::MAX => Err(::codegen::rt::ExcludedVariant { module: #module, key: key.name().to_string() }),
                    i => Ok(&VARIANTS[i]),
                }
            }
        }
    };
    quote! {
        #out
        /// One point of the variant matrix.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub struct VariantKey { #(#fields),* }
        const KEY_NAMES: [&str; #total_lit] = [#(#names),*];
        const KEY_VARIANT: [usize; #total_lit] = [#(#map),*];
        impl VariantKey {
            /// Every key that is not excluded, in key order.
            pub const ALL: &'static [VariantKey] = &[#(#valid),*];
            /// Position of the key in the full matrix.
            pub const fn index(self) -> usize { #index }
            /// The stable name, e.g. `t16_msaa4_scalar`.
            pub const fn name(self) -> &'static str { KEY_NAMES[self.index()] }
            /// Whether an `exclude(..)` constraint removed this key.
            pub const fn is_excluded(self) -> bool { KEY_VARIANT[self.index()] == usize::MAX }
        }
        impl ::core::fmt::Display for VariantKey {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result { f.write_str(self.name()) }
        }
        #lookup
    }
}

fn entry_point(e: &EntryPointInfo) -> TokenStream {
    let name = &e.name;
    let stage = format_ident!("{}", format!("{:?}", e.stage));
    let [x, y, z] = e.workgroup_size;
    let workgroup_memory = e.workgroup_memory;
    let loc = |l: &crate::rt::Location| {
        let location = l.location;
        let format = format_ident!("{}", format!("{:?}", l.format));
        quote!(::codegen::rt::Location { location: #location, format: ::codegen::rt::ValueFormat::#format })
    };
    let inputs = e.inputs.iter().map(loc);
    let outputs = e.outputs.iter().map(loc);
    quote!(::codegen::rt::EntryPoint {
        name: #name,
        stage: ::codegen::rt::Stage::#stage,
        workgroup_size: [#x, #y, #z],
        workgroup_memory: #workgroup_memory,
        inputs: &[#(#inputs),*],
        outputs: &[#(#outputs),*],
    })
}

fn binding(b: &BindingInfo) -> TokenStream {
    let rt = quote!(::codegen::rt);
    let (name, group, bnd) = (&b.name, b.group, b.binding);
    let v = b.visibility;
    let (vc, vv, vf) = (v.compute, v.vertex, v.fragment);
    let dim = |d: ViewDimension| {
        let d = format_ident!("{}", format!("{d:?}"));
        quote!(#rt::ViewDimension::#d)
    };
    let kind = match b.kind {
        BindingKind::Uniform { min_size } => {
            quote!(#rt::BindingKind::Uniform { min_size: #min_size })
        }
        BindingKind::Storage {
            read_only,
            min_size,
        } => quote!(#rt::BindingKind::Storage { read_only: #read_only, min_size: #min_size }),
        BindingKind::Texture {
            sample_type,
            view_dimension,
            multisampled,
        } => {
            let st = match sample_type {
                SampleType::Float { filterable } => {
                    quote!(#rt::SampleType::Float { filterable: #filterable })
                }
                SampleType::Depth => quote!(#rt::SampleType::Depth),
                SampleType::Uint => quote!(#rt::SampleType::Uint),
                SampleType::Sint => quote!(#rt::SampleType::Sint),
            };
            let d = dim(view_dimension);
            quote!(#rt::BindingKind::Texture { sample_type: #st, view_dimension: #d, multisampled: #multisampled })
        }
        BindingKind::StorageTexture {
            format,
            access,
            view_dimension,
        } => {
            let f = format_ident!("{}", format!("{format:?}"));
            let a = format_ident!(
                "{}",
                match access {
                    StorageAccess::ReadOnly => "ReadOnly",
                    StorageAccess::WriteOnly => "WriteOnly",
                    StorageAccess::ReadWrite => "ReadWrite",
                }
            );
            let d = dim(view_dimension);
            quote!(#rt::BindingKind::StorageTexture { format: #rt::StorageFormat::#f, access: #rt::StorageAccess::#a, view_dimension: #d })
        }
        BindingKind::Sampler { comparison } => {
            quote!(#rt::BindingKind::Sampler { comparison: #comparison })
        }
    };
    quote!(#rt::Binding { name: #name, group: #group, binding: #bnd, visibility: #rt::Visibility { compute: #vc, vertex: #vv, fragment: #vf }, kind: #kind })
}

pub(super) fn variant_table(c: &Compiled) -> TokenStream {
    let module = c.module.name.as_str();
    // Each variant's SPIR-V is a constant of its own, empty in a browser build (wasm32), which
    // takes WGSL only: the words would be most of the module's size there.
    let spirv_consts = c.variants.iter().enumerate().map(|(i, v)| {
        let name = format_ident!("__SPIRV_{}", i);
        let words = v.spirv.iter().map(|w| Literal::u32_unsuffixed(*w));
        quote! {
            #[cfg(not(target_arch = "wasm32"))]
            const #name: &[u32] = &[#(#words),*];
            #[cfg(target_arch = "wasm32")]
            const #name: &[u32] = &[];
        }
    });
    let variants = c.variants.iter().enumerate().map(|(i, v)| {
        let names = &v.names;
        let wgsl = &v.wgsl;
        let spirv = format_ident!("__SPIRV_{}", i);
        let (maj, min) = v.spirv_version;
        let eps = v.reflection.entry_points.iter().map(entry_point);
        let bindings = v.reflection.bindings.iter().map(binding);
        let crate::rt::Features { subgroup, int64 } = v.reflection.features;
        quote! {
            ::codegen::rt::Variant {
                module: #module,
                names: &[#(#names),*],
                wgsl: #wgsl,
                spirv: #spirv,
                spirv_version: (#maj, #min),
                entry_points: &[#(#eps),*],
                bindings: &[#(#bindings),*],
                features: ::codegen::rt::Features { subgroup: #subgroup, int64: #int64 },
            }
        }
    });
    quote! {
        #(#spirv_consts)*
        const VARIANT_TABLE: &[::codegen::rt::Variant] = &[#(#variants),*];
        /// Every distinct variant (keys with identical output share one).
        pub static VARIANTS: &[::codegen::rt::Variant] = VARIANT_TABLE;
        /// This module's name and variants.
        pub static MODULE: ::codegen::rt::Module = ::codegen::rt::Module { name: #module, variants: VARIANT_TABLE };
    }
}
