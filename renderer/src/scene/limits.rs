//! Whether a [`Scene`] can be uploaded to a device: every index it holds points at something,
//! and every image and buffer fits the device's limits. Checked before anything is allocated, so
//! a scene the device cannot hold is a [`SceneError`], never a wgpu validation panic.

use super::{Image, Material, Mesh, Scene, SceneError, TextureRef};

impl Scene {
    /// Checks that the scene is consistent (instances name meshes, primitives name materials,
    /// textures name images, attributes match) and fits `limits`.
    pub fn check_for_device(&self, limits: &wgpu::Limits) -> Result<(), SceneError> {
        self.check_references()?;
        for (i, image) in self.images.iter().enumerate() {
            check_image(i, image, limits)?;
        }
        let primitives = || self.meshes.iter().flat_map(|m| &m.primitives);
        let vertices: u64 = primitives().map(|p| p.positions.len() as u64).sum();
        let indices: u64 = primitives().map(|p| p.indices.len() as u64).sum();
        check_geometry(vertices, indices, limits)?;
        // One draw record per primitive of every instance, in one storage binding.
        let draws: u64 = self
            .instances
            .iter()
            .map(|i| self.meshes[i.mesh].primitives.len() as u64)
            .sum();
        check_limit(
            "the scene's draw records (bytes, one per primitive of every instance)",
            draws * size_of::<shaders_gen::forward::forward::Draw>() as u64,
            limits
                .max_storage_buffer_binding_size
                .min(limits.max_buffer_size),
            "split the scene",
        )?;
        Ok(())
    }

    fn check_references(&self) -> Result<(), SceneError> {
        for (i, instance) in self.instances.iter().enumerate() {
            if instance.mesh >= self.meshes.len() {
                return Err(SceneError::Inconsistent(format!(
                    "instance {i} names mesh {} of {}",
                    instance.mesh,
                    self.meshes.len()
                )));
            }
        }
        for mesh in &self.meshes {
            check_mesh(mesh, self.materials.len())?;
        }
        for material in &self.materials {
            check_material(material, self.images.len())?;
        }
        Ok(())
    }
}

/// Checks that image `i` has pixels and fits `limits`.
pub(crate) fn check_image(
    i: usize,
    image: &Image,
    limits: &wgpu::Limits,
) -> Result<(), SceneError> {
    if image.width == 0 || image.height == 0 {
        return Err(SceneError::Inconsistent(format!(
            "image {i} is {}x{} pixels",
            image.width, image.height
        )));
    }
    check_limit(
        &format!("image {i}'s side"),
        image.width.max(image.height).into(),
        limits.max_texture_dimension_2d.into(),
        "scale the image down",
    )
}

/// Checks that `vertices` and `indices`, every mesh's together, fit one buffer per attribute
/// (the widest is 16 bytes a vertex) and one index buffer (`GpuScene`).
pub(crate) fn check_geometry(
    vertices: u64,
    indices: u64,
    limits: &wgpu::Limits,
) -> Result<(), SceneError> {
    check_limit(
        "the scene's widest vertex stream (bytes, every mesh together)",
        vertices * size_of::<glam::Vec4>() as u64,
        limits.max_buffer_size,
        "split the scene",
    )?;
    check_limit(
        "the scene's index buffer (bytes, every mesh together)",
        indices * size_of::<u32>() as u64,
        limits.max_buffer_size,
        "split the scene",
    )
}

/// Checks that `mesh`'s attributes match, its indices name its vertices and its primitives
/// name one of `materials` materials.
pub(crate) fn check_mesh(mesh: &Mesh, materials: usize) -> Result<(), SceneError> {
    let bad = |what: String| Err(SceneError::Inconsistent(what));
    for (p, primitive) in mesh.primitives.iter().enumerate() {
        let n = primitive.positions.len();
        let lengths = [
            primitive.normals.len(),
            primitive.uvs.len(),
            primitive.tangents.len(),
        ];
        if lengths.iter().any(|&l| l != n) {
            return bad(format!(
                "mesh `{}` primitive {p} has {n} positions but {lengths:?} normals, UVs and \
                 tangents",
                mesh.name
            ));
        }
        let optional = [
            ("TEXCOORD_1", primitive.uvs1.len()),
            ("COLOR_0", primitive.colors.len()),
        ];
        if let Some((name, l)) = optional.iter().find(|(_, l)| *l != 0 && *l != n) {
            return bad(format!(
                "mesh `{}` primitive {p} has {n} positions but {l} {name} values",
                mesh.name
            ));
        }
        if let Some(&index) = primitive.indices.iter().find(|&&i| i as usize >= n) {
            return bad(format!(
                "mesh `{}` primitive {p} uses vertex {index} of {n}",
                mesh.name
            ));
        }
        if let Some(m) = primitive.material
            && m >= materials
        {
            return bad(format!(
                "mesh `{}` primitive {p} names material {m} of {materials}",
                mesh.name
            ));
        }
    }
    Ok(())
}

/// Checks that `material`'s textures name one of `images` images.
pub(crate) fn check_material(material: &Material, images: usize) -> Result<(), SceneError> {
    match textures(material).find(|t| t.image >= images) {
        Some(t) => Err(SceneError::Inconsistent(format!(
            "material `{}` samples image {} of {images}",
            material.name, t.image
        ))),
        None => Ok(()),
    }
}

fn textures(m: &Material) -> impl Iterator<Item = TextureRef> {
    [
        m.base_color_texture,
        m.metallic_roughness_texture,
        m.normal_texture,
        m.occlusion_texture,
        m.emissive_texture,
    ]
    .into_iter()
    .flatten()
}

fn check_limit(what: &str, value: u64, limit: u64, advice: &'static str) -> Result<(), SceneError> {
    if value > limit {
        return Err(SceneError::DeviceLimit {
            what: what.to_owned(),
            value,
            limit,
            advice,
        });
    }
    Ok(())
}
