//! Scene culling on the GPU: before the geometry passes, one compute dispatch tests every
//! opaque and masked draw's world box against the main view's frustum and writes the result
//! into the indirect arguments the pre-Z, forward and G-buffer passes draw with
//! ([`FrameResources::scene_draws`]), one multi-draw per batch of a pipeline and a material.
//!
//! The layout ([`BatchLayout`]), the arguments and the boxes live on the GPU across frames:
//! a frame where nothing moved uploads the frustum and nothing else, so its CPU cost does not
//! grow with the scene. A moved instance rewrites its draws' boxes; one that becomes mirrored
//! or stops being so rebuilds the layout (its draws change pipeline).
//!
//! With [`crate::frame_data::RendererConfig::cull_draws`] off the dispatch does not run and
//! every slot draws: the same batches in the same order, so culling changes only which draws
//! run. A device without `INDIRECT_FIRST_INSTANCE` draws every slot directly.

mod blended;
mod compact;
pub mod occlusion;
mod view_draws;

use crate::frame_data::ConfigError;
pub use compact::{CompactKernels, Compaction};

use std::sync::Arc;

use shaders_gen::culling::instance_cull::{self, CullParams, Frustum};

use super::Pass;
use crate::GpuContext;
use crate::frame_data::{
    BlendedDraws, FrameInputs, FrameReport, FrameResources, OcclusionDraws, OcclusionPacked,
    RenderError, SceneDrawList, SceneDrawReport,
};
use crate::graph::{Buffer, BufferAccess, Handle, ImportAccess, RenderGraph};
use crate::readback_ring::ReadbackRing;
use blended::BlendedKernels;
use view_draws::{CullShared, ViewDraws};

/// The scene-culling pass.
#[derive(Debug)]
pub struct SceneCullPass {
    /// The program, the frustum parameters and the counter of slots drawn this frame.
    shared: CullShared,
    pipeline: wgpu::ComputePipeline,
    readback: ReadbackRing,
    /// The prepared scene's draws on the GPU (built on the first frame of a scene).
    draws: Option<ViewDraws>,
    /// Whether the device draws indirectly with a first instance.
    indirect: bool,
    /// Whether this frame runs the dispatch, and whether it is occlusion culling's first phase.
    culling: bool,
    occlusion: bool,
    /// The newest count that arrived, and its frame.
    last_visible: Option<(u64, u32)>,
    /// For polling the count's readback.
    device: wgpu::Device,
    /// The compaction kernels, where the device draws with counts from a buffer, and this
    /// frame's compaction of the culled slot lists (kept while the layout and lists hold).
    compact: Option<Arc<CompactKernels>>,
    compaction: Option<Arc<Compaction>>,
}

impl SceneCullPass {
    pub fn new(gpu: &GpuContext) -> Result<Self, RenderError> {
        let device = gpu.device();
        let variant = instance_cull::variant(instance_cull::VariantKey::ALL[0]);
        let program = gpu.program(variant)?;
        let pipeline = program.compute_pipeline(device, "cull_frustum")?;
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("scene cull params"),
            size: size_of::<CullParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let visible = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("scene draws visible"),
            size: 8,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let features = device.features();
        let compact = features
            .contains(
                wgpu::Features::MULTI_DRAW_INDIRECT_COUNT | wgpu::Features::INDIRECT_FIRST_INSTANCE,
            )
            .then(|| CompactKernels::new(gpu).map(Arc::new))
            .transpose()?;
        Ok(Self {
            compact,
            compaction: None,
            shared: CullShared {
                program,
                params,
                visible,
                blended: Arc::new(BlendedKernels::new(gpu)?),
            },
            pipeline,
            readback: ReadbackRing::new(device, "scene draws visible", 2),
            draws: None,
            indirect: device
                .features()
                .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
            culling: false,
            occlusion: false,
            last_visible: None,
            device: device.clone(),
        })
    }
}

impl Pass for SceneCullPass {
    fn name(&self) -> &'static str {
        "scene culling"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let gpu = &frame.gpu;
        let current = self.draws.take().filter(|d| d.follows(frame));
        let mut draws = match current {
            Some(mut d) => {
                // The same scene, perhaps with meshes and materials added since.
                d.scene = Arc::clone(&frame.scene);
                d.follow_instances(gpu, &self.shared, &frame.instances)?;
                d
            }
            None => ViewDraws::new(gpu, &self.shared, frame)?,
        };
        let c = &frame.config;
        self.culling = c.cull_draws && self.indirect && draws.layout.slot_count() > 0;
        self.occlusion = self.culling
            && c.occlusion_cull
            && c.path.has_prepass()
            && draws.layout.draw_count() >= c.occlusion_min_draws;
        if self.culling {
            draws.culled();
        } else {
            draws.draw_every_slot(gpu.queue());
        }
        self.compaction = self.compaction_for(gpu, &draws)?;
        let camera = &frame.camera;
        let [left, right, bottom, top, near, far] = camera.frustum_planes();
        let params = CullParams::new(
            Frustum::new(left, right, bottom, top, near, far),
            draws.layout.slot_count(),
            draws.slack(),
            u32::from(self.occlusion),
            0,
        );
        gpu.queue()
            .write_buffer(&self.shared.params, 0, bytemuck::bytes_of(&params));
        if let Some(b) = draws.blended.as_ref().filter(|_| self.indirect) {
            b.prepare(gpu.queue(), &self.shared.blended, camera, c.cull_draws);
        }
        self.draws = Some(draws);
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let draws = self
            .draws
            .as_ref()
            .ok_or(RenderError::Config(ConfigError::MissingInput {
                pass: "scene culling",
                input: "the scene's draws (built in prepare)",
            }))?;
        let mut args = resources.import_buffer(
            graph,
            "scene draw args",
            &draws.args,
            ImportAccess::ReadWrite,
        );
        if self.culling {
            let (pipeline, group) = (self.pipeline.clone(), draws.bind_group.clone());
            let visible = self.shared.visible.clone();
            let groups = draws.layout.slot_count().div_ceil(instance_cull::WORKGROUP);
            graph
                .add_pass(self.name())
                .write_buffer(&mut args, BufferAccess::StorageWrite)
                .execute(move |ctx| {
                    ctx.encoder.clear_buffer(&visible, 0, None);
                    let mut pass = ctx.encoder.begin_compute("scene culling");
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &group, &[]);
                    pass.dispatch_workgroups(groups, 1, 1);
                });
        }
        let (args_buffer, counts, packed_late) =
            self.add_compaction(graph, resources, draws, &mut args);
        let occlusion = self.occlusion.then(|| {
            let o = &draws.occlusion;
            let mut import = |name, buffer| {
                resources.import_buffer(graph, name, buffer, ImportAccess::ReadWrite)
            };
            OcclusionDraws {
                boxes: draws.box_buffer.clone(),
                slot_draws: draws.slot_draws.clone(),
                slot_count: draws.layout.slot_count(),
                slack: draws.slack(),
                history: o.history.clone(),
                late: import("scene draw args, late", &o.late),
                late_buffer: o.late.clone(),
                all: import("scene draw args, both phases", &o.all),
                all_buffer: o.all.clone(),
                visible: self.shared.visible.clone(),
                first_buffer: draws.args.clone(),
                packed: packed_late,
            }
        });
        let blended = self.blended_draws(graph, frame, resources, draws);
        resources.scene_draws = Some(SceneDrawList {
            layout: Arc::clone(&draws.layout),
            args,
            args_buffer,
            slot_args: draws.args.clone(),
            indirect: self.indirect,
            counts,
            occlusion,
            blended,
        });
        Ok(())
    }

    fn after_execute(
        &mut self,
        frame: &FrameInputs,
        _resources: &FrameResources,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        if self.culling {
            self.readback
                .record(encoder, &[(&self.shared.visible, 8)], frame.index);
        }
    }

    fn after_submit(&mut self, _frame: &FrameInputs, report: &mut FrameReport) {
        self.readback.after_submit();
        report.scene_draws = self.report();
    }
}

impl SceneCullPass {
    /// Packs the frustum's slot list after the culling dispatch (and readies the late and
    /// both-phases lists' packing for occlusion culling), where the device draws with counts:
    /// the arguments the first geometry passes draw, their counts, and what occlusion culling
    /// packs. `args` becomes the packed list's handle.
    fn add_compaction(
        &self,
        graph: &mut RenderGraph,
        resources: &mut FrameResources,
        draws: &ViewDraws,
        args: &mut Handle<Buffer>,
    ) -> (wgpu::Buffer, Option<wgpu::Buffer>, Option<OcclusionPacked>) {
        let (Some(kernels), Some(compaction)) = (&self.compact, &self.compaction) else {
            return (draws.args.clone(), None, None);
        };
        let mut packed_late = None;
        {
            let mut import = |name, buffer| {
                resources.import_buffer(graph, name, buffer, ImportAccess::ReadWrite)
            };
            let mut packed = import("scene draw args, packed", &compaction.packed[0].args);
            if self.occlusion {
                let late = import("scene draw args, late, packed", &compaction.packed[1].args);
                let all = import(
                    "scene draw args, both phases, packed",
                    &compaction.packed[2].args,
                );
                let (k, c) = (Arc::clone(kernels), Arc::clone(compaction));
                packed_late = Some(OcclusionPacked {
                    record: Arc::new(move |encoder: &mut crate::graph::PassEncoder<'_>| {
                        c.record(&k, encoder, 1);
                        c.record(&k, encoder, 2);
                    }),
                    late,
                    late_args: compaction.packed[1].args.clone(),
                    late_counts: compaction.packed[1].counts.clone(),
                    all,
                    all_args: compaction.packed[2].args.clone(),
                    all_counts: compaction.packed[2].counts.clone(),
                });
            }
            let (kernels, compaction) = (Arc::clone(kernels), Arc::clone(compaction));
            let args_buffer = compaction.packed[0].args.clone();
            let counts = Some(compaction.packed[0].counts.clone());
            graph
                .add_pass("scene draw compaction")
                .read_buffer(*args, BufferAccess::StorageRead)
                .write_buffer(&mut packed, BufferAccess::StorageWrite)
                .execute(move |ctx| compaction.record(&kernels, &mut ctx.encoder, 0));
            *args = packed;
            (args_buffer, counts, packed_late)
        }
    }

    /// The compaction of this frame's culled slot lists (the frustum's; with occlusion culling
    /// its late and both-phases lists too): the last one while it still fits, else a new one;
    /// none without culling or where the device cannot draw with counts.
    fn compaction_for(
        &self,
        gpu: &GpuContext,
        draws: &ViewDraws,
    ) -> Result<Option<Arc<Compaction>>, shader_bind::BindError> {
        let Some(kernels) = self.compact.as_ref().filter(|_| self.culling) else {
            return Ok(None);
        };
        let o = &draws.occlusion;
        let lists: Vec<&wgpu::Buffer> = if self.occlusion {
            vec![&draws.args, &o.late, &o.all]
        } else {
            vec![&draws.args]
        };
        Ok(Some(match &self.compaction {
            Some(c) if c.fits(&draws.layout, &lists) => Arc::clone(c),
            _ => Arc::new(Compaction::new(gpu, kernels, &draws.layout, &lists)?),
        }))
    }

    /// The frame's blended draws back to front: ordered on the GPU by a pass of their own
    /// where the device draws indirectly, else listed on the CPU.
    fn blended_draws(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
        draws: &ViewDraws,
    ) -> BlendedDraws {
        let cull = frame.config.cull_draws;
        let Some(order) = draws.blended.as_ref().filter(|_| self.indirect) else {
            return BlendedDraws::Listed(draws.blended_back_to_front(&frame.camera, cull).into());
        };
        let mut args = resources.import_buffer(
            graph,
            "blended draw args",
            &order.args,
            ImportAccess::ReadWrite,
        );
        let record = order.recorder(&self.shared.blended);
        graph
            .add_pass("blended order")
            .write_buffer(&mut args, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                let mut pass = ctx.encoder.begin_compute("blended order");
                record(&mut pass);
            });
        BlendedDraws::Sorted {
            args,
            args_buffer: order.args.clone(),
            count: order.count(),
            count_buffer: order.count_buffer.clone(),
        }
    }

    /// The scene's draws and the newest culled count that has arrived (polling first).
    pub fn report(&mut self) -> Option<SceneDrawReport> {
        if let Some((at, words)) = self.readback.poll(&self.device) {
            // The slots drawn, in either phase with occlusion culling (`instance_cull`).
            self.last_visible = Some((at, words[1]));
        }
        let draws = self.draws.as_ref()?;
        Some(SceneDrawReport {
            draws: draws.layout.draw_count(),
            slots: draws.layout.slot_count(),
            batches: draws.layout.batches.len() as u32,
            blended: draws.layout.blended.len() as u32,
            occlusion: self.occlusion,
            packed: self.culling && self.compaction.is_some(),
            visible: self
                .last_visible
                .filter(|_| self.culling)
                .map(|(_, visible)| visible),
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::frame_data::frustum_planes;

    fn inside(planes: &[glam::Vec4; 6], p: Vec3) -> bool {
        planes.iter().all(|q| q.truncate().dot(p) + q.w >= 0.0)
    }

    #[test]
    fn the_planes_keep_what_projects_into_the_view_and_nothing_else() {
        let view =
            glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 2.0, 10.0), Vec3::ZERO, Vec3::Y);
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.5, 50.0);
        let planes = frustum_planes(projection * view);
        let clip = |p: Vec3| (projection * view).project_point3(p);
        // A grid of points: the planes agree with the projection wherever it is unambiguous.
        for x in -20..=20 {
            for y in -20..=20 {
                for z in -60..=12 {
                    let p = Vec3::new(x as f32, y as f32, z as f32);
                    let eye_depth = -(view.transform_point3(p).z);
                    if eye_depth <= 0.0 {
                        assert!(!inside(&planes, p), "{p} is behind the eye");
                        continue;
                    }
                    let c = clip(p);
                    let margin = 1e-3;
                    let clearly_in = c.x.abs() < 1.0 - margin
                        && c.y.abs() < 1.0 - margin
                        && c.z > margin
                        && c.z < 1.0 - margin;
                    let clearly_out = c.x.abs() > 1.0 + margin
                        || c.y.abs() > 1.0 + margin
                        || c.z < -margin
                        || c.z > 1.0 + margin;
                    if clearly_in {
                        assert!(inside(&planes, p), "{p} projects to {c}");
                    }
                    if clearly_out {
                        assert!(!inside(&planes, p), "{p} projects to {c}");
                    }
                }
            }
        }
        // An infinite far plane keeps everything in front.
        let infinite = glam::camera::rh::proj::directx::perspective_infinite(1.0, 1.5, 0.5);
        let planes = frustum_planes(infinite * view);
        assert!(inside(&planes, Vec3::new(0.0, 0.0, -1e6)));
    }
}
