//! Instances added, removed and moved by handle, frame after frame, render the same as a city
//! built with the final instances from the start, on the forward, deferred and visibility
//! paths, culled and not, with shadow-casting lights whose static cache must follow every
//! edit; and handles of removed instances, unknown meshes and non-finite transforms are
//! refused.

use glam::{Mat4, Quat, Vec3};
use renderer::frame::InputError;
use renderer::frame::{RenderError, RenderPath, Renderer};
use renderer::scene::{Instance, Scene, SceneLight};
use tests::frames::{largest_difference, render_frame_from, render_one_frame};
use tests::gpu::gpu_test;

use super::{city, config, street_camera, street_lights};

/// One edit of the scene, applied to the renderer by handle and to the reference scene by
/// hand (`Scene::instances`, removed entries dropped at the end).
enum Edit {
    Remove(usize),
    Add(usize, Mat4),
    /// Moves the `n`-th added instance.
    MoveAdded(usize, Mat4),
    /// Removes the `n`-th added instance.
    RemoveAdded(usize),
    /// Marks the `n`-th added instance dynamic and static again, `times` times each: more
    /// changes than the table's change log keeps, so the passes must walk every instance.
    ToggleDynamic(usize, usize),
}

/// The mesh named `name`.
pub(super) fn mesh(scene: &Scene, name: &str) -> usize {
    scene
        .meshes
        .iter()
        .position(|m| m.name == name)
        .unwrap_or_else(|| panic!("the city has a {name} mesh"))
}

/// A sun that casts shadows, with the street lights.
pub(super) fn lights_with_sun(lights: &[SceneLight]) -> Vec<SceneLight> {
    let mut all = lights.to_vec();
    all.push(SceneLight {
        kind: renderer::scene::LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(0.4, -1.0, 0.3).normalize(),
        color: Vec3::ONE,
        intensity: 2.0,
        range: None,
        casts_shadow: true,
    });
    all
}

#[test]
fn instances_added_and_removed_by_handle_render_as_a_city_built_with_them() {
    let base = city(600);
    let lights = lights_with_sun(&street_lights(&base));
    let camera = street_camera(&base.scene);
    let scene = &base.scene;
    let eye = camera.eye;
    let ahead = |x: f32, z: f32, scale: Vec3| {
        Mat4::from_scale_rotation_translation(
            scale,
            Quat::from_rotation_y(0.3),
            eye + Vec3::new(x, -1.7, z),
        )
    };
    let (tower, canopy, screen, dome) = (
        mesh(scene, "tower"),
        mesh(scene, "canopy"),
        mesh(scene, "screen"),
        mesh(scene, "dome"),
    );
    // Frame by frame: remove a tenth of the city (towers, panes, grilles among them), add
    // instances in front of the camera (some take removed slots, some append draws, one is
    // mirrored, one blended, one masked), then move and remove some of the added ones.
    let removed: Vec<usize> = (0..scene.instances.len()).step_by(10).collect();
    let steps: Vec<Vec<Edit>> = vec![
        removed.iter().map(|&i| Edit::Remove(i)).collect(),
        vec![
            Edit::Add(tower, ahead(25.0, -3.0, Vec3::new(3.0, 6.0, 3.0))),
            Edit::Add(tower, ahead(32.0, 3.0, Vec3::new(-3.0, 5.0, 3.0))),
            Edit::Add(canopy, ahead(20.0, 0.0, Vec3::ONE)),
            Edit::Add(screen, ahead(16.0, 1.5, Vec3::ONE)),
            Edit::Add(dome, ahead(40.0, -4.0, Vec3::splat(2.0))),
        ],
        (0..40)
            .map(|k| {
                let m = [tower, dome, screen][k % 3];
                let at = ahead(
                    45.0 + 4.0 * k as f32,
                    -6.0 + (k % 5) as f32 * 3.0,
                    Vec3::ONE,
                );
                Edit::Add(m, at)
            })
            .collect(),
        vec![
            Edit::ToggleDynamic(2, 40_000),
            Edit::MoveAdded(0, ahead(22.0, 4.0, Vec3::new(2.0, 4.0, -2.0))),
            Edit::RemoveAdded(1),
            Edit::RemoveAdded(6),
            Edit::Add(tower, ahead(28.0, -5.0, Vec3::new(2.0, 3.0, 2.0))),
        ],
    ];
    // The reference: the final instances in a scene built with them.
    let mut built: Vec<Option<Instance>> = scene.instances.iter().cloned().map(Some).collect();
    let mut added_at = Vec::new();
    for step in &steps {
        for edit in step {
            match *edit {
                Edit::Remove(i) => built[i] = None,
                Edit::Add(mesh, m) => {
                    added_at.push(built.len());
                    built.push(Some(Instance {
                        mesh,
                        world_from_mesh: m,
                    }));
                }
                Edit::MoveAdded(n, m) => {
                    if let Some(i) = built[added_at[n]].as_mut() {
                        i.world_from_mesh = m;
                    }
                }
                Edit::RemoveAdded(n) => built[added_at[n]] = None,
                Edit::ToggleDynamic(..) => {}
            }
        }
    }
    let mut reference = scene.clone();
    reference.instances = built.into_iter().flatten().collect();
    gpu_test(|gpu| {
        let paths = [
            (RenderPath::Tiled, true),
            (RenderPath::Tiled, false),
            (RenderPath::Tbdr, true),
            (RenderPath::Visibility, true),
        ];
        for (path, cull) in paths {
            let config = config(path, 4, cull);
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(scene).expect("the city fits");
            renderer.set_lights(&lights).expect("lights fit");
            let first = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let mut added = Vec::new();
            for step in &steps {
                for edit in step {
                    match *edit {
                        Edit::Remove(i) => {
                            let h = renderer.scene_instance(i).expect("a scene instance");
                            renderer.remove_instance(h).expect("a live instance");
                        }
                        Edit::Add(mesh, m) => {
                            added.push(renderer.add_instance(mesh, m).expect("a city mesh"));
                        }
                        Edit::MoveAdded(n, m) => renderer
                            .set_instance_transform(added[n], m)
                            .expect("a live instance"),
                        Edit::RemoveAdded(n) => {
                            renderer.remove_instance(added[n]).expect("a live instance");
                        }
                        Edit::ToggleDynamic(n, times) => {
                            for _ in 0..times {
                                for dynamic in [true, false] {
                                    renderer
                                        .set_instance_dynamic(added[n], dynamic)
                                        .expect("a live instance");
                                }
                            }
                        }
                    }
                }
                render_one_frame(gpu, &mut renderer, &camera);
            }
            let edited = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let expected = render_frame_from(gpu, &reference, config, &lights, &camera).rgba;
            let worst = largest_difference(&edited, &expected);
            assert_eq!(
                worst, 0,
                "{path:?}, culling {cull}: the edited city differs from the built one by {worst}"
            );
            assert!(
                largest_difference(&first, &edited) > 32,
                "{path:?}: the edits must show in the frame"
            );
            let live = renderer.instances().iter().filter(|s| s.live).count();
            assert_eq!(live, reference.instances.len());
            assert!(
                renderer.instances().len() < reference.instances.len() + removed.len(),
                "added instances of a removed mesh take the removed slots"
            );
        }
    });
}

#[test]
fn stale_handles_unknown_meshes_and_broken_transforms_are_refused() {
    let base = city(50);
    gpu_test(|gpu| {
        let mut renderer =
            Renderer::new(gpu, config(RenderPath::Tiled, 1, true)).expect("renderer");
        let err = renderer
            .add_instance(0, Mat4::IDENTITY)
            .expect_err("no scene yet");
        assert!(
            matches!(err, RenderError::Input(InputError::NoScene)),
            "{err}"
        );
        renderer.prepare_scene(&base.scene).expect("the city fits");
        let first = renderer.scene_instance(0).expect("instance 0");
        let mesh = renderer.instance(first).expect("live").mesh;
        renderer.remove_instance(first).expect("live");
        assert!(renderer.instance(first).is_none());
        let err = renderer.remove_instance(first).expect_err("removed twice");
        assert!(
            matches!(
                err,
                RenderError::Input(InputError::StaleInstance { index: 0 })
            ),
            "{err}"
        );
        // The next instance of that mesh takes the slot; the old handle stays refused.
        let again = renderer.add_instance(mesh, Mat4::IDENTITY).expect("a mesh");
        assert_eq!(again.index(), 0);
        let err = renderer
            .set_instance_transform(first, Mat4::IDENTITY)
            .expect_err("the old handle");
        assert!(
            matches!(err, RenderError::Input(InputError::StaleInstance { .. })),
            "{err}"
        );
        // Slot 0 now holds an added instance, not the scene's instance 0.
        let err = renderer
            .scene_instance(0)
            .expect_err("the scene's instance 0 is gone");
        assert!(
            matches!(
                err,
                RenderError::Input(InputError::NoSuchInstance { index: 0, .. })
            ),
            "{err}"
        );
        assert_eq!(renderer.instance(again).map(|s| s.mesh), Some(mesh));
        let meshes = base.scene.meshes.len();
        let err = renderer
            .add_instance(meshes, Mat4::IDENTITY)
            .expect_err("no such mesh");
        assert!(
            matches!(err, RenderError::Input(InputError::NoSuchMesh { mesh, count }) if mesh == meshes && count == meshes),
            "{err}"
        );
        let nan = Mat4::from_translation(Vec3::new(f32::NAN, 0.0, 0.0));
        let err = renderer.add_instance(mesh, nan).expect_err("a NaN");
        assert!(
            matches!(err, RenderError::Input(InputError::NotFiniteTransform)),
            "{err}"
        );
        let err = renderer
            .set_instance_transform(again, nan)
            .expect_err("a NaN");
        assert!(
            matches!(err, RenderError::Input(InputError::NotFiniteTransform)),
            "{err}"
        );
        assert_eq!(
            renderer.instance(again).map(|s| s.world_from_mesh),
            Some(Mat4::IDENTITY)
        );
        // A new scene: the earlier scene's handles are refused, whatever their slots hold now
        // (slot 1 holds the same mesh, never removed, in both).
        let second = renderer.scene_instance(1).expect("instance 1");
        renderer.prepare_scene(&base.scene).expect("the city fits");
        for old in [again, second] {
            let err = renderer
                .set_instance_transform(old, Mat4::IDENTITY)
                .expect_err("a handle of the earlier scene");
            assert!(
                matches!(err, RenderError::Input(InputError::StaleInstance { .. })),
                "{err}"
            );
            assert!(renderer.instance(old).is_none());
        }
        let fresh = renderer
            .scene_instance(0)
            .expect("the new scene's instance 0");
        assert_ne!(fresh, again);
    });
}
