//! Runs the stages in order for every variant: the library's main entry points.
//!
//! Holds no logic of its own beyond ordering, deduplication and timing.

use crate::back::{spv, wgsl};
use crate::ir::Module;
use crate::reflect::{Reflection, reflect};
use crate::variants::{self, Key, check_capabilities};
use proc_macro2::TokenStream;
use std::collections::HashMap;
use std::time::{Duration, Instant};

/// One distinct generated variant.
#[derive(Debug)]
pub struct CompiledVariant {
    /// Names of every key with this exact output.
    pub names: Vec<String>,
    /// WGSL text.
    pub wgsl: String,
    /// Where each WGSL range came from.
    pub source_map: wgsl::SourceMap,
    /// SPIR-V words.
    pub spirv: Vec<u32>,
    /// SPIR-V version.
    pub spirv_version: (u8, u8),
    /// Reflection.
    pub reflection: Reflection,
    /// Time to print, validate, write SPIR-V and reflect this variant.
    pub gen_time: Duration,
}

/// Struct layout as computed by `naga::proc::Layouter` on the validated module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NagaStructLayout {
    /// Size in bytes.
    pub size: u32,
    /// Alignment in bytes.
    pub align: u32,
    /// Member offsets.
    pub offsets: Vec<u32>,
}

/// A compiled module.
#[derive(Debug)]
pub struct Compiled {
    /// The typed IR.
    pub module: Module,
    /// Every key of the matrix (excluded ones too), in key order.
    pub keys: Vec<Key>,
    /// For each key, the index of its variant in `variants` (`None` when excluded).
    pub key_variant: Vec<Option<usize>>,
    /// Distinct variants, in order of first key.
    pub variants: Vec<CompiledVariant>,
    /// naga's layout of each struct (by struct index).
    pub naga_layouts: Vec<Option<NagaStructLayout>>,
}

fn naga_layouts(m: &Module, module: &naga::Module) -> Vec<Option<NagaStructLayout>> {
    let mut layouter = naga::proc::Layouter::default();
    if layouter.update(module.to_ctx()).is_err() {
        return vec![None; m.structs.len()];
    }
    m.structs
        .iter()
        .map(|s| {
            module.types.iter().find_map(|(h, t)| match &t.inner {
                naga::TypeInner::Struct { members, .. } if t.name.as_deref() == Some(&s.name) => {
                    Some(NagaStructLayout {
                        size: layouter[h].size,
                        align: layouter[h].alignment * 1,
                        offsets: members.iter().map(|mb| mb.offset).collect(),
                    })
                }
                _ => None,
            })
        })
        .collect()
}

/// Compiles a shader module: the attribute arguments and the `mod` item.
pub fn compile(args: TokenStream, item: &syn::ItemMod) -> syn::Result<Compiled> {
    let module = crate::front::lower(args, item)?;
    let keys = variants::enumerate(&module)?;
    let mut variants: Vec<CompiledVariant> = vec![];
    let mut by_output: HashMap<(String, bool), usize> = HashMap::new();
    let mut key_variant = vec![];
    let mut naga_layouts_out = None;
    for key in &keys {
        if key.excluded {
            key_variant.push(None);
            continue;
        }
        let start = Instant::now();
        check_capabilities(&module, &key.env, key.subgroup, &key.name)?;
        variants::check_globals(&module, &key.env, &key.name)?;
        let (text, map) = wgsl::write_string(
            &module,
            &key.env,
            wgsl::Options {
                subgroup: key.subgroup,
            },
        );
        if let Some(&i) = by_output.get(&(text.clone(), key.subgroup)) {
            variants[i].names.push(key.name.clone());
            key_variant.push(Some(i));
            continue;
        }
        let validated = crate::validate::validate(
            &text,
            &map,
            key.subgroup,
            &key.name,
            module.span,
            &|name| {
                module
                    .functions
                    .iter()
                    .find(|f| f.name == name)
                    .map(|f| f.span)
            },
        )?;
        let spirv = spv::write_vec(&validated, key.subgroup).map_err(|e| {
            syn::Error::new(
                module.span,
                format!("naga SPIR-V backend failed for variant `{}`: {e}", key.name),
            )
        })?;
        if naga_layouts_out.is_none() {
            naga_layouts_out = Some(naga_layouts(&module, &validated.module));
        }
        let reflection = reflect(&module, &key.env, key.subgroup);
        let i = variants.len();
        by_output.insert((text.clone(), key.subgroup), i);
        variants.push(CompiledVariant {
            names: vec![key.name.clone()],
            wgsl: text,
            source_map: map,
            spirv,
            spirv_version: spv::version(key.subgroup),
            reflection,
            gen_time: start.elapsed(),
        });
        key_variant.push(Some(i));
    }
    let naga_layouts = naga_layouts_out.unwrap_or_default();
    Ok(Compiled {
        module,
        keys,
        key_variant,
        variants,
        naga_layouts,
    })
}

/// Every `#[shader(..)]` module of a Rust source file (at any nesting depth), with its
/// attribute arguments, the attribute removed.
pub fn shader_modules(file: &syn::File) -> Vec<(TokenStream, syn::ItemMod)> {
    fn is_shader(a: &syn::Attribute) -> bool {
        a.path()
            .segments
            .last()
            .is_some_and(|s| s.ident == "shader")
    }
    fn walk(items: &[syn::Item], out: &mut Vec<(TokenStream, syn::ItemMod)>) {
        for item in items {
            let syn::Item::Mod(m) = item else { continue };
            if let Some(attr) = m.attrs.iter().find(|a| is_shader(a)) {
                let args = match &attr.meta {
                    syn::Meta::List(l) => l.tokens.clone(),
                    _ => TokenStream::new(),
                };
                let mut item = m.clone();
                item.attrs.retain(|a| !is_shader(a));
                out.push((args, item));
            } else if let Some((_, content)) = &m.content {
                walk(content, out);
            }
        }
    }
    let mut out = vec![];
    walk(&file.items, &mut out);
    out
}

/// Compiles every `#[shader(..)]` module of Rust source text (tools such as
/// `cargo xtask shaders`, which also want per-variant timings): `(module name, result)`.
pub fn compile_source_all(src: &str) -> syn::Result<Vec<(String, syn::Result<Compiled>)>> {
    let file = syn::parse_file(src)?;
    Ok(shader_modules(&file)
        .into_iter()
        .map(|(args, item)| (item.ident.to_string(), compile(args, &item)))
        .collect())
}

/// Compiles the first `#[shader(..)]` module found in Rust source text (golden tests, tools).
pub fn compile_source(src: &str) -> syn::Result<Compiled> {
    let file = syn::parse_file(src)?;
    match shader_modules(&file).into_iter().next() {
        Some((args, item)) => compile(args, &item),
        None => Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            "no `#[shader(..)] mod` found",
        )),
    }
}

/// The declarations of a module that failed to compile, as a [`Compiled`] without variants,
/// when its declarations at least lower (see [`crate::emit::stub`]).
pub fn declarations(args: TokenStream, item: &syn::ItemMod) -> Option<Compiled> {
    let module = crate::front::lower_declarations(args, item).ok()?;
    let keys = variants::enumerate(&module).ok()?;
    let key_variant = keys.iter().map(|k| (!k.excluded).then_some(0)).collect();
    let naga_layouts = vec![None; module.structs.len()];
    Some(Compiled {
        module,
        keys,
        key_variant,
        variants: vec![],
        naga_layouts,
    })
}

/// The whole macro: compiles and emits the generated Rust module.
pub fn expand(args: TokenStream, item: TokenStream) -> syn::Result<TokenStream> {
    let item: syn::ItemMod = syn::parse2(item)?;
    let compiled = compile(args, &item)?;
    Ok(crate::emit::emit(&item, &compiled))
}
