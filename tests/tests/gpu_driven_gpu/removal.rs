//! Meshes and materials removed from a prepared city at run time: refused while something
//! still uses them, then gone (the frame is the city's own again), their vertices, indices,
//! material slot and atlas room given back, and taken by the meshes and materials added next,
//! which render as a city built with them from the start.

use glam::{Mat4, Quat, Vec3};
use renderer::frame::InputError;
use renderer::frame::{RenderError, RenderPath, Renderer};
use renderer::scene::{AlphaMode, Image, Instance, Material, Mesh, Scene, TextureRef};
use tests::frames::{largest_difference, render_frame_from, render_one_frame};
use tests::gpu::gpu_test;

use super::edits::mesh;
use super::{city, config, street_camera, street_lights};

/// An 8×8 checker of two colours.
fn checker(a: [u8; 4], b: [u8; 4]) -> Image {
    Image {
        width: 8,
        height: 8,
        rgba8: (0..64u32)
            .flat_map(|i| if (i % 8 + i / 8) % 2 == 0 { a } else { b })
            .collect(),
    }
}

/// The city's first opaque material with its base colour read from `image`.
fn textured(scene: &Scene, image: usize) -> Material {
    let facade = (scene.materials.iter())
        .position(|m| m.alpha_mode == AlphaMode::Opaque)
        .expect("an opaque facade");
    let mut m = scene.materials[facade].clone();
    m.name = format!("checker {image}");
    m.base_color_texture = Some(TextureRef {
        image,
        tex_coord: 0,
        sampler: Default::default(),
        transform: Default::default(),
    });
    m
}

/// The city's mesh `name` with every primitive drawn with `material`.
fn with_material(scene: &Scene, name: &str, material: Option<usize>) -> Mesh {
    let mut m = scene.meshes[mesh(scene, name)].clone();
    m.name = format!("added {name}");
    for p in &mut m.primitives {
        p.material = material;
    }
    m
}

/// Textures held and atlas room taken, and the atlas's pages.
fn atlas_state(r: &Renderer) -> ((usize, u64), (u32, u32)) {
    let atlas = r.material_atlas().expect("a scene");
    (atlas.usage(), atlas.pages())
}

#[test]
fn meshes_and_materials_removed_at_run_time_give_their_room_to_the_next_ones() {
    let base = city(300);
    let scene = &base.scene;
    let lights = street_lights(&base);
    let camera = street_camera(scene);
    let (red, green) = (
        checker([230, 40, 30, 255], [30, 60, 220, 255]),
        checker([40, 200, 60, 255], [240, 220, 40, 255]),
    );
    let eye = camera.eye;
    let placed = [
        Mat4::from_scale_rotation_translation(
            Vec3::new(3.0, 5.0, 3.0),
            Quat::from_rotation_y(0.4),
            eye + Vec3::new(18.0, -1.7, -2.0),
        ),
        Mat4::from_translation(eye + Vec3::new(22.0, 1.0, 0.0))
            * Mat4::from_scale(Vec3::splat(2.0)),
    ];
    // The reference: the city built with the green tower only.
    let mut reference = scene.clone();
    reference.images.push(green.clone());
    reference
        .materials
        .push(textured(scene, scene.images.len()));
    reference
        .meshes
        .push(with_material(scene, "tower", Some(scene.materials.len())));
    reference.instances.push(Instance {
        mesh: scene.meshes.len(),
        world_from_mesh: placed[0],
    });
    gpu_test(|gpu| {
        let config = config(RenderPath::Tiled, 4, true);
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(scene).expect("the city fits");
        renderer.set_lights(&lights).expect("lights fit");
        let first = render_one_frame(gpu, &mut renderer, &camera).rgba;
        let (geometry, atlas) = (
            renderer.geometry_usage().expect("a scene"),
            atlas_state(&renderer),
        );
        let default = renderer.default_material().expect("a scene");
        let red_image = renderer.add_image(&red).expect("an image");
        let green_image = renderer.add_image(&green).expect("an image");
        let red_material = renderer
            .add_material(&textured(scene, red_image))
            .expect("a material");
        let red_tower = renderer
            .add_mesh(&with_material(scene, "tower", Some(red_material)))
            .expect("a mesh");
        let dome = renderer
            .add_mesh(&with_material(scene, "dome", None))
            .expect("a mesh");
        let tower = renderer.add_instance(red_tower, placed[0]).expect("a mesh");
        let domed = renderer.add_instance(dome, placed[1]).expect("a mesh");
        let added = render_one_frame(gpu, &mut renderer, &camera).rgba;
        assert!(
            largest_difference(&first, &added) > 64,
            "the additions show"
        );
        let grown = renderer.geometry_usage().expect("a scene");
        let atlas_with_red = atlas_state(&renderer);

        // Nothing in use can go.
        let err = renderer
            .remove_mesh(red_tower)
            .expect_err("an instance uses it");
        assert!(
            matches!(
                err,
                RenderError::Input(InputError::MeshInUse { instances: 1, .. })
            ),
            "{err}"
        );
        let err = (renderer.remove_material(red_material)).expect_err("the red tower uses it");
        assert!(
            err.to_string()
                .contains(&format!("drawn by mesh {red_tower}")),
            "{err}"
        );
        let err = renderer.remove_material(default).expect_err("the default");
        assert!(err.to_string().contains("default material"), "{err}");

        for handle in [tower, domed] {
            renderer.remove_instance(handle).expect("a live instance");
        }
        renderer
            .remove_mesh(red_tower)
            .expect("no instance uses it");
        renderer.remove_mesh(dome).expect("no instance uses it");
        renderer
            .remove_material(red_material)
            .expect("no mesh uses it");
        let err = renderer.remove_mesh(dome).expect_err("removed already");
        assert!(err.to_string().contains("removed already"), "{err}");
        let err = renderer.add_instance(dome, placed[1]).expect_err("removed");
        assert!(
            matches!(err, RenderError::Input(InputError::MeshRemoved { .. })),
            "{err}"
        );
        let err = (renderer.set_material(red_material, &scene.materials[0])).expect_err("removed");
        assert!(err.to_string().contains("was removed"), "{err}");
        let err = renderer
            .add_mesh(&with_material(scene, "tower", Some(red_material)))
            .expect_err("a removed material");
        assert!(err.to_string().contains("was removed"), "{err}");
        // Their room is free again, and the frame is the city's own.
        let removed = renderer.geometry_usage().expect("a scene");
        assert_eq!(
            (removed.vertices, removed.indices),
            (geometry.vertices, geometry.indices)
        );
        assert_eq!(
            atlas_state(&renderer).0,
            atlas.0,
            "the red checker released"
        );
        let after_removal = render_one_frame(gpu, &mut renderer, &camera).rgba;
        assert_eq!(largest_difference(&first, &after_removal), 0);

        // The next material takes the removed one's index and atlas room, the next mesh its
        // vertices and indices: nothing grows.
        let green_material = renderer
            .add_material(&textured(scene, green_image))
            .expect("a material");
        assert_eq!(green_material, red_material, "the removed index is reused");
        assert_eq!(
            atlas_state(&renderer),
            atlas_with_red,
            "the red room is reused"
        );
        let green_tower = renderer
            .add_mesh(&with_material(scene, "tower", Some(green_material)))
            .expect("a mesh");
        assert_eq!(green_tower, dome + 1, "mesh indices are not reused");
        let regrown = renderer.geometry_usage().expect("a scene");
        assert_eq!(
            (regrown.vertex_capacity, regrown.index_capacity),
            (grown.vertex_capacity, grown.index_capacity),
            "the streams did not grow"
        );
        let tower_size = regrown.vertices - geometry.vertices;
        assert!(tower_size > 0 && regrown.vertices < grown.vertices);
        renderer
            .add_instance(green_tower, placed[0])
            .expect("a mesh");
        let edited = render_one_frame(gpu, &mut renderer, &camera).rgba;
        let expected = render_frame_from(gpu, &reference, config, &lights, &camera).rgba;
        let worst = largest_difference(&edited, &expected);
        assert_eq!(
            worst, 0,
            "the city with its room reused differs from the built one by {worst}"
        );
        assert!(
            largest_difference(&first, &edited) > 64,
            "the green tower shows"
        );
    });
}
