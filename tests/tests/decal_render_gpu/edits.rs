//! Decals added, removed and moved over the same materials keep the packed atlas and write only
//! their records (in place when they fit); materials added and removed keep it too, new ones
//! written into free room; each draws exactly as a renderer given the final set from the start.
//! Another atlas configuration packs the atlas again.

use glam::{Mat4, Vec3};
use renderer::decals::{DecalAtlasConfig, DecalImage, DecalMaterial, DecalSet};
use renderer::demo::procedural_lights;
use renderer::frame::default_camera;
use renderer::frame::{DecalUpload, RenderPath, Renderer, RendererConfig};
use tests::frames::{committed_scene, largest_difference, render_frame_with, render_one_frame};
use tests::gpu::gpu_test;

use super::{changed_pixels, decal_set};

/// Decals added, removed and moved over the same materials keep the packed atlas and write only
/// their records, and the frame equals a renderer given the final set from the start; a set
/// whose materials differ writes only the new ones into free room, and draws as a fresh set.
#[test]
fn decals_and_decal_materials_edited_keep_the_atlas_and_draw_as_a_fresh_set() {
    let scene = committed_scene();
    let size = (scene.bounds.max - scene.bounds.min).length();
    let lights = procedural_lights(scene.bounds, 64, 5, size * 0.05, size * 0.3);
    let first = decal_set(&scene, 1);
    // Every third decal removed, the rest shifted, and the other seed's decals added.
    let mut edited = DecalSet {
        materials: first.materials.clone(),
        decals: first
            .decals
            .iter()
            .enumerate()
            .filter(|(i, _)| i % 3 != 0)
            .map(|(_, d)| {
                let mut d = *d;
                d.world_from_box =
                    Mat4::from_translation(Vec3::splat(size * 0.01)) * d.world_from_box;
                d
            })
            .collect(),
    };
    edited.decals.extend(decal_set(&scene, 2).decals);
    let config = RendererConfig {
        width: 128,
        height: 96,
        msaa: 4,
        path: RenderPath::Clustered,
        tile: 16,
        ambient: renderer::frame::Ambient::uniform(Vec3::splat(0.3)),
        ..Default::default()
    };
    let camera = default_camera(&scene, 128.0 / 96.0);
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(&scene).expect("the scene fits");
        renderer.set_lights(&lights).expect("lights fit");
        assert_eq!(
            renderer.set_decals(&first).expect("decals fit"),
            DecalUpload::Repacked
        );
        let before = render_one_frame(gpu, &mut renderer, &camera).rgba;
        assert_eq!(
            renderer.set_decals(&edited).expect("decals fit"),
            DecalUpload::RecordsOnly,
            "the same materials keep the atlas"
        );
        let after = render_one_frame(gpu, &mut renderer, &camera).rgba;
        let fresh = render_frame_with(gpu, &scene, config, &lights, &edited, &camera).rgba;
        let worst = largest_difference(&after, &fresh);
        assert_eq!(
            worst, 0,
            "the edited decals differ from a fresh set by {worst}"
        );
        assert!(
            changed_pixels(&before, &after, 8) > 0,
            "the edits must show in the frame"
        );
        // Fewer decals than before: written into the same records buffer.
        let fewer = DecalSet {
            materials: edited.materials.clone(),
            decals: edited.decals.iter().step_by(2).cloned().collect(),
        };
        assert_eq!(
            renderer.set_decals(&fewer).expect("decals fit"),
            DecalUpload::RecordsOnly
        );
        let thinned = render_one_frame(gpu, &mut renderer, &camera).rgba;
        let fresh = render_frame_with(gpu, &scene, config, &lights, &fewer, &camera).rgba;
        let worst = largest_difference(&thinned, &fresh);
        assert_eq!(
            worst, 0,
            "the thinned decals differ from a fresh set by {worst}"
        );
        assert!(
            changed_pixels(&after, &thinned, 8) > 0,
            "the removals must show"
        );
        // Material 0 replaced by a recoloured copy and a striped material added, which a
        // third of the decals take: both go into free room, and material 0's room is given
        // back; the rest of the atlas stays.
        let mut other = fewer.clone();
        let mut recoloured = other.materials[0].clone();
        recoloured.name.push_str(" recoloured");
        for texel in recoloured.base_color.rgba.chunks_mut(4) {
            texel[..3].rotate_left(1);
        }
        other.materials[0] = recoloured;
        other.materials.push(DecalMaterial {
            name: "stripes".into(),
            base_color: DecalImage::from_fn(24, 40, |x, y| {
                if (x + y / 3) % 6 < 3 {
                    [250, 240, 40, 255]
                } else {
                    [20, 20, 20, 160]
                }
            }),
            normal: None,
            orm: None,
            emissive: None,
        });
        let striped = other.materials.len() - 1;
        for d in other.decals.iter_mut().step_by(3) {
            d.material = striped;
        }
        assert_eq!(
            renderer.set_decals(&other).expect("decals fit"),
            DecalUpload::MaterialsInPlace {
                added: 2,
                removed: 1
            },
            "new materials go into free room"
        );
        let in_place = render_one_frame(gpu, &mut renderer, &camera).rgba;
        let fresh = render_frame_with(gpu, &scene, config, &lights, &other, &camera).rgba;
        let worst = largest_difference(&in_place, &fresh);
        assert_eq!(
            worst, 0,
            "materials added in place differ from a fresh atlas by {worst}"
        );
        assert!(
            changed_pixels(&thinned, &in_place, 8) > 0,
            "the new materials must show"
        );
        // Another atlas configuration packs again.
        let packing = DecalAtlasConfig {
            mip_levels: 4,
            ..Default::default()
        };
        assert_eq!(
            (renderer.set_decals_with(&other, packing)).expect("decals fit"),
            DecalUpload::Repacked,
        );
    });
}
