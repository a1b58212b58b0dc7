//! Runtime reflection: the plain data that generated code stores in `static` tables.
//!
//! Everything here is usable in `static` items (`&'static` slices and strings only) and has no
//! dependency at all, so user crates can depend on `codegen` with `default-features = false`.
//! This module must never grow a dependency on the compiler or on any GPU API: `renderer`
//! turns these descriptions into wgpu objects.

use core::fmt;

/// One generated shader variant: WGSL, SPIR-V and everything needed to build pipelines.
#[derive(Debug, Clone, Copy)]
pub struct Variant {
    /// The DSL module this variant belongs to.
    pub module: &'static str,
    /// Stable names of every variant key that produced this exact output (deduplicated).
    pub names: &'static [&'static str],
    /// The WGSL source, as printed by the DSL's own printer and validated by naga.
    pub wgsl: &'static str,
    /// SPIR-V words from naga's SPIR-V backend; empty in a browser build (`wasm32`), which
    /// takes WGSL only.
    pub spirv: &'static [u32],
    /// The SPIR-V version of [`Variant::spirv`], `(major, minor)`.
    pub spirv_version: (u8, u8),
    /// Entry points, in declaration order.
    pub entry_points: &'static [EntryPoint],
    /// Resource bindings, sorted by `(group, binding)`.
    pub bindings: &'static [Binding],
    /// Device features this variant needs.
    pub features: Features,
}

impl Variant {
    /// The first (canonical) name of this variant.
    pub fn name(&self) -> &'static str {
        self.names.first().copied().unwrap_or("default")
    }

    /// Looks up an entry point by name.
    pub fn entry_point(&self, name: &str) -> Option<&'static EntryPoint> {
        self.entry_points.iter().find(|e| e.name == name)
    }

    /// The bindings of one bind group, in binding order.
    pub fn group(&self, group: u32) -> impl Iterator<Item = &'static Binding> {
        self.bindings.iter().filter(move |b| b.group == group)
    }

    /// Whether an entry point of this variant uses the `sample_mask` built-in: its SPIR-V
    /// decorates a variable `BuiltIn SampleMask`. naga 30, which wgpu writes its SPIR-V with,
    /// declares that variable as a scalar, which Vulkan refuses
    /// (VUID-SampleMask-SampleMask-04359); this variant's own [`Variant::spirv`] declares the
    /// array. `false` in a browser build, which has no SPIR-V.
    pub fn uses_sample_mask(&self) -> bool {
        const DECORATE: u32 = 71;
        const BUILT_IN: u32 = 11;
        const SAMPLE_MASK: u32 = 20;
        let words = self.spirv;
        let mut at = 5; // after the header
        while let Some(&first) = words.get(at) {
            let (count, opcode) = ((first >> 16) as usize, first & 0xffff);
            if opcode == DECORATE && words.get(at + 2..at + 4) == Some(&[BUILT_IN, SAMPLE_MASK]) {
                return true;
            }
            at += count.max(1);
        }
        false
    }

    /// One past the highest bind group index used (the number of bind group layouts needed).
    pub fn group_count(&self) -> u32 {
        self.bindings.iter().map(|b| b.group + 1).max().unwrap_or(0)
    }
}

/// Features a variant needs from the device.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Features {
    /// Subgroup operations (wgpu `Features::SUBGROUP`).
    pub subgroup: bool,
    /// 64-bit integers: the variant's WGSL uses `u64` (wgpu `Features::SHADER_INT64`, and
    /// `Features::SHADER_INT64_ATOMIC_MIN_MAX` for its `Atomic<u64>` `fetch_min`/`fetch_max`;
    /// both are needed).
    pub int64: bool,
}

/// A shader stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    /// `#[compute]`
    Compute,
    /// `#[vertex]`
    Vertex,
    /// `#[fragment]`
    Fragment,
}

/// An entry point of a variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EntryPoint {
    /// The function name, also its name in WGSL and SPIR-V.
    pub name: &'static str,
    /// Its stage.
    pub stage: Stage,
    /// The workgroup size; `[0, 0, 0]` for vertex and fragment.
    pub workgroup_size: [u32; 3],
    /// Bytes of workgroup memory it uses, each variable rounded up to 16 bytes as WebGPU's
    /// `maxComputeWorkgroupStorageSize` counts them; 0 for vertex and fragment.
    pub workgroup_memory: u32,
    /// User-defined inputs (`#[location]` parameters and IO struct fields), by location: for a
    /// vertex entry point, the vertex attributes.
    pub inputs: &'static [Location],
    /// User-defined outputs, by location: for a fragment entry point, the color targets.
    pub outputs: &'static [Location],
}

/// A user-defined entry point input or output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Location {
    /// `#[location(N)]`
    pub location: u32,
    /// The value's type, named like wgpu's `VertexFormat`.
    pub format: ValueFormat,
}

/// The type of a location value, named like wgpu's `VertexFormat` variants.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ValueFormat {
    /// `f32`
    Float32,
    /// `Vec2`
    Float32x2,
    /// `Vec3`
    Float32x3,
    /// `Vec4`
    Float32x4,
    /// `u32`
    Uint32,
    /// `UVec2`
    Uint32x2,
    /// `UVec3`
    Uint32x3,
    /// `UVec4`
    Uint32x4,
    /// `i32`
    Sint32,
    /// `IVec2`
    Sint32x2,
    /// `IVec3`
    Sint32x3,
    /// `IVec4`
    Sint32x4,
}

/// Which stages see a binding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Visibility {
    /// Visible to compute entry points.
    pub compute: bool,
    /// Visible to vertex entry points.
    pub vertex: bool,
    /// Visible to fragment entry points.
    pub fragment: bool,
}

/// One resource binding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Binding {
    /// The `static` item's name in the DSL module.
    pub name: &'static str,
    /// `@group`
    pub group: u32,
    /// `@binding`
    pub binding: u32,
    /// The stages whose entry points use it (every stage of the module when none does).
    pub visibility: Visibility,
    /// What kind of resource it is.
    pub kind: BindingKind,
}

/// The kind of resource behind a binding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BindingKind {
    /// A uniform buffer; `min_size` is the WGSL size of its type.
    Uniform {
        /// Minimum binding size in bytes.
        min_size: u64,
    },
    /// A storage buffer; for runtime-sized arrays `min_size` is one element.
    Storage {
        /// `true` unless declared `read_write`.
        read_only: bool,
        /// Minimum binding size in bytes.
        min_size: u64,
    },
    /// A sampled texture.
    Texture {
        /// The texel type seen by the shader.
        sample_type: SampleType,
        /// The view dimension.
        view_dimension: ViewDimension,
        /// Whether it is multisampled.
        multisampled: bool,
    },
    /// A storage texture.
    StorageTexture {
        /// The texel format.
        format: StorageFormat,
        /// How the shader accesses it.
        access: StorageAccess,
        /// The view dimension.
        view_dimension: ViewDimension,
    },
    /// A sampler.
    Sampler {
        /// A comparison sampler (`SamplerComparison`).
        comparison: bool,
    },
}

/// Sample type of a sampled texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SampleType {
    /// `f32` texels.
    Float {
        /// Whether a filtering sampler may be used with it.
        filterable: bool,
    },
    /// Depth texture.
    Depth,
    /// `u32` texels.
    Uint,
    /// `i32` texels.
    Sint,
}

/// Texture view dimension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ViewDimension {
    /// `texture_2d` and friends.
    D2,
    /// `texture_2d_array` and friends.
    D2Array,
}

/// Storage texture access mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StorageAccess {
    /// `read`
    ReadOnly,
    /// `write`
    WriteOnly,
    /// `read_write`
    ReadWrite,
}

/// Storage texture formats the DSL accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StorageFormat {
    Rgba8Unorm,
    Rgba8Snorm,
    Rgba8Uint,
    Rgba8Sint,
    Rgba16Uint,
    Rgba16Sint,
    Rgba16Float,
    R32Uint,
    R32Sint,
    R32Float,
    Rg32Uint,
    Rg32Sint,
    Rg32Float,
    Rgba32Uint,
    Rgba32Sint,
    Rgba32Float,
    Bgra8Unorm,
}

/// A whole generated module: its name and every (deduplicated) variant.
#[derive(Debug, Clone, Copy)]
pub struct Module {
    /// The DSL module's name.
    pub name: &'static str,
    /// Every variant, in key order.
    pub variants: &'static [Variant],
}

impl Module {
    /// Finds a variant by one of its stable names.
    pub fn variant_named(&self, name: &str) -> Option<&'static Variant> {
        self.variants.iter().find(|v| v.names.contains(&name))
    }
}

/// A variant key that a constraint (`exclude(..)`) removed from the matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExcludedVariant {
    /// The DSL module.
    pub module: &'static str,
    /// The stable name the key would have had.
    pub key: String,
}

impl fmt::Display for ExcludedVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "variant `{}` of shader module `{}` is excluded by one of its `exclude(..)` constraints",
            self.key, self.module
        )
    }
}

impl std::error::Error for ExcludedVariant {}
