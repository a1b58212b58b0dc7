//! Depth probe: in a frame a tool asked to capture, copies one depth sample per probe point into
//! a buffer and the light grid beside it, so tools can measure the frame (see [`capture`]).
//! In other frames it adds nothing to the graph.

pub mod capture;

use crate::frame_data::ConfigError;
use std::sync::Arc;

use capture::{PendingCapture, ProbeGpu, ProbePipeline};

use shaders_gen::inspect::depth_probe;

use super::Pass;
use crate::culling::CullCamera;
use crate::frame_data::{FrameInputs, FrameResources, RenderError};
use crate::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};

/// The depth-probe pass: its kernel (built on the first capture) and the capture in progress.
#[derive(Debug, Default)]
pub struct DepthProbePass {
    kernel: Option<Arc<ProbePipeline>>,
    /// This frame's probe buffers, when the frame captures.
    current: Option<Arc<ProbeGpu>>,
    pending: Option<PendingCapture>,
}

impl DepthProbePass {
    pub fn new() -> Self {
        Self::default()
    }

    /// The newest capture recorded and not yet taken.
    pub fn take_pending(&mut self) -> Option<PendingCapture> {
        self.pending.take()
    }
}

impl Pass for DepthProbePass {
    fn name(&self) -> &'static str {
        "depth probe"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        self.current = None;
        let Some(stride) = frame.capture else {
            return Ok(());
        };
        if self.kernel.is_none() {
            self.kernel = Some(Arc::new(ProbePipeline::new(&frame.gpu, frame.config.msaa)?));
        }
        if let Some(kernel) = &self.kernel {
            let probe = ProbeGpu::new(frame.gpu.device(), kernel, frame.screen(), stride);
            self.current = Some(Arc::new(probe));
        }
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        _frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let Some(probe) = self.current.clone() else {
            return Ok(());
        };
        let depth = resources
            .depth
            .ok_or(RenderError::Config(ConfigError::CaptureNeedsDepth))?;
        let mut probes = resources.import_buffer(
            graph,
            "depth probes",
            &probe.output,
            ImportAccess::ReadWrite,
        );
        graph
            .add_pass(self.name())
            .read_texture(depth, TextureAccess::Sampled)
            .write_buffer(&mut probes, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                let view = ctx.texture(depth).create_view(&Default::default());
                let program = &probe.kernel.program;
                let built = depth_probe::Group0 {
                    params: probe.params.as_entire_buffer_binding(),
                    probes: probe.output.as_entire_buffer_binding(),
                    depth: Some(&view),
                    depth_ms: Some(&view),
                }
                .bind_group(
                    ctx.device,
                    program.layout(0),
                    program.variant,
                    "depth probe",
                );
                let Some(bind_group) = ctx.bind(built) else {
                    return;
                };
                let mut pass = ctx.encoder.begin_compute("depth probe");
                pass.set_pipeline(&probe.kernel.pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                let side = depth_probe::WORKGROUP_SIDE;
                pass.dispatch_workgroups(
                    probe.grid.x.div_ceil(side),
                    probe.grid.y.div_ceil(side),
                    1,
                );
            });
        Ok(())
    }

    /// Copies the light grid right after the frame's passes, in the same submission.
    fn after_execute(
        &mut self,
        frame: &FrameInputs,
        resources: &FrameResources,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let Some(probe) = self.current.take() else {
            return;
        };
        let lists = resources.light_lists.as_ref();
        let grid_copy = lists.map(|l| {
            let copy = frame.gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("captured light grid"),
                size: l.grid_buffer.size(),
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(&l.grid_buffer, 0, &copy, 0, l.grid_buffer.size());
            copy
        });
        let c = &frame.config;
        self.pending = Some(PendingCapture {
            probe,
            stride: frame.capture.unwrap_or(1),
            msaa: c.msaa,
            camera: CullCamera {
                view: frame.camera.view,
                projection: frame.camera.projection,
                width: c.width,
                height: c.height,
            },
            lights: frame.lights.spheres.clone(),
            method: lists.map(|l| l.method),
            grid_copy,
        });
    }
}
