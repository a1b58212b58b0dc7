//! Which passes a configuration runs, in order. Adding a pass to a path is one entry here.

use crate::GpuContext;
use crate::frame_data::ConfigError;
use crate::frame_data::{FrameView, ParticleLighting, RenderError, RenderPath, RendererConfig};
use crate::materials::MaterialProgram;
use crate::passes::Pass;
use crate::passes::deferred::{GBufferPass, LightVolumePass, TbdrPass};
use crate::passes::depth_probe::DepthProbePass;
use crate::passes::forward::{ForwardPass, OverlayPass};
use crate::passes::heatmap::HeatmapPass;
use crate::passes::light_cull::LightCullPass;
use crate::passes::particles::{ParticleDrawPass, ParticleLightPass, ParticleSimPass};
use crate::passes::prez::PrezPass;
use crate::passes::scene_cull::SceneCullPass;
use crate::passes::scene_cull::occlusion::OcclusionCullPass;
use crate::passes::shadow::{ShadowAtlasViewPass, ShadowPass};
use crate::passes::tonemap::TonemapPass;
use crate::passes::visibility::{VisRasterPass, VisShadePass};

/// The ordered passes of `config`, the forward and G-buffer passes with pipelines for every
/// material program of `materials` besides glTF PBR's:
///
/// Scene culling comes first on every path (the geometry passes draw its batches). With
/// occlusion culling (`cull_draws` and `occlusion_cull`), pre-Z (the visibility raster on the
/// visibility path) is followed by occlusion culling and its late half.
///
/// | path | passes |
/// |---|---|
/// | naive | shadow atlas → particles* → forward (own depth) → particle draw → tonemap |
/// | naive-prez | pre-Z → shadow atlas → particles* → forward → particle draw → tonemap → depth probe |
/// | tiled, 2.5D, clustered | pre-Z → light culling → shadow atlas → particles* → forward → particle draw → tonemap → depth probe |
/// | tbdr, tbdr-per-sample | pre-Z → light culling† → shadow atlas → particles* → G-buffer → TBDR shading → forward‡ → particle draw → overlay§ → tonemap → depth probe |
/// | deferred | pre-Z → light culling† → shadow atlas → particles* → G-buffer → deferred base → light volumes → forward‡ → particle draw → overlay§ → tonemap → depth probe |
/// | visibility | visibility raster → light culling (clustered) → shadow atlas → particles* → visibility shading → forward‡ → particle draw → overlay§ → tonemap → depth probe |
/// | shading-frequency view | as the deferred path, edge pixels red |
/// | particle-atlas view | as the path, the tonemap showing the lit atlas |
/// | heatmap view (culled paths) | pre-Z → light culling → light heatmap → depth probe |
/// | shadow-atlas view | (pre-Z → light culling →) shadow atlas → shadow atlas view |
///
/// `particles*` is the particle simulation and layout, then (atlas lighting, or the atlas
/// view) the particle lighting; the particle passes add work only when the renderer has
/// particles. The depth probe adds work only to frames a tool asked to capture. † On the
/// deferred paths light culling adds work only for the passes that read lists (blended
/// surfaces, decals, particles). ‡ Blended surfaces only, over the deferred image (with MSAA into
/// a transparent overlay, which the particles draw into too). § With MSAA: the overlay laid over
/// the deferred image, then the erasers of what was drawn into the overlay (graph passes
/// `erase blended`, `erase particles`; `passes::overlay_erase`). The tonemap is a compute kernel and a copy into the target (graph passes
/// `tonemap`, `tonemap copy`) where the target takes copies and `compute_tonemap` is set, else
/// a full-screen fragment pass (`TonemapPass`).
pub fn passes_for(
    gpu: &GpuContext,
    config: &RendererConfig,
    materials: &[MaterialProgram],
) -> Result<Vec<Box<dyn Pass>>, RenderError> {
    if config.view == FrameView::ShadingFrequency && !config.path.is_deferred() {
        return Err(RenderError::Config(ConfigError::ShadingFrequencyNeedsTbdr));
    }
    // Every path draws the scene through the batches scene culling publishes.
    let mut passes: Vec<Box<dyn Pass>> = vec![Box::new(SceneCullPass::new(gpu)?)];
    let occlusion = config.cull_draws && config.occlusion_cull;
    if config.path == RenderPath::Visibility {
        let raster = VisRasterPass::new(gpu, config)?;
        let late = occlusion.then(|| raster.late());
        passes.push(Box::new(raster));
        if let Some(late) = late {
            passes.push(Box::new(OcclusionCullPass::new(gpu, config)?));
            passes.push(Box::new(late));
        }
    }
    if config.path.has_prez() {
        let prez = PrezPass::new(gpu, config)?;
        let late = occlusion.then(|| prez.late());
        passes.push(Box::new(prez));
        if let Some(late) = late {
            passes.push(Box::new(OcclusionCullPass::new(gpu, config)?));
            passes.push(Box::new(late));
        }
    }
    if config.path.is_culled() {
        passes.push(Box::new(LightCullPass::new(gpu)));
    }
    match config.view {
        FrameView::Heatmap | FrameView::DecalHeatmap => {
            passes.push(Box::new(HeatmapPass::new(gpu, config)?));
        }
        FrameView::ShadowAtlas => {
            passes.push(Box::new(ShadowPass::new(gpu, config)?));
            passes.push(Box::new(ShadowAtlasViewPass::new(gpu, config)?));
        }
        FrameView::Lit | FrameView::ParticleAtlas | FrameView::ShadingFrequency => {
            passes.push(Box::new(ShadowPass::new(gpu, config)?));
            passes.push(Box::new(ParticleSimPass::new(gpu)));
            let atlas_lit = config.particle_lighting == ParticleLighting::Atlas;
            if atlas_lit || config.view == FrameView::ParticleAtlas {
                passes.push(Box::new(ParticleLightPass::new(gpu, config)?));
            }
            if config.path == RenderPath::Visibility {
                passes.push(Box::new(VisShadePass::new(gpu, config, materials)?));
            } else if config.path.is_deferred() {
                passes.push(Box::new(GBufferPass::new(gpu, config, materials)?));
                passes.push(Box::new(TbdrPass::new(gpu, config)?));
                if config.path == RenderPath::Deferred {
                    passes.push(Box::new(LightVolumePass::new(gpu, config)?));
                }
            }
            passes.push(Box::new(ForwardPass::new(gpu, config, materials)?));
            passes.push(Box::new(ParticleDrawPass::new(gpu, config)?));
            if config.path.is_deferred() && config.msaa > 1 {
                passes.push(Box::new(OverlayPass::new(gpu, config.msaa)?));
            }
            passes.push(Box::new(TonemapPass::new(gpu, config)?));
        }
    }
    if config.path != RenderPath::Naive {
        passes.push(Box::new(DepthProbePass::new()));
    }
    Ok(passes)
}
