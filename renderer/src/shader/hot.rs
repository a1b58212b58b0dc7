//! Hot reload: WGSL that replaces a generated variant's while the program runs.
//!
//! A tool (the viewer) recompiles an edited `shaders_gen` source with the DSL compiler and
//! installs ([`install_all`]) each variant whose WGSL changed; every [`super::ShaderProgram`] created after
//! that uses the replacement, so rebuilding the renderer picks it up. A replacement must keep
//! its variant's interface (entry points, their inputs and outputs, and bindings): the host
//! code, bind groups and host structs were compiled against it. [`install_all`] checks that and
//! validates the WGSL with naga first, so a bad replacement is an error, never a wgpu panic.

use std::collections::BTreeMap;
use std::sync::{Arc, RwLock};

use codegen::rt::{BindingKind, Location, Stage, Variant, Visibility};

/// An entry point as a replacement must keep it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EntryInterface {
    /// The function name in WGSL.
    pub name: String,
    /// Its stage.
    pub stage: Stage,
    /// The workgroup size; `[0, 0, 0]` for vertex and fragment entry points.
    pub workgroup_size: [u32; 3],
    /// User-defined inputs by location (vertex attributes for a vertex entry point).
    pub inputs: Vec<Location>,
    /// User-defined outputs by location (colour targets for a fragment entry point).
    pub outputs: Vec<Location>,
}

/// A binding as a replacement must keep it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BindingInterface {
    /// The bind group number N of the WGSL group attribute.
    pub group: u32,
    /// The binding number N within the group.
    pub binding: u32,
    /// Resource type (buffer, texture, sampler) and its parameters.
    pub kind: BindingKind,
    /// The stages that see it.
    pub visibility: Visibility,
}

/// What host code relies on in a variant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Interface {
    /// Entry points, in the variant's order.
    pub entry_points: Vec<EntryInterface>,
    /// Bindings, in the variant's order.
    pub bindings: Vec<BindingInterface>,
}

impl Interface {
    /// The interface of a generated variant.
    pub fn of(v: &Variant) -> Interface {
        Interface {
            entry_points: v
                .entry_points
                .iter()
                .map(|e| EntryInterface {
                    name: e.name.to_owned(),
                    stage: e.stage,
                    workgroup_size: e.workgroup_size,
                    inputs: e.inputs.to_vec(),
                    outputs: e.outputs.to_vec(),
                })
                .collect(),
            bindings: v
                .bindings
                .iter()
                .map(|b| BindingInterface {
                    group: b.group,
                    binding: b.binding,
                    kind: b.kind,
                    visibility: b.visibility,
                })
                .collect(),
        }
    }
}

/// Why a replacement was refused.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum HotReloadError {
    /// No generated variant has this module and name; check [`Replacement::module`] and
    /// [`Replacement::variant`] against `shaders_gen`.
    #[error("no generated shader variant `{module}::{variant}` to replace")]
    NoSuchVariant {
        /// The module asked for.
        module: String,
        /// The variant name asked for.
        variant: String,
    },
    /// The replacement's entry points or bindings differ from the generated variant's; such an
    /// edit needs a rebuild, not a hot reload.
    #[error(
        "the edit changes the interface of `{module}::{variant}` ({what}); host code was built \
         against it, so rebuild the program for this edit"
    )]
    InterfaceChanged {
        /// The DSL module, as the replacement gives it.
        module: String,
        /// The variant name, as the replacement gives it.
        variant: String,
        /// The first difference found, for the message.
        what: String,
    },
    /// The replacement WGSL does not parse or fails naga validation.
    #[error("the replacement WGSL of `{module}::{variant}` does not validate: {message}")]
    Invalid {
        /// The DSL module, as the replacement gives it.
        module: String,
        /// The variant name, as the replacement gives it.
        variant: String,
        /// naga's diagnostic, rendered against the replacement source.
        message: String,
    },
}

type Replacements = BTreeMap<(String, String), Arc<str>>;

static REPLACEMENTS: RwLock<Replacements> = RwLock::new(BTreeMap::new());

/// The generated variant `module::variant` (any of its names).
fn generated(module: &str, variant: &str) -> Option<&'static Variant> {
    shaders_gen::MODULES
        .iter()
        .find(|m| m.name == module)
        .and_then(|m| m.variant_named(variant))
}

fn first_difference(old: &Interface, new: &Interface) -> String {
    let names = |i: &Interface| {
        i.entry_points
            .iter()
            .map(|e| e.name.clone())
            .collect::<Vec<_>>()
    };
    if names(old) != names(new) {
        return format!("entry points {:?} became {:?}", names(old), names(new));
    }
    if let Some((o, n)) = old
        .entry_points
        .iter()
        .zip(&new.entry_points)
        .find(|(o, n)| o != n)
    {
        return format!("entry point `{}` changed: {o:?} became {n:?}", o.name);
    }
    let binds = |i: &Interface| {
        i.bindings
            .iter()
            .map(|b| (b.group, b.binding))
            .collect::<Vec<_>>()
    };
    if binds(old) != binds(new) {
        return format!("bindings {:?} became {:?}", binds(old), binds(new));
    }
    "a binding's type or visibility changed".to_owned()
}

/// A replacement of one generated variant's WGSL.
#[derive(Debug, Clone)]
pub struct Replacement {
    /// The DSL module.
    pub module: String,
    /// One of the variant's names.
    pub variant: String,
    /// The new WGSL (the DSL compiler's output for the edited source).
    pub wgsl: String,
    /// The new variant's interface, as the DSL compiler reflects it.
    pub interface: Interface,
}

/// Checks one replacement: the variant exists, keeps its interface, and its WGSL validates.
/// Returns the key the table stores it under.
fn check(r: &Replacement) -> Result<(String, String), HotReloadError> {
    let (module, variant) = (r.module.as_str(), r.variant.as_str());
    let original = generated(module, variant).ok_or_else(|| HotReloadError::NoSuchVariant {
        module: module.to_owned(),
        variant: variant.to_owned(),
    })?;
    let old = Interface::of(original);
    if old != r.interface {
        return Err(HotReloadError::InterfaceChanged {
            module: module.to_owned(),
            variant: variant.to_owned(),
            what: first_difference(&old, &r.interface),
        });
    }
    let invalid = |message: String| HotReloadError::Invalid {
        module: module.to_owned(),
        variant: variant.to_owned(),
        message,
    };
    validate(&r.wgsl).map_err(invalid)?;
    Ok((original.module.to_owned(), original.name().to_owned()))
}

/// naga's parse and validation of `wgsl`, its diagnostic rendered against the source.
#[cfg(not(target_arch = "wasm32"))]
fn validate(wgsl: &str) -> Result<(), String> {
    let parsed = naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string(wgsl))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&parsed)
    .map_err(|e| e.emit_to_string(wgsl))?;
    Ok(())
}

/// In a browser the renderer is built without naga (a large share of the module for a tool
/// that has no files to watch there): every replacement is refused, so none reaches the
/// device unvalidated.
#[cfg(target_arch = "wasm32")]
fn validate(_wgsl: &str) -> Result<(), String> {
    Err("hot reload validates replacements with naga, which the browser build leaves out".into())
}

/// Makes `replacements` the whole set of replaced variants, for every shader program created
/// from now on (a variant not listed goes back to its generated WGSL). All or nothing: when
/// one is refused, nothing changes.
pub fn install_all(replacements: &[Replacement]) -> Result<(), HotReloadError> {
    let mut table = Replacements::new();
    for r in replacements {
        let key = check(r)?;
        table.insert(key, Arc::from(r.wgsl.as_str()));
    }
    *REPLACEMENTS
        .write()
        .unwrap_or_else(std::sync::PoisonError::into_inner) = table;
    Ok(())
}

/// Drops every replacement: programs created from now on use the generated WGSL again.
pub fn clear() {
    REPLACEMENTS
        .write()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .clear();
}

/// How many variants are replaced now.
pub fn installed() -> usize {
    REPLACEMENTS
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .len()
}

/// The WGSL a program of `variant` compiles: its replacement, or the generated source.
pub(crate) fn wgsl_of(variant: &'static Variant) -> std::borrow::Cow<'static, str> {
    let table = REPLACEMENTS
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    match table.get(&(variant.module.to_owned(), variant.name().to_owned())) {
        Some(wgsl) => std::borrow::Cow::Owned(wgsl.to_string()),
        None => std::borrow::Cow::Borrowed(variant.wgsl),
    }
}

#[cfg(test)]
mod tests {
    use super::{HotReloadError, Interface, Replacement, check};

    #[test]
    fn a_replacement_must_keep_the_interface_and_validate() {
        let tonemap = shaders_gen::MODULES
            .iter()
            .find(|m| m.name == "tonemap")
            .expect("the tonemap module");
        let v = &tonemap.variants[0];
        let same = Replacement {
            module: "tonemap".into(),
            variant: v.name().into(),
            wgsl: v.wgsl.into(),
            interface: Interface::of(v),
        };
        // Checked only: installing would change every program this test binary creates.
        assert!(check(&same).is_ok());
        let mut fewer = same.clone();
        fewer.interface.bindings.pop();
        assert!(matches!(
            check(&fewer),
            Err(HotReloadError::InterfaceChanged { .. })
        ));
        let broken = Replacement {
            wgsl: "fn broken( {".into(),
            ..same.clone()
        };
        assert!(matches!(
            check(&broken),
            Err(HotReloadError::Invalid { .. })
        ));
        let unknown = Replacement {
            module: "no_such_module".into(),
            ..same
        };
        assert!(matches!(
            check(&unknown),
            Err(HotReloadError::NoSuchVariant { .. })
        ));
    }
}
