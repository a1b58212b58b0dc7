//! A generated city at an engine's scale: any number of instances of a few dozen shared meshes
//! (towers, domes, columns, masked grilles and hedges, glass canopies) over 40 materials, on
//! blocks laid out in rings around the origin, with a street-level camera at the centre.
//!
//! Deterministic: `city(n)` is the same scene on every machine, and the first blocks of a
//! larger city are the blocks of a smaller one, so the street camera sees the same streets at
//! every size and only what lies beyond grows (what a renderer's cost should follow).

use glam::{Mat4, Quat, Vec3, Vec4};

use super::textures::{grille, leaves};
use super::{SceneBuilder, box_primitive, sphere_primitive};
use crate::scene::{Aabb, AlphaMode, CameraProjection, Material, Scene, SceneCamera, TextureRef};

/// Distance between the corners of neighbouring blocks: a 40 m block and a 12 m street.
pub const CITY_BLOCK_PITCH: f32 = 52.0;
/// A block's side.
const BLOCK: f32 = 40.0;
/// Where the tools put procedural lights: the streets of the two inner rings of blocks, from
/// street level to the lower floors.
pub(super) const LIGHT_REGION: Aabb = Aabb {
    min: Vec3::new(-2.0 * CITY_BLOCK_PITCH, 0.5, -2.0 * CITY_BLOCK_PITCH),
    max: Vec3::new(2.0 * CITY_BLOCK_PITCH, 12.0, 2.0 * CITY_BLOCK_PITCH),
};
/// Their radii: pools of light on the street.
pub(super) const LIGHT_RADII: (f32, f32) = (4.0, 14.0);
/// The most instances a generated city may have.
pub(super) const MAX_INSTANCES: usize = 1_000_000;
/// Facade materials (opaque), before the masked, glass and ground ones: 40 in all.
const FACADES: usize = 32;

/// The city's shared meshes, each a primitive with its material.
struct Kit {
    /// A unit box (x, z from −½ to ½, y from 0 to 1) per facade material.
    towers: Vec<usize>,
    /// A unit-radius sphere per dome material.
    domes: Vec<usize>,
    column: usize,
    /// A 6 m × 3 m double-sided grille and hedge (alpha-masked), facing +Z.
    screens: [usize; 2],
    /// A 10 m × 6 m glass canopy (blended), one per tint.
    canopies: Vec<usize>,
    pavement: usize,
}

fn kit(b: &mut SceneBuilder) -> Kit {
    let facade = |i: usize| {
        // Warm and cool stones, brick reds, painted plaster, a few metals.
        let hue = hash(i as u32, 0, 11);
        let base = Vec3::new(0.35, 0.33, 0.3).lerp(Vec3::new(0.7, 0.5, 0.4), hue);
        let tint = Vec3::new(
            hash(i as u32, 1, 12),
            hash(i as u32, 2, 13),
            hash(i as u32, 3, 14),
        );
        Material {
            name: format!("facade {i}"),
            base_color: (base * (0.7 + 0.3 * tint)).extend(1.0),
            metallic: if i % 8 == 7 { 1.0 } else { 0.0 },
            roughness: 0.35 + 0.6 * hash(i as u32, 4, 15),
            ..Material::gltf_default()
        }
    };
    let unit_box = (Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 1.0, 0.5));
    let towers: Vec<usize> = (0..FACADES)
        .map(|i| {
            let m = b.add_material(facade(i));
            b.mesh("tower", box_primitive(unit_box.0, unit_box.1, m, false))
        })
        .collect();
    let domes = (0..FACADES)
        .step_by(4)
        .map(|i| b.mesh("dome", sphere_primitive(Vec3::ZERO, 1.0, i)))
        .collect();
    let column = b.mesh("column", box_primitive(unit_box.0, unit_box.1, 1, false));
    let screens = [grille(), leaves()].map(|image| {
        let image = b.image(image);
        let m = b.add_material(Material {
            name: "screen".into(),
            base_color_texture: Some(TextureRef::new(image)),
            metallic: 0.0,
            roughness: 0.6,
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            double_sided: true,
            ..Material::gltf_default()
        });
        let plane = box_primitive(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 3.0, 0.0), m, true);
        b.mesh("screen", plane)
    });
    let canopies = [
        Vec4::new(0.55, 0.75, 0.8, 0.3),
        Vec4::new(0.8, 0.6, 0.4, 0.4),
        Vec4::new(0.5, 0.8, 0.55, 0.35),
        Vec4::new(0.7, 0.7, 0.75, 0.25),
    ]
    .map(|tint| {
        let m = b.add_material(Material {
            name: "glass".into(),
            base_color: tint,
            metallic: 0.0,
            roughness: 0.05,
            alpha_mode: AlphaMode::Blend,
            ..Material::gltf_default()
        });
        let pane = box_primitive(
            Vec3::new(-5.0, 0.0, 0.0),
            Vec3::new(5.0, 0.0, 6.0),
            m,
            false,
        );
        b.mesh("canopy", pane)
    })
    .to_vec();
    let paving = b.material("paving", Vec3::splat(0.32), 0.85);
    let pavement = b.mesh(
        "pavement",
        box_primitive(Vec3::ZERO, Vec3::new(BLOCK, 0.2, BLOCK), paving, false),
    );
    Kit {
        towers,
        domes,
        column,
        screens,
        canopies,
        pavement,
    }
}

/// A city of exactly `instances` instances (at least 1; the first is the asphalt under
/// everything), its camera at street level looking down the street along +X at the centre.
pub fn city(instances: usize) -> Scene {
    let mut b = SceneBuilder::new();
    let kit = kit(&mut b);
    let asphalt = b.material("asphalt", Vec3::splat(0.05), 0.95);
    let rings = ring_count(instances);
    let half = rings as f32 * CITY_BLOCK_PITCH + CITY_BLOCK_PITCH;
    let ground = box_primitive(
        Vec3::new(-half, 0.0, -half),
        Vec3::new(half, 0.0, half),
        asphalt,
        false,
    );
    let ground = b.mesh("ground", ground);
    b.place(ground, Mat4::IDENTITY);
    'blocks: for (i, j) in blocks_by_ring(rings) {
        let corner = Vec3::new(
            i as f32 * CITY_BLOCK_PITCH + 6.0,
            0.0,
            j as f32 * CITY_BLOCK_PITCH + 6.0,
        );
        for (mesh, world) in block(&kit, i, j, corner) {
            if b.instance_count() == instances {
                break 'blocks;
            }
            b.place(mesh, world);
        }
    }
    let eye = Vec3::new(-CITY_BLOCK_PITCH * 0.5, 1.7, 0.5);
    let target = eye + Vec3::new(100.0, 4.0, -6.0);
    b.camera(SceneCamera {
        world_from_view: glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse(),
        projection: CameraProjection::Perspective {
            yfov: 60f32.to_radians(),
            aspect: None,
            znear: 0.1,
            zfar: Some(half * 3.0),
        },
    });
    b.build()
}

/// Rings of blocks enough for `instances` (a block holds at most 37 instances and at least
/// 5). Ring `r` is the blocks whose nearer corner is `r` blocks from the crossing at the origin.
fn ring_count(instances: usize) -> i32 {
    let mut rings = 1;
    while (2 * rings) * (2 * rings) * 5 < instances as i32 {
        rings += 1;
    }
    rings
}

/// Block coordinates of `rings` rings around the crossing at the origin (blocks `-rings` to
/// `rings − 1` each way), inner rings first.
fn blocks_by_ring(rings: i32) -> Vec<(i32, i32)> {
    let ring = |i: i32| if i >= 0 { i } else { -i - 1 };
    let mut blocks: Vec<(i32, i32)> = (-rings..rings)
        .flat_map(|i| (-rings..rings).map(move |j| (i, j)))
        .collect();
    blocks.sort_by_key(|&(i, j)| (ring(i).max(ring(j)), i, j));
    blocks
}

/// The instances of block `(i, j)` at `corner`: its pavement, then four lots, each a tower and
/// maybe a dome, four columns, a screen and a glass canopy.
fn block(kit: &Kit, i: i32, j: i32, corner: Vec3) -> Vec<(usize, Mat4)> {
    let mut out = vec![(kit.pavement, Mat4::from_translation(corner))];
    let (bi, bj) = (i as u32, j as u32);
    for lot in 0..4u32 {
        let r = |salt: u32| hash(bi.wrapping_mul(4) + lot, bj, salt);
        let centre = corner
            + Vec3::new(
                if lot & 1 == 0 { 10.0 } else { 30.0 },
                0.2,
                if lot & 2 == 0 { 10.0 } else { 30.0 },
            );
        let (w, d) = (10.0 + 6.0 * r(1), 10.0 + 6.0 * r(2));
        let h = 8.0 + 52.0 * r(3) * r(3);
        let facade = (r(4) * FACADES as f32) as usize % FACADES;
        let tower =
            Mat4::from_scale_rotation_translation(Vec3::new(w, h, d), Quat::IDENTITY, centre);
        out.push((kit.towers[facade], tower));
        if r(5) < 0.3 {
            let radius = 0.4 * w.min(d);
            let dome = Mat4::from_scale_rotation_translation(
                Vec3::new(radius, radius * 0.8, radius),
                Quat::IDENTITY,
                centre + Vec3::Y * h,
            );
            out.push((kit.domes[facade / 4], dome));
        }
        // The lot's street side faces away from the block's middle.
        let out_z = if lot & 2 == 0 { -1.0 } else { 1.0 };
        let front = centre + Vec3::Z * out_z * (d * 0.5 + 1.5);
        if r(6) < 0.4 {
            for k in 0..4 {
                let x = (k as f32 - 1.5) * w / 4.0;
                let column = Mat4::from_scale_rotation_translation(
                    Vec3::new(0.6, 5.0, 0.6),
                    Quat::IDENTITY,
                    front + Vec3::X * x,
                );
                out.push((kit.column, column));
            }
        }
        if r(7) < 0.35 {
            let screen = kit.screens[(r(8) * 2.0) as usize % 2];
            out.push((
                screen,
                Mat4::from_translation(front + Vec3::Z * out_z * 0.8),
            ));
        }
        if r(9) < 0.25 {
            let canopy = kit.canopies[(r(10) * 4.0) as usize % 4];
            let at = front + Vec3::Y * 3.5 - Vec3::Z * out_z * 1.0;
            let turn = if out_z < 0.0 {
                std::f32::consts::PI
            } else {
                0.0
            };
            let world = Mat4::from_rotation_translation(Quat::from_rotation_y(turn), at);
            out.push((canopy, world));
        }
    }
    out
}

/// A hash of `(x, y, salt)` to `[0, 1)`.
fn hash(x: u32, y: u32, salt: u32) -> f32 {
    let mut h =
        x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ salt.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^= h >> 15;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_city_has_exactly_the_instances_asked_for_and_is_deterministic() {
        for n in [1, 7, 1_000, 20_000] {
            let scene = city(n);
            assert_eq!(scene.instances.len(), n);
            scene
                .check_for_device(&wgpu::Limits::default())
                .unwrap_or_else(|e| panic!("city:{n}: {e}"));
        }
        assert_eq!(city(500), city(500));
        // A larger city starts with the smaller one's blocks.
        let (small, large) = (city(300), city(3_000));
        assert_eq!(small.instances[..], large.instances[..300]);
    }

    #[test]
    fn a_city_has_forty_materials_with_masked_and_blended_ones() {
        let scene = city(2_000);
        assert_eq!(scene.materials.len(), 40);
        let count = |f: fn(&AlphaMode) -> bool| {
            let used: std::collections::HashSet<usize> = scene
                .instances
                .iter()
                .flat_map(|i| &scene.meshes[i.mesh].primitives)
                .filter_map(|p| p.material)
                .filter(|&m| f(&scene.materials[m].alpha_mode))
                .collect();
            used.len()
        };
        assert_eq!(count(|m| matches!(m, AlphaMode::Mask { .. })), 2);
        assert_eq!(count(|m| *m == AlphaMode::Blend), 4);
        assert!(count(|m| *m == AlphaMode::Opaque) >= 30);
    }
}
