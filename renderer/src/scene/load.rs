//! Reading a glTF file into a [`Scene`].

use std::path::Path;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

use super::load_checks::{check_accessors, precheck};
use super::{
    Aabb, AlphaMode, Image, Instance, LightKind, Material, Mesh, Primitive, Scene,
    SceneError, SceneLight, TextureRef, camera, resources, tangents,
};

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
        } = gltf::Gltf::from_slice(bytes).map_err(gltf_err)?;
        check_accessors(&doc, path)?;
        resources::check_uris(&doc, base, path)?;
        // gltf decodes image `data:` URIs only when given a folder. With no folder, every URI
        // is a `data:` URI (checked above), so the stand-in folder is never read.
        let base = base.or(Some(Path::new(".")));
        let buffers = gltf::import_buffers(&doc, base, blob).map_err(gltf_err)?;
        let images = gltf::import_images(&doc, base, &buffers).map_err(gltf_err)?;
        let ctx = Ctx { path };
        let meshes = doc
            .meshes()
            .map(|m| ctx.mesh(&m, &buffers))
            .collect::<Result<Vec<_>, _>>()?;
        let images = images
            .into_iter()
            .enumerate()
            .map(|(i, data)| ctx.image(i, data))
            .collect::<Result<Vec<_>, _>>()?;
        let materials = doc.materials().map(|m| material(&m)).collect();
        let mut scene = Self {
            meshes,
            materials,
            images,
            instances: Vec::new(),
            cameras: Vec::new(),
            lights: Vec::new(),
            bounds: Aabb::EMPTY,
            warnings: Vec::new(),
        };
        for (node, world) in ctx.node_transforms(&doc)? {
            scene.place(&node, world);
        }
        Ok(scene)
    }

    /// Adds what `node` carries (mesh instance, camera, light) at `world`.
    fn place(&mut self, node: &gltf::Node<'_>, world: Mat4) {
        if let Some(mesh) = node.mesh()
            && let Some(primitives) = self.meshes.get(mesh.index()).map(|m| &m.primitives)
        {
            for p in primitives {
                self.bounds = self.bounds.union(p.bounds.transformed(world));
            }
            self.instances.push(Instance {
                mesh: mesh.index(),
                world_from_mesh: world,
            });
        }
        if let Some(camera) = node.camera().and_then(|c| camera::camera_of(&c, world)) {
            self.cameras.push(camera);
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

    fn mesh(
        &self,
        mesh: &gltf::Mesh<'_>,
        buffers: &[gltf::buffer::Data],
    ) -> Result<Mesh, SceneError> {
        let name = mesh
            .name()
            .map_or_else(|| format!("#{}", mesh.index()), str::to_owned);
        let primitives = mesh
            .primitives()
            .enumerate()
            .map(|(i, p)| self.primitive(&name, i, &p, buffers))
            .collect::<Result<Vec<_>, _>>()?;
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
        if p.mode() != gltf::mesh::Mode::Triangles {
            return Err(SceneError::NotTriangles {
                path,
                mesh: mesh.to_owned(),
                primitive: index,
                mode: p.mode(),
            });
        }
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
        let normals: Vec<Vec3> = match reader.read_normals() {
            Some(it) => it.map(Vec3::from).collect(),
            None => flat_normals(&positions, &indices),
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
        let bounds = positions.iter().fold(Aabb::EMPTY, |b, &p| b.with_point(p));
        Ok(Primitive {
            positions,
            normals,
            uvs,
            uvs1: Vec::new(),
            colors: Vec::new(),
            tangents,
            indices,
            material: p.material().index(),
            bounds,
        })
    }

    fn image(&self, index: usize, data: gltf::image::Data) -> Result<Image, SceneError> {
        use gltf::image::Format;
        let px = data.width as usize * data.height as usize;
        let rgba8 = match data.format {
            Format::R8G8B8A8 => data.pixels,
            Format::R8G8B8 => data
                .pixels
                .chunks_exact(3)
                .flat_map(|c| [c[0], c[1], c[2], 255])
                .collect(),
            Format::R8G8 => data
                .pixels
                .chunks_exact(2)
                .flat_map(|c| [c[0], c[1], 0, 255])
                .collect(),
            Format::R8 => data.pixels.iter().flat_map(|&c| [c, c, c, 255]).collect(),
            format => {
                return Err(SceneError::ImageFormat {
                    path: self.path.to_path_buf(),
                    image: index,
                    format,
                });
            }
        };
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

/// Face normals for primitives without a NORMAL attribute (vertices shared by faces get the
/// last face's normal).
fn flat_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
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

fn texture_ref(info: Option<gltf::texture::Info<'_>>) -> Option<TextureRef> {
    info.map(|t| TextureRef {
        tex_coord: t.tex_coord(),
        ..TextureRef::new(t.texture().source().index())
    })
}

fn material(m: &gltf::Material<'_>) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let normal = m.normal_texture();
    let occlusion = m.occlusion_texture();
    Material {
        name: m.name().unwrap_or("").to_owned(),
        base_color: Vec4::from(pbr.base_color_factor()),
        base_color_texture: texture_ref(pbr.base_color_texture()),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: texture_ref(pbr.metallic_roughness_texture()),
        normal_scale: normal.as_ref().map_or(1.0, |n| n.scale()),
        normal_texture: normal.map(|t| TextureRef {
            tex_coord: t.tex_coord(),
            ..TextureRef::new(t.texture().source().index())
        }),
        occlusion_strength: occlusion.as_ref().map_or(1.0, |o| o.strength()),
        occlusion_texture: occlusion.map(|t| TextureRef {
            tex_coord: t.tex_coord(),
            ..TextureRef::new(t.texture().source().index())
        }),
        emissive: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        emissive_texture: texture_ref(m.emissive_texture()),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: m.alpha_cutoff().unwrap_or(0.5),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        double_sided: m.double_sided(),
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
