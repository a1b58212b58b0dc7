//! The golden corpus also compiles through the proc-macro: host types with naga-asserted
//! layouts, key types and variant tables for every program, including the 24-variant kernel.

mod tile_cull_mod {
    include!("../../tests/dsl-golden/tile_cull.rs");
}
mod graphics_mod {
    include!("../../tests/dsl-golden/graphics.rs");
}
mod expressions_mod {
    include!("../../tests/dsl-golden/expressions.rs");
}
mod subgroups_mod {
    include!("../../tests/dsl-golden/subgroups.rs");
}
mod sample_grad_mod {
    include!("../../tests/dsl-golden/sample_grad.rs");
}
mod atomic_u64_mod {
    include!("../../tests/dsl-golden/atomic_u64.rs");
}

use tile_cull_mod::tile_cull;

#[test]
fn tile_cull_has_24_variants_with_reflection() {
    assert_eq!(tile_cull::VariantKey::ALL.len(), 24);
    assert_eq!(tile_cull::VARIANTS.len(), 24);
    for key in tile_cull::VariantKey::ALL {
        let v = tile_cull::variant(*key);
        assert!(v.names.contains(&key.name()));
        let tile = key.tile.value();
        assert_eq!(v.entry_points[0].workgroup_size, [tile, tile, 1]);
        assert_eq!(v.features.subgroup, key.scalarize);
        let depth = v
            .bindings
            .iter()
            .find(|b| b.binding == 4)
            .expect("depth binding");
        let multisampled = key.msaa.value() > 1;
        assert!(
            matches!(depth.kind, codegen::rt::BindingKind::Texture { multisampled: m, .. } if m == multisampled)
        );
    }
    let key = tile_cull::VariantKey {
        tile: tile_cull::Tile::T16,
        msaa: tile_cull::Msaa::Msaa4,
        scalarize: true,
    };
    assert_eq!(key.to_string(), "t16_msaa4_scalar");
    assert_eq!(size_of::<tile_cull::Light>(), 32);
    assert_eq!(size_of::<tile_cull::Camera>(), 224);
}

#[test]
fn graphics_entry_points_reflect_locations() {
    let v = graphics_mod::graphics::variant(graphics_mod::graphics::VariantKey {
        msaa: graphics_mod::graphics::Msaa::Msaa4,
    });
    let vs = v.entry_point("vs").expect("vertex entry point");
    assert_eq!(vs.inputs.len(), 1);
    assert_eq!(vs.inputs[0].format, codegen::rt::ValueFormat::Float32x3);
    let fs = v.entry_point("fs").expect("fragment entry point");
    assert_eq!(fs.outputs.len(), 1);
    assert_eq!(expressions_mod::expressions::VARIANTS.len(), 1);
    assert_eq!(subgroups_mod::subgroups::VARIANTS.len(), 2);
}

#[test]
fn sample_grad_textures_are_visible_to_fragment_and_compute() {
    let v = &sample_grad_mod::sample_grad::VARIANTS[0];
    assert!(v.wgsl.contains("textureSampleGrad(LAYERS, LINEAR"));
    for name in ["ALBEDO", "LAYERS", "LINEAR"] {
        let b = v.bindings.iter().find(|b| b.name == name).expect("binding");
        assert!(b.visibility.fragment && b.visibility.compute && !b.visibility.vertex);
    }
}

#[test]
fn u64_host_types_constants_and_features() {
    use atomic_u64_mod::atomic_u64;
    // `u64` fields are 8-aligned on both sides (the layout is asserted against naga).
    let f = atomic_u64::Fragment::new(0.5, 7, u64::MAX);
    assert_eq!(size_of::<atomic_u64::Fragment>(), 16);
    assert_eq!(core::mem::offset_of!(atomic_u64::Fragment, packed), 8);
    assert_eq!(f.packed, u64::MAX);
    assert_eq!(atomic_u64::CLEARED, u64::MAX);
    assert_eq!(atomic_u64::VARIANTS.len(), 2);
    for v in atomic_u64::VARIANTS {
        assert!(v.features.int64 && !v.features.subgroup, "{}", v.name());
    }
    assert!(!sample_grad_mod::sample_grad::VARIANTS[0].features.int64);
}
