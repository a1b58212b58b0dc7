//! Flat quads built in code, and the camera, light and pixel helpers the material tests share.

use glam::{Vec2, Vec3, Vec4};
use renderer::frame::{FrameCamera, RenderPath, RendererConfig};
use renderer::scene::{Aabb, Instance, LightKind, Mesh, Primitive, Scene, SceneLight};

pub const W: u32 = 160;
pub const H: u32 = 120;

/// A flat quad with corners `min`, `max` in the plane `z = min.z` facing +Z (or `y = min.y`
/// facing +Y when `min.y == max.y`), every vertex with `uv0`, `uv1` (none when `None`) and
/// `color` (none when `None`), or per-corner UVs from `uv0_of`.
pub struct Quad {
    pub min: Vec3,
    pub max: Vec3,
    pub uv0: fn(Vec2) -> Vec2,
    pub uv1: Option<fn(Vec2) -> Vec2>,
    pub color: Option<Vec4>,
    pub material: usize,
}

impl Quad {
    pub fn primitive(&self) -> Primitive {
        let (a, b) = (self.min, self.max);
        let horizontal = a.y == b.y;
        // Corners in (s, t) ∈ {0, 1}², counter-clockwise seen from the facing side.
        let corners = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        let positions: Vec<Vec3> = corners
            .iter()
            .map(|st| {
                if horizontal {
                    Vec3::new(a.x + st.x * (b.x - a.x), a.y, b.z - st.y * (b.z - a.z))
                } else {
                    Vec3::new(a.x + st.x * (b.x - a.x), a.y + st.y * (b.y - a.y), a.z)
                }
            })
            .collect();
        let normal = if horizontal { Vec3::Y } else { Vec3::Z };
        Primitive {
            normals: vec![normal; 4],
            uvs: corners.iter().map(|&st| (self.uv0)(st)).collect(),
            uvs1: self
                .uv1
                .map_or_else(Vec::new, |f| corners.iter().map(|&st| f(st)).collect()),
            colors: self.color.map_or_else(Vec::new, |c| vec![c; 4]),
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
            indices: vec![0, 1, 2, 0, 2, 3],
            material: Some(self.material),
            bounds: Aabb {
                min: a.min(b),
                max: a.max(b),
            },
            positions,
        }
    }
}

/// Adds `quad` to `scene` as its own mesh and instance.
pub fn add_quad(scene: &mut Scene, quad: &Quad) {
    let primitive = quad.primitive();
    scene.bounds = scene.bounds.union(primitive.bounds);
    scene.meshes.push(Mesh {
        name: "quad".into(),
        primitives: vec![primitive],
    });
    scene.instances.push(Instance {
        mesh: scene.meshes.len() - 1,
        world_from_mesh: glam::Mat4::IDENTITY,
    });
}

/// The pixel `world` projects to.
pub fn pixel(camera: &FrameCamera, world: Vec3) -> (u32, u32) {
    let clip = camera.projection * camera.view * world.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (
        ((ndc.x + 1.0) * 0.5 * W as f32) as u32,
        ((1.0 - ndc.y) * 0.5 * H as f32) as u32,
    )
}

pub fn rgb(rgba: &[u8], (x, y): (u32, u32)) -> [i32; 3] {
    let i = ((y * W + x) * 4) as usize;
    [rgba[i], rgba[i + 1], rgba[i + 2]].map(i32::from)
}

pub fn config(path: RenderPath) -> RendererConfig {
    RendererConfig {
        width: W,
        height: H,
        msaa: 1,
        path,
        ambient: renderer::frame::Ambient::OFF,
        sky: Vec3::new(0.0, 0.0, 0.2),
        ..Default::default()
    }
}

/// A white directional light along −Z, unshadowed.
pub fn head_on_light() -> SceneLight {
    SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::NEG_Z,
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
        casts_shadow: false,
    }
}
