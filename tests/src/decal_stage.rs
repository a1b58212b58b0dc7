//! A small stage for the decal image tests: a floor, an opaque shelf floating above part of it, a
//! blended pane, a camera looking down at them, and a CPU ray cast that says which surfaces a
//! pixel shows and where, so a test can tell the pixels a decal box may touch from those it must
//! leave alone.

use glam::{Mat4, Vec2, Vec3, Vec4};
use renderer::decals::{DecalImage, DecalMaterial, OrientedBox};
use renderer::frame::FrameCamera;
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{AlphaMode, Material, Scene, SceneLight};

/// Image size of the stage tests.
pub const WIDTH: u32 = 128;
pub const HEIGHT: u32 = 96;

/// A horizontal rectangle of the stage, `height` above the origin, over `min..max` in XZ.
#[derive(Debug, Clone, Copy)]
pub struct Slab {
    pub height: f32,
    pub min: Vec2,
    pub max: Vec2,
    pub blended: bool,
}

/// The floor (y = 0, 8 × 8), the shelf (y = 1, opaque, over x ≥ 0.6) and the pane (y = 0.5,
/// blended, over x ≤ −1.2), nearest the camera first.
pub const SLABS: [Slab; 3] = [
    Slab {
        height: 1.0,
        min: Vec2::new(0.6, -4.0),
        max: Vec2::new(4.0, 4.0),
        blended: false,
    },
    Slab {
        height: 0.5,
        min: Vec2::new(-4.0, -4.0),
        max: Vec2::new(-1.2, 4.0),
        blended: true,
    },
    Slab {
        height: 0.0,
        min: Vec2::new(-4.0, -4.0),
        max: Vec2::new(4.0, 4.0),
        blended: false,
    },
];

/// The stage's scene: the [`SLABS`] as flat boxes (the pane half transparent blue).
pub fn scene() -> Scene {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", Vec3::splat(0.6), 0.8);
    let shelf = b.material("shelf", Vec3::new(0.45, 0.45, 0.6), 0.8);
    let pane = b.add_material(Material {
        name: "pane".into(),
        base_color: Vec4::new(0.2, 0.4, 0.9, 0.5),
        roughness: 0.5,
        metallic: 0.0,
        alpha_mode: AlphaMode::Blend,
        double_sided: true,
        ..Material::gltf_default()
    });
    for (slab, material) in SLABS.iter().zip([shelf, pane, floor]) {
        b.cuboid(
            Vec3::new(slab.min.x, slab.height, slab.min.y),
            Vec3::new(slab.max.x, slab.height, slab.max.y),
            material,
        );
    }
    b.build()
}

/// Looking down at the origin from 7 up and 4.5 back.
pub fn camera() -> FrameCamera {
    let (eye, aspect) = (Vec3::new(0.0, 7.0, 4.5), WIDTH as f32 / HEIGHT as f32);
    FrameCamera::look_at(
        eye,
        Vec3::ZERO,
        Vec3::Y,
        55f32.to_radians(),
        aspect,
        (0.1, 50.0),
    )
}

/// A white light straight above and a little behind, reaching everything on the stage.
pub fn lights() -> Vec<SceneLight> {
    vec![SceneLight {
        kind: renderer::scene::LightKind::Point,
        position: Vec3::new(0.5, 6.0, 1.0),
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        intensity: 60.0,
        range: Some(20.0),
        casts_shadow: false,
    }]
}

/// A decal material of one colour, `side` texels square.
pub fn solid(name: &str, side: u32, rgba: [u8; 4]) -> DecalMaterial {
    DecalMaterial {
        name: name.into(),
        base_color: DecalImage::solid(side, side, rgba),
        normal: None,
        orm: None,
        emissive: None,
    }
}

/// The camera ray through image position `(x, y)` (pixels, top left origin): origin and unit
/// direction.
pub fn ray(camera: &FrameCamera, x: f32, y: f32) -> (Vec3, Vec3) {
    let world_from_clip = (camera.projection * camera.view).inverse();
    let ndc = Vec2::new(x / WIDTH as f32 * 2.0 - 1.0, 1.0 - y / HEIGHT as f32 * 2.0);
    let far = world_from_clip.project_point3(ndc.extend(1.0));
    (camera.eye, (far - camera.eye).normalize())
}

impl Slab {
    /// Where the ray meets the slab, if it does (in front of the origin).
    pub fn hit(&self, (origin, direction): (Vec3, Vec3)) -> Option<Vec3> {
        let t = (self.height - origin.y) / direction.y;
        let p = origin + direction * t;
        let inside = p.x >= self.min.x && p.x <= self.max.x && p.z >= self.min.y;
        (t > 0.0 && inside && p.z <= self.max.y).then_some(p)
    }
}

/// The points the camera ray through image position `(x, y)` shows: every blended slab in front
/// of the first opaque one, then that one, nearest first.
pub fn visible_points(camera: &FrameCamera, x: f32, y: f32) -> Vec<Vec3> {
    let ray = ray(camera, x, y);
    let mut points = Vec::new();
    for slab in SLABS {
        if let Some(p) = slab.hit(ray) {
            points.push(p);
            if !slab.blended {
                break;
            }
        }
    }
    points
}

/// How the decal boxes relate to what one pixel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reach {
    /// No surface the pixel shows (at its centre or its corners) lies in a box.
    Outside,
    /// Some do, some do not: an edge pixel, left alone by the tests.
    Edge,
    /// Every ray through the pixel shows a surface point inside `box_index`.
    Inside { box_index: usize },
}

/// Where pixel `(x, y)` stands against `boxes`: its centre and four corners are cast.
pub fn reach(camera: &FrameCamera, boxes: &[OrientedBox], x: u32, y: u32) -> Reach {
    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
    let rays = [
        (0.0, 0.0),
        (-0.5, -0.5),
        (0.5, -0.5),
        (-0.5, 0.5),
        (0.5, 0.5),
    ];
    let mut touched = Vec::new();
    for (dx, dy) in rays {
        let inside = visible_points(camera, cx + dx, cy + dy)
            .into_iter()
            .find_map(|p| boxes.iter().position(|b| grown(b).contains(p)));
        touched.push(inside);
    }
    match touched[0] {
        Some(box_index) if touched.iter().all(|t| *t == Some(box_index)) => {
            Reach::Inside { box_index }
        }
        _ if touched.iter().all(Option::is_none) => Reach::Outside,
        _ => Reach::Edge,
    }
}

/// `b` a hair larger, so that a point on its face counts as inside.
fn grown(b: &OrientedBox) -> OrientedBox {
    let mut g = *b;
    g.half += Vec3::splat(1e-3);
    g
}

/// The world transform of a box centred at `center` lying on the stage's horizontal surfaces
/// (+Z up), `width` along X, `depth` along Z and `thickness` up and down.
pub fn flat_box(center: Vec3, width: f32, depth: f32, thickness: f32) -> Mat4 {
    Mat4::from_cols(
        Vec4::new(width, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -depth, 0.0),
        Vec4::new(0.0, thickness, 0.0, 0.0),
        center.extend(1.0),
    )
}
