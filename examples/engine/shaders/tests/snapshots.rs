//! The engine module's generated WGSL, snapshotted as an engine's CI would, and its generated
//! bind-group builders, which take the library crate's part by name.

use engine_shaders::{bricks, engine_lit};
use shader_bind::wgpu;

#[test]
fn every_variant_s_wgsl_is_snapshotted() {
    assert_eq!(engine_lit::VARIANTS.len(), 2);
    for &key in engine_lit::VariantKey::ALL {
        let variant = engine_lit::variant(key);
        // The renderer's PBR and octahedral code and the engine's library are merged in.
        assert!(variant.wgsl.contains("fn shade_light("), "{key}");
        assert!(variant.wgsl.contains("fn tinted("), "{key}");
        assert_eq!(
            variant.wgsl.contains("fn octahedral_decode("),
            key.packed,
            "{key}"
        );
        insta::assert_snapshot!(format!("engine_lit_{key}"), variant.wgsl);
    }
}

/// Group 0 is the module's own; group 1 is the engine library's part, named after it.
#[test]
fn the_builders_take_the_library_crate_s_part_by_name() {
    fn groups<'a>(
        buffers: [&'a wgpu::Buffer; 4],
    ) -> (engine_lit::Group0<'a>, engine_lit::Group1<'a>) {
        let [points, light, out, tint] = buffers;
        (
            engine_lit::Group0 {
                points: points.as_entire_buffer_binding(),
                light: light.as_entire_buffer_binding(),
                out: out.as_entire_buffer_binding(),
            },
            engine_lit::Group1 {
                surface: engine_shader_lib::surface::Group1 {
                    tint: tint.as_entire_buffer_binding(),
                },
            },
        )
    }
    let _ = groups;
    let variant = engine_lit::variant(engine_lit::VariantKey::ALL[0]);
    let names: Vec<(u32, u32, &str)> = variant
        .bindings
        .iter()
        .map(|b| (b.group, b.binding, b.name))
        .collect();
    assert_eq!(
        names,
        [
            (0, 0, "POINTS"),
            (0, 1, "LIGHT"),
            (0, 2, "OUT"),
            (1, 0, "TINT")
        ]
    );
    // The host type of the library's struct is the library crate's own.
    let tint = engine_shader_lib::surface::Tint::new(glam::Vec3::ONE, 0.25);
    assert_eq!(bytemuck::bytes_of(&tint).len(), 16);
}

/// The material's variants are the renderer's material frame around the engine's surface: the
/// frame's entry points (the forward ones at `msaa` 0, the visibility path's kernel at its
/// sample counts, and the blended entry points over the compute rasteriser's buffer at its
/// sample counts), the renderer's light loop and the engine's pattern library merged in, and
/// the parameter records at group 0, binding 19. The plain forward list kinds and the MSAA 4
/// kernels (over the raster targets, and over the compute rasteriser's buffer, `vis64`) are
/// snapshotted.
#[test]
fn the_material_is_the_frame_around_the_engines_surface() {
    assert_eq!(
        bricks::VARIANTS.len(),
        34,
        "list × blend × scalarize, less naive scalar; the kernels of 1, 2, 4 and 8 samples, \
         plain and scalarized, reading the raster targets or the compute rasteriser's buffer; \
         and blended surfaces over that buffer at 1, 2, 4 and 8 samples, plain and scalarized"
    );
    for &key in bricks::VariantKey::ALL {
        let Ok(variant) = bricks::variant(key) else {
            let kernel = key.msaa != bricks::Msaa::Msaa0;
            let excluded = if kernel {
                key.list != bricks::List::List2 || (key.blend && !key.vis64)
            } else {
                (key.list == bricks::List::List0 && key.scalarize) || key.vis64
            };
            assert!(excluded, "{key}");
            continue;
        };
        let entries: &[&str] = if key.msaa == bricks::Msaa::Msaa0 {
            &["vs_forward", "fs_forward", "fs_gbuffer"]
        } else if key.blend {
            &[
                "vs_forward",
                "vs_blend",
                "fs_blend_list",
                "vis_blend_args",
                "vis_shade_blended",
                "fs_blend_listed",
                "fs_forward_vis64",
            ]
        } else {
            &["vis_shade"]
        };
        assert_eq!(variant.entry_points.len(), entries.len(), "{key}");
        for entry in entries {
            assert!(variant.entry_point(entry).is_some(), "{key}: {entry}");
        }
        assert!(variant.wgsl.contains("fn brick_mask("), "{key}");
        assert!(variant.wgsl.contains("fn light_contribution("), "{key}");
        assert!(
            variant
                .wgsl
                .contains("@group(0) @binding(19) var<storage, read> PARAMS: array<Bricks>;"),
            "{key}"
        );
        let snapshotted = !key.blend
            && !key.scalarize
            && matches!(key.msaa, bricks::Msaa::Msaa0 | bricks::Msaa::Msaa4);
        if snapshotted {
            insta::assert_snapshot!(format!("bricks_{key}"), variant.wgsl);
        }
    }
}
