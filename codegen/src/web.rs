//! What a browser needs of a variant: its WGSL with the `enable` directives WebGPU requires
//! ([`browser_wgsl`]), and whether it fits WebGPU's limits ([`web_issues`]).
//!
//! A variant's [`Variant::wgsl`] is what naga validated. Browsers also require
//! `enable subgroups;` before subgroup built-ins, a directive naga 30's front end rejects, so
//! the directive is added here, after validation, and nothing else changes: a browser compiles
//! the same statements naga validated, one line further down.
//!
//! WebGPU's limits are tighter than Vulkan's, and an adapter may offer more than WebGPU's
//! defaults only where the page asks for them. [`web_issues`] lists every way a variant goes
//! beyond a set of [`WebLimits`] ([`WebLimits::DEFAULT`]: what every WebGPU device has), and
//! whether an adapter could lift it ([`WebIssue::is_limit`]) or WebGPU has no such feature at
//! all (64-bit integers).

use std::fmt;

use crate::rt::{BindingKind, Stage, StorageAccess, Variant};

/// The WebGPU limits a variant is checked against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WebLimits {
    /// `maxComputeInvocationsPerWorkgroup`.
    pub invocations_per_workgroup: u32,
    /// `maxComputeWorkgroupSizeX`, `Y` and `Z`.
    pub workgroup_size: [u32; 3],
    /// `maxComputeWorkgroupStorageSize`, bytes.
    pub workgroup_storage: u32,
    /// `maxBindGroups`.
    pub bind_groups: u32,
    /// `maxStorageBuffersPerShaderStage`.
    pub storage_buffers_per_stage: u32,
    /// `maxStorageTexturesPerShaderStage`.
    pub storage_textures_per_stage: u32,
    /// `maxSampledTexturesPerShaderStage`.
    pub sampled_textures_per_stage: u32,
    /// `maxSamplersPerShaderStage`.
    pub samplers_per_stage: u32,
    /// `maxUniformBuffersPerShaderStage`.
    pub uniform_buffers_per_stage: u32,
}

impl WebLimits {
    /// WebGPU's default limits: what every WebGPU device gives a page that asks for nothing
    /// more.
    pub const DEFAULT: Self = Self {
        invocations_per_workgroup: 256,
        workgroup_size: [256, 256, 64],
        workgroup_storage: 16_384,
        bind_groups: 4,
        storage_buffers_per_stage: 8,
        storage_textures_per_stage: 4,
        sampled_textures_per_stage: 16,
        samplers_per_stage: 16,
        uniform_buffers_per_stage: 12,
    };
}

/// One way a variant goes beyond WebGPU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum WebIssue {
    /// It uses 64-bit integers, which WebGPU does not have.
    Int64,
    /// An entry point's workgroup has more invocations than the limit.
    Invocations {
        /// The entry point.
        entry: &'static str,
        /// Its invocations per workgroup.
        invocations: u32,
        /// The limit.
        max: u32,
    },
    /// An entry point's workgroup is larger than the limit along one axis.
    WorkgroupSize {
        /// The entry point.
        entry: &'static str,
        /// Its workgroup size.
        size: [u32; 3],
        /// The limit per axis.
        max: [u32; 3],
    },
    /// An entry point uses more workgroup memory than the limit.
    WorkgroupStorage {
        /// The entry point.
        entry: &'static str,
        /// Bytes it uses (each variable rounded up to 16).
        bytes: u32,
        /// The limit.
        max: u32,
    },
    /// It binds more groups than the limit.
    BindGroups {
        /// Groups it needs (one past the highest index).
        count: u32,
        /// The limit.
        max: u32,
    },
    /// A writable storage buffer or texture is visible to the vertex stage, which WebGPU
    /// forbids.
    WritableInVertex {
        /// The binding's name.
        binding: &'static str,
    },
    /// One stage sees more resources of one kind than the limit.
    PerStage {
        /// The stage.
        stage: Stage,
        /// The kind, as WebGPU's limit names it ("storage buffers", ...).
        kind: &'static str,
        /// How many of them the stage sees.
        count: u32,
        /// The limit.
        max: u32,
    },
}

impl WebIssue {
    /// Whether an adapter may lift it (a limit the page can ask more of), rather than WebGPU
    /// lacking the feature.
    pub fn is_limit(&self) -> bool {
        !matches!(self, Self::Int64 | Self::WritableInVertex { .. })
    }
}

impl fmt::Display for WebIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Int64 => write!(f, "64-bit integers (WebGPU has none)"),
            Self::Invocations {
                entry,
                invocations,
                max,
            } => write!(
                f,
                "`{entry}`: {invocations} invocations per workgroup (limit {max})"
            ),
            Self::WorkgroupSize { entry, size, max } => {
                write!(f, "`{entry}`: workgroup size {size:?} (limit {max:?})")
            }
            Self::WorkgroupStorage { entry, bytes, max } => {
                write!(
                    f,
                    "`{entry}`: {bytes} bytes of workgroup memory (limit {max})"
                )
            }
            Self::BindGroups { count, max } => write!(f, "{count} bind groups (limit {max})"),
            Self::WritableInVertex { binding } => {
                write!(f, "`{binding}` is writable and seen by the vertex stage")
            }
            Self::PerStage {
                stage,
                kind,
                count,
                max,
            } => write!(f, "{count} {kind} in the {stage:?} stage (limit {max})"),
        }
    }
}

/// What a variant with subgroup operations starts with in a browser: the extension, and the
/// subgroup uniformity analysis turned off. WGSL's analysis cannot prove that a scalarization
/// loop (`subgroupBroadcastFirst` of a value, then the lanes holding it, until none is left)
/// calls its subgroup operations in subgroup-uniform control flow, and rejects it by default;
/// the loop is correct wherever the lanes that leave it stop taking part, which is what WGSL
/// (and the Vulkan path, where this WGSL already runs) guarantees.
pub const SUBGROUP_DIRECTIVES: &str = "enable subgroups;\ndiagnostic(off, subgroup_uniformity);\n";

/// The variant's WGSL as a browser takes it: the `enable` directives its features need, then
/// [`Variant::wgsl`] unchanged.
pub fn browser_wgsl(variant: &Variant) -> String {
    let mut out = String::with_capacity(variant.wgsl.len() + 32);
    out.push_str(browser_directives(variant));
    out.push_str(variant.wgsl);
    out
}

/// What [`browser_wgsl`] puts before the variant's WGSL (empty for a variant that uses no
/// feature a browser must enable): for a renderer that prefixes another source of the same
/// variant, such as a hot-reloaded replacement.
pub fn browser_directives(variant: &Variant) -> &'static str {
    if variant.features.subgroup {
        SUBGROUP_DIRECTIVES
    } else {
        ""
    }
}

/// Every way `variant` goes beyond `limits` (none: it runs on any WebGPU device with those
/// limits, and the `subgroups` feature where [`crate::rt::Features::subgroup`] says so).
pub fn web_issues(variant: &Variant, limits: &WebLimits) -> Vec<WebIssue> {
    let mut issues = Vec::new();
    if variant.features.int64 {
        issues.push(WebIssue::Int64);
    }
    for e in variant
        .entry_points
        .iter()
        .filter(|e| e.stage == Stage::Compute)
    {
        let [x, y, z] = e.workgroup_size;
        let invocations = x.saturating_mul(y).saturating_mul(z);
        if invocations > limits.invocations_per_workgroup {
            issues.push(WebIssue::Invocations {
                entry: e.name,
                invocations,
                max: limits.invocations_per_workgroup,
            });
        }
        if e.workgroup_size
            .iter()
            .zip(limits.workgroup_size)
            .any(|(&n, max)| n > max)
        {
            issues.push(WebIssue::WorkgroupSize {
                entry: e.name,
                size: e.workgroup_size,
                max: limits.workgroup_size,
            });
        }
        if e.workgroup_memory > limits.workgroup_storage {
            issues.push(WebIssue::WorkgroupStorage {
                entry: e.name,
                bytes: e.workgroup_memory,
                max: limits.workgroup_storage,
            });
        }
    }
    let groups = variant.group_count();
    if groups > limits.bind_groups {
        issues.push(WebIssue::BindGroups {
            count: groups,
            max: limits.bind_groups,
        });
    }
    for b in variant.bindings.iter().filter(|b| b.visibility.vertex) {
        let writable = match b.kind {
            BindingKind::Storage { read_only, .. } => !read_only,
            BindingKind::StorageTexture { access, .. } => access != StorageAccess::ReadOnly,
            _ => false,
        };
        if writable {
            issues.push(WebIssue::WritableInVertex { binding: b.name });
        }
    }
    for stage in [Stage::Compute, Stage::Vertex, Stage::Fragment] {
        per_stage(variant, stage, limits, &mut issues);
    }
    issues
}

/// The per-stage resource counts of `stage` against `limits`.
fn per_stage(variant: &Variant, stage: Stage, limits: &WebLimits, issues: &mut Vec<WebIssue>) {
    let sees = |v: crate::rt::Visibility| match stage {
        Stage::Compute => v.compute,
        Stage::Vertex => v.vertex,
        Stage::Fragment => v.fragment,
    };
    let mut counts = [0u32; 5];
    for b in variant.bindings.iter().filter(|b| sees(b.visibility)) {
        let kind = match b.kind {
            BindingKind::Storage { .. } => 0,
            BindingKind::StorageTexture { .. } => 1,
            BindingKind::Texture { .. } => 2,
            BindingKind::Sampler { .. } => 3,
            BindingKind::Uniform { .. } => 4,
        };
        counts[kind] += 1;
    }
    let kinds = [
        ("storage buffers", limits.storage_buffers_per_stage),
        ("storage textures", limits.storage_textures_per_stage),
        ("sampled textures", limits.sampled_textures_per_stage),
        ("samplers", limits.samplers_per_stage),
        ("uniform buffers", limits.uniform_buffers_per_stage),
    ];
    for ((kind, max), count) in kinds.into_iter().zip(counts) {
        if count > max {
            issues.push(WebIssue::PerStage {
                stage,
                kind,
                count,
                max,
            });
        }
    }
}

#[cfg(test)]
#[path = "web_tests.rs"]
mod tests;
