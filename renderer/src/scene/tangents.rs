//! Vertex data a file may omit, generated: flat normals, and tangents (MikkTSpace).

use glam::{Vec2, Vec3, Vec4};

struct Geometry<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    indices: &'a [u32],
    tangents: Vec<Vec4>,
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.index(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.index(face, vert)].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[self.index(face, vert)].to_array()
    }

    fn set_tangent(
        &mut self,
        tangent: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(t) = tangent {
            let i = self.index(face, vert);
            self.tangents[i] = Vec4::from_array(t.tangent_encoded());
        }
    }
}

impl Geometry<'_> {
    fn index(&self, face: usize, vert: usize) -> usize {
        self.indices[face * 3 + vert] as usize
    }
}

/// Per-vertex tangents (xyz, handedness in w). Vertices shared by faces take the tangent of the
/// last face MikkTSpace visits; if generation fails (degenerate UVs), a tangent perpendicular to
/// the normal is used so shading stays defined.
pub fn generate(positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2], indices: &[u32]) -> Vec<Vec4> {
    let mut g = Geometry {
        positions,
        normals,
        uvs,
        indices,
        tangents: normals.iter().map(|n| fallback(*n)).collect(),
    };
    if bevy_mikktspace::generate_tangents(&mut g).is_err() {
        return normals.iter().map(|n| fallback(*n)).collect();
    }
    g.tangents
}

fn fallback(n: Vec3) -> Vec4 {
    n.any_orthonormal_vector().extend(1.0)
}

/// Face normals for primitives without a NORMAL attribute (vertices shared by faces get the
/// last face's normal).
pub(super) fn flat_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::Y; positions.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        let n = (b - a).cross(c - a).normalize_or(Vec3::Y);
        for &i in tri {
            normals[i as usize] = n;
        }
    }
    normals
}
