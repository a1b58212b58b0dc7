//! Which texture-coordinate set each texture samples, checked per (primitive, material): a
//! texture's `texCoord` belongs to the material, the sets to the primitive. A set the
//! primitive lacks is invalid glTF; the loader warns and the texture samples `TEXCOORD_0`
//! there (a primitive without `TEXCOORD_1` draws with its `TEXCOORD_0` in that stream). Sets
//! 2 and up are not loaded: references to them become set 0, with a warning.

use super::{Material, Scene, SceneWarning, TextureRef, modes};

/// Every texture reference of `m`.
fn refs_mut(m: &mut Material) -> [&mut Option<TextureRef>; 5] {
    [
        &mut m.base_color_texture,
        &mut m.metallic_roughness_texture,
        &mut m.normal_texture,
        &mut m.occlusion_texture,
        &mut m.emissive_texture,
    ]
}

/// The sets (1 and up, each once, ascending) that the textures of `m` sample.
fn sets(m: &Material) -> Vec<u32> {
    let mut sets: Vec<u32> = [
        m.base_color_texture,
        m.metallic_roughness_texture,
        m.normal_texture,
        m.occlusion_texture,
        m.emissive_texture,
    ]
    .iter()
    .flatten()
    .map(|t| t.tex_coord)
    .filter(|&s| s > 0)
    .collect();
    sets.sort_unstable();
    sets.dedup();
    sets
}

fn material_name(m: &Material, index: usize) -> String {
    if m.name.is_empty() {
        format!("#{index}")
    } else {
        m.name.clone()
    }
}

impl Scene {
    /// Warns about every drawn primitive of `doc` whose material samples a set the primitive
    /// lacks, and about sets the renderer does not load; then points references to sets 2 and
    /// up at set 0, so every [`TextureRef::tex_coord`] is 0 or 1.
    pub(super) fn check_uv_sets(&mut self, doc: &gltf::Document) {
        let mut unsupported: Vec<(usize, u32)> = Vec::new();
        for mesh in doc.meshes() {
            let Some(loaded) = self.meshes.get(mesh.index()) else {
                continue;
            };
            if loaded.primitives.is_empty() {
                continue;
            }
            let name = loaded.name.clone();
            for p in mesh
                .primitives()
                .filter(|p| modes::undrawn(p.mode()).is_none())
            {
                let Some((mi, material)) = p
                    .material()
                    .index()
                    .and_then(|i| self.materials.get(i).map(|m| (i, m)))
                else {
                    continue;
                };
                for set in sets(material) {
                    let has = p.get(&gltf::Semantic::TexCoords(set)).is_some();
                    if !has {
                        self.warnings.push(SceneWarning::MissingTexCoord {
                            mesh: name.clone(),
                            primitive: p.index(),
                            material: material_name(material, mi),
                            set,
                        });
                    } else if set >= 2 && !unsupported.contains(&(mi, set)) {
                        unsupported.push((mi, set));
                        self.warnings.push(SceneWarning::UnsupportedTexCoord {
                            material: material_name(material, mi),
                            set,
                        });
                    }
                }
            }
        }
        for m in &mut self.materials {
            for t in refs_mut(m).into_iter().flatten() {
                if t.tex_coord >= 2 {
                    t.tex_coord = 0;
                }
            }
        }
    }
}
