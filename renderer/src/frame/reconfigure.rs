//! Changing a renderer's configuration in place: the passes and their programs are built again
//! for the new configuration; the scene, instances, lights, decals and particle systems stay
//! uploaded.

use super::{Renderer, check_config, pass_list};
use crate::frame_data::{RenderError, RendererConfig};
use crate::graph::GraphCache;

impl Renderer {
    /// Switches to `config` (path, MSAA, tile, views, exposure, culling, size, ...) without
    /// uploading the scene again: the scene's buffers, its instances (edits included), the
    /// decals and their atlas stay; the passes are built for `config`; the lights are ranged
    /// again where the cutoff or exposure changed ([`Renderer::set_lights`]).
    ///
    /// Particle systems start again from their warm-up (their simulation state lives in the
    /// particle passes), and per-pass caches (the shadow atlas's static cache, the compiled
    /// graph) are rebuilt on the next frame. A configuration the device cannot run is an
    /// error, and the renderer stays as it was.
    pub fn reconfigure(&mut self, config: RendererConfig) -> Result<(), RenderError> {
        check_config(&self.gpu, &config)?;
        let passes = pass_list::passes_for(&self.gpu, &config)?;
        let ranging = (config.light_cutoff, config.exposure)
            != (self.config.light_cutoff, self.config.exposure);
        let lights = if ranging {
            Some(self.ranged_lights(&self.light_sources, &config)?)
        } else {
            None
        };
        if let Some(lights) = lights {
            self.lights = std::sync::Arc::new(lights);
        }
        self.passes = passes;
        self.config = config;
        self.graph_cache = GraphCache::new();
        if let Some(p) = &mut self.particles {
            // A new generation: the rebuilt particle passes build their state from it.
            p.generation += 1;
        }
        Ok(())
    }
}
