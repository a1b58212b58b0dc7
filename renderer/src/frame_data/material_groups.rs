//! A scene's materials on the GPU: one storage buffer of `GpuMaterial` records and the material
//! atlas of their textures (`scene::MaterialAtlas`), bound once as group 2 of every geometry
//! program: the forward and G-buffer programs' layout, and the masked pre-Z and shadow-caster
//! programs' own. A draw's record names its material, so no draw has a bind group of its own.

use codegen::rt::Variant;
use shader_bind::{GroupResources as _, Resources};
use shaders_gen::forward::forward;
use shaders_gen::shared::material_table::{self, GpuMaterial, NO_TEXTURE};
use wgpu::util::DeviceExt as _;

use super::material_inputs::uv_map;
use crate::scene::{
    AlphaMode, AtlasGrowth, AtlasKey, Image, Material, MaterialAtlas, SceneError, TextureRef,
};
use crate::shader::bind_group_layout_entries;

/// The forward variant the scene's draw-record (group 1) and material (group 2) layouts are
/// made from: groups 1 and 2 are the same in every forward variant.
#[expect(
    clippy::expect_used,
    reason = "the naive, opaque, plain forward variant is never excluded"
)]
pub(super) fn forward_variant() -> &'static Variant {
    forward::variant(forward::VariantKey {
        list: forward::List::List0,
        blend: false,
        scalarize: false,
        // The forward programs (the visibility kernels are `msaa` above 0).
        msaa: forward::Msaa::Msaa0,
        vis64: false,
    })
    .expect("the naive, opaque, plain forward variant always exists")
}

/// The bind-group layouts of the scene's draw-record and material groups, with the variants
/// they are made from (which number the groups' bindings).
#[derive(Debug, Clone)]
pub(super) struct SceneLayouts {
    pub(super) draw: wgpu::BindGroupLayout,
    material: wgpu::BindGroupLayout,
    mask_material: wgpu::BindGroupLayout,
    forward: &'static Variant,
    mask: &'static Variant,
}

impl SceneLayouts {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        use shaders_gen::forward::prez;
        let layout = |variant: &Variant, group: u32| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(variant.module),
                entries: &bind_group_layout_entries(variant, group),
            })
        };
        // Group 2 of the masked pre-Z (and masked shadow casters) besides the forward one.
        let forward = forward_variant();
        let mask = prez::variant(prez::VariantKey { alpha_mask: true });
        Self {
            draw: layout(forward, 1),
            material: layout(forward, 2),
            mask_material: layout(mask, 2),
            forward,
            mask,
        }
    }
}

/// Every material's record and texture, and the two bind groups that reach them.
#[derive(Debug, Clone)]
pub(super) struct MaterialTable {
    pub(super) atlas: std::sync::Arc<MaterialAtlas>,
    records: wgpu::Buffer,
    /// Records the buffer has room for.
    capacity: usize,
    /// Group 2 of the forward and G-buffer programs.
    pub(super) group: wgpu::BindGroup,
    /// Group 2 of the masked pre-Z and masked shadow-caster programs.
    pub(super) mask_group: wgpu::BindGroup,
}

impl MaterialTable {
    /// Packs every texture of `materials` into a new atlas and writes their records, with room
    /// for twice as many.
    pub(super) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &SceneLayouts,
        images: &[std::sync::Arc<Image>],
        (materials, programs): (&[Material], &[u32]),
    ) -> Result<Self, SceneError> {
        let keys: Vec<AtlasKey> = materials.iter().flat_map(atlas_keys).collect();
        let atlas = MaterialAtlas::new(device, queue, images, &keys)
            .map_err(|e| SceneError::Inconsistent(format!("material textures: {e}")))?;
        let capacity = (materials.len() * 2).max(8);
        let mut records: Vec<GpuMaterial> = materials
            .iter()
            .enumerate()
            .map(|(index, m)| material_record(m, index, programs[index], &atlas))
            .collect();
        records.resize(capacity, bytemuck::Zeroable::zeroed());
        let records = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("materials"),
            contents: bytemuck::cast_slice(&records),
            // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
        });
        let (group, mask_group) = groups(device, layouts, &records, &atlas)
            .map_err(|e| SceneError::Inconsistent(format!("material group: {e}")))?;
        Ok(Self {
            group,
            mask_group,
            atlas: std::sync::Arc::new(atlas),
            records,
            capacity,
        })
    }

    /// Writes `material`'s record at `index` in place, adding its textures to the atlas in
    /// place where it does not hold them, or returns `false` when that needs a new table (no
    /// room for the record, or an image larger than an atlas page).
    pub(super) fn write(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (layouts, images): (&SceneLayouts, &[std::sync::Arc<Image>]),
        index: usize,
        (material, program): (&Material, u32),
    ) -> bool {
        if index >= self.capacity {
            return false;
        }
        let keys: Vec<AtlasKey> = atlas_keys(material).collect();
        if !keys.iter().all(|k| self.atlas.index(k).is_some()) {
            let mut atlas = (*self.atlas).clone();
            match atlas.add(device, queue, images, &keys) {
                Ok(AtlasGrowth::Held) => {}
                Ok(AtlasGrowth::Grown) => {
                    // A group that cannot be bound: the new table reports why.
                    let Ok(built) = groups(device, layouts, &self.records, &atlas) else {
                        return false;
                    };
                    (self.group, self.mask_group) = built;
                    self.atlas = std::sync::Arc::new(atlas);
                }
                // Packing anew reports what the device cannot hold.
                Ok(AtlasGrowth::NeedsRepack) | Err(_) => return false,
            }
        }
        let record = material_record(material, index, program, &self.atlas);
        let offset = (index * size_of::<GpuMaterial>()) as u64;
        queue.write_buffer(&self.records, offset, bytemuck::bytes_of(&record));
        true
    }
}

impl MaterialTable {
    /// Releases the atlas's textures that no material of `materials` samples: later
    /// materials' textures take their room. Returns how many were released.
    pub(super) fn release_unused(&mut self, materials: &[Material]) -> usize {
        let in_use: std::collections::HashSet<AtlasKey> =
            materials.iter().flat_map(atlas_keys).collect();
        if self.atlas.usage().0 == in_use.len() {
            return 0;
        }
        std::sync::Arc::make_mut(&mut self.atlas).release(&in_use)
    }
}

impl MaterialTable {
    /// Group 2 (records and atlas) of `program`, whose layout differs from the geometry
    /// passes' (a compute program's).
    pub(super) fn group_for(
        &self,
        device: &wgpu::Device,
        program: &crate::shader::ShaderProgram,
    ) -> Result<wgpu::BindGroup, shader_bind::BindError> {
        let mut resources = Resources::new();
        let table = material_table::Group2 {
            materials: self.records.as_entire_buffer_binding(),
        };
        table.collect(&mut resources);
        self.atlas.bindings().collect(&mut resources);
        program.bind_group(
            device,
            material_table::Group2::GROUP,
            &resources,
            "materials",
        )
    }
}

/// Group 2 of the forward and G-buffer programs, and of the masked depth programs: the
/// `material_table` library's records and the `material_atlas` library's atlas, collected by
/// binding name and numbered from each layout's variant.
fn groups(
    device: &wgpu::Device,
    layouts: &SceneLayouts,
    records: &wgpu::Buffer,
    atlas: &MaterialAtlas,
) -> Result<(wgpu::BindGroup, wgpu::BindGroup), shader_bind::BindError> {
    let mut resources = Resources::new();
    let table = material_table::Group2 {
        materials: records.as_entire_buffer_binding(),
    };
    table.collect(&mut resources);
    atlas.bindings().collect(&mut resources);
    let group = material_table::Group2::GROUP;
    Ok((
        resources.build(
            device,
            &layouts.material,
            layouts.forward,
            group,
            "materials",
        )?,
        resources.build(
            device,
            &layouts.mask_material,
            layouts.mask,
            group,
            "materials (masked depth)",
        )?,
    ))
}

/// The five texture slots of `m` in `GpuMaterial` order (base colour, normal,
/// metallic-roughness, occlusion, emissive), each with whether it holds sRGB colour.
fn texture_slots(m: &Material) -> [(Option<TextureRef>, bool); 5] {
    [
        (m.base_color_texture, true),
        (m.normal_texture, false),
        (m.metallic_roughness_texture, false),
        (m.occlusion_texture, false),
        (m.emissive_texture, true),
    ]
}

/// Each texture reference of `m` as the atlas keys it.
fn atlas_keys(m: &Material) -> impl Iterator<Item = AtlasKey> {
    texture_slots(m)
        .into_iter()
        .filter_map(|(t, colour)| t.map(|t| key(t, colour)))
}

fn key(t: TextureRef, colour: bool) -> AtlasKey {
    AtlasKey {
        image: t.image,
        sampler: t.sampler,
        colour,
    }
}

/// The `GpuMaterial` record of `m`, material `index` (the alpha cutoff is 0 unless the material
/// is masked), with each texture's UV set, transform and atlas index, where its parameter
/// record is (at its own index, `material_params`) and the number of its material program in
/// the scene (`program`: 0 for glTF PBR).
pub fn material_record(
    m: &Material,
    index: usize,
    program: u32,
    atlas: &MaterialAtlas,
) -> GpuMaterial {
    let cutoff = match m.alpha_mode {
        AlphaMode::Mask { cutoff } => cutoff,
        _ => 0.0,
    };
    let [base_color, normal, metallic_roughness, occlusion, emissive] =
        texture_slots(m).map(|(t, colour)| {
            t.and_then(|t| atlas.index(&key(t, colour)))
                .unwrap_or(NO_TEXTURE)
        });
    GpuMaterial::new(
        m.base_color,
        m.emissive,
        m.metallic,
        m.roughness,
        m.normal_scale,
        m.occlusion_strength,
        cutoff,
        uv_map(m.base_color_texture),
        uv_map(m.normal_texture),
        uv_map(m.metallic_roughness_texture),
        uv_map(m.occlusion_texture),
        uv_map(m.emissive_texture),
        base_color,
        normal,
        metallic_roughness,
        occlusion,
        emissive,
        u32::from(m.double_sided),
        index as u32,
        program,
    )
}
