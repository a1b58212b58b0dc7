//! Changing a renderer's configuration or its material programs in place: the passes and their
//! programs are built again; the scene, instances, lights, decals and particle systems stay
//! uploaded.

use super::{Renderer, check_config, pass_list};
use crate::frame_data::{RenderError, RendererConfig};
use crate::graph::GraphCache;
use crate::materials::MaterialProgram;

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
        let config = check_config(&self.gpu, config)?;
        let passes = pass_list::passes_for(&self.gpu, &config, &self.materials)?;
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

    /// Registers a material written in the shader DSL: from the next frame, materials whose
    /// `custom` names it ([`crate::scene::CustomShading`]) are drawn with its programs on every
    /// path (the forward and G-buffer passes are built again with its pipelines; the scene and
    /// everything else stay uploaded). A program of the same name replaces the registered one
    /// (its materials' parameter records must keep its size). A program the device cannot run
    /// (a scalarized variant on a device without subgroups, where the configuration
    /// scalarizes) is an error, and nothing changes.
    pub fn register_material(&mut self, program: MaterialProgram) -> Result<(), RenderError> {
        let mut materials = self.materials.clone();
        match materials.iter_mut().find(|p| p.name() == program.name()) {
            Some(registered) => *registered = program,
            None => materials.push(program),
        }
        if let Some((scene, _)) = &self.scene {
            for material in &scene.materials {
                crate::materials::check_material(material, &materials)?;
            }
        }
        let passes = pass_list::passes_for(&self.gpu, &self.config, &materials)?;
        let mut views = Vec::with_capacity(self.views.len());
        for v in &self.views {
            views.push(super::extra_view::view_passes(
                &self.gpu, &v.config, &materials,
            )?);
        }
        self.passes = passes;
        for (v, passes) in self.views.iter_mut().zip(views) {
            v.passes = passes;
        }
        self.materials = materials;
        self.graph_cache = GraphCache::new();
        Ok(())
    }

    /// The material programs registered, in registration order.
    pub fn material_programs(&self) -> &[MaterialProgram] {
        &self.materials
    }
}
