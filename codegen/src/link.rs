//! Linking libraries into a using module or library: the compilation with the libraries merged
//! in, and what the emitter needs of each library (its path and host items), after checking
//! that every library struct keeps the library's memory layout in the module.
//!
//! `libs` are always the whole graph the module reaches, ordered by `front::order`
//! (dependencies first, each once).

use crate::front::{Library, Mode};
use crate::pipeline::{Compiled, LinkedLibrary, compile_module, with_keys};
use proc_macro2::TokenStream;

/// Compiles a shader module with the libraries its `uses(..)` reaches (`libs`, ordered): their
/// items are merged into the module before lowering, and every variant is validated with the
/// library code in it.
pub fn compile_linked(
    args: TokenStream,
    item: &syn::ItemMod,
    libs: &[Library],
) -> syn::Result<Compiled> {
    let module = crate::front::lower_with(args, item, libs, Mode::Shader)?;
    let mut compiled = compile_module(module)?;
    compiled.libraries = link_libraries(&compiled, libs, true)?;
    Ok(compiled)
}

/// Compiles a `#[library]` that uses other libraries (`libs`, its ordered graph) over its own
/// axis matrix, every function kept: the library is validated once, with what it uses.
pub fn compile_library_linked(
    args: TokenStream,
    item: &syn::ItemMod,
    libs: &[Library],
) -> syn::Result<Compiled> {
    let module = crate::front::lower_with(args, item, libs, Mode::Library)?;
    let mut compiled = compile_module(module)?;
    compiled.libraries = link_libraries(&compiled, libs, true)?;
    Ok(compiled)
}

/// [`crate::declarations`] of a library that uses libraries (the error stub's host items).
pub fn library_declarations_linked(
    args: TokenStream,
    item: &syn::ItemMod,
    libs: &[Library],
) -> Option<Compiled> {
    let module = crate::front::lower_with(args, item, libs, Mode::Declarations).ok()?;
    let mut c = with_keys(module).ok()?;
    c.libraries = link_libraries(&c, libs, false).ok()?;
    Some(c)
}

/// [`crate::declarations`] of a module that uses libraries.
pub fn declarations_linked(
    args: TokenStream,
    item: &syn::ItemMod,
    libs: &[Library],
) -> Option<Compiled> {
    let module = crate::front::lower_with(args, item, libs, Mode::Declarations).ok()?;
    let mut c = with_keys(module).ok()?;
    c.libraries = link_libraries(&c, libs, false).ok()?;
    Some(c)
}

/// What the emitter needs of each library, after checking that each library struct has the
/// same memory layout in the module as in the library (the host type is the library's).
fn link_libraries(
    c: &Compiled,
    libs: &[Library],
    check_layouts: bool,
) -> syn::Result<Vec<LinkedLibrary>> {
    let mut out: Vec<LinkedLibrary> = vec![];
    for (i, lib) in libs.iter().enumerate() {
        // Each library is lowered with the part of the graph it reaches itself, and knows its
        // own dependencies as linked, so its exports are its own host items only.
        let reached = crate::front::reached_by(libs, i);
        let deps: Vec<Library> = reached.iter().map(|&k| libs[k].clone()).collect();
        let own = crate::front::lower_with(lib.args.clone(), &lib.item, &deps, Mode::Library)?;
        let mut own = with_keys(own)?;
        own.libraries = reached.iter().map(|&k| out[k].clone()).collect();
        let (m, env) = (&c.module, &c.keys[0].env);
        for (lid, s) in own.module.structs.iter().enumerate() {
            let Some(id) = m.structs.iter().position(|x| x.name == s.name) else {
                continue;
            };
            if !check_layouts {
                break;
            }
            let here = crate::layout::struct_layout(id, m, env);
            let there = crate::layout::struct_layout(lid, &own.module, &own.keys[0].env);
            if here != there {
                return Err(syn::Error::new(
                    s.span,
                    format!(
                        "struct `{}` of {} gets a different memory layout in module `{}` than in the library (uniform-buffer rules apply in one of them only), so the library's host type would not fit; use it in the same kind of buffer in both",
                        s.name,
                        lib.described(),
                        m.name
                    ),
                ));
            }
        }
        let names = own
            .module
            .structs
            .iter()
            .map(|s| s.name.clone())
            .chain(own.module.consts.iter().map(|k| k.name.clone()))
            .collect();
        out.push(LinkedLibrary {
            path: lib.path.clone(),
            names,
            exports: crate::emit::host_names(&own),
            groups: crate::emit::declared_groups(
                own.module.globals.iter().filter(|g| !g.from_library),
            ),
            bindings: own
                .module
                .globals
                .iter()
                .filter(|g| !g.from_library && g.binding.is_some())
                .map(|g| g.name.clone())
                .collect(),
        });
    }
    Ok(out)
}
