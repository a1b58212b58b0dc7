//! `cargo xtask shaders --doc`: one Markdown page per DSL module, for an engine engineer who
//! should not have to open WGSL: the module's own documentation, its variant axes, the variant
//! table (axis values, entry points and workgroup sizes, features, validation, and whether it
//! runs in a browser: `codegen::web`), the bindings
//! (which variants have each), and the host structs with every field's offset and size.
//!
//! Offsets come from the DSL's layout (`codegen::layout`, what the generated host structs copy)
//! and are checked against naga's layouter on the validated module: a disagreement is printed
//! on the page, not hidden.

use std::fmt::Write as _;

use codegen::Compiled;
use codegen::ir::{Lit, Module, Scalar, TexKind, Ty};
use codegen::rt::{BindingKind, Stage};
use codegen::variants::Env;
use codegen::web::{WebLimits, web_issues};

/// What validated each variant, in `compiled.variants` order.
pub struct Validation {
    /// spirv-val's verdict on the variant (`ok`, `FAILED`, `not installed`).
    pub spirv_val: &'static str,
    /// What spirv-val printed when it rejected the variant.
    pub message: Option<String>,
}

/// The page of one module.
pub fn module_page(
    compiled: &Compiled,
    item: &syn::ItemMod,
    library: bool,
    validation: &[Validation],
) -> String {
    let m = &compiled.module;
    let mut page = String::new();
    let kind = if library { "library" } else { "shader module" };
    let _ = writeln!(page, "# `{}` ({kind})\n", m.name);
    let docs = doc_comment(&item.attrs);
    if !docs.is_empty() {
        let _ = writeln!(page, "{docs}\n");
    }
    axes(&mut page, m);
    variants(&mut page, compiled, validation);
    bindings(&mut page, compiled);
    structs(&mut page, compiled);
    page
}

/// The `///` lines of an item, joined as Markdown.
fn doc_comment(attrs: &[syn::Attribute]) -> String {
    attrs
        .iter()
        .filter_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) if nv.path.is_ident("doc") => match &nv.value {
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) => Some(s.value()),
                _ => None,
            },
            _ => None,
        })
        .map(|line| line.strip_prefix(' ').unwrap_or(&line).to_owned())
        .collect::<Vec<_>>()
        .join("\n")
}

fn lit(l: &Lit) -> String {
    match l {
        Lit::Bool(b) => b.to_string(),
        Lit::Int(i, _) => i.to_string(),
        Lit::Float(f, _) => f.to_string(),
    }
}

fn axes(page: &mut String, m: &Module) {
    if m.axes.is_empty() {
        let _ = writeln!(page, "No variant axes: one variant.\n");
        return;
    }
    let _ = writeln!(
        page,
        "## Variant axes\n\n| axis | type | values | label |\n|---|---|---|---|"
    );
    for a in &m.axes {
        let values: Vec<String> = a.values.iter().map(lit).collect();
        let _ = writeln!(
            page,
            "| `{}` | `{}` | {} | `{}` |",
            a.name,
            scalar(a.ty),
            values.join(", "),
            a.label
        );
    }
    page.push('\n');
}

fn variants(page: &mut String, c: &Compiled, validation: &[Validation]) {
    let excluded = c.keys.iter().filter(|k| k.excluded).count();
    let _ = writeln!(
        page,
        "## Variants\n\n{} distinct variant(s) of {} key(s){}. Every variant is validated by naga \
         when it is generated; spirv-val checks the SPIR-V.\n",
        c.variants.len(),
        c.keys.len(),
        if excluded > 0 {
            format!(", {excluded} excluded by `exclude(..)`")
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        page,
        "| variant | axis values | entry points | features | WGSL bytes | SPIR-V words | naga | spirv-val | in a browser |\n|---|---|---|---|---:|---:|---|---|---|"
    );
    for (i, v) in c.variants.iter().enumerate() {
        let key = c.keys.iter().find(|k| k.name == v.names[0]);
        let values = key.map_or_else(String::new, |k| {
            c.module
                .axes
                .iter()
                .zip(&k.env.values)
                .map(|(a, l)| format!("{}={}", a.name, lit(l)))
                .collect::<Vec<_>>()
                .join(" ")
        });
        let entries: Vec<String> = v
            .reflection
            .entry_points
            .iter()
            .map(|e| match e.stage {
                Stage::Compute => format!(
                    "`{}` compute {}×{}×{}",
                    e.name, e.workgroup_size[0], e.workgroup_size[1], e.workgroup_size[2]
                ),
                Stage::Vertex => format!("`{}` vertex", e.name),
                Stage::Fragment => format!("`{}` fragment", e.name),
            })
            .collect();
        let name = if v.names.len() > 1 {
            format!("`{}` (= `{}`)", v.names[0], v.names[1..].join("`, `"))
        } else {
            format!("`{}`", v.names[0])
        };
        let _ = writeln!(
            page,
            "| {name} | {values} | {} | {} | {} | {} | ok | {} | {} |",
            if entries.is_empty() {
                "-".to_owned()
            } else {
                entries.join("<br>")
            },
            features(v.reflection.features),
            v.wgsl.len(),
            v.spirv.len(),
            validation.get(i).map_or("not run", |r| r.spirv_val),
            browser(&c.module.name, v)
        );
    }
    page.push('\n');
    let rejected: Vec<(&str, &str)> = c
        .variants
        .iter()
        .zip(validation)
        .filter_map(|(v, r)| Some((v.names[0].as_str(), r.message.as_deref()?)))
        .collect();
    if !rejected.is_empty() {
        let _ = writeln!(page, "spirv-val's messages:\n");
        for (name, message) in rejected {
            let first = message.lines().next().unwrap_or("").trim();
            let _ = writeln!(page, "- `{name}`: {first}");
        }
        page.push('\n');
    }
}

/// Whether the variant runs in a browser with WebGPU's default limits: `yes`, what it needs
/// beyond them (limits an adapter may offer), or why it cannot.
fn browser(module: &str, v: &codegen::CompiledVariant) -> String {
    let variant = as_rt(module, v);
    let issues = web_issues(&variant, &WebLimits::DEFAULT);
    let list = |limits: bool| {
        issues
            .iter()
            .filter(|i| i.is_limit() == limits)
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("; ")
    };
    let subgroups = if variant.features.subgroup {
        " (the `subgroups` feature)"
    } else {
        ""
    };
    if issues.iter().any(|i| !i.is_limit()) {
        format!("no: {}", list(false))
    } else if issues.is_empty() {
        format!("yes{subgroups}")
    } else {
        format!("above the default limits{subgroups}: {}", list(true))
    }
}

/// A compiled variant as the runtime's [`codegen::rt::Variant`] (its strings leaked: the
/// command runs once).
fn as_rt(module: &str, v: &codegen::CompiledVariant) -> codegen::rt::Variant {
    let leak = |s: &str| -> &'static str { Box::leak(s.to_owned().into_boxed_str()) };
    let r = &v.reflection;
    let entry_points: Vec<codegen::rt::EntryPoint> = r
        .entry_points
        .iter()
        .map(|e| codegen::rt::EntryPoint {
            name: leak(&e.name),
            stage: e.stage,
            workgroup_size: e.workgroup_size,
            workgroup_memory: e.workgroup_memory,
            inputs: Vec::leak(e.inputs.clone()),
            outputs: Vec::leak(e.outputs.clone()),
        })
        .collect();
    let bindings: Vec<codegen::rt::Binding> = r
        .bindings
        .iter()
        .map(|b| codegen::rt::Binding {
            name: leak(&b.name),
            group: b.group,
            binding: b.binding,
            visibility: b.visibility,
            kind: b.kind,
        })
        .collect();
    codegen::rt::Variant {
        module: leak(module),
        names: Vec::leak(v.names.iter().map(|n| leak(n)).collect()),
        wgsl: leak(&v.wgsl),
        spirv: Vec::leak(v.spirv.clone()),
        spirv_version: v.spirv_version,
        entry_points: Vec::leak(entry_points),
        bindings: Vec::leak(bindings),
        features: r.features,
    }
}

fn binding_kind(kind: &BindingKind) -> String {
    match kind {
        BindingKind::Uniform { .. } => "uniform buffer".into(),
        BindingKind::Storage {
            read_only: true, ..
        } => "storage buffer, read".into(),
        BindingKind::Storage {
            read_only: false, ..
        } => "storage buffer, read-write".into(),
        BindingKind::Texture {
            multisampled: true, ..
        } => "texture, multisampled".into(),
        BindingKind::Texture { .. } => "texture".into(),
        BindingKind::StorageTexture { .. } => "storage texture".into(),
        BindingKind::Sampler { comparison: true } => "comparison sampler".into(),
        BindingKind::Sampler { comparison: false } => "sampler".into(),
    }
}

/// One binding of the module, as the variants that have it reflect it.
struct BindingRow {
    group: u32,
    binding: u32,
    name: String,
    kind: String,
    stages: String,
    variants: Vec<String>,
}

fn bindings(page: &mut String, c: &Compiled) {
    // Every (group, binding, static) any variant has, with the variants that have it.
    let mut rows: Vec<BindingRow> = vec![];
    for v in &c.variants {
        for b in &v.reflection.bindings {
            let same = |r: &&mut BindingRow| {
                (r.group, r.binding, &r.name) == (b.group, b.binding, &b.name)
            };
            if let Some(row) = rows.iter_mut().find(same) {
                row.variants.push(v.names[0].clone());
                continue;
            }
            let stages = [
                (b.visibility.compute, "compute"),
                (b.visibility.vertex, "vertex"),
                (b.visibility.fragment, "fragment"),
            ]
            .iter()
            .filter(|(on, _)| *on)
            .map(|(_, s)| *s)
            .collect::<Vec<_>>()
            .join(", ");
            rows.push(BindingRow {
                group: b.group,
                binding: b.binding,
                name: b.name.clone(),
                kind: binding_kind(&b.kind),
                stages,
                variants: vec![v.names[0].clone()],
            });
        }
    }
    if rows.is_empty() {
        let _ = writeln!(page, "## Bindings\n\nNone.\n");
        return;
    }
    rows.sort_by(|a, b| (a.group, a.binding, &a.name).cmp(&(b.group, b.binding, &b.name)));
    let _ = writeln!(
        page,
        "## Bindings\n\nThe host binds each through the generated builder's field named in the \
         second column (`module::Group<N>`; a library's bindings through its part).\n\n\
         | group | binding | static | builder field | type | kind | stages | variants |\n\
         |---:|---:|---|---|---|---|---|---|"
    );
    let env = first_env(c);
    for r in rows {
        let ty = c
            .module
            .globals
            .iter()
            .find(|g| g.name == r.name)
            .map_or_else(String::new, |g| rust_type(&g.ty, &c.module, env));
        let which = if r.variants.len() == c.variants.len() {
            "all".to_owned()
        } else {
            r.variants.join(", ")
        };
        let field = codegen::emit::builder_field(c, &r.name)
            .map_or_else(|| "–".to_owned(), |f| format!("`{f}`"));
        let _ = writeln!(
            page,
            "| {} | {} | `{}` | {field} | `{ty}` | {} | {} | {which} |",
            r.group, r.binding, r.name, r.kind, r.stages
        );
    }
    page.push('\n');
}

fn first_env(c: &Compiled) -> Option<&Env> {
    c.keys.iter().find(|k| !k.excluded).map(|k| &k.env)
}

fn structs(page: &mut String, c: &Compiled) {
    let Some(env) = first_env(c) else {
        return;
    };
    let m = &c.module;
    if m.structs.is_empty() {
        return;
    }
    let _ = writeln!(
        page,
        "## Host structs\n\nThe generated Rust structs (`bytemuck::Pod`) have exactly these \
         offsets; padding is explicit. Layouts of the first variant.\n"
    );
    for (id, s) in m.structs.iter().enumerate() {
        let layout = codegen::layout::struct_layout(id, m, env);
        let used = [
            (s.uses.uniform, "uniform"),
            (s.uses.storage, "storage"),
            (s.uses.io, "entry point IO"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| *n)
        .collect::<Vec<_>>();
        let _ = writeln!(
            page,
            "### `{}`\n\n{} bytes, aligned to {}{}.\n",
            s.name,
            layout.layout.size,
            layout.layout.align,
            if used.is_empty() {
                String::new()
            } else {
                format!("; used in {}", used.join(", "))
            }
        );
        if let Some(Some(naga)) = c.naga_layouts.get(id) {
            let ours: Vec<u32> = layout.members.iter().map(|m| m.offset).collect();
            if naga.offsets != ours || naga.size != layout.layout.size {
                let _ = writeln!(
                    page,
                    "**naga's layouter disagrees**: size {}, offsets {:?}.\n",
                    naga.size, naga.offsets
                );
            }
        }
        let _ = writeln!(
            page,
            "| field | type | offset | size |\n|---|---|---:|---:|"
        );
        for (f, l) in s.fields.iter().zip(&layout.members) {
            let size = l.size_attr.unwrap_or(l.ty.size);
            let _ = writeln!(
                page,
                "| `{}` | `{}` | {} | {size} |",
                f.name,
                rust_type(&f.ty, m, Some(env)),
                l.offset
            );
        }
        page.push('\n');
    }
}

fn scalar(s: Scalar) -> &'static str {
    match s.concretize() {
        Scalar::Bool => "bool",
        Scalar::I32 => "i32",
        Scalar::U32 => "u32",
        _ => "f32",
    }
}

/// A DSL type as the shader author writes it, array lengths evaluated in `env`.
fn rust_type(ty: &Ty, m: &Module, env: Option<&Env>) -> String {
    match ty {
        Ty::Unit => "()".into(),
        Ty::Scalar(s) => scalar(*s).into(),
        Ty::Vector(n, s) => {
            let prefix = match s.concretize() {
                Scalar::Bool => "B",
                Scalar::I32 => "I",
                Scalar::U32 => "U",
                _ => "",
            };
            format!("{prefix}Vec{n}")
        }
        Ty::Matrix(c, _) => format!("Mat{c}"),
        Ty::Array(t, len) => {
            let n = env
                .and_then(|e| codegen::layout::array_len(len, m, e))
                .map_or_else(|| "N".to_owned(), |n| n.to_string());
            format!("[{}; {n}]", rust_type(t, m, env))
        }
        Ty::RuntimeArray(t) => format!("[{}]", rust_type(t, m, env)),
        Ty::Struct(id) => m.structs.get(*id).map_or("?".into(), |s| s.name.clone()),
        Ty::Atomic(s) => format!("Atomic<{}>", scalar(*s)),
        Ty::Texture(t) => {
            let kind = match t.kind {
                TexKind::Depth => "Depth".to_owned(),
                TexKind::Sampled(s) => format!("<{}>", scalar(s)),
            };
            let ms = if t.multisampled { "Multisampled" } else { "" };
            let array = if t.arrayed { "Array" } else { "" };
            match t.kind {
                TexKind::Depth => format!("Texture{kind}{ms}2d{array}"),
                TexKind::Sampled(_) => format!("Texture{ms}2d{array}{kind}"),
            }
        }
        Ty::StorageTexture(f, _) => format!("StorageTexture2d<{}>", f.rust),
        Ty::Sampler { comparison: true } => "SamplerComparison".into(),
        Ty::Sampler { comparison: false } => "Sampler".into(),
        Ty::Ptr(t) => format!("&mut {}", rust_type(t, m, env)),
    }
}

/// The index page: every module with its variant count, linking to its page.
pub fn index_page(modules: &[(String, usize, bool)]) -> String {
    let mut page = String::from(
        "# DSL modules\n\nGenerated by `cargo xtask shaders --doc` from `shaders_gen`'s sources.\n\n\
         | module | kind | variants |\n|---|---|---:|\n",
    );
    for (name, variants, library) in modules {
        let kind = if *library { "library" } else { "shader" };
        let _ = writeln!(page, "| [`{name}`]({name}.md) | {kind} | {variants} |");
    }
    page
}

/// The device features a variant needs, as the tables print them (`-` for none).
pub(crate) fn features(f: codegen::rt::Features) -> &'static str {
    match (f.subgroup, f.int64) {
        (false, false) => "-",
        (true, false) => "SUBGROUP",
        (false, true) => "INT64",
        (true, true) => "SUBGROUP, INT64",
    }
}

#[cfg(test)]
#[path = "shaders_doc_tests.rs"]
mod tests;
