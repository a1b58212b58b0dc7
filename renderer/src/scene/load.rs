//! Reading a glTF file into a [`Scene`].

use std::path::Path;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

use super::instancing::{self, NodeMeshes};
use super::load_checks::{check_accessors, parse, precheck, unsupported_features};
use super::{
    Aabb, Image, LightKind, Mesh, Primitive, Scene, SceneError, SceneLight, SceneWarning, camera,
    image_formats, modes, resources, tangents,
};
use super::{material_load, morph, vertex_attrs};

impl Scene {
    /// Loads a `.gltf` (with its buffers and images) or `.glb` file. External buffers and images
    /// must be files inside the scene's folder (or `data:` URIs).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| SceneError::Gltf {
            path: path.to_path_buf(),
            source: gltf::Error::Io(e),
        })?;
        let base = path.parent().unwrap_or_else(|| Path::new("."));
        Self::from_bytes(&bytes, Some(base), path)
    }

    /// Loads a self-contained scene from memory: a `.glb`, or a `.gltf` whose buffers and images
    /// are `data:` URIs. Errors name the scene `<memory>`.
    pub fn from_slice(bytes: &[u8]) -> Result<Self, SceneError> {
        Self::from_bytes(bytes, None, Path::new("<memory>"))
    }

    fn from_bytes(bytes: &[u8], base: Option<&Path>, path: &Path) -> Result<Self, SceneError> {
        let gltf_err = |source| SceneError::Gltf {
            path: path.to_path_buf(),
            source,
        };
        precheck(bytes, path)?;
        let gltf::Gltf {
            document: doc,
            blob,
        } = parse(bytes).map_err(gltf_err)?;
        let ctx = Ctx { path };
        let nodes = ctx.node_transforms(&doc)?;
        // Only the meshes the scene's nodes use are read.
        let mut used = vec![false; doc.meshes().len()];
        for mesh in nodes.iter().filter_map(|(node, _)| node.mesh()) {
            if let Some(u) = used.get_mut(mesh.index()) {
                *u = true;
            }
        }
        check_accessors(&doc, &used, path)?;
        resources::check_uris(&doc, base, path)?;
        // gltf decodes image `data:` URIs only when given a folder. With no folder, every URI
        // is a `data:` URI (checked above), so the stand-in folder is never read.
        let base = base.or(Some(Path::new(".")));
        let buffers = gltf::import_buffers(&doc, base, blob).map_err(gltf_err)?;
        let images = gltf::import_images(&doc, base, &buffers).map_err(gltf_err)?;
        let mut warnings = unsupported_features(&doc);
        let mut meshes = doc
            .meshes()
            .map(|m| match used.get(m.index()) {
                Some(true) => ctx.mesh(&m, m.weights().unwrap_or(&[]), &buffers, &mut warnings),
                _ => Ok(unused_mesh(&m, &mut warnings)),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let images = images
            .into_iter()
            .enumerate()
            .map(|(i, data)| ctx.image(i, data))
            .collect::<Result<Vec<_>, _>>()?;
        let materials = doc
            .materials()
            .map(|m| material_load::material(&m, path))
            .collect::<Result<Vec<_>, _>>()?;
        // A node whose own morph weights differ from its mesh's draws its own copy of the mesh.
        let mut node_mesh = vec![None; doc.nodes().len()];
        for (node, _) in &nodes {
            if let (Some(m), Some(w)) = (node.mesh(), node.weights())
                && morph::node_differs(&m, w)
                && let Some(slot) = node_mesh.get_mut(node.index())
            {
                *slot = Some(meshes.len());
                meshes.push(ctx.mesh(&m, w, &buffers, &mut Vec::new())?);
            }
        }
        let node_meshes = NodeMeshes {
            mesh: node_mesh,
            instances: instancing::node_instances(
                &doc,
                nodes.iter().map(|(n, _)| n),
                &buffers,
                path,
            )?,
        };
        let mut scene = Self {
            meshes,
            materials,
            images,
            instances: Vec::new(),
            cameras: Vec::new(),
            lights: Vec::new(),
            bounds: Aabb::EMPTY,
            warnings,
        };
        scene.check_uv_sets(&doc);
        for (node, world) in nodes {
            scene.place(&node, world, &node_meshes);
        }
        Ok(scene)
    }

    /// Adds what `node` carries (mesh instances, camera, light) at `world`.
    fn place(&mut self, node: &gltf::Node<'_>, world: Mat4, node_meshes: &NodeMeshes) {
        self.place_mesh(node, world, node_meshes);
        if let Some(camera) = node.camera() {
            self.cameras.push(camera::camera_of(&camera, world));
        }
        if let Some(light) = node.light() {
            self.lights.push(light_of(&light, world));
        }
    }
}

struct Ctx<'a> {
    path: &'a Path,
}

impl Ctx<'_> {
    /// Every node of the default scene (or of the first; or every root node when the file has
    /// no scene) with its world transform, parents first. Walked without recursion, so a deep
    /// hierarchy cannot exhaust the stack; a node reached twice (a cycle, or two parents) is an
    /// error, as glTF requires the nodes to form trees.
    fn node_transforms<'d>(
        &self,
        doc: &'d gltf::Document,
    ) -> Result<Vec<(gltf::Node<'d>, Mat4)>, SceneError> {
        let roots: Vec<gltf::Node<'d>> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(s) => s.nodes().collect(),
            None => {
                let mut is_child = vec![false; doc.nodes().len()];
                for child in doc.nodes().flat_map(|n| n.children()) {
                    if let Some(flag) = is_child.get_mut(child.index()) {
                        *flag = true;
                    }
                }
                doc.nodes()
                    .filter(|n| !is_child.get(n.index()).copied().unwrap_or(false))
                    .collect()
            }
        };
        let mut reached = vec![false; doc.nodes().len()];
        let mut out = Vec::new();
        let mut stack: Vec<(gltf::Node<'d>, Mat4)> = roots
            .into_iter()
            .rev()
            .map(|n| (n, Mat4::IDENTITY))
            .collect();
        while let Some((node, parent)) = stack.pop() {
            match reached.get_mut(node.index()) {
                Some(seen @ false) => *seen = true,
                _ => {
                    return Err(SceneError::NodeHierarchy {
                        path: self.path.to_path_buf(),
                        node: node.index(),
                    });
                }
            }
            let (t, r, s) = node.transform().decomposed();
            let world = parent
                * Mat4::from_scale_rotation_translation(
                    Vec3::from(s),
                    Quat::from_array(r),
                    Vec3::from(t),
                );
            let children: Vec<_> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|c| (c, world)));
            out.push((node, world));
        }
        Ok(out)
    }

    /// The mesh's triangle primitives (strips and fans as lists); points and lines are
    /// skipped with a warning each, and a strip or fan too short for a triangle is dropped.
    /// Morph targets are applied at `weights` (empty: as read).
    fn mesh(
        &self,
        mesh: &gltf::Mesh<'_>,
        weights: &[f32],
        buffers: &[gltf::buffer::Data],
        warnings: &mut Vec<SceneWarning>,
    ) -> Result<Mesh, SceneError> {
        let name = mesh_name(mesh);
        let mut primitives = Vec::new();
        for (i, p) in mesh.primitives().enumerate() {
            if let Some(mode) = modes::undrawn(p.mode()) {
                warnings.push(SceneWarning::SkippedPrimitive {
                    mesh: name.clone(),
                    primitive: i,
                    mode,
                });
                continue;
            }
            let read = self.primitive(&name, i, &p, buffers)?;
            let primitive = morph::apply(read, &p, weights, buffers, &name, self.path)?;
            if !primitive.indices.is_empty() {
                primitives.push(primitive);
            }
        }
        Ok(Mesh { name, primitives })
    }

    fn primitive(
        &self,
        mesh: &str,
        index: usize,
        p: &gltf::Primitive<'_>,
        buffers: &[gltf::buffer::Data],
    ) -> Result<Primitive, SceneError> {
        let path = self.path.to_path_buf();
        let reader = p.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| SceneError::MissingAttribute {
                path: path.clone(),
                mesh: mesh.to_owned(),
                primitive: index,
                attribute: "POSITION",
            })?
            .map(Vec3::from)
            .collect();
        let n = positions.len();
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..n as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(SceneError::IndexOutOfRange {
                path,
                mesh: mesh.to_owned(),
                primitive: index,
                index: bad,
                vertices: n,
            });
        }
        let indices = modes::triangle_list(p.mode(), indices);
        let normals: Vec<Vec3> = match reader.read_normals() {
            Some(it) => it.map(Vec3::from).collect(),
            None => tangents::flat_normals(&positions, &indices),
        };
        let uvs: Vec<Vec2> = match reader.read_tex_coords(0) {
            Some(it) => it.into_f32().map(Vec2::from).collect(),
            None => vec![Vec2::ZERO; n],
        };
        let length_error = |what: &str, got: usize| SceneError::AttributeLength {
            path: path.clone(),
            what: format!("mesh `{mesh}` primitive {index} {what}"),
            got,
            expected: n,
        };
        for (what, got) in [("NORMAL", normals.len()), ("TEXCOORD_0", uvs.len())] {
            if got != n {
                return Err(length_error(what, got));
            }
        }
        // Generated only once NORMAL and TEXCOORD_0 are known to match POSITION.
        let tangents: Vec<Vec4> = match reader.read_tangents() {
            Some(it) => it.map(Vec4::from).collect(),
            None => tangents::generate(&positions, &normals, &uvs, &indices),
        };
        if tangents.len() != n {
            return Err(length_error("TANGENT", tangents.len()));
        }
        let (uvs1, colors) = vertex_attrs::read(p, &reader, n, length_error)?;
        let bounds = positions.iter().fold(Aabb::EMPTY, |b, &p| b.with_point(p));
        Ok(Primitive {
            positions,
            normals,
            uvs,
            uvs1,
            colors,
            tangents,
            indices,
            material: p.material().index(),
            bounds,
        })
    }

    fn image(&self, index: usize, data: gltf::image::Data) -> Result<Image, SceneError> {
        let px = data.width as usize * data.height as usize;
        let rgba8 = image_formats::to_rgba8(data.format, data.pixels);
        if rgba8.len() != px * 4 {
            return Err(SceneError::Inconsistent(format!(
                "{}: image {index} decoded to {} bytes for {}x{} pixels",
                self.path.display(),
                rgba8.len(),
                data.width,
                data.height
            )));
        }
        Ok(Image {
            width: data.width,
            height: data.height,
            rgba8,
        })
    }
}

/// A mesh's name in messages: its own, else `#<index>`.
fn mesh_name(mesh: &gltf::Mesh<'_>) -> String {
    mesh.name()
        .map_or_else(|| format!("#{}", mesh.index()), str::to_owned)
}

/// A mesh no node of the scene uses: not read, kept without primitives so mesh indices stay
/// the file's, and named by a warning.
fn unused_mesh(mesh: &gltf::Mesh<'_>, warnings: &mut Vec<SceneWarning>) -> Mesh {
    let name = mesh_name(mesh);
    warnings.push(SceneWarning::UnusedMesh { mesh: name.clone() });
    Mesh {
        name,
        primitives: Vec::new(),
    }
}

fn light_of(light: &gltf::khr_lights_punctual::Light<'_>, world: Mat4) -> SceneLight {
    use gltf::khr_lights_punctual::Kind;
    let kind = match light.kind() {
        Kind::Point => LightKind::Point,
        Kind::Directional => LightKind::Directional,
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => LightKind::Spot {
            inner_cone: inner_cone_angle,
            outer_cone: outer_cone_angle,
        },
    };
    SceneLight {
        kind,
        position: world.transform_point3(Vec3::ZERO),
        // glTF lights point down their node's −Z.
        direction: world
            .transform_vector3(Vec3::NEG_Z)
            .normalize_or(Vec3::NEG_Z),
        color: Vec3::from(light.color()),
        intensity: light.intensity(),
        range: light.range(),
        casts_shadow: true,
    }
}
