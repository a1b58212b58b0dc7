//! The window: winit events in, one renderer frame into the swapchain texture per redraw, the
//! overlay on top, the settings keys that rebuild the renderer, and shader hot reload (the
//! watched sources recompiled, the renderer rebuilt on the new WGSL, a refused edit shown).

use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use renderer::frame::{FrameView, ParticleLighting, RenderPath, Renderer, RendererConfig};
use renderer::graph::PassTiming;
use renderer::{GpuContext, GpuOptions, readback};
use viewer::fly::{Fly, Held};
use viewer::scene::{Shown, load, procedural};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use viewer::hot_reload::{Outcome, Watch};

use crate::args::Args;
use crate::overlay::Overlay;

/// The viewer: its arguments and scene before the window opens, then the running state.
pub struct App {
    args: Args,
    shown: Shown,
    running: Option<Running>,
    frame: u32,
    error: Option<anyhow::Error>,
    /// The shader sources watched for hot reload.
    watch: Option<Watch>,
    /// Reload screenshots written so far; one is due when `shot_due`.
    shots: u32,
    shot_due: bool,
}

/// Everything that lives while the window does.
struct Running {
    window: Arc<Window>,
    gpu: GpuContext,
    surface: wgpu::Surface<'static>,
    surface_config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    config: RendererConfig,
    overlay: Overlay,
    fly: Fly,
    held: Held,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    timings: Vec<PassTiming>,
    last: Instant,
    light_count: usize,
    message: Option<String>,
}

impl App {
    pub fn new(args: Args) -> Result<App> {
        let shown = load(
            args.scene.as_deref(),
            args.lights,
            args.decals,
            args.particles,
            args.seed,
        )?;
        let watch = if args.no_watch {
            None
        } else {
            args.watch_shaders
                .clone()
                .or_else(viewer::hot_reload::default_dir)
                .map(Watch::new)
        };
        if let Some(w) = &watch {
            eprintln!("hot reload: watching {}", w.dir().display());
        }
        Ok(App {
            args,
            shown,
            running: None,
            frame: 0,
            error: None,
            watch,
            shots: 0,
            shot_due: true,
        })
    }

    /// The run's outcome once the event loop has returned.
    pub fn finish(self) -> Result<()> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error = Some(e);
        event_loop.exit();
    }

    fn open(&self, event_loop: &ActiveEventLoop) -> Result<Running> {
        let (w, h) = self.args.size;
        let window = Arc::new(
            event_loop.create_window(
                Window::default_attributes()
                    .with_title("renderer viewer")
                    .with_inner_size(PhysicalSize::new(w, h)),
            )?,
        );
        let gpu = GpuContext::new_blocking(&GpuOptions::from_env())?;
        let surface = gpu.instance.create_surface(window.clone())?;
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .context("the surface offers no format")?;
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if self.args.screenshot.is_some() || self.args.reload_shots.is_some() {
            anyhow::ensure!(
                caps.usages.contains(wgpu::TextureUsages::COPY_SRC),
                "--screenshot/--reload-shots: this surface cannot be copied from"
            );
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let size = window.inner_size();
        let surface_config = wgpu::SurfaceConfiguration {
            usage,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::default(),
        };
        surface.configure(&gpu.device, &surface_config);
        let msaa = if gpu.capabilities().msaa_counts().contains(&self.args.msaa) {
            self.args.msaa
        } else {
            1
        };
        let config = RendererConfig {
            width: surface_config.width,
            height: surface_config.height,
            msaa,
            path: self.args.path,
            scalarize: renderer::gpu::scalarize_auto(
                &gpu,
                renderer::gpu::ScalarizedKernel::Forward,
            ),
            output_format: format,
            ..viewer::scene::look(&self.shown)
        };
        let renderer = build(&gpu, config, &self.shown, &self.shown.lights)?;
        let overlay = Overlay::new(&window, &gpu.device, format);
        Ok(Running {
            window,
            renderer,
            config,
            overlay,
            fly: self.shown.start,
            held: Held::default(),
            drag: None,
            cursor: (0.0, 0.0),
            timings: vec![],
            last: Instant::now(),
            light_count: self.args.lights,
            message: None,
            gpu,
            surface,
            surface_config,
        })
    }

    /// Renders one frame; `Ok(false)` when the run is over.
    fn redraw(&mut self) -> Result<bool> {
        let scripted = self.args.frames.is_some();
        let frame = self.frame;
        let script = self.args.script.clone().unwrap_or_default().0;
        let r = self.running.as_mut().expect("window open");
        let dt = if scripted {
            1.0 / 60.0
        } else {
            r.last.elapsed().as_secs_f32().min(0.1)
        };
        r.last = Instant::now();
        let mut held = r.held;
        if scripted {
            let (down, pressed) = viewer::script::at(&script, frame);
            held = held_from(&down);
            for key in pressed {
                r.action(key, &self.shown)?;
            }
        }
        r.fly.step(held, dt);
        if let Some(outcome) = self.watch.as_mut().and_then(Watch::poll) {
            r.hot_reloaded(outcome, &self.shown);
            self.shot_due = true;
        }
        let texture = match r.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                r.surface.configure(&r.gpu.device, &r.surface_config);
                return Ok(true);
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(true);
            }
            other => anyhow::bail!("cannot get the next swapchain texture: {other:?}"),
        };
        let aspect = r.config.width as f32 / r.config.height as f32;
        let report = r.renderer.render(&r.fly.camera(aspect), &texture.texture)?;
        if let Some(t) = report.timings {
            r.timings = t;
        }
        let last = self.args.frames.is_some_and(|n| frame + 1 >= n);
        let shot = self.args.screenshot.as_ref().filter(|_| last);
        if let Some(path) = shot.filter(|_| !self.args.screenshot_overlay) {
            screenshot(&r.gpu, &texture.texture, path)?;
        }
        let reload_shot = self
            .args
            .reload_shots
            .as_ref()
            .filter(|_| self.shot_due)
            .map(|dir| dir.join(format!("reload-{}", self.shots)));
        if let Some(stem) = &reload_shot {
            screenshot(&r.gpu, &texture.texture, &stem.with_extension("png"))?;
        }
        let status = r.status();
        r.overlay
            .draw(&r.window, &r.gpu, &texture.texture, &r.timings, &status);
        if let Some(path) = shot.filter(|_| self.args.screenshot_overlay) {
            screenshot(&r.gpu, &texture.texture, path)?;
        }
        if let Some(stem) = &reload_shot {
            let overlay = stem.with_file_name(format!("reload-{}-overlay.png", self.shots));
            screenshot(&r.gpu, &texture.texture, &overlay)?;
            eprintln!("hot reload: wrote {}", stem.with_extension("png").display());
            self.shots += 1;
        }
        self.shot_due = false;
        // Shot 0 is the first frame; shot k follows reload k.
        let reloads_done = self.args.exit_after_reloads.is_some_and(|n| self.shots > n);
        r.window.pre_present_notify();
        r.gpu.queue.present(texture);
        self.frame += 1;
        Ok(!last && !reloads_done)
    }
}

fn held_from(down: &[char]) -> Held {
    Held {
        forward: down.contains(&'w'),
        back: down.contains(&'s'),
        left: down.contains(&'a'),
        right: down.contains(&'d'),
        up: down.contains(&'e'),
        down: down.contains(&'q'),
    }
}

/// A renderer for `config` with the scene and `lights` uploaded.
fn build(
    gpu: &GpuContext,
    config: RendererConfig,
    shown: &Shown,
    lights: &[renderer::scene::SceneLight],
) -> Result<Renderer> {
    let mut r = Renderer::new(gpu, config)?;
    r.prepare_scene(&shown.scene)?;
    r.set_lights(lights)?;
    r.set_decals(&shown.decals)?;
    if let Some(p) = &shown.particles {
        r.set_particles(p, renderer::particles::WARMUP_STEPS)?;
    }
    Ok(r)
}

/// Copies the swapchain texture (BGRA or RGBA, 8 bits) to a PNG.
fn screenshot(gpu: &GpuContext, texture: &wgpu::Texture, path: &std::path::Path) -> Result<()> {
    let mut rgba = readback::read_texture_rgba8(&gpu.device, &gpu.queue, texture)?;
    if matches!(
        texture.format(),
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for px in rgba.chunks_mut(4) {
            px.swap(0, 2);
        }
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    image::save_buffer(
        path,
        &rgba,
        texture.width(),
        texture.height(),
        image::ExtendedColorType::Rgba8,
    )
    .with_context(|| format!("writing {}", path.display()))
}

impl Running {
    /// A settings key: path, MSAA, tile, heatmap, decal heatmap, shadow atlas or light count;
    /// rebuilds the
    /// renderer.
    fn action(&mut self, key: char, shown: &Shown) -> Result<()> {
        let mut config = self.config;
        match key {
            '1'..='8' => config.path = RenderPath::ALL[key as usize - '1' as usize],
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
            '+' => self.light_count = (self.light_count * 2).clamp(1, 65_536),
            '-' => self.light_count = (self.light_count / 2).max(1),
            _ => return Ok(()),
        }
        let lights = procedural(shown, self.light_count);
        match build(&self.gpu, config, shown, &lights) {
            Ok(r) => {
                self.renderer = r;
                self.config = config;
                self.message = None;
            }
            // A combination the renderer refuses (a heatmap of the naive path): say so.
            Err(e) => self.message = Some(e.to_string()),
        }
        Ok(())
    }

    /// After a hot reload: rebuilds the renderer on the new WGSL, or keeps the running one and
    /// says why the edit was refused.
    fn hot_reloaded(&mut self, outcome: Outcome, shown: &Shown) {
        let message = match outcome {
            Outcome::Installed(n) => {
                let lights = procedural(shown, self.light_count);
                match build(&self.gpu, self.config, shown, &lights) {
                    Ok(r) => {
                        self.renderer = r;
                        format!("hot reload: {n} shader variant(s) replaced")
                    }
                    Err(e) => format!("hot reload: the renderer did not rebuild: {e:#}"),
                }
            }
            Outcome::Refused(why) => {
                format!("shader edit refused: {why} (the last good shaders keep running)")
            }
        };
        eprintln!("{message}");
        self.message = Some(message);
    }

    fn status(&self) -> Vec<String> {
        let c = &self.config;
        // A message (a refused setting, a hot reload and why it was refused) comes first, where
        // even a small window shows it.
        let mut lines: Vec<String> = self.message.clone().into_iter().collect();
        lines.extend([
            format!(
                "{:?}, MSAA {}, tile {}, {:?}, particles lit {}",
                c.path,
                c.msaa,
                c.tile,
                c.view,
                c.particle_lighting.name()
            ),
            format!("{} lights, {}x{}", self.light_count, c.width, c.height),
            format!("adapter: {}", self.gpu.report.name),
        ]);
        lines
    }

    fn key(&mut self, code: KeyCode, pressed: bool, shown: &Shown) -> Result<()> {
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
            KeyCode::KeyF => self.action('f', shown)?,
            KeyCode::KeyM => self.action('m', shown)?,
            KeyCode::KeyT => self.action('t', shown)?,
            KeyCode::KeyH => self.action('h', shown)?,
            KeyCode::KeyV => self.action('v', shown)?,
            KeyCode::KeyC => self.action('c', shown)?,
            KeyCode::KeyP => self.action('p', shown)?,
            KeyCode::KeyO => self.action('o', shown)?,
            KeyCode::Equal | KeyCode::NumpadAdd => self.action('+', shown)?,
            KeyCode::Minus | KeyCode::NumpadSubtract => self.action('-', shown)?,
            _ => {}
        }
        Ok(())
    }

    /// Follows the window's size; a size the device cannot render (0, or past its largest
    /// texture side) keeps the last one and says why.
    fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        self.renderer.resize(size.width, size.height)?;
        self.surface_config.width = size.width;
        self.surface_config.height = size.height;
        self.surface
            .configure(&self.gpu.device, &self.surface_config);
        self.config.width = size.width;
        self.config.height = size.height;
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(r) => self.running = Some(r),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else {
            return;
        };
        if r.overlay.on_event(&r.window, &event) {
            return;
        }
        let result = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::Resized(size) => r.resize(size),
            WindowEvent::KeyboardInput { event, .. } => match event.physical_key {
                PhysicalKey::Code(KeyCode::Escape) => {
                    event_loop.exit();
                    Ok(())
                }
                PhysicalKey::Code(code) if !event.repeat => {
                    r.key(code, event.state == ElementState::Pressed, &self.shown)
                }
                _ => Ok(()),
            },
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                r.drag = (state == ElementState::Pressed).then_some(r.cursor);
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                r.cursor = (position.x, position.y);
                if let Some((x, y)) = r.drag {
                    r.fly.turn((position.x - x) as f32, (position.y - y) as f32);
                    r.drag = Some(r.cursor);
                }
                Ok(())
            }
            WindowEvent::RedrawRequested => match self.redraw() {
                Ok(true) => Ok(()),
                Ok(false) => {
                    event_loop.exit();
                    Ok(())
                }
                Err(e) => Err(e),
            },
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }
}
