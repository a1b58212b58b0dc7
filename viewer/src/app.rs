//! The window: winit events in, one renderer frame into the swapchain texture per redraw, the
//! overlay on top, the settings keys that rebuild the renderer, and shader hot reload (the
//! watched sources recompiled off this thread, the renderer rebuilt on the new WGSL, a refused
//! edit shown). What the settings keys, reloads and resizes do to the running state is in
//! [`settings`].

mod settings;

use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use renderer::frame::{Renderer, RendererConfig};
use renderer::graph::PassTiming;
use renderer::{GpuContext, GpuOptions, readback};
use viewer::fly::{Fly, Held};
use viewer::scene::{Shown, load};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use viewer::hot_reload::Watch;

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
    /// The newest frame's scene draws and CPU time (prepare + record + submit, ms).
    draws: Option<renderer::frame::SceneDrawReport>,
    cpu_ms: f64,
    last: Instant,
    light_count: usize,
    message: Option<String>,
    /// Instances added with `I` (kept across renderer rebuilds).
    added: viewer::instances::Added,
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
                .and_then(|dir| match Watch::new(dir) {
                    Ok(w) => Some(w),
                    // The viewer runs on without hot reload.
                    Err(e) => {
                        eprintln!("hot reload: off: {e}");
                        None
                    }
                })
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
        let surface = gpu.instance().create_surface(window.clone())?;
        let caps = surface.get_capabilities(gpu.adapter());
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .context("the surface offers no format")?;
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        // Frames copied into the swap chain let the renderer tonemap in compute.
        usage |= caps.usages & wgpu::TextureUsages::COPY_DST;
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
        surface.configure(gpu.device(), &surface_config);
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
        let overlay = Overlay::new(&window, gpu.device(), format);
        // With the renderer's choices for the device made (the visibility raster).
        let config = *renderer.config();
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
            draws: None,
            cpu_ms: 0.0,
            last: Instant::now(),
            light_count: self.args.lights,
            message: None,
            added: viewer::instances::Added::default(),
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
            r.hot_reloaded(outcome);
            self.shot_due = true;
        }
        let texture = match r.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                r.surface.configure(r.gpu.device(), &r.surface_config);
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
        r.draws = report.scene_draws.or(r.draws);
        r.cpu_ms = report.cpu_upload_ms + report.cpu_graph_ms + report.cpu_submit_ms;
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
        r.gpu.queue().present(texture);
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
    let mut rgba = readback::read_texture_rgba8(gpu.device(), gpu.queue(), texture)?;
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
