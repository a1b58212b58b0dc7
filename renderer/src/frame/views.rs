//! Several views of one scene in one frame: besides the main view (the renderer's own
//! configuration and camera), an engine adds views ([`Renderer::add_view`]), each with its own
//! size, path, MSAA, tile size, exposure and camera (split screen, a minimap, a reflection), and
//! renders them together ([`Renderer::render_views`]).
//!
//! One frame graph holds every view. The scene, instances, lights, decals and materials are the
//! renderer's, uploaded once. The shadow atlas is drawn once, planned for the main view's camera
//! (its resolutions and cascades), and every view shades with it. The particles are stepped once,
//! in the main view; each further view lays them out, sorts and lights them for its own camera
//! (`ParticleSimPass::follow`). Everything else (scene culling, pre-Z, light culling, the
//! shading passes, tonemapping) runs per view, with the view's own passes and uniforms.

use crate::frame_data::InputError;
use std::sync::Arc;

use super::extra_view::{ExtraView, ViewFrame, view_passes};
use super::{Renderer, check_config};
use crate::frame_data::{
    CameraUniform, FrameCamera, FrameInputs, FrameReport, FrameResources, RenderError,
    RendererConfig, ViewId, ViewTarget,
};
use crate::graph::{ImportAccess, RenderGraph, TextureDesc};
use crate::passes::particles::ParticleSimPass;

impl Renderer {
    /// Adds a view of the scene with its own `config` (size, path, MSAA, tile, exposure, view,
    /// particle lighting; the light cutoff, shadow settings and scene culling thresholds are the
    /// main view's), drawn with the main view by [`Renderer::render_views`]. A configuration
    /// the device cannot run is an error.
    pub fn add_view(&mut self, config: RendererConfig) -> Result<ViewId, RenderError> {
        let config = check_config(&self.gpu, config)?;
        let id = ViewId(self.views.iter().map(|v| v.id.0 + 1).max().unwrap_or(1));
        self.views.push(ExtraView {
            id,
            passes: view_passes(&self.gpu, &config, &self.materials)?,
            config,
            camera_uniform: CameraUniform::new(self.gpu.device()),
        });
        self.graph_cache = crate::graph::GraphCache::new();
        Ok(id)
    }

    /// Changes view `id`'s configuration (its passes built again; the scene stays).
    pub fn reconfigure_view(
        &mut self,
        id: ViewId,
        config: RendererConfig,
    ) -> Result<(), RenderError> {
        let config = check_config(&self.gpu, config)?;
        let passes = view_passes(&self.gpu, &config, &self.materials)?;
        let view = self.view_mut(id)?;
        view.passes = passes;
        view.config = config;
        self.graph_cache = crate::graph::GraphCache::new();
        Ok(())
    }

    /// Removes view `id`.
    pub fn remove_view(&mut self, id: ViewId) -> Result<(), RenderError> {
        let count = self.views.len();
        self.views.retain(|v| v.id != id);
        if self.views.len() == count {
            return Err(RenderError::Input(InputError::NoSuchView(id)));
        }
        self.graph_cache = crate::graph::GraphCache::new();
        Ok(())
    }

    /// View `id`'s configuration.
    pub fn view_config(&self, id: ViewId) -> Option<&RendererConfig> {
        self.views.iter().find(|v| v.id == id).map(|v| &v.config)
    }

    fn view_mut(&mut self, id: ViewId) -> Result<&mut ExtraView, RenderError> {
        self.views
            .iter_mut()
            .find(|v| v.id == id)
            .ok_or(RenderError::Input(InputError::NoSuchView(id)))
    }

    /// Renders one frame of the main view into `target` (as [`Renderer::render`]) and of
    /// every view of `views` into its own target, in one frame graph and one submission:
    /// the shadow atlas drawn once and the particles stepped once, for all of them. The report
    /// is the main view's, with each further view's in [`FrameReport::views`], in `views`'
    /// order. A view listed twice, an unknown view or a target that does not match its view
    /// is an error, and nothing is drawn.
    pub fn render_views(
        &mut self,
        camera: &FrameCamera,
        target: &wgpu::Texture,
        views: &[ViewTarget<'_>],
    ) -> Result<FrameReport, RenderError> {
        for (i, v) in views.iter().enumerate() {
            if views[..i].iter().any(|w| w.view == v.view) {
                return Err(RenderError::Input(InputError::ViewTwice(v.view)));
            }
            let config = self
                .view_config(v.view)
                .ok_or(RenderError::Input(InputError::NoSuchView(v.view)))?;
            super::check_target(config, v.target)?;
        }
        self.render_with(camera, target, views)
    }

    /// Each further view's inputs for this frame, their passes prepared (the particle
    /// simulation following `main`'s).
    pub(super) fn prepare_views(
        &mut self,
        main: &FrameInputs,
        views: &[ViewTarget<'_>],
    ) -> Result<Vec<ViewFrame>, RenderError> {
        let systems = self
            .pass::<ParticleSimPass>()
            .and_then(|p| p.system().cloned());
        let mut frames = Vec::with_capacity(views.len());
        for v in views {
            let index = self
                .views
                .iter()
                .position(|e| e.id == v.view)
                .ok_or(RenderError::Input(InputError::NoSuchView(v.view)))?;
            let view = &mut self.views[index];
            view.camera_uniform.write(main.gpu.queue(), v.camera);
            let inputs = FrameInputs {
                config: view.config,
                camera: *v.camera,
                camera_uniform: view.camera_uniform.clone(),
                capture: None,
                target_usage: v.target.usage(),
                target_format: v.target.format(),
                ..main.clone()
            };
            for pass in &mut view.passes {
                if let Some(sim) =
                    (pass.as_mut() as &mut dyn std::any::Any).downcast_mut::<ParticleSimPass>()
                {
                    sim.follow(systems.as_ref().map(Arc::clone));
                }
                pass.prepare(&inputs)?;
            }
            frames.push(ViewFrame {
                index,
                inputs,
                target: v.target.clone(),
                resources: None,
            });
        }
        Ok(frames)
    }

    /// Adds every further view's passes to `graph`, after the main view's (`main`: its
    /// resources, whose shadow atlas and stepped particles the views share).
    pub(super) fn add_views_to_graph(
        &self,
        graph: &mut RenderGraph,
        main: &FrameResources,
        frames: &mut [ViewFrame],
    ) -> Result<(), RenderError> {
        for frame in frames {
            let c = &frame.inputs.config;
            let desc = TextureDesc::new_2d(c.width, c.height, c.output_format);
            let output = graph.import_texture("view output", desc, ImportAccess::ReadWrite);
            let mut resources = FrameResources::new(output);
            resources.shadows = main.shadows.clone();
            resources.main_particles = main.particles.as_ref().map(|p| p.simulated);
            for pass in &self.views[frame.index].passes {
                pass.add_to_graph(graph, &frame.inputs, &mut resources)?;
            }
            resources.run_left_erasers(graph)?;
            frame.resources = Some(resources);
        }
        Ok(())
    }

    /// Binds each view's target and imports in `compiled`.
    pub(super) fn bind_views(compiled: &mut crate::graph::CompiledGraph, frames: &[ViewFrame]) {
        for frame in frames {
            if let Some(resources) = &frame.resources {
                compiled.bind_texture(resources.output, &frame.target);
                resources.bind_imports(compiled);
            }
        }
    }

    /// Every further view's passes after the frame's execution.
    pub(super) fn views_after_execute(
        &mut self,
        frames: &[ViewFrame],
        encoder: &mut wgpu::CommandEncoder,
    ) {
        for frame in frames {
            if let Some(resources) = &frame.resources {
                for pass in &mut self.views[frame.index].passes {
                    pass.after_execute(&frame.inputs, resources, encoder);
                }
            }
        }
    }

    /// Every further view's report, its passes' sections after submission.
    pub(super) fn views_after_submit(&mut self, frames: &[ViewFrame]) -> Vec<FrameReport> {
        frames
            .iter()
            .map(|frame| {
                let mut report = FrameReport::default();
                for pass in &mut self.views[frame.index].passes {
                    pass.after_submit(&frame.inputs, &mut report);
                }
                report
            })
            .collect()
    }
}
