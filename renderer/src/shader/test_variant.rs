//! A reflected compute variant (two bind groups, SUBGROUP, 16×16 workgroups) shared by the
//! tests of this module and of `layout`, and a copy of it that needs 64-bit integers instead.

use codegen::rt::{
    Binding, BindingKind, EntryPoint, Features, SampleType, Stage, Variant, ViewDimension,
    Visibility,
};

const BINDINGS: &[Binding] = &[
    Binding {
        name: "CAMERA",
        group: 0,
        binding: 0,
        visibility: Visibility {
            compute: true,
            vertex: false,
            fragment: false,
        },
        kind: BindingKind::Uniform { min_size: 80 },
    },
    Binding {
        name: "DEPTH",
        group: 0,
        binding: 3,
        visibility: Visibility {
            compute: true,
            vertex: false,
            fragment: true,
        },
        kind: BindingKind::Texture {
            sample_type: SampleType::Depth,
            view_dimension: ViewDimension::D2,
            multisampled: true,
        },
    },
    Binding {
        name: "GRID",
        group: 1,
        binding: 0,
        visibility: Visibility {
            compute: true,
            vertex: false,
            fragment: false,
        },
        kind: BindingKind::Storage {
            read_only: false,
            min_size: 8,
        },
    },
];
pub(super) const VARIANT: Variant = Variant {
    module: "cull",
    names: &["t16"],
    wgsl: "",
    spirv: &[],
    spirv_version: (1, 0),
    entry_points: &[EntryPoint {
        name: "main",
        stage: Stage::Compute,
        workgroup_size: [16, 16, 1],
        workgroup_memory: 0,
        inputs: &[],
        outputs: &[],
    }],
    bindings: BINDINGS,
    features: Features {
        subgroup: true,
        int64: false,
    },
};

/// The same variant without subgroup operations but with 64-bit integers (`u64`, the compute
/// rasteriser's `Atomic<u64>` `fetch_min`).
pub(super) const INT64_VARIANT: Variant = Variant {
    module: "raster",
    names: &["t16"],
    features: Features {
        subgroup: false,
        int64: true,
    },
    ..VARIANT
};
