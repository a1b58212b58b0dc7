//! Triangle meshes of simple shapes, in world space: boxes (and planes) and UV spheres, with
//! normals, UVs in world units and tangents.

use glam::{Vec2, Vec3, Vec4};

use crate::scene::{Aabb, Primitive};

/// The faces of a box: outward normal, then the face's u and v axes (u × v = normal).
const FACES: [[Vec3; 3]; 6] = [
    [Vec3::X, Vec3::NEG_Z, Vec3::Y],
    [Vec3::NEG_X, Vec3::Z, Vec3::Y],
    [Vec3::Y, Vec3::X, Vec3::NEG_Z],
    [Vec3::NEG_Y, Vec3::X, Vec3::Z],
    [Vec3::Z, Vec3::X, Vec3::Y],
    [Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y],
];

/// A box from `min` to `max`. A plane (one extent zero) keeps its two faces across the flat axis,
/// or only the one facing along the positive axis when `double_sided`: such a face already shows
/// from both sides, and a second at the same depth would fight it (which face wins would then
/// depend on the depth test and the draw order).
pub(super) fn cuboid(min: Vec3, max: Vec3, material: usize, double_sided: bool) -> Primitive {
    let (center, half) = ((min + max) * 0.5, (max - min) * 0.5);
    let flat_axis = (0..3).find(|&a| half[a] == 0.0);
    let mut p = Primitive {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        uvs1: Vec::new(),
        colors: Vec::new(),
        tangents: Vec::new(),
        indices: Vec::new(),
        material: Some(material),
        bounds: Aabb { min, max },
    };
    for [n, u, v] in FACES {
        let dropped = flat_axis.is_some_and(|a| n[a] == 0.0 || (double_sided && n[a] < 0.0));
        if dropped {
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

/// A UV sphere: 16 rings of 32 segments, UVs around (u) and from pole to pole (v).
pub(super) fn sphere(center: Vec3, radius: f32, material: usize) -> Primitive {
    const RINGS: u32 = 16;
    const SEGMENTS: u32 = 32;
    let mut p = Primitive {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        uvs1: Vec::new(),
        colors: Vec::new(),
        tangents: Vec::new(),
        indices: Vec::new(),
        material: Some(material),
        bounds: Aabb {
            min: center - Vec3::splat(radius),
            max: center + Vec3::splat(radius),
        },
    };
    for ring in 0..=RINGS {
        let v = ring as f32 / RINGS as f32;
        let (sin_t, cos_t) = (v * std::f32::consts::PI).sin_cos();
        for seg in 0..=SEGMENTS {
            let u = seg as f32 / SEGMENTS as f32;
            let (sin_p, cos_p) = (u * std::f32::consts::TAU).sin_cos();
            let n = Vec3::new(sin_t * cos_p, cos_t, -sin_t * sin_p);
            p.positions.push(center + n * radius);
            p.normals.push(n);
            p.uvs.push(Vec2::new(u * 4.0, v * 2.0));
            p.tangents.push(Vec4::new(-sin_p, 0.0, -cos_p, 1.0));
        }
    }
    let row = SEGMENTS + 1;
    for ring in 0..RINGS {
        for seg in 0..SEGMENTS {
            let a = ring * row + seg;
            let b = a + row;
            p.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    p
}
