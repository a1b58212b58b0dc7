//! A reflected compute variant (two bind groups, SUBGROUP, 16×16 workgroups) shared by the
//! tests of this module and of `layout`.

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
        inputs: &[],
        outputs: &[],
    }],
    bindings: BINDINGS,
    features: Features { subgroup: true },
};
