//! Seeded procedural placement (`--decals N`): decals scattered over a scene's surfaces, each
//! box centred on a surface point and facing out along the triangle's normal.

use glam::{Vec3, Vec4Swizzles as _};

use super::setup::Rng;
use crate::decals::{Decal, box_on_surface};
use crate::scene::Scene;

/// A world-space triangle of the scene.
struct Triangle {
    corners: [Vec3; 3],
    area: f32,
}

fn triangles(scene: &Scene) -> Vec<Triangle> {
    let mut out = Vec::new();
    for instance in &scene.instances {
        let m = instance.world_from_mesh;
        for p in &scene.meshes[instance.mesh].primitives {
            for t in p.indices.chunks_exact(3) {
                let corners = [0, 1, 2].map(|k| {
                    let v = p.positions[t[k] as usize];
                    (m * v.extend(1.0)).xyz()
                });
                let area = 0.5
                    * (corners[1] - corners[0])
                        .cross(corners[2] - corners[0])
                        .length();
                if area.is_finite() && area > 0.0 {
                    out.push(Triangle { corners, area });
                }
            }
        }
    }
    out
}

/// `count` decals of materials `0..materials` on `scene`'s surfaces, chosen by area (so big
/// floors get more than small props), seeded. Sides run from 3% to 10% of the scene's
/// diagonal, boxes are half as deep as they are wide, and sort keys 0 to 3 layer overlapping
/// ones. Empty when the scene has no triangles or there are no materials.
pub fn scatter(scene: &Scene, count: usize, materials: usize, seed: u64) -> Vec<Decal> {
    let tris = triangles(scene);
    let total: f32 = tris.iter().map(|t| t.area).sum();
    if tris.is_empty() || materials == 0 || total <= 0.0 {
        return Vec::new();
    }
    let mut cumulative = Vec::with_capacity(tris.len());
    let mut sum = 0.0;
    for t in &tris {
        sum += t.area;
        cumulative.push(sum);
    }
    let diagonal = (scene.bounds.max - scene.bounds.min).length().max(1e-3);
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let pick = rng.range(0.0, total);
            let i = cumulative
                .partition_point(|&c| c < pick)
                .min(tris.len() - 1);
            let [a, b, c] = tris[i].corners;
            let (mut u, mut v) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let point = a + (b - a) * u + (c - a) * v;
            let normal = (b - a).cross(c - a).normalize();
            let side = diagonal * rng.range(0.03, 0.10);
            let roll = rng.range(0.0, std::f32::consts::TAU);
            let mut decal = Decal::new(
                box_on_surface(point, normal, roll, Vec3::new(side, side, side * 0.5)),
                (rng.next_u64() % materials as u64) as usize,
            );
            decal.sort_key = (rng.next_u64() % 4) as i32;
            decal
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decals_sit_on_the_courtyard_facing_out_and_repeat_by_seed() {
        let scene = crate::scene::procedural::courtyard();
        let a = scatter(&scene, 64, 3, 9);
        assert_eq!(a, scatter(&scene, 64, 3, 9), "seeded");
        assert_ne!(a, scatter(&scene, 64, 3, 10));
        assert_eq!(a.len(), 64);
        for d in &a {
            let b = d.bounds().expect("a valid box");
            assert!(d.material < 3);
            let grown = (scene.bounds.max - scene.bounds.min) * 0.01;
            assert!(
                b.center.cmpge(scene.bounds.min - grown).all()
                    && b.center.cmple(scene.bounds.max + grown).all(),
                "centred on a surface of the scene"
            );
        }
        assert!(
            scatter(&scene, 5, 0, 1).is_empty(),
            "no materials, no decals"
        );
    }
}
