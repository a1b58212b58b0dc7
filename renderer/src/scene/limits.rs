//! Whether a [`Scene`] can be uploaded to a device: every index it holds points at something,
//! and every image and buffer fits the device's limits. Checked before anything is allocated, so
//! a scene the device cannot hold is a [`SceneError`], never a wgpu validation panic.

use super::{Material, Scene, SceneError, TextureRef};

impl Scene {
    /// Checks that the scene is consistent (instances name meshes, primitives name materials,
    /// textures name images, attributes match) and fits `limits`.
    pub fn check_for_device(&self, limits: &wgpu::Limits) -> Result<(), SceneError> {
        self.check_references()?;
        for (i, image) in self.images.iter().enumerate() {
            let largest = image.width.max(image.height);
            if image.width == 0 || image.height == 0 {
                return Err(SceneError::Inconsistent(format!(
                    "image {i} is {}x{} pixels",
                    image.width, image.height
                )));
            }
            check_limit(
                &format!("image {i}'s side"),
                largest.into(),
                limits.max_texture_dimension_2d.into(),
                "scale the image down",
            )?;
        }
        for mesh in &self.meshes {
            for (p, primitive) in mesh.primitives.iter().enumerate() {
                let bytes = [
                    size_of_val(primitive.positions.as_slice()),
                    size_of_val(primitive.normals.as_slice()),
                    size_of_val(primitive.uvs.as_slice()),
                    size_of_val(primitive.tangents.as_slice()),
                    size_of_val(primitive.indices.as_slice()),
                ];
                let largest = bytes.into_iter().max().unwrap_or(0);
                check_limit(
                    &format!(
                        "mesh `{}` primitive {p}'s largest vertex buffer (bytes)",
                        mesh.name
                    ),
                    largest as u64,
                    limits.max_buffer_size,
                    "split the mesh",
                )?;
            }
        }
        Ok(())
    }

    fn check_references(&self) -> Result<(), SceneError> {
        let bad = |what: String| Err(SceneError::Inconsistent(what));
        for (i, instance) in self.instances.iter().enumerate() {
            if instance.mesh >= self.meshes.len() {
                return bad(format!(
                    "instance {i} names mesh {} of {}",
                    instance.mesh,
                    self.meshes.len()
                ));
            }
        }
        for mesh in &self.meshes {
            for (p, primitive) in mesh.primitives.iter().enumerate() {
                let n = primitive.positions.len();
                let lengths = [
                    primitive.normals.len(),
                    primitive.uvs.len(),
                    primitive.tangents.len(),
                ];
                if lengths.iter().any(|&l| l != n) {
                    return bad(format!(
                        "mesh `{}` primitive {p} has {n} positions but {lengths:?} normals, \
                         UVs and tangents",
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
                    && m >= self.materials.len()
                {
                    return bad(format!(
                        "mesh `{}` primitive {p} names material {m} of {}",
                        mesh.name,
                        self.materials.len()
                    ));
                }
            }
        }
        for material in &self.materials {
            if let Some(t) = textures(material).find(|t| t.image >= self.images.len()) {
                return bad(format!(
                    "material `{}` samples image {} of {}",
                    material.name,
                    t.image,
                    self.images.len()
                ));
            }
        }
        Ok(())
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
