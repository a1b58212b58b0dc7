//! The running window's responses that change its state: the settings keys (path, MSAA, tile,
//! views, the visibility rasteriser, draw culling, light count), each reconfiguring the
//! renderer in place (the scene, its added instances, decals and lights stay uploaded); hot
//! reload outcomes (the programs built again on the new WGSL, or the refusal shown); the
//! overlay's status lines; and window resizes.

use anyhow::Result;
use renderer::frame::{FrameView, ParticleLighting, RenderPath, VisibilityRaster};
use viewer::hot_reload::Outcome;
use viewer::scene::{Shown, procedural};
use winit::dpi::PhysicalSize;
use winit::keyboard::KeyCode;

use super::Running;

impl Running {
    /// A settings key: path, MSAA, tile, heatmap, decal heatmap, shadow atlas, the visibility
    /// path's rasteriser, draw culling or light count; reconfigures the renderer
    /// ([`renderer::frame::Renderer::reconfigure`]), or replaces its lights.
    pub(super) fn action(&mut self, key: char, shown: &Shown) -> Result<()> {
        let mut config = self.config;
        match key {
            '1'..='9' => config.path = RenderPath::ALL[key as usize - '1' as usize],
            'm' => {
                let counts = self.gpu.capabilities().msaa_counts();
                let i = counts.iter().position(|&c| c == config.msaa).unwrap_or(0);
                config.msaa = counts[(i + 1) % counts.len()];
            }
            't' => {
                config.tile = [8, 16, 32][([8, 16, 32]
                    .iter()
                    .position(|&t| t == config.tile)
                    .unwrap_or(0)
                    + 1)
                    % 3]
            }
            'h' => {
                config.view = match config.view {
                    FrameView::Heatmap => FrameView::Lit,
                    _ => FrameView::Heatmap,
                }
            }
            'v' => {
                config.view = match config.view {
                    FrameView::ShadowAtlas => FrameView::Lit,
                    _ => FrameView::ShadowAtlas,
                }
            }
            'c' => {
                config.view = match config.view {
                    FrameView::DecalHeatmap => FrameView::Lit,
                    _ => FrameView::DecalHeatmap,
                }
            }
            'p' => {
                config.particle_lighting = match config.particle_lighting {
                    ParticleLighting::Atlas => ParticleLighting::PerPixel,
                    ParticleLighting::PerPixel => ParticleLighting::Atlas,
                }
            }
            // The visibility path's rasteriser (a device without 64-bit atomics refuses the
            // compute one). The configuration shown is the renderer's, `Auto` made concrete.
            'r' => {
                config.visibility_raster = match config.visibility_raster {
                    VisibilityRaster::Compute => VisibilityRaster::Hardware,
                    VisibilityRaster::Auto | VisibilityRaster::Hardware => {
                        VisibilityRaster::Compute
                    }
                }
            }
            'o' => {
                config.view = match config.view {
                    FrameView::ParticleAtlas => FrameView::Lit,
                    _ => FrameView::ParticleAtlas,
                }
            }
            'f' => {
                config.view = match config.view {
                    FrameView::ShadingFrequency => FrameView::Lit,
                    _ => FrameView::ShadingFrequency,
                }
            }
            // Frustum and occlusion culling → frustum only → none → both again.
            'g' => {
                (config.cull_draws, config.occlusion_cull) =
                    match (config.cull_draws, config.occlusion_cull) {
                        (true, true) => (true, false),
                        (true, false) => (false, false),
                        _ => (true, true),
                    };
            }
            '+' => self.light_count = (self.light_count * 2).clamp(1, 65_536),
            '-' => self.light_count = (self.light_count / 2).max(1),
            _ => return Ok(()),
        }
        if matches!(key, '+' | '-') {
            let lights = procedural(shown, self.light_count);
            if let Err(e) = self.renderer.set_lights(&lights) {
                self.message = Some(e.to_string());
            }
            return Ok(());
        }
        match self.renderer.reconfigure(config) {
            Ok(()) => {
                self.config = *self.renderer.config();
                self.message = None;
            }
            // A combination the renderer refuses (a heatmap of the naive path): say so.
            Err(e) => self.message = Some(e.to_string()),
        }
        Ok(())
    }

    /// After a hot reload: builds the renderer's programs again on the new WGSL (the scene stays
    /// uploaded), or keeps the running ones and says why the edit was refused.
    pub(super) fn hot_reloaded(&mut self, outcome: Outcome) {
        let message = match outcome {
            Outcome::Installed(n) => match self.renderer.reconfigure(self.config) {
                Ok(()) => format!("hot reload: {n} shader variant(s) replaced"),
                Err(e) => format!("hot reload: the renderer did not rebuild: {e:#}"),
            },
            Outcome::Refused(why) => {
                format!("shader edit refused: {why} (the last good shaders keep running)")
            }
            Outcome::WatchError(why) => format!("hot reload: {why}"),
        };
        eprintln!("{message}");
        self.message = Some(message);
    }

    pub(super) fn status(&self) -> Vec<String> {
        let c = &self.config;
        // A message (a refused setting, a hot reload and why it was refused) comes first, where
        // even a small window shows it.
        let mut lines: Vec<String> = self.message.clone().into_iter().collect();
        lines.extend([
            format!(
                "{:?}{}, MSAA {}, tile {}, {:?}, particles lit {}",
                c.path,
                if c.path == RenderPath::Visibility {
                    format!(" ({} raster, R)", c.visibility_raster.name())
                } else {
                    String::new()
                },
                c.msaa,
                c.tile,
                c.view,
                c.particle_lighting.name()
            ),
            format!("{} lights, {}x{}", self.light_count, c.width, c.height),
            self.draws.map_or_else(String::new, |d| {
                let culling = if d.occlusion {
                    "frustum and occlusion culling"
                } else {
                    "frustum culling"
                };
                let kept = match d.visible {
                    Some(v) if c.cull_draws => format!("{v} drawn after GPU {culling} (G)"),
                    _ => "all drawn, culling off (G)".into(),
                };
                format!(
                    "{} draws in {} batches: {kept}; CPU {:.2} ms; {} instances added (I, U)",
                    d.draws + d.blended,
                    d.batches,
                    self.cpu_ms,
                    self.added.count()
                )
            }),
            format!("adapter: {}", self.gpu.report().name),
        ]);
        lines
    }

    pub(super) fn key(&mut self, code: KeyCode, pressed: bool, shown: &Shown) -> Result<()> {
        let held = &mut self.held;
        match code {
            KeyCode::KeyW => held.forward = pressed,
            KeyCode::KeyS => held.back = pressed,
            KeyCode::KeyA => held.left = pressed,
            KeyCode::KeyD => held.right = pressed,
            KeyCode::KeyE => held.up = pressed,
            KeyCode::KeyQ => held.down = pressed,
            _ if !pressed => {}
            KeyCode::Digit1 => self.action('1', shown)?,
            KeyCode::Digit2 => self.action('2', shown)?,
            KeyCode::Digit3 => self.action('3', shown)?,
            KeyCode::Digit4 => self.action('4', shown)?,
            KeyCode::Digit5 => self.action('5', shown)?,
            KeyCode::Digit6 => self.action('6', shown)?,
            KeyCode::Digit7 => self.action('7', shown)?,
            KeyCode::Digit8 => self.action('8', shown)?,
            KeyCode::Digit9 => self.action('9', shown)?,
            KeyCode::KeyF => self.action('f', shown)?,
            KeyCode::KeyM => self.action('m', shown)?,
            KeyCode::KeyT => self.action('t', shown)?,
            KeyCode::KeyH => self.action('h', shown)?,
            KeyCode::KeyV => self.action('v', shown)?,
            KeyCode::KeyC => self.action('c', shown)?,
            KeyCode::KeyP => self.action('p', shown)?,
            KeyCode::KeyO => self.action('o', shown)?,
            KeyCode::KeyR => self.action('r', shown)?,
            KeyCode::KeyG => self.action('g', shown)?,
            KeyCode::KeyI => self.added.add_batch(&mut self.renderer, shown, &self.fly)?,
            KeyCode::KeyU => self.added.remove_batch(&mut self.renderer)?,
            KeyCode::Equal | KeyCode::NumpadAdd => self.action('+', shown)?,
            KeyCode::Minus | KeyCode::NumpadSubtract => self.action('-', shown)?,
            _ => {}
        }
        Ok(())
    }

    /// Follows the window's size; a size the device cannot render (0, or past its largest
    /// texture side) keeps the last one and says why.
    pub(super) fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        self.renderer.resize(size.width, size.height)?;
        self.surface_config.width = size.width;
        self.surface_config.height = size.height;
        self.surface
            .configure(self.gpu.device(), &self.surface_config);
        self.config.width = size.width;
        self.config.height = size.height;
        Ok(())
    }
}
