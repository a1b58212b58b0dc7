//! Runs the stages in order for every variant: the library's main entry points.
//!
//! Holds no logic of its own beyond ordering, deduplication and timing.

use crate::back::{spv, wgsl};
use crate::front::Mode;
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
    /// The libraries merged into the module (empty for a library or a module without
    /// `uses(..)`): the generated module re-exports their host items instead of defining
    /// copies.
    pub libraries: Vec<LinkedLibrary>,
}

/// A library merged into a module, as the emitter needs it.
#[derive(Debug, Clone)]
pub struct LinkedLibrary {
    /// The path in `uses(..)`.
    pub path: syn::Path,
    /// Every struct and const name the library defines (the using module defines no host
    /// item of these names).
    pub names: Vec<String>,
    /// The host items the library's own generated module defines, which the using module
    /// re-exports.
    pub exports: Vec<String>,
    /// The bind groups the library declares bindings in itself: the using module's builder of
    /// each has a field holding the library's part.
    pub groups: Vec<u32>,
    /// The resource statics the library declares itself (its part's fields).
    pub bindings: Vec<String>,
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
    compile_module(crate::front::lower(args, item)?)
}

/// Compiles a `#[library]` module on its own, over its axis matrix: every function is kept
/// and validated by naga (a module without entry points is fine for naga).
pub fn compile_library(args: TokenStream, item: &syn::ItemMod) -> syn::Result<Compiled> {
    compile_module(crate::front::lower_with(args, item, &[], Mode::Library)?)
}

pub(crate) fn compile_module(module: Module) -> syn::Result<Compiled> {
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
        let wgsl::Printed { text, map, int64 } = wgsl::write_string(
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
            int64,
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
        let reflection = reflect(&module, &key.env, key.subgroup, int64);
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
        libraries: vec![],
    })
}

/// The declarations of a module that failed to compile, as a [`Compiled`] without variants,
/// when its declarations at least lower (see [`crate::emit::stub`]).
pub fn declarations(args: TokenStream, item: &syn::ItemMod) -> Option<Compiled> {
    with_keys(crate::front::lower_declarations(args, item).ok()?).ok()
}

/// A lowered module as a [`Compiled`] without variants: its keys, each valid key pointing at
/// variant 0 (for the emitter's declarations-only outputs).
pub(crate) fn with_keys(module: Module) -> syn::Result<Compiled> {
    let keys = variants::enumerate(&module)?;
    let key_variant = keys.iter().map(|k| (!k.excluded).then_some(0)).collect();
    let naga_layouts = vec![None; module.structs.len()];
    Ok(Compiled {
        module,
        keys,
        key_variant,
        variants: vec![],
        naga_layouts,
        libraries: vec![],
    })
}
