//! Scenes built in code rather than loaded: boxes, planes and spheres with PBR materials (flat
//! or with procedural textures), for tests that need a particular geometry (a grazing floor,
//! thin rails), for the built-in demo scene, [`courtyard`], and for scenes at an engine's
//! scale, [`city`] (a generated city of any number of instances sharing a few meshes).
//! [`builtin`] finds either by the name the tools take (`courtyard`, `city:N`).

mod builtin;
mod city;
mod courtyard;
mod shapes;
mod textures;

pub use courtyard::{
    LIGHT_RADII as COURTYARD_LIGHT_RADII, LIGHT_REGION as COURTYARD_LIGHT_REGION,
    LOOK_AMBIENT as COURTYARD_AMBIENT, LOOK_EV as COURTYARD_EV, LOOK_SKY as COURTYARD_SKY,
    courtyard,
};

pub use builtin::{BuiltinScene, builtin};
pub use city::{CITY_BLOCK_PITCH, city};

use glam::{Mat4, Vec3};

use super::{Aabb, AlphaMode, Image, Instance, Material, Mesh, Primitive, Scene, SceneCamera};
use shapes::{cuboid, sphere};

/// Builds a [`Scene`] one box at a time.
#[derive(Debug, Default)]
pub struct SceneBuilder {
    scene: Option<Scene>,
}

impl SceneBuilder {
    /// An empty builder (no meshes, materials, lights or camera).
    pub fn new() -> Self {
        Self::default()
    }

    fn scene(&mut self) -> &mut Scene {
        self.scene.get_or_insert_with(|| Scene {
            meshes: Vec::new(),
            materials: Vec::new(),
            images: Vec::new(),
            instances: Vec::new(),
            cameras: Vec::new(),
            lights: Vec::new(),
            bounds: Aabb::EMPTY,
            warnings: Vec::new(),
        })
    }

    /// Adds an opaque dielectric material of linear `color` and `roughness`; returns its index.
    pub fn material(&mut self, name: &str, color: Vec3, roughness: f32) -> usize {
        let scene = self.scene();
        scene.materials.push(Material {
            name: name.to_owned(),
            base_color: color.extend(1.0),
            metallic: 0.0,
            roughness,
            alpha_mode: AlphaMode::Opaque,
            ..Material::gltf_default()
        });
        scene.materials.len() - 1
    }

    /// Adds any material; returns its index.
    pub fn add_material(&mut self, material: Material) -> usize {
        let scene = self.scene();
        scene.materials.push(material);
        scene.materials.len() - 1
    }

    /// Adds an RGBA8 image for materials to sample; returns its index.
    pub fn image(&mut self, image: Image) -> usize {
        let scene = self.scene();
        scene.images.push(image);
        scene.images.len() - 1
    }

    /// Adds a camera.
    pub fn camera(&mut self, camera: SceneCamera) -> &mut Self {
        self.scene().cameras.push(camera);
        self
    }

    /// Adds an axis-aligned box from `min` to `max` (a flat plane when one extent is zero: it
    /// then keeps only the two faces across that axis, or one when `material` is double-sided)
    /// with `material`.
    pub fn cuboid(&mut self, min: Vec3, max: Vec3, material: usize) -> &mut Self {
        let double_sided = self
            .scene()
            .materials
            .get(material)
            .is_some_and(|m| m.double_sided);
        self.primitive("box", cuboid(min, max, material, double_sided))
    }

    /// Adds a sphere (a UV sphere of 16 rings × 32 segments).
    pub fn sphere(&mut self, center: Vec3, radius: f32, material: usize) -> &mut Self {
        self.primitive("sphere", sphere(center, radius, material))
    }

    /// Adds a mesh of one primitive without placing it; returns its index for [`Self::place`].
    pub fn mesh(&mut self, name: &str, primitive: Primitive) -> usize {
        let scene = self.scene();
        scene.meshes.push(Mesh {
            name: name.to_owned(),
            primitives: vec![primitive],
        });
        scene.meshes.len() - 1
    }

    /// Places an instance of mesh `mesh` (from [`Self::mesh`]) at `world_from_mesh`.
    pub fn place(&mut self, mesh: usize, world_from_mesh: Mat4) -> &mut Self {
        let scene = self.scene();
        let bounds = scene.meshes[mesh]
            .primitives
            .iter()
            .fold(Aabb::EMPTY, |b, p| {
                b.union(p.bounds.transformed(world_from_mesh))
            });
        scene.bounds = scene.bounds.union(bounds);
        scene.instances.push(Instance {
            mesh,
            world_from_mesh,
        });
        self
    }

    /// Instances placed so far.
    pub fn instance_count(&self) -> usize {
        self.scene.as_ref().map_or(0, |s| s.instances.len())
    }

    fn primitive(&mut self, kind: &str, primitive: Primitive) -> &mut Self {
        let scene = self.scene();
        scene.bounds = scene.bounds.union(primitive.bounds);
        scene.meshes.push(Mesh {
            name: format!("{kind} {}", scene.meshes.len()),
            primitives: vec![primitive],
        });
        scene.instances.push(Instance {
            mesh: scene.meshes.len() - 1,
            world_from_mesh: Mat4::IDENTITY,
        });
        self
    }

    /// The scene built so far.
    pub fn build(&mut self) -> Scene {
        let mut scene = self.scene.take().unwrap_or_else(|| {
            let mut empty = Self::new();
            empty.scene().clone()
        });
        if scene.bounds.is_empty() {
            scene.bounds = Aabb {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
            };
        }
        scene
    }
}

/// The primitive of a box from `min` to `max` (see [`SceneBuilder::cuboid`]), for
/// [`SceneBuilder::mesh`].
pub fn box_primitive(min: Vec3, max: Vec3, material: usize, double_sided: bool) -> Primitive {
    cuboid(min, max, material, double_sided)
}

/// The primitive of a sphere (see [`SceneBuilder::sphere`]), for [`SceneBuilder::mesh`].
pub fn sphere_primitive(center: Vec3, radius: f32, material: usize) -> Primitive {
    sphere(center, radius, material)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_has_six_outward_faces_and_a_plane_two() {
        let mut b = SceneBuilder::new();
        let m = b.material("grey", Vec3::splat(0.5), 0.6);
        b.cuboid(Vec3::ZERO, Vec3::ONE, m);
        b.cuboid(Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 0.0, 5.0), m);
        let scene = b.build();
        let cube = &scene.meshes[0].primitives[0];
        assert_eq!(cube.indices.len(), 36);
        let plane = &scene.meshes[1].primitives[0];
        assert_eq!(plane.indices.len(), 12);
        // Every triangle winds counter-clockwise seen from outside: its geometric normal points
        // the way of its vertex normal.
        for prim in [cube, plane] {
            for t in prim.indices.chunks(3) {
                let [a, b, c] = [0, 1, 2].map(|i| prim.positions[t[i] as usize]);
                let geometric = (b - a).cross(c - a);
                assert!(geometric.dot(prim.normals[t[0] as usize]) > 0.0);
            }
        }
        let mut b = SceneBuilder::new();
        let m = b.material("grey", Vec3::splat(0.5), 0.6);
        b.sphere(Vec3::new(1.0, 2.0, 3.0), 0.5, m);
        let ball = b.build();
        let sphere = &ball.meshes[0].primitives[0];
        for t in sphere.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|i| sphere.positions[t[i] as usize]);
            let geometric = (b - a).cross(c - a);
            // Pole triangles are degenerate (two vertices at the pole); the rest face out.
            if geometric.length() > 1e-6 {
                assert!(geometric.dot(a - Vec3::new(1.0, 2.0, 3.0)) > 0.0);
            }
        }
        assert_eq!(scene.bounds.min, Vec3::new(-5.0, 0.0, -5.0));
        assert_eq!(scene.bounds.max, Vec3::new(5.0, 1.0, 5.0));
        assert_eq!(scene.triangle_count(), 12 + 4);
    }

    #[test]
    fn a_double_sided_plane_has_one_face_so_nothing_fights_it() {
        let mut b = SceneBuilder::new();
        let leaves = b.add_material(Material {
            double_sided: true,
            ..Material::gltf_default()
        });
        b.cuboid(Vec3::new(-1.0, 2.0, -1.0), Vec3::new(1.0, 2.0, 1.0), leaves);
        b.cuboid(Vec3::ZERO, Vec3::ONE, leaves);
        let scene = b.build();
        let plane = &scene.meshes[0].primitives[0];
        assert_eq!(plane.indices.len(), 6);
        assert!(plane.normals.iter().all(|&n| n == Vec3::Y));
        assert_eq!(
            scene.meshes[1].primitives[0].indices.len(),
            36,
            "boxes keep six"
        );
    }
}
