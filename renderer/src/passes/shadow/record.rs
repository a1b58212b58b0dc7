//! Recording a frame's shadow work: per chunk of work items, the culling dispatch, then the
//! static cache's pass and the shadow atlas's pass, each starting its regions (clears and
//! static-cache copies) and then drawing the casters: two multi-draws per item where the GPU
//! culled them, one draw per cast where the CPU listed them.

use std::sync::Arc;

use super::super::SceneDraws;
use super::culling::CullDispatches;
use super::gpu::CasterPipelines;
use super::work::{CastList, Start, WorkItem};
use crate::frame_data::PreparedScene;
use crate::graph::{PassEncoder, TimedPass};
use crate::scene::{AlphaMode, VertexStreams};
use crate::shadow::atlas::AtlasRect;

/// Where a frame's casts come from.
pub enum CastSource {
    /// Culled on the GPU, chunk by chunk: each work item draws its run of `dispatches.stride`
    /// argument slots, the first `opaque` with the opaque pipeline, the rest masked.
    Culled {
        dispatches: CullDispatches,
        args: wgpu::Buffer,
        opaque: u32,
    },
    /// Listed on the CPU, drawn one by one: per item, its first cast and count.
    Listed(Arc<CastList>),
}

/// What the recording of one frame needs.
pub struct Recording {
    pub items: Vec<WorkItem>,
    pub casts: CastSource,
    pub scene: Arc<PreparedScene>,
    pub instances: Arc<crate::frame_data::InstanceTable>,
    pub caster: CasterPipelines,
    pub clear: wgpu::RenderPipeline,
    pub copy: wgpu::RenderPipeline,
    pub caster_group: wgpu::BindGroup,
    pub copy_group: Option<wgpu::BindGroup>,
    pub static_atlas: Option<wgpu::TextureView>,
}

impl Recording {
    /// Records the work items in order: per chunk of GPU-culled work, the culling dispatch,
    /// then the chunk's static-cache redraws, then its draws into the shadow atlas.
    pub fn record(&self, encoder: &mut PassEncoder<'_>, atlas: &wgpu::TextureView) {
        match &self.casts {
            CastSource::Culled { dispatches, .. } => {
                dispatches.clear_counts(encoder);
                for (c, chunk) in dispatches.chunks.iter().enumerate() {
                    dispatches.cull(encoder, c);
                    let range = chunk.start as usize..chunk.end as usize;
                    self.record_items(encoder, atlas, range);
                }
            }
            CastSource::Listed(_) => {
                self.record_items(encoder, atlas, 0..self.items.len());
            }
        }
    }

    /// Items `range` (a chunk's: its runs are numbered from `range.start`): the static
    /// cache's, then the shadow atlas's.
    fn record_items(
        &self,
        encoder: &mut PassEncoder<'_>,
        atlas: &wgpu::TextureView,
        range: std::ops::Range<usize>,
    ) {
        let chunk_start = range.start;
        let (into_static, into_atlas): (Vec<usize>, Vec<usize>) =
            range.partition(|&i| self.items[i].in_static_cache());
        let runs = [
            (into_static, self.static_atlas.as_ref()),
            (into_atlas, Some(atlas)),
        ];
        for (items, view) in runs {
            let Some(view) = view.filter(|_| !items.is_empty()) else {
                continue;
            };
            let label = if view == atlas {
                "shadow atlas"
            } else {
                "shadow static cache"
            };
            let mut pass = depth_pass(encoder, label, view);
            self.start_regions(&mut pass, &items);
            self.draw_casters(&mut pass, &items, chunk_start);
        }
    }

    /// Clears or copies the regions of `items` (indices into the frame's items), each
    /// pipeline set once.
    fn start_regions(&self, pass: &mut wgpu::RenderPass<'_>, items: &[usize]) {
        for copies in [false, true] {
            let mut set = false;
            for item in items.iter().map(|&i| &self.items[i]) {
                if (item.start == Start::CopyStatic) != copies {
                    continue;
                }
                if !set {
                    pass.set_pipeline(if copies { &self.copy } else { &self.clear });
                    if let Some(g) = self.copy_group.as_ref().filter(|_| copies) {
                        pass.set_bind_group(0, g, &[]);
                    }
                    set = true;
                }
                set_region(pass, item.rect);
                pass.draw(0..3, 0..1);
            }
        }
    }

    /// Draws the casters of `items` into their regions, after the regions started: the
    /// scene's streams, the caster group and each pipeline bound once per pass. Culled on the
    /// GPU, an item is two multi-draws (opaque, then masked casters, each of its run's part);
    /// listed, its casts one by one. Item `i`'s run is `i - chunk_start`.
    fn draw_casters<'a>(
        &'a self,
        pass: &mut wgpu::RenderPass<'a>,
        items: &[usize],
        chunk_start: usize,
    ) {
        pass.set_bind_group(0, &self.caster_group, &[]);
        let mask_group = Some(self.scene.mask_group());
        match &self.casts {
            CastSource::Culled {
                dispatches,
                args,
                opaque,
            } => {
                let parts = [
                    ((&self.caster.opaque, None), 0, *opaque),
                    (
                        (&self.caster.masked, mask_group),
                        *opaque,
                        dispatches.stride - opaque,
                    ),
                ];
                for (k, (state, offset, slots)) in parts.into_iter().enumerate() {
                    if slots == 0 {
                        continue;
                    }
                    let mut draws =
                        SceneDraws::new(pass, &self.scene, &self.instances, VertexStreams::Mask);
                    for &i in items {
                        let item = &self.items[i];
                        set_region(draws.pass(), item.rect);
                        let run = (i - chunk_start) as u64;
                        let at = run * u64::from(dispatches.stride) + u64::from(offset);
                        if dispatches.compact {
                            let count_at = 4 * (1 + 2 * i as u64 + k as u64);
                            let count = (&dispatches.counts, count_at);
                            draws.multi_draw_count(state, args, at, count, slots);
                        } else {
                            draws.multi_draw(state.0, state.1, args, at, slots);
                        }
                    }
                }
            }
            CastSource::Listed(list) => {
                let (casts, runs) = (&list.casts, &list.runs);
                let mut draws =
                    SceneDraws::new(pass, &self.scene, &self.instances, VertexStreams::Mask);
                for &i in items {
                    set_region(draws.pass(), self.items[i].rect);
                    let (first, count) = runs[i];
                    let listed = &casts[first as usize..(first + count) as usize];
                    for (cast, c) in (first..).zip(listed) {
                        let Some(draw) = self.instances.draws.get(c.draw as usize) else {
                            continue;
                        };
                        let masked = (self.scene.materials.get(draw.material))
                            .is_some_and(|m| matches!(m.alpha_mode, AlphaMode::Mask { .. }));
                        let (pipeline, group) = if masked {
                            (&self.caster.masked, mask_group)
                        } else {
                            (&self.caster.opaque, None)
                        };
                        draws.draw(pipeline, group, draw.geometry, cast);
                    }
                }
            }
        }
    }
}

fn set_region(pass: &mut wgpu::RenderPass<'_>, rect: AtlasRect) {
    let (x, y, s) = (rect.x as f32, rect.y as f32, rect.side as f32);
    pass.set_viewport(x, y, s, s, 0.0, 1.0);
    pass.set_scissor_rect(rect.x, rect.y, rect.side, rect.side);
}

/// A depth-only render pass over `view` that keeps its contents. (Clearing a whole atlas in
/// frames that redraw every region instead of a triangle per region was measured: −0.2 ms in
/// the city's spot-light frames, +0.18 ms in the courtyard's, so regions are cleared alone.)
fn depth_pass<'e>(
    encoder: &'e mut PassEncoder<'_>,
    label: &str,
    view: &wgpu::TextureView,
) -> TimedPass<'e, wgpu::RenderPass<'e>> {
    encoder.begin_render(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
