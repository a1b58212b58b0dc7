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
        if (config.light_cutoff, config.exposure)
            != (self.config.light_cutoff, self.config.exposure)
        {
            // Before anything else changes, so an error leaves the renderer as it was.
            self.lights = std::sync::Arc::new(self.ranged_lights(&self.light_sources, &config)?);
        }
        // The rebuilt particle passes hold no state, so they build it from the systems.
        self.passes = passes;
        self.config = config;
        self.graph_cache = GraphCache::new();
        Ok(())
    }
}
