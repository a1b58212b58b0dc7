//! `EXT_mesh_gpu_instancing`: a node with this extension draws its mesh once per instance, at
//! the node's world transform times the instance's translation × rotation × scale (read from
//! the `TRANSLATION`, `ROTATION` and `SCALE` accessors; a missing one is the identity), and
//! never at the node's own transform alone. gltf 1.4.1 has no typed support, so the extension
//! is read from the node's JSON.

use std::path::Path;

use glam::{Mat4, Quat, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};

use super::{Instance, Scene, SceneError};

pub(super) const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// Where each node's mesh is drawn, beyond the node itself.
pub(super) struct NodeMeshes {
    /// `mesh[node]`: the node's own morphed copy of its mesh (its `weights` differ from the
    /// mesh's), if any.
    pub mesh: Vec<Option<usize>>,
    /// `instances[node]`: the node's instance transforms (mesh space to node space), if it
    /// has the extension and a mesh.
    pub instances: Vec<Option<Vec<Mat4>>>,
}

impl Scene {
    /// Adds `node`'s mesh (if any) at `world`: once, or once per instance of its
    /// `EXT_mesh_gpu_instancing`; each instance widens the scene's bounds.
    pub(super) fn place_mesh(&mut self, node: &gltf::Node<'_>, world: Mat4, extra: &NodeMeshes) {
        let Some(mesh) = node.mesh() else {
            return;
        };
        let index = extra
            .mesh
            .get(node.index())
            .copied()
            .flatten()
            .unwrap_or(mesh.index());
        let Some(bounds) = self.meshes.get(index).map(|m| {
            m.primitives
                .iter()
                .fold(super::Aabb::EMPTY, |b, p| b.union(p.bounds))
        }) else {
            return;
        };
        let single = [Mat4::IDENTITY];
        let locals = match extra.instances.get(node.index()) {
            Some(Some(locals)) => locals.as_slice(),
            _ => &single,
        };
        for local in locals {
            let world_from_mesh = world * *local;
            self.bounds = self.bounds.union(bounds.transformed(world_from_mesh));
            self.instances.push(Instance {
                mesh: index,
                world_from_mesh,
            });
        }
    }
}

/// The instance transforms of every node of `nodes` (indexed by node) that has a mesh and the
/// extension. A malformed extension, an accessor index past the file's accessors, an accessor
/// of a type the extension does not allow, data its buffer does not hold or attributes of
/// different counts are errors naming the node.
pub(super) fn node_instances<'d>(
    doc: &'d gltf::Document,
    nodes: impl IntoIterator<Item = &'d gltf::Node<'d>>,
    buffers: &[gltf::buffer::Data],
    path: &Path,
) -> Result<Vec<Option<Vec<Mat4>>>, SceneError> {
    let mut out = vec![None; doc.nodes().len()];
    for node in nodes {
        if let (Some(_), Some(ext), Some(slot)) = (
            node.mesh(),
            node.extension_value(EXTENSION),
            out.get_mut(node.index()),
        ) {
            *slot = Some(instances(doc, node, ext, buffers, path)?);
        }
    }
    Ok(out)
}

fn instances(
    doc: &gltf::Document,
    node: &gltf::Node<'_>,
    ext: &gltf::json::Value,
    buffers: &[gltf::buffer::Data],
    path: &Path,
) -> Result<Vec<Mat4>, SceneError> {
    let bad = |what: String| {
        SceneError::Inconsistent(format!(
            "{}: node {} {EXTENSION} {what}",
            path.display(),
            node.index()
        ))
    };
    let Some(attributes) = ext.get("attributes").and_then(|a| a.as_object()) else {
        return Err(bad("has no `attributes` object".into()));
    };
    let mut count = None;
    let mut accessors = Vec::new();
    for (name, value) in attributes {
        let accessor = value
            .as_u64()
            .and_then(|i| usize::try_from(i).ok())
            .and_then(|i| doc.accessors().nth(i))
            .ok_or_else(|| {
                bad(format!(
                    "attribute {name} names accessor {value}, but the file has {} accessors",
                    doc.accessors().len()
                ))
            })?;
        if *count.get_or_insert(accessor.count()) != accessor.count() {
            return Err(bad(format!(
                "attribute {name} has {} values where the others have {}; all must have the \
                 same count",
                accessor.count(),
                count.unwrap_or_default()
            )));
        }
        accessors.push((name.as_str(), accessor));
    }
    let Some(count) = count else {
        return Err(bad("has no attributes".into()));
    };
    let mut translations = vec![Vec3::ZERO; count];
    let mut rotations = vec![Quat::IDENTITY; count];
    let mut scales = vec![Vec3::ONE; count];
    for (name, a) in accessors {
        let read = Reader {
            accessor: &a,
            buffers,
            name,
            bad: &bad,
        };
        match name {
            "TRANSLATION" => translations = read.vec3()?,
            "SCALE" => scales = read.vec3()?,
            "ROTATION" => {
                rotations = read
                    .vec4()?
                    .into_iter()
                    .map(|q| {
                        (q.length_squared() > 0.0)
                            .then(|| Quat::from_vec4(q).normalize())
                            .ok_or_else(|| bad("ROTATION holds a zero quaternion".into()))
                    })
                    .collect::<Result<_, _>>()?;
            }
            // Custom attributes (`_ID` and the like) are the application's.
            _ => {}
        }
    }
    Ok((0..count)
        .map(|i| Mat4::from_scale_rotation_translation(scales[i], rotations[i], translations[i]))
        .collect())
}

/// Reads one instancing attribute, checking its type against the extension's table.
struct Reader<'r, 'a> {
    accessor: &'r gltf::Accessor<'a>,
    buffers: &'r [gltf::buffer::Data],
    name: &'r str,
    bad: &'r dyn Fn(String) -> SceneError,
}

impl Reader<'_, '_> {
    fn wrong_type(&self, allowed: &str) -> SceneError {
        (self.bad)(format!(
            "attribute {} is {:?} {:?}{}; the extension allows {allowed}",
            self.name,
            self.accessor.dimensions(),
            self.accessor.data_type(),
            if self.accessor.normalized() {
                " normalized"
            } else {
                ""
            },
        ))
    }

    fn items<T: gltf::accessor::Item>(&self) -> Result<Vec<T>, SceneError> {
        let buffers = self.buffers;
        if !fits(self.accessor, buffers) {
            return Err((self.bad)(format!(
                "attribute {}: its {} values do not fit in its buffer view",
                self.name,
                self.accessor.count()
            )));
        }
        let items: Vec<T> = gltf::accessor::Iter::<T>::new(self.accessor.clone(), |b| {
            buffers.get(b.index()).map(|d| &d.0[..])
        })
        .map(Iterator::collect)
        .unwrap_or_default();
        if items.len() != self.accessor.count() {
            return Err((self.bad)(format!(
                "attribute {}: only {} of its {} values can be read from its buffer",
                self.name,
                items.len(),
                self.accessor.count()
            )));
        }
        Ok(items)
    }

    /// `TRANSLATION` and `SCALE`: float VEC3.
    fn vec3(&self) -> Result<Vec<Vec3>, SceneError> {
        if self.accessor.dimensions() != Dimensions::Vec3
            || self.accessor.data_type() != DataType::F32
        {
            return Err(self.wrong_type("float VEC3"));
        }
        Ok(self
            .items::<[f32; 3]>()?
            .into_iter()
            .map(Vec3::from)
            .collect())
    }

    /// `ROTATION`: float VEC4, or normalized signed byte or short VEC4.
    fn vec4(&self) -> Result<Vec<Vec4>, SceneError> {
        let allowed = "float, or normalized byte or short, VEC4";
        if self.accessor.dimensions() != Dimensions::Vec4 {
            return Err(self.wrong_type(allowed));
        }
        let normalized = self.accessor.normalized();
        Ok(match self.accessor.data_type() {
            DataType::F32 => self
                .items::<[f32; 4]>()?
                .into_iter()
                .map(Vec4::from)
                .collect(),
            DataType::I8 if normalized => self
                .items::<[i8; 4]>()?
                .into_iter()
                .map(|c| Vec4::from(c.map(|x| (f32::from(x) / 127.0).max(-1.0))))
                .collect(),
            DataType::I16 if normalized => self
                .items::<[i16; 4]>()?
                .into_iter()
                .map(|c| Vec4::from(c.map(|x| (f32::from(x) / 32767.0).max(-1.0))))
                .collect(),
            _ => return Err(self.wrong_type(allowed)),
        })
    }
}

/// Whether `a`'s `count` elements (and its sparse indices and values) lie inside their buffer
/// views, computed without overflow (gltf's reader does this arithmetic unchecked). An
/// accessor without a view (zeros plus sparse values) may claim no more values than the
/// file's buffers hold bytes, so a count read from the JSON cannot make the loader allocate
/// without bound.
pub(super) fn fits(a: &gltf::Accessor<'_>, buffers: &[gltf::buffer::Data]) -> bool {
    let within = |view: gltf::buffer::View<'_>, offset: usize, count: usize, size: usize| {
        let stride = view.stride().unwrap_or(size);
        count
            .checked_sub(1)
            .and_then(|last| last.checked_mul(stride))
            .and_then(|bytes| bytes.checked_add(offset))
            .and_then(|bytes| bytes.checked_add(size))
            .is_some_and(|end| end <= view.length())
    };
    let count = a.count();
    let base = match a.view() {
        Some(view) => within(view, a.offset(), count, a.size()),
        None => count <= buffers.iter().map(|b| b.0.len()).sum(),
    };
    base && a.sparse().is_none_or(|s| {
        s.count() <= count
            && within(
                s.indices().view(),
                s.indices().offset(),
                s.count(),
                s.indices().index_type().size(),
            )
            && within(s.values().view(), s.values().offset(), s.count(), a.size())
    })
}
