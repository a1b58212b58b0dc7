//! A further view's state: its configuration, its own passes (the main view's list less the
//! shared shadow atlas and the depth probe) and camera uniform, and its part of a frame.

use crate::frame::pass_list;
use crate::frame_data::{
    CameraUniform, FrameInputs, FrameResources, RenderError, RendererConfig, ViewId,
};
use crate::passes::Pass;
use crate::passes::depth_probe::DepthProbePass;
use crate::passes::particles::ParticleSimPass;
use crate::passes::shadow::ShadowPass;

/// A further view's configuration, passes and camera uniform.
#[derive(Debug)]
pub(crate) struct ExtraView {
    pub(super) id: ViewId,
    pub(super) config: RendererConfig,
    pub(super) passes: Vec<Box<dyn Pass>>,
    pub(super) camera_uniform: CameraUniform,
}

/// A further view's part of one frame: its inputs, and once added to the graph, its output
/// and resources.
pub(crate) struct ViewFrame {
    pub(super) index: usize,
    pub(super) inputs: FrameInputs,
    pub(super) target: wgpu::Texture,
    pub(super) resources: Option<FrameResources>,
}

/// The passes of a further view of `config`: the main view's list less the shadow atlas (the
/// main view's is shared) and the depth probe (a tool's capture of the main view), its
/// particle simulation following the main view's.
pub(super) fn view_passes(
    gpu: &crate::GpuContext,
    config: &RendererConfig,
    materials: &[crate::materials::MaterialProgram],
) -> Result<Vec<Box<dyn Pass>>, RenderError> {
    let mut passes = pass_list::passes_for(gpu, config, materials)?;
    passes.retain(|p| {
        let p = p.as_ref() as &dyn std::any::Any;
        !(p.is::<ShadowPass>() || p.is::<DepthProbePass>())
    });
    for pass in &mut passes {
        if let Some(sim) =
            (pass.as_mut() as &mut dyn std::any::Any).downcast_mut::<ParticleSimPass>()
        {
            sim.follow(None);
        }
    }
    Ok(passes)
}
