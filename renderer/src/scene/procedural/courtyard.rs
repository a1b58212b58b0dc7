//! The built-in demo scene: a stone courtyard with an arcade of columns and round arches along
//! its back, a second arcade down its left side, glass panes and an iron grille between
//! columns, a leaf canopy, rails in front of the far wall, and PBR spheres on plinths at
//! several depths, open to the sky. It is what light culling is about: depth discontinuities
//! inside tiles (thin columns, rails and grille bars in front of far walls) and many lights
//! close to surfaces. Deterministic: no file, no random state.

use glam::{Vec3, Vec4};

use super::SceneBuilder;
use super::textures::{grille, leaves, stone_tiles};
use crate::scene::{Aabb, AlphaMode, CameraProjection, Material, Scene, SceneCamera, TextureRef};

/// The courtyard's exposure in stops, its ambient (a dusk sky's fill light) and its sky colour
/// (linear HDR), chosen so that 1,024 lights read as pools of colour with the architecture still
/// visible.
pub const LOOK_EV: f32 = 0.5;
/// See [`LOOK_EV`].
pub const LOOK_AMBIENT: Vec3 = Vec3::new(0.05, 0.055, 0.07);
/// See [`LOOK_EV`].
pub const LOOK_SKY: Vec3 = Vec3::new(0.025, 0.03, 0.05);
/// Light radii (min, max) that make pools on the floor and columns.
pub const LIGHT_RADII: (f32, f32) = (0.8, 2.6);

/// Where the courtyard's point lights belong: the open floor and the arcades, up to 3 m.
pub const LIGHT_REGION: Aabb = Aabb {
    min: Vec3::new(-12.5, 0.3, -11.0),
    max: Vec3::new(12.5, 3.0, 9.5),
};

struct Palette {
    stone: usize,
    plaster: usize,
    column: usize,
    bronze: usize,
    glass: usize,
    grille: usize,
    leaves: usize,
    spheres: Vec<usize>,
}

fn pbr(b: &mut SceneBuilder, name: &str, color: Vec4, roughness: f32, metallic: f32) -> usize {
    b.add_material(Material {
        name: name.into(),
        base_color: color,
        metallic,
        roughness,
        alpha_mode: if color.w < 1.0 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        },
        ..Material::gltf_default()
    })
}

fn textured(b: &mut SceneBuilder, name: &str, image: usize, roughness: f32, mask: bool) -> usize {
    b.add_material(Material {
        name: name.into(),
        base_color_texture: Some(TextureRef::new(image)),
        metallic: 0.0,
        roughness,
        alpha_mode: if mask {
            AlphaMode::Mask { cutoff: 0.5 }
        } else {
            AlphaMode::Opaque
        },
        double_sided: mask,
        ..Material::gltf_default()
    })
}

fn palette(b: &mut SceneBuilder) -> Palette {
    let (tiles, bars, canopy) = (b.image(stone_tiles()), b.image(grille()), b.image(leaves()));
    let stone = textured(b, "stone floor", tiles, 0.75, false);
    let grille = textured(b, "iron grille", bars, 0.5, true);
    let leaves = textured(b, "leaves", canopy, 0.6, true);
    let plaster = pbr(b, "plaster", Vec4::new(0.55, 0.45, 0.36, 1.0), 0.9, 0.0);
    let column = pbr(b, "limestone", Vec4::new(0.62, 0.6, 0.55, 1.0), 0.55, 0.0);
    let bronze = pbr(b, "bronze", Vec4::new(0.7, 0.45, 0.25, 1.0), 0.35, 1.0);
    let glass = pbr(b, "glass", Vec4::new(0.55, 0.75, 0.8, 0.3), 0.05, 0.0);
    // Roughness left to right, metals then dielectrics.
    let spheres = [
        ("gold", Vec4::new(1.0, 0.77, 0.34, 1.0), 0.15, 1.0),
        ("copper", Vec4::new(0.95, 0.64, 0.54, 1.0), 0.45, 1.0),
        ("steel", Vec4::new(0.56, 0.57, 0.58, 1.0), 0.75, 1.0),
        ("red lacquer", Vec4::new(0.6, 0.05, 0.04, 1.0), 0.1, 0.0),
        ("blue clay", Vec4::new(0.1, 0.2, 0.5, 1.0), 0.6, 0.0),
        ("chalk", Vec4::new(0.8, 0.8, 0.78, 1.0), 0.95, 0.0),
    ]
    .map(|(name, color, roughness, metallic)| pbr(b, name, color, roughness, metallic))
    .to_vec();
    Palette {
        stone,
        plaster,
        column,
        bronze,
        glass,
        grille,
        leaves,
        spheres,
    }
}

/// A column (base, shaft, capital) standing on the floor at `(x, z)`, 5 m tall.
fn column(b: &mut SceneBuilder, p: &Palette, x: f32, z: f32) {
    let at = |half: f32, y0: f32, y1: f32| {
        (
            Vec3::new(x - half, y0, z - half),
            Vec3::new(x + half, y1, z + half),
        )
    };
    for (half, y0, y1) in [(0.6, 0.0, 0.35), (0.4, 0.35, 4.7), (0.55, 4.7, 5.0)] {
        let (min, max) = at(half, y0, y1);
        b.cuboid(min, max, p.column);
    }
}

/// A round arch of stone blocks springing from two column tops, along x (or z when
/// `along_z`), with its centre at `(cx, 5.0, cz)`.
fn arch(b: &mut SceneBuilder, p: &Palette, cx: f32, cz: f32, span: f32, along_z: bool) {
    const BLOCKS: u32 = 9;
    let radius = span * 0.5;
    for i in 0..BLOCKS {
        let t = (i as f32 + 0.5) / BLOCKS as f32 * std::f32::consts::PI;
        let (s, c) = t.sin_cos();
        let (u, y) = (c * radius, 5.0 + s * radius);
        let (half_u, half_y, depth) = (0.22, 0.22, 0.35);
        let (dx, dz) = if along_z {
            (depth, half_u)
        } else {
            (half_u, depth)
        };
        let (x, z) = if along_z { (cx, cz + u) } else { (cx + u, cz) };
        b.cuboid(
            Vec3::new(x - dx, y - half_y, z - dz),
            Vec3::new(x + dx, y + half_y, z + dz),
            p.column,
        );
    }
}

/// Builds the courtyard, with a camera looking across it at the back arcade.
pub fn courtyard() -> Scene {
    let mut b = SceneBuilder::new();
    let p = palette(&mut b);
    // Floor, the back wall and the right wall (the left side is the open arcade).
    b.cuboid(
        Vec3::new(-14.0, 0.0, -14.0),
        Vec3::new(14.0, 0.0, 12.0),
        p.stone,
    );
    b.cuboid(
        Vec3::new(-14.0, 0.0, -13.0),
        Vec3::new(14.0, 7.5, -12.5),
        p.plaster,
    );
    b.cuboid(
        Vec3::new(13.5, 0.0, -13.0),
        Vec3::new(14.0, 4.0, 12.0),
        p.plaster,
    );
    arcades(&mut b, &p);
    screens_and_rails(&mut b, &p);
    fountain_and_spheres(&mut b, &p);
    let eye = Vec3::new(9.0, 3.4, 11.0);
    let target = Vec3::new(-2.5, 2.0, -5.0);
    b.camera(SceneCamera {
        world_from_view: glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse(),
        projection: CameraProjection::Perspective {
            yfov: 55f32.to_radians(),
            aspect: None,
            znear: 0.1,
            zfar: Some(80.0),
        },
    });
    b.build()
}

/// The back arcade (six columns, five arches, an entablature) and the left one.
fn arcades(b: &mut SceneBuilder, p: &Palette) {
    let xs = [-10.0, -6.0, -2.0, 2.0, 6.0, 10.0];
    for x in xs {
        column(b, p, x, -8.0);
    }
    for pair in xs.windows(2) {
        arch(b, p, (pair[0] + pair[1]) * 0.5, -8.0, 3.2, false);
    }
    b.cuboid(
        Vec3::new(-10.6, 7.1, -8.4),
        Vec3::new(10.6, 7.6, -7.6),
        p.column,
    );
    let zs = [-4.0, 0.0, 4.0, 8.0];
    for z in zs {
        column(b, p, -10.0, z);
    }
    for pair in zs.windows(2) {
        arch(b, p, -10.0, (pair[0] + pair[1]) * 0.5, 3.2, true);
    }
}

/// Between columns a glass pane and iron grilles, a leaf canopy over the far corner, and thin
/// rails in front of the back wall.
fn screens_and_rails(b: &mut SceneBuilder, p: &Palette) {
    b.cuboid(
        Vec3::new(-10.03, 0.4, 0.4),
        Vec3::new(-9.97, 3.4, 3.6),
        p.glass,
    );
    b.cuboid(
        Vec3::new(-5.6, 0.35, -8.0),
        Vec3::new(-2.4, 3.6, -8.0),
        p.grille,
    );
    b.cuboid(
        Vec3::new(6.4, 0.35, -8.0),
        Vec3::new(9.6, 3.6, -8.0),
        p.grille,
    );
    b.cuboid(
        Vec3::new(7.0, 4.2, -12.4),
        Vec3::new(13.4, 4.2, -8.6),
        p.leaves,
    );
    for i in 0..25 {
        let x = -12.0 + i as f32;
        b.cuboid(
            Vec3::new(x - 0.03, 0.0, -11.6),
            Vec3::new(x + 0.03, 1.1, -11.54),
            p.bronze,
        );
    }
    b.cuboid(
        Vec3::new(-12.1, 1.05, -11.62),
        Vec3::new(12.1, 1.12, -11.52),
        p.bronze,
    );
}

/// A fountain (a basin of four low walls round a bronze pillar), a glass cube, and the PBR
/// spheres on plinths at three depths.
fn fountain_and_spheres(b: &mut SceneBuilder, p: &Palette) {
    let (fx, fz) = (1.5, -1.5);
    for (min, max) in [
        ((-1.6, -1.6), (1.6, -1.3)),
        ((-1.6, 1.3), (1.6, 1.6)),
        ((-1.6, -1.3), (-1.3, 1.3)),
        ((1.3, -1.3), (1.6, 1.3)),
    ] {
        b.cuboid(
            Vec3::new(fx + min.0, 0.0, fz + min.1),
            Vec3::new(fx + max.0, 0.6, fz + max.1),
            p.column,
        );
    }
    b.cuboid(
        Vec3::new(fx - 0.2, 0.0, fz - 0.2),
        Vec3::new(fx + 0.2, 1.8, fz + 0.2),
        p.bronze,
    );
    b.cuboid(
        Vec3::new(-5.5, 0.0, 3.0),
        Vec3::new(-4.0, 1.5, 4.5),
        p.glass,
    );
    for (i, &m) in p.spheres.iter().enumerate() {
        let x = -7.0 + 2.6 * i as f32;
        let z = [5.0, -4.0, 1.5][i % 3];
        b.cuboid(
            Vec3::new(x - 0.5, 0.0, z - 0.5),
            Vec3::new(x + 0.5, 0.8, z + 0.5),
            p.column,
        );
        b.sphere(Vec3::new(x, 1.45, z), 0.65, m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_courtyard_is_deterministic_and_has_every_material_kind() {
        let a = courtyard();
        let b = courtyard();
        assert_eq!(a.meshes.len(), b.meshes.len());
        assert_eq!(
            a.meshes[7].primitives[0].positions,
            b.meshes[7].primitives[0].positions
        );
        assert_eq!(a.images, b.images);
        let modes: Vec<AlphaMode> = a.materials.iter().map(|m| m.alpha_mode).collect();
        assert!(modes.contains(&AlphaMode::Opaque));
        assert!(modes.contains(&AlphaMode::Blend));
        assert!(modes.contains(&AlphaMode::Mask { cutoff: 0.5 }));
        assert!(a.materials.iter().any(|m| m.metallic == 1.0));
        assert!(
            a.materials
                .iter()
                .any(|m| m.metallic == 0.0 && m.roughness < 0.2)
        );
        assert_eq!(a.cameras.len(), 1);
        assert!(a.triangle_count() > 5_000, "{}", a.triangle_count());
        // The light region lies inside the scene.
        assert!(a.bounds.min.cmple(LIGHT_REGION.min).all());
        assert!(a.bounds.max.cmpge(LIGHT_REGION.max).all());
    }
}
