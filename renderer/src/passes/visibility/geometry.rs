//! The `vis_geometry` library's group 3: where each draw's triangles are (`DRAW_GEOMETRY`,
//! kept by the raster pass from the instance table) and the scene's index and vertex streams,
//! and the sequence index buffer the raster pass draws through.

use shaders_gen::visibility::geometry::vis_geometry;
use wgpu::util::DeviceExt as _;

use crate::frame_data::{InstanceTable, PreparedScene};
use crate::shader::ShaderProgram;

/// The per-draw records of `instances`, in draw order: first index, base vertex, first
/// triangle (the triangles of the draws before it) and triangle count.
pub(super) fn draw_geometry(instances: &InstanceTable) -> Vec<vis_geometry::DrawGeometry> {
    let mut first_triangle = 0u32;
    instances
        .draws
        .iter()
        .map(|d| {
            let g = d.geometry;
            let triangles = g.index_count / 3;
            let record = vis_geometry::DrawGeometry::new(
                g.first_index,
                g.base_vertex as u32,
                first_triangle,
                triangles,
            );
            first_triangle = first_triangle.saturating_add(triangles);
            record
        })
        .collect()
}

/// The triangle directory `triangle_of` narrows its search with, to follow `records`: for
/// each block of `1 << TRIANGLE_BLOCK_SHIFT` triangle IDs, and one past the last, a record
/// whose `first_index` is the last draw whose first triangle is at or before the block's first.
pub(super) fn triangle_directory(
    records: &[vis_geometry::DrawGeometry],
) -> Vec<vis_geometry::DrawGeometry> {
    let shift = vis_geometry::TRIANGLE_BLOCK_SHIFT;
    let triangles = records
        .last()
        .map_or(0, |r| r.first_triangle.saturating_add(r.triangle_count));
    let blocks = (triangles >> shift) + 2;
    (0..blocks)
        .map(|b| {
            let first = b.saturating_mul(1 << shift);
            let after = records.partition_point(|r| r.first_triangle <= first);
            let draw = after.saturating_sub(1) as u32;
            vis_geometry::DrawGeometry::new(draw, 0, 0, 0)
        })
        .collect()
}

/// A storage buffer holding `records` and their triangle directory (one record at least: a
/// binding is never empty).
pub(super) fn draw_geometry_buffer(
    device: &wgpu::Device,
    records: &[vis_geometry::DrawGeometry],
) -> wgpu::Buffer {
    let mut contents = records.to_vec();
    contents.extend(triangle_directory(records));
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("visibility draw geometry"),
        contents: bytemuck::cast_slice(&contents),
        // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    })
}

/// An index buffer of `0..count`: drawn through it, an indexed draw's `vertex_index` is its
/// position in the scene's index buffer plus its base vertex.
pub(super) fn sequence_buffer(device: &wgpu::Device, count: u32) -> wgpu::Buffer {
    let indices: Vec<u32> = (0..count.max(1)).collect();
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("visibility sequence indices"),
        contents: bytemuck::cast_slice(&indices),
        usage: wgpu::BufferUsages::INDEX,
    })
}

/// Group 3 of `program` (a `vis_raster` or `vis_shade` variant): `draw_geometry` and the
/// scene's streams, through the library's generated builder.
pub(crate) fn geometry_group(
    device: &wgpu::Device,
    program: &ShaderProgram,
    scene: &PreparedScene,
    draw_geometry: &wgpu::Buffer,
) -> Result<wgpu::BindGroup, shader_bind::BindError> {
    let g = &scene.gpu.geometry;
    let part = vis_geometry::Group3 {
        draw_geometry: draw_geometry.as_entire_buffer_binding(),
        scene_indices: g.indices.as_entire_buffer_binding(),
        positions: g.positions.as_entire_buffer_binding(),
        normals: g.normals.as_entire_buffer_binding(),
        tangents: g.tangents.as_entire_buffer_binding(),
        uv0: g.uvs.as_entire_buffer_binding(),
        uv1: g.uvs1.as_entire_buffer_binding(),
        colors: g.colors.as_entire_buffer_binding(),
    };
    program.bind_group(
        device,
        vis_geometry::Group3::GROUP,
        &shader_bind::Resources::of(&part),
        "visibility geometry",
    )
}

/// What the pass keeps between frames for the scene it last drew: the draws' geometry records
/// (rebuilt when a draw's triangles change, not when an instance only moves) and the sequence
/// index buffer (grown with the scene's index buffer).
#[derive(Debug, Default)]
pub(super) struct SceneState {
    /// Scene id, instance table id and revision the records were checked at.
    pub(super) key: Option<(u32, u32, u64)>,
    pub(super) records: Vec<vis_geometry::DrawGeometry>,
    /// `records` on the GPU.
    pub(super) draw_geometry: Option<wgpu::Buffer>,
    pub(super) sequence: Option<(wgpu::Buffer, u64)>,
}

impl SceneState {
    /// Whether the kept records still describe `table` of scene `scene`: the same scene and
    /// table, as many draws, and every draw of an instance changed since the kept revision
    /// still where it was (moving, restyling or removing an instance keeps its triangles; a
    /// reused slot takes a mesh of the same geometry only if the records say so).
    pub(super) fn still_valid(&self, scene: u32, table: &InstanceTable) -> bool {
        let Some((kept_scene, kept_table, revision)) = self.key else {
            return false;
        };
        if kept_scene != scene
            || kept_table != table.id()
            || self.records.len() != table.draws.len()
        {
            return false;
        }
        let Some(changed) = table.changed_since(revision) else {
            return false;
        };
        changed.iter().all(|&i| {
            table.states[i].draws().all(|d| {
                let g = table.draws[d].geometry;
                self.records.get(d).is_some_and(|kept| {
                    kept.first_index == g.first_index
                        && kept.base_vertex == g.base_vertex as u32
                        && kept.triangle_count == g.index_count / 3
                })
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The directory's draw for each block is the last draw whose first triangle is at or
    /// before the block's first ID, found here by a walk over every draw; draws without
    /// triangles (several draws at one first triangle) included.
    #[test]
    fn the_triangle_directory_names_the_draw_of_each_blocks_first_triangle() {
        let block = 1u32 << vis_geometry::TRIANGLE_BLOCK_SHIFT;
        let counts = [0, 5, block, 0, 0, 3 * block + 7, 1, 0, 2, block - 1, 0];
        let mut first = 0;
        let records: Vec<_> = counts
            .iter()
            .map(|&n| {
                let r = vis_geometry::DrawGeometry::new(0, 0, first, n);
                first += n;
                r
            })
            .collect();
        let directory = triangle_directory(&records);
        assert_eq!(directory.len() as u32, first / block + 2);
        for (b, entry) in directory.iter().enumerate() {
            let start = b as u32 * block;
            let walked = (0..records.len())
                .rfind(|&d| records[d].first_triangle <= start)
                .unwrap_or(0);
            assert_eq!(entry.first_index, walked as u32, "block {b}");
        }
    }
}
