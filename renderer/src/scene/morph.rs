//! Morph targets at load: a primitive's positions, normals and tangents (xyz) plus each
//! target's deltas times its weight, with the mesh's default `weights` (or, for a node with
//! its own `weights`, that node's, on its own copy of the mesh). Animation is not played, so
//! these weights are the ones that show.

use std::path::Path;

use glam::Vec3;
use gltf::accessor::{DataType, Dimensions};

use super::{Aabb, Primitive, SceneError, tangents};

/// Whether a node with `node_weights` draws `mesh` differently from the mesh's own weights
/// (missing weights count as 0), so it needs its own morphed copy. A mesh without morph
/// targets never does.
pub(super) fn node_differs(mesh: &gltf::Mesh<'_>, node_weights: &[f32]) -> bool {
    let has_targets = mesh.primitives().any(|p| p.morph_targets().len() > 0);
    let mesh_weights = mesh.weights().unwrap_or(&[]);
    let at = |w: &[f32], i: usize| w.get(i).copied().unwrap_or(0.0);
    has_targets
        && (0..mesh_weights.len().max(node_weights.len()))
            .any(|i| at(mesh_weights, i) != at(node_weights, i))
}

/// `p` (read from `gp` of mesh `mesh`) with `gp`'s morph targets applied at `weights`; empty
/// `weights` (the mesh has none) leaves it as read. Otherwise there must be one weight per
/// target. Normals the file gives are morphed and renormalized, and tangents it gives are
/// morphed in xyz; normals or tangents the loader generated are generated again from the
/// morphed geometry. Bounds follow the morphed positions.
pub(super) fn apply(
    mut p: Primitive,
    gp: &gltf::Primitive<'_>,
    weights: &[f32],
    buffers: &[gltf::buffer::Data],
    mesh: &str,
    path: &Path,
) -> Result<Primitive, SceneError> {
    let targets: Vec<_> = gp.morph_targets().collect();
    if weights.is_empty() || targets.is_empty() {
        return Ok(p);
    }
    let where_ = |what: String| format!("mesh `{mesh}` primitive {} {what}", gp.index());
    if weights.len() != targets.len() {
        return Err(SceneError::Inconsistent(format!(
            "{}: {} weights for {} morph targets; glTF requires one weight per target",
            path.display(),
            where_(format!("is given {}", weights.len())),
            targets.len(),
        )));
    }
    let n = p.positions.len();
    let file_normals = gp.get(&gltf::Semantic::Normals).is_some();
    let file_tangents = gp.get(&gltf::Semantic::Tangents).is_some();
    for (t, (target, &w)) in targets.iter().zip(weights).enumerate() {
        if w == 0.0 {
            continue;
        }
        let read = |accessor: Option<gltf::Accessor<'_>>, attribute: &str| {
            accessor
                .map(|a| {
                    deltas(
                        &a,
                        buffers,
                        n,
                        path,
                        &where_(format!("morph target {t} {attribute}")),
                    )
                })
                .transpose()
        };
        if let Some(d) = read(target.positions(), "POSITION")? {
            add(&mut p.positions, &d, w);
        }
        if file_normals && let Some(d) = read(target.normals(), "NORMAL")? {
            add(&mut p.normals, &d, w);
        }
        if file_tangents && let Some(d) = read(target.tangents(), "TANGENT")? {
            for (tangent, delta) in p.tangents.iter_mut().zip(&d) {
                *tangent += (*delta * w).extend(0.0);
            }
        }
    }
    if file_normals {
        for normal in &mut p.normals {
            *normal = normal.normalize_or(Vec3::Y);
        }
    } else {
        p.normals = tangents::flat_normals(&p.positions, &p.indices);
    }
    if file_tangents {
        for tangent in &mut p.tangents {
            let xyz = tangent.truncate().normalize_or(Vec3::X);
            *tangent = xyz.extend(tangent.w);
        }
    } else {
        p.tangents = tangents::generate(&p.positions, &p.normals, &p.uvs, &p.indices);
    }
    p.bounds = p
        .positions
        .iter()
        .fold(Aabb::EMPTY, |b, &v| b.with_point(v));
    Ok(p)
}

fn add(values: &mut [Vec3], deltas: &[Vec3], w: f32) {
    for (v, d) in values.iter_mut().zip(deltas) {
        *v += *d * w;
    }
}

/// A target's deltas: float VEC3 (sparse or not), one per vertex.
fn deltas(
    a: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
    vertices: usize,
    path: &Path,
    what: &str,
) -> Result<Vec<Vec3>, SceneError> {
    if a.dimensions() != Dimensions::Vec3 || a.data_type() != DataType::F32 {
        return Err(SceneError::Inconsistent(format!(
            "{}: {what} is {:?} {:?}; morph deltas must be float VEC3",
            path.display(),
            a.dimensions(),
            a.data_type()
        )));
    }
    let length_error = |got| SceneError::AttributeLength {
        path: path.to_path_buf(),
        what: what.to_owned(),
        got,
        expected: vertices,
    };
    if a.count() != vertices {
        return Err(length_error(a.count()));
    }
    if !super::instancing::fits(a, buffers) {
        return Err(SceneError::Inconsistent(format!(
            "{}: {what}'s values do not fit in its buffer view",
            path.display()
        )));
    }
    let values: Vec<Vec3> = gltf::accessor::Iter::<[f32; 3]>::new(a.clone(), |b| {
        buffers.get(b.index()).map(|d| &d.0[..])
    })
    .map(|it| it.map(Vec3::from).collect())
    .unwrap_or_default();
    if values.len() != vertices {
        return Err(length_error(values.len()));
    }
    Ok(values)
}
