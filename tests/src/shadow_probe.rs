//! A probe pass that copies the shadow atlas after every frame's shadow pass, so tests can
//! compare the depth two renderers drew, texel for texel.

use renderer::frame::ConfigError;
use std::sync::{Arc, Mutex};

use renderer::GpuContext;
use renderer::frame::{RenderError, Renderer};
use renderer::frame_data::{FrameInputs, FrameResources};
use renderer::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};
use renderer::passes::Pass;

use crate::frame_probe::{ShadowCopies, ShadowInputs};

/// Copies the shadow atlas (and its views) into buffers the test reads after the frame.
#[derive(Debug, Default)]
pub struct ShadowAtlasProbe {
    copies: Arc<Mutex<Option<ShadowCopies>>>,
}

impl ShadowAtlasProbe {
    /// Inserts a probe after `renderer`'s shadow pass; the handle reads what it copied.
    pub fn insert(renderer: &mut Renderer) -> Result<ShadowAtlasReader, RenderError> {
        let probe = Self::default();
        let reader = ShadowAtlasReader {
            copies: Arc::clone(&probe.copies),
        };
        renderer.insert_pass_after("shadow atlas", Box::new(probe))?;
        Ok(reader)
    }
}

/// Reads what the probe copied in the last frame.
#[derive(Debug, Clone)]
pub struct ShadowAtlasReader {
    copies: Arc<Mutex<Option<ShadowCopies>>>,
}

impl ShadowAtlasReader {
    /// The last frame's shadow atlas (blocking until the copy is done).
    pub fn read(&self, gpu: &GpuContext) -> Result<ShadowInputs, String> {
        let copies = self.copies.lock().map_err(|e| e.to_string())?.clone();
        copies.ok_or("no frame copied the shadow atlas")?.read(gpu)
    }
}

impl Pass for ShadowAtlasProbe {
    fn name(&self) -> &'static str {
        "shadow atlas probe"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let shadows =
            resources
                .shadows
                .clone()
                .ok_or(RenderError::Config(ConfigError::MissingInput {
                    pass: "shadow atlas probe",
                    input: "the shadow atlas",
                }))?;
        let copies = ShadowCopies::new(
            frame.gpu.device(),
            &shadows,
            frame.config.fitted_shadows().atlas_size,
        );
        // The copy is the pass's tracked output, so the graph keeps the pass.
        let marker = frame.gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadow atlas probe"),
            size: 4,
            usage: wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut out = resources.import_buffer(
            graph,
            "shadow atlas probe",
            &marker,
            ImportAccess::ReadWrite,
        );
        graph
            .add_pass(self.name())
            .read_texture(shadows.atlas, TextureAccess::CopySrc)
            .write_buffer(&mut out, BufferAccess::CopyDst)
            .execute({
                let copies = copies.clone();
                move |ctx| copies.record(ctx, &shadows)
            });
        if let Ok(mut slot) = self.copies.lock() {
            *slot = Some(copies);
        }
        Ok(())
    }
}
