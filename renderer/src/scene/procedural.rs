//! Scenes built in code rather than loaded: boxes and planes with flat PBR materials, for tests
//! that need a particular geometry (a grazing floor, thin rails) and for built-in demo scenes.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::{Aabb, AlphaMode, Instance, Material, Mesh, Primitive, Scene};

/// Builds a [`Scene`] one box at a time.
#[derive(Debug, Default)]
pub struct SceneBuilder {
    scene: Option<Scene>,
}

impl SceneBuilder {
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

    /// Adds an axis-aligned box from `min` to `max` (a flat plane when one extent is zero: it
    /// then keeps only the two faces across that axis) with `material`.
    pub fn cuboid(&mut self, min: Vec3, max: Vec3, material: usize) -> &mut Self {
        let primitive = cuboid(min, max, material);
        let scene = self.scene();
        scene.bounds = scene.bounds.union(primitive.bounds);
        scene.meshes.push(Mesh {
            name: format!("box {}", scene.meshes.len()),
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

/// The faces of a box: outward normal, then the face's u and v axes (u × v = normal).
const FACES: [[Vec3; 3]; 6] = [
    [Vec3::X, Vec3::NEG_Z, Vec3::Y],
    [Vec3::NEG_X, Vec3::Z, Vec3::Y],
    [Vec3::Y, Vec3::X, Vec3::NEG_Z],
    [Vec3::NEG_Y, Vec3::X, Vec3::Z],
    [Vec3::Z, Vec3::X, Vec3::Y],
    [Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y],
];

fn cuboid(min: Vec3, max: Vec3, material: usize) -> Primitive {
    let (center, half) = ((min + max) * 0.5, (max - min) * 0.5);
    let flat_axis = (0..3).find(|&a| half[a] == 0.0);
    let mut p = Primitive {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        tangents: Vec::new(),
        indices: Vec::new(),
        material: Some(material),
        bounds: Aabb { min, max },
    };
    for [n, u, v] in FACES {
        // A plane keeps only its two faces across the flat axis.
        if flat_axis.is_some_and(|a| n[a] == 0.0) {
            continue;
        }
        let base = p.positions.len() as u32;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let corner = n + u * su + v * sv;
            p.positions.push(center + corner * half);
            p.normals.push(n);
            // UVs in world units, so textures and tangents keep their scale on long boxes.
            let extent = Vec2::new((u * half).length(), (v * half).length());
            p.uvs.push(Vec2::new(su, -sv) * extent);
            p.tangents.push(Vec4::new(u.x, u.y, u.z, 1.0));
        }
        p.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    p
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
        assert_eq!(scene.bounds.min, Vec3::new(-5.0, 0.0, -5.0));
        assert_eq!(scene.bounds.max, Vec3::new(5.0, 1.0, 5.0));
        assert_eq!(scene.triangle_count(), 12 + 4);
    }
}
