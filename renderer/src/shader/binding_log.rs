//! What a program's bind groups held when they were last built, kept on request: a tool reads
//! it back after the GPU ran (the tests' host replay of a kernel, which must see exactly the
//! buffers and textures the dispatch was given, not a second gathering of them).

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use shader_bind::BoundResource;

/// One group's resources by binding name.
type GroupResources = Vec<(&'static str, BoundResource)>;

/// The resources of each bind group a program built, by group, then binding name; empty and
/// not kept until [`BindingLog::start`]. Clones of a program share it.
#[derive(Debug, Clone, Default)]
pub(crate) struct BindingLog {
    groups: Arc<Mutex<Option<BTreeMap<u32, GroupResources>>>>,
}

impl BindingLog {
    /// Keeps every group built from now on (the last build of each group).
    #[cfg(any(test, feature = "internals"))]
    pub(crate) fn start(&self) {
        if let Ok(mut groups) = self.groups.lock() {
            groups.get_or_insert_with(BTreeMap::new);
        }
    }

    /// Group `group` of `variant` was built from `resources`: the variant's bindings among
    /// them are kept if the log was started (a builder also holds the resources of bindings
    /// other variants of its module have).
    pub(crate) fn note(
        &self,
        variant: &codegen::rt::Variant,
        group: u32,
        resources: &shader_bind::Resources<'_>,
    ) {
        if let Ok(mut groups) = self.groups.lock()
            && let Some(groups) = groups.as_mut()
        {
            let mut bound = resources.snapshot();
            bound.retain(|(name, _)| variant.group(group).any(|b| b.name == *name));
            groups.insert(group, bound);
        }
    }

    /// Every kept resource: group, binding name, resource.
    #[cfg(any(test, feature = "internals"))]
    pub(crate) fn bound(&self) -> Vec<(u32, &'static str, BoundResource)> {
        let Ok(groups) = self.groups.lock() else {
            return Vec::new();
        };
        groups
            .iter()
            .flatten()
            .flat_map(|(group, named)| named.iter().map(|(n, r)| (*group, *n, r.clone())))
            .collect()
    }
}
