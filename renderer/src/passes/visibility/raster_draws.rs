//! Recording the visibility raster pass's draws (`super::raster`): its render pass over the
//! depth target (and the hardware raster's ID target) and the scene's batches, drawn through
//! the sequence index buffer.

use std::sync::Arc;

use crate::frame_data::{InstanceTable, SceneDrawList};
use crate::graph::{Handle, PassContext, Texture};
use crate::passes::{BatchState, FacePipelines, SceneDraws, face_pipeline};
use crate::scene::VertexStreams;

/// What one frame's visibility pass records with.
pub(crate) struct Recording {
    pub(crate) plain: FacePipelines,
    pub(crate) masked: FacePipelines,
    pub(crate) scene: Arc<crate::frame_data::PreparedScene>,
    pub(crate) instances: Arc<InstanceTable>,
    pub(crate) camera: wgpu::BindGroup,
    /// The masked program's group 0 (with the compute rasteriser's buffer under it).
    pub(crate) mask_camera: wgpu::BindGroup,
    /// Group 3 of the plain and the masked programs.
    pub(crate) geometry: wgpu::BindGroup,
    pub(crate) mask_geometry: wgpu::BindGroup,
    pub(crate) sequence: wgpu::Buffer,
    pub(crate) list: SceneDrawList,
    pub(crate) targets: RasterTargets,
}

/// What a recording draws into, and which batches.
pub(crate) struct RasterTargets {
    pub(crate) depth: Handle<Texture>,
    /// The ID target (the hardware raster's; none under the compute rasteriser).
    pub(crate) ids: Option<Handle<Texture>>,
    /// The depth target's load and store: cleared and stored (the first half), loaded and
    /// stored (the second), or a scratch target neither loaded nor stored (the masked draws
    /// under the compute raster).
    pub(crate) depth_ops: (wgpu::LoadOp<f32>, wgpu::StoreOp),
    /// Under the compute raster: the opaque batches are the compute rasteriser's.
    pub(crate) masked_only: bool,
}

impl Recording {
    /// Draws every batch of its list (only the masked ones, into the compute raster's buffer,
    /// under the compute raster), through the sequence index buffer; the IDs are loaded.
    pub(crate) fn record(&self, ctx: &mut PassContext<'_>) {
        let depth_view = ctx
            .texture(self.targets.depth)
            .create_view(&Default::default());
        let ids_view = self
            .targets
            .ids
            .map(|ids| ctx.texture(ids).create_view(&Default::default()));
        let ids_attachment = ids_view
            .as_ref()
            .map(|view| wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    // Never cleared: a sample no triangle covers keeps an old ID, and its
                    // cleared depth (1.0) tells every reader it is sky. On chips whose
                    // fixed-function fill is slow, the clear cost a quarter of the pass
                    // (0.59 of 2.26 ms at MSAA 4 on the H200; BENCHMARKS.md).
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            });
        let mut pass = ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
            label: Some("visibility"),
            color_attachments: if ids_attachment.is_some() {
                std::slice::from_ref(&ids_attachment)
            } else {
                &[]
            },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: self.targets.depth_ops.0,
                    store: self.targets.depth_ops.1,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let mut draws = SceneDraws::new(
            &mut pass,
            &self.scene,
            &self.instances,
            VertexStreams::Position,
        );
        // Drawn through the sequence: `vertex_index` is the position in the index buffer (plus
        // the base vertex), from which the shader pulls the vertex.
        draws
            .pass()
            .set_index_buffer(self.sequence.slice(..), wgpu::IndexFormat::Uint32);
        draws.draw_batches_with(&self.list, &self.instances, |batch| {
            if self.targets.masked_only && !batch.masked {
                return None;
            }
            let (pipelines, group0, group3) = if batch.masked {
                (&self.masked, &self.mask_camera, &self.mask_geometry)
            } else {
                (&self.plain, &self.camera, &self.geometry)
            };
            Some(BatchState {
                pipeline: face_pipeline(pipelines, batch.double_sided, batch.mirrored),
                group2: batch.masked.then(|| self.scene.mask_group()),
                program_groups: Some((group0, Some(group3))),
            })
        });
    }
}
