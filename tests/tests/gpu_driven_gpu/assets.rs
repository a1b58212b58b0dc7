//! Meshes, materials and images added to a prepared city at run time, and materials replaced
//! (recoloured, or turned to glass), render as a city built with them from the start, on the forward and deferred paths, culled and not; and meshes and
//! materials naming what does not exist are refused with the reason.

use glam::{Mat4, Quat, Vec3, Vec4};
use renderer::frame::InputError;
use renderer::frame::{RenderError, RenderPath, Renderer};
use renderer::scene::{AlphaMode, Image, Instance, TextureRef};
use tests::frames::{largest_difference, render_frame_from, render_one_frame};
use tests::gpu::gpu_test;

use super::edits::mesh;
use super::{city, config, street_camera, street_lights};

#[test]
fn meshes_materials_and_images_added_at_run_time_render_as_a_city_built_with_them() {
    let base = city(300);
    let scene = &base.scene;
    let lights = street_lights(&base);
    let camera = street_camera(scene);
    // A checker image, a material sampling it, a tower of that material and a dome of the
    // default material; three instances in front of the camera.
    let checker = Image {
        width: 8,
        height: 8,
        rgba8: (0..64u32)
            .flat_map(|i| {
                let on = (i % 8 + i / 8) % 2 == 0;
                if on {
                    [230, 40, 30, 255]
                } else {
                    [30, 60, 220, 255]
                }
            })
            .collect(),
    };
    let facade = scene
        .materials
        .iter()
        .position(|m| m.alpha_mode == AlphaMode::Opaque)
        .expect("an opaque facade");
    let mut material = scene.materials[facade].clone();
    material.name = "added checker".into();
    let with_image = |image: usize| {
        let mut m = material.clone();
        m.base_color_texture = Some(TextureRef {
            image,
            ..m.base_color_texture.unwrap_or(TextureRef {
                image,
                tex_coord: 0,
                sampler: Default::default(),
                transform: Default::default(),
            })
        });
        m
    };
    let with_material = |name: &str, material: Option<usize>| {
        let mut m = scene.meshes[mesh(scene, name)].clone();
        m.name = format!("added {name}");
        for p in &mut m.primitives {
            p.material = material;
        }
        m
    };
    let eye = camera.eye;
    let placed = [
        Mat4::from_scale_rotation_translation(
            Vec3::new(3.0, 5.0, 3.0),
            Quat::from_rotation_y(0.4),
            eye + Vec3::new(18.0, -1.7, -2.0),
        ),
        Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 4.0, 2.0),
            Quat::IDENTITY,
            eye + Vec3::new(26.0, -1.7, 4.0),
        ),
        Mat4::from_translation(eye + Vec3::new(22.0, 1.0, 0.0))
            * Mat4::from_scale(Vec3::splat(2.0)),
    ];
    // The reference: a scene built with all of it (the material before the default one).
    let mut reference = scene.clone();
    reference.images.push(checker.clone());
    reference.materials.push(with_image(scene.images.len()));
    let (tower, dome) = (reference.meshes.len(), reference.meshes.len() + 1);
    reference
        .meshes
        .push(with_material("tower", Some(scene.materials.len())));
    reference.meshes.push(with_material("dome", None));
    for (k, &m) in placed.iter().enumerate() {
        let mesh = if k < 2 { tower } else { dome };
        reference.instances.push(Instance {
            mesh,
            world_from_mesh: m,
        });
    }
    gpu_test(|gpu| {
        for (path, cull) in [(RenderPath::Tiled, true), (RenderPath::Tbdr, false)] {
            let config = config(path, 4, cull);
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(scene).expect("the city fits");
            renderer.set_lights(&lights).expect("lights fit");
            let first = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let image = renderer.add_image(&checker).expect("an image");
            assert_eq!(image, scene.images.len());
            let atlas = |r: &Renderer| {
                let a = r.material_atlas().expect("a scene");
                (a.additions(), a.pages())
            };
            let (before, pages) = atlas(&renderer);
            let added = renderer
                .add_material(&with_image(image))
                .expect("a material");
            assert_eq!(added, renderer.default_material().expect("a scene") + 1);
            // The checker went into the atlas in place, not by packing every image again.
            assert_eq!(atlas(&renderer), (before + 1, pages));
            let tower = renderer
                .add_mesh(&with_material("tower", Some(added)))
                .expect("a mesh");
            let dome = renderer
                .add_mesh(&with_material("dome", None))
                .expect("a mesh");
            assert_eq!((tower, dome), (scene.meshes.len(), scene.meshes.len() + 1));
            // A frame with the new mesh and material unused changes nothing.
            let unused = render_one_frame(gpu, &mut renderer, &camera).rgba;
            assert_eq!(largest_difference(&first, &unused), 0);
            for (k, &m) in placed.iter().enumerate() {
                let mesh = if k < 2 { tower } else { dome };
                renderer.add_instance(mesh, m).expect("an added mesh");
            }
            let edited = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let expected = render_frame_from(gpu, &reference, config, &lights, &camera).rgba;
            let worst = largest_difference(&edited, &expected);
            assert_eq!(
                worst, 0,
                "{path:?}, culling {cull}: the city with added meshes differs from the built one by \
                 {worst}"
            );
            assert!(
                largest_difference(&first, &edited) > 64,
                "{path:?}: the added instances must show"
            );
        }
    });
}

#[test]
fn meshes_and_materials_that_name_nothing_are_refused() {
    let base = city(50);
    let scene = &base.scene;
    gpu_test(|gpu| {
        let mut renderer =
            Renderer::new(gpu, config(RenderPath::Tiled, 1, true)).expect("renderer");
        let err = renderer
            .add_mesh(&scene.meshes[0])
            .expect_err("no scene yet");
        assert!(
            matches!(err, RenderError::Input(InputError::NoScene)),
            "{err}"
        );
        renderer.prepare_scene(scene).expect("the city fits");
        let materials = renderer.default_material().expect("a scene") + 1;
        let mut unknown = scene.meshes[0].clone();
        unknown.primitives[0].material = Some(materials);
        let err = renderer
            .add_mesh(&unknown)
            .expect_err("an unknown material");
        assert!(
            err.to_string()
                .contains(&format!("names material {materials} of {materials}")),
            "{err}"
        );
        let mut broken = scene.meshes[0].clone();
        let vertices = broken.primitives[0].positions.len() as u32;
        broken.primitives[0].indices[0] = vertices;
        let err = renderer
            .add_mesh(&broken)
            .expect_err("an index past the vertices");
        assert!(
            err.to_string().contains(&format!("uses vertex {vertices}")),
            "{err}"
        );
        let mut material = scene.materials[0].clone();
        let images = scene.images.len();
        material.emissive_texture = Some(TextureRef {
            image: images,
            tex_coord: 0,
            sampler: Default::default(),
            transform: Default::default(),
        });
        let err = renderer
            .add_material(&material)
            .expect_err("an unknown image");
        assert!(
            err.to_string()
                .contains(&format!("samples image {images} of {images}")),
            "{err}"
        );
        let empty = Image {
            width: 0,
            height: 4,
            rgba8: Vec::new(),
        };
        let err = renderer.add_image(&empty).expect_err("no pixels");
        assert!(err.to_string().contains("0x4 pixels"), "{err}");
        // Nothing refused was added: the next mesh takes the next index.
        assert_eq!(
            renderer.add_mesh(&scene.meshes[0]).expect("a mesh"),
            scene.meshes.len()
        );
    });
}

#[test]
fn materials_replaced_at_run_time_render_as_a_city_built_with_them() {
    let base = city(300);
    let scene = &base.scene;
    let lights = street_lights(&base);
    let camera = street_camera(scene);
    let opaque: Vec<usize> = (0..scene.materials.len())
        .filter(|&m| scene.materials[m].alpha_mode == AlphaMode::Opaque)
        .collect();
    // One facade material recoloured, every other one turned into blended glass: their draws
    // leave the opaque batches for the blended list.
    let mut replaced = scene.clone();
    let recoloured = opaque[0];
    replaced.materials[recoloured].base_color = Vec4::new(0.9, 0.2, 0.1, 1.0);
    for &m in opaque.iter().skip(1).step_by(2) {
        let material = &mut replaced.materials[m];
        material.alpha_mode = AlphaMode::Blend;
        material.base_color.w = 0.5;
    }
    let changed: Vec<usize> = (0..scene.materials.len())
        .filter(|&m| replaced.materials[m] != scene.materials[m])
        .collect();
    assert!(changed.len() > 2, "a recoloured material and glass");
    gpu_test(|gpu| {
        for (path, cull) in [(RenderPath::Tiled, true), (RenderPath::Tbdr, true)] {
            let config = config(path, 4, cull);
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(scene).expect("the city fits");
            renderer.set_lights(&lights).expect("lights fit");
            let first = render_one_frame(gpu, &mut renderer, &camera).rgba;
            for &m in &changed {
                renderer
                    .set_material(m, &replaced.materials[m])
                    .expect("a material of the scene");
            }
            let edited = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let expected = render_frame_from(gpu, &replaced, config, &lights, &camera).rgba;
            let worst = largest_difference(&edited, &expected);
            assert_eq!(
                worst, 0,
                "{path:?}: the city with replaced materials differs from the built one by {worst}"
            );
            assert!(
                largest_difference(&first, &edited) > 64,
                "{path:?}: the change shows"
            );
            let count = renderer.default_material().expect("a scene") + 1;
            let err = renderer
                .set_material(count, &scene.materials[0])
                .expect_err("no such material");
            assert!(err.to_string().contains("does not exist"), "{err}");
        }
    });
}
