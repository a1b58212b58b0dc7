//! Host types for GPU structs and host constants.
//!
//! Each host struct is `#[repr(C, align(A))]` with glam fields and explicit `_padN` fields that
//! reproduce the WGSL layout of its address space; `const` asserts check size, alignment and
//! every offset against the numbers naga's `Layouter` computed for the validated WGSL.

use crate::Compiled;
use crate::ir::{Lit, Module, Scalar, Ty};
use crate::layout::{array_len, layout_of, struct_layout};
use crate::variants::{Env, eval};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

fn host_ty(ty: &Ty, m: &Module, env: &Env) -> Option<TokenStream> {
    let g = quote!(::codegen::__private::glam);
    Some(match ty {
        Ty::Scalar(Scalar::F32) => quote!(f32),
        Ty::Scalar(Scalar::U32) | Ty::Atomic(Scalar::U32) => quote!(u32),
        Ty::Scalar(Scalar::I32) | Ty::Atomic(Scalar::I32) => quote!(i32),
        Ty::Scalar(Scalar::U64) | Ty::Atomic(Scalar::U64) => quote!(u64),
        Ty::Vector(n, s) => {
            let prefix = match s {
                Scalar::F32 => "",
                Scalar::U32 => "U",
                Scalar::I32 => "I",
                _ => return None,
            };
            let id = format_ident!("{prefix}Vec{n}");
            quote!(#g::#id)
        }
        Ty::Matrix(2, 2) => quote!([#g::Vec2; 2]),
        Ty::Matrix(4, 4) => quote!(#g::Mat4),
        Ty::Matrix(3, 3) => quote!([#g::Vec4; 3]),
        Ty::Array(t, len) => {
            let e = layout_of(t, m, env);
            if host_size(t, m, env)? != crate::layout::round_up(e.size, e.align) {
                return None;
            }
            let inner = host_ty(t, m, env)?;
            let n = Literal::usize_unsuffixed(array_len(len, m, env)? as usize);
            quote!([#inner; #n])
        }
        Ty::Struct(id) => {
            if !hostable(*id, m, env) {
                return None;
            }
            let id = Ident::new(&m.structs[*id].name, Span::call_site());
            quote!(#id)
        }
        _ => return None,
    })
}

fn host_size(ty: &Ty, m: &Module, env: &Env) -> Option<u32> {
    Some(match ty {
        Ty::Matrix(3, 3) => 48,
        Ty::Array(t, len) => host_size(t, m, env)? * array_len(len, m, env)?,
        t => layout_of(t, m, env).size,
    })
}

/// Whether a struct gets a host type: not entry point IO, and every field has a host type.
pub(crate) fn hostable(id: usize, m: &Module, env: &Env) -> bool {
    let s = &m.structs[id];
    !s.uses.io && s.fields.iter().all(|f| host_ty(&f.ty, m, env).is_some())
}

/// Whether the module defines struct `id` itself (not a library's, which it re-exports).
fn own_item(c: &Compiled, name: &str) -> bool {
    !c.libraries
        .iter()
        .any(|l| l.names.iter().any(|n| n == name))
}

/// The structs that get a host type.
fn host_structs(c: &Compiled) -> impl Iterator<Item = usize> + '_ {
    let m = &c.module;
    let env = &c.keys[0].env;
    (0..m.structs.len()).filter(move |&id| hostable(id, m, env) && own_item(c, &m.structs[id].name))
}

/// Names of the host structs [`structs`] defines.
pub(super) fn struct_names(c: &Compiled) -> Vec<String> {
    host_structs(c)
        .map(|id| c.module.structs[id].name.clone())
        .collect()
}

/// Names of the host constants [`consts`] defines.
pub(super) fn const_names(c: &Compiled) -> Vec<String> {
    host_consts(c).map(|(k, _)| k.name.clone()).collect()
}

fn host_consts(c: &Compiled) -> impl Iterator<Item = (&crate::ir::Const, crate::variants::Value)> {
    let m = &c.module;
    let env = &c.keys[0].env;
    m.consts.iter().filter_map(move |k| {
        if crate::front::mentions_axis(&k.value, m) || !own_item(c, &k.name) {
            return None;
        }
        eval(&k.value, m, env).map(|v| (k, v))
    })
}

pub(super) fn structs(c: &Compiled) -> TokenStream {
    let m = &c.module;
    let env = &c.keys[0].env;
    let mut out = TokenStream::new();
    for id in host_structs(c) {
        let s = &m.structs[id];
        let layout = struct_layout(id, m, env);
        let name = Ident::new(&s.name, Span::call_site());
        let mut fields = vec![];
        let mut field_tys = vec![];
        let mut ctor_args = vec![];
        let mut ctor_inits = vec![];
        let mut cursor = 0u32;
        let mut pad = 0;
        let mut push_pad = |bytes: u32,
                            fields: &mut Vec<TokenStream>,
                            field_tys: &mut Vec<TokenStream>,
                            inits: &mut Vec<TokenStream>| {
            let p = format_ident!("_pad{}", pad.to_string());
            pad += 1;
            let n = Literal::usize_unsuffixed((bytes / 4) as usize);
            fields.push(quote!(#[doc(hidden)] pub #p: [u32; #n]));
            field_tys.push(quote!([u32; #n]));
            inits.push(quote!(#p: [0; #n]));
        };
        for (f, ml) in s.fields.iter().zip(&layout.members) {
            if ml.offset > cursor {
                push_pad(
                    ml.offset - cursor,
                    &mut fields,
                    &mut field_tys,
                    &mut ctor_inits,
                );
            }
            let fname = Ident::new(&f.name, Span::call_site());
            #[expect(
                clippy::expect_used,
                reason = "only host-shareable structs reach the host emitter, so every field has a host type"
            )]
            let ty = host_ty(&f.ty, m, env).expect("hostable");
            fields.push(quote!(pub #fname: #ty));
            field_tys.push(ty.clone());
            ctor_args.push(quote!(#fname: #ty));
            ctor_inits.push(quote!(#fname));
            #[expect(
                clippy::expect_used,
                reason = "only host-shareable structs reach the host emitter, so every field has a host size"
            )]
            let size = host_size(&f.ty, m, env).expect("hostable");
            cursor = ml.offset + size;
        }
        if layout.layout.size > cursor {
            push_pad(
                layout.layout.size - cursor,
                &mut fields,
                &mut field_tys,
                &mut ctor_inits,
            );
        }
        let align = Literal::usize_unsuffixed(layout.layout.align as usize);
        let mut asserts = vec![];
        if let Some(Some(nl)) = c.naga_layouts.get(id) {
            let size = Literal::usize_unsuffixed(nl.size as usize);
            let nalign = Literal::usize_unsuffixed(nl.align as usize);
            let msg = format!("host type `{}` does not match naga's layout", s.name);
            asserts.push(quote!(assert!(::core::mem::size_of::<#name>() == #size, #msg);));
            asserts.push(quote!(assert!(::core::mem::align_of::<#name>() == #nalign, #msg);));
            for (f, off) in s.fields.iter().zip(&nl.offsets) {
                let fname = Ident::new(&f.name, Span::call_site());
                let off = Literal::usize_unsuffixed(*off as usize);
                asserts
                    .push(quote!(assert!(::core::mem::offset_of!(#name, #fname) == #off, #msg);));
            }
        }
        let doc = format!(
            "Host type of the shader struct `{}` (layout asserted against naga at compile time; padding is generated).",
            s.name
        );
        out.extend(quote! {
            #[doc = #doc]
            #[repr(C, align(#align))]
            #[derive(Clone, Copy, Debug, PartialEq, Default)]
            pub struct #name { #(#fields,)* }
            impl #name {
                /// Builds the value, zeroing the generated padding.
                #[allow(clippy::too_many_arguments, reason = "one argument per field")]
                pub const fn new(#(#ctor_args),*) -> Self {
                    Self { #(#ctor_inits),* }
                }
            }
            // SAFETY: every field is `Pod`, and the assert below proves there are no implicit
            // padding bytes (the generated `_pad` fields cover every gap).
            unsafe impl ::codegen::__private::bytemuck::Zeroable for #name {}
            // SAFETY: see above.
            unsafe impl ::codegen::__private::bytemuck::Pod for #name {}
            const _: () = {
                assert!(::core::mem::size_of::<#name>() == 0 #(+ ::core::mem::size_of::<#field_tys>())*, "implicit padding in generated host type");
                #(#asserts)*
            };
        });
    }
    out
}

pub(super) fn consts(c: &Compiled) -> TokenStream {
    let mut out = TokenStream::new();
    for (k, v) in host_consts(c) {
        let name = Ident::new(&k.name, Span::call_site());
        let (ty, val) = match v.to_lit(&k.ty) {
            Lit::Bool(b) => (quote!(bool), quote!(#b)),
            Lit::Int(i, Scalar::I32) => {
                let l = Literal::i32_suffixed(i as i32);
                (quote!(i32), quote!(#l))
            }
            Lit::Int(i, Scalar::U32) => {
                let l = Literal::u32_suffixed(i as u32);
                (quote!(u32), quote!(#l))
            }
            Lit::Int(i, Scalar::U64) => {
                let l = Literal::u64_suffixed(i as u64);
                (quote!(u64), quote!(#l))
            }
            Lit::Float(f, _) => {
                let l = Literal::f32_suffixed(f as f32);
                (quote!(f32), quote!(#l))
            }
            Lit::Int(i, _) => {
                let l = Literal::f32_suffixed(i as f32);
                (quote!(f32), quote!(#l))
            }
        };
        out.extend(quote!(pub const #name: #ty = #val;));
    }
    out
}
