//! The page's API to JavaScript (wasm32 only): [`WebDemo`] opens the browser's WebGPU device,
//! renders the [`Showcase`] into an offscreen target each frame, copies it onto the page's
//! canvas, and reads it back without blocking for tests. Nothing here waits on the GPU: the
//! browser runs the readback's mapping from its event loop.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::{Arc, Mutex, PoisonError};

use renderer::frame::{FrameCamera, Renderer, create_target};
use renderer::graph::PassTiming;
use renderer::{GpuContext, GpuOptions};
use wasm_bindgen::prelude::*;

use crate::showcase::{Orbit, Settings, Showcase};

/// Panics reach the browser's console with their message (wasm32's default prints nothing).
#[wasm_bindgen(start)]
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        web_sys::console::error_1(&JsValue::from_str(&info.to_string()));
    }));
}

/// The demo: a device, the showcase, its renderer and where frames go.
#[wasm_bindgen]
#[derive(Debug)]
pub struct WebDemo {
    state: Rc<RefCell<State>>,
}

#[derive(Debug)]
struct State {
    gpu: GpuContext,
    /// The page's canvas, configured as `Rgba8Unorm`; `None` renders offscreen only (tests).
    canvas: Option<(wgpu::Surface<'static>, wgpu::SurfaceConfiguration)>,
    settings: Settings,
    showcase: Showcase,
    renderer: Renderer,
    /// The renderer's output (`Rgba8UnormSrgb`, stored as `Rgba8Unorm` where the compute
    /// tonemap writes it: `create_target`), copied onto the canvas: the canvas takes no sRGB
    /// format, and a copy keeps the encoded bytes.
    target: wgpu::Texture,
    orbit: Orbit,
    /// The newest frame's per-pass GPU timings (empty without timestamp queries).
    timings: Vec<PassTiming>,
    /// What the browser reported wrong since it was last taken: a validation or out-of-memory
    /// error drops the submission it happened in, so a frame is never trusted while any is
    /// pending (`WebDemo::read_frame` refuses it).
    errors: DeviceErrors,
}

/// The device's uncaptured errors, in the order the browser delivered them.
type DeviceErrors = Arc<Mutex<Vec<String>>>;

/// Records every uncaptured error of `gpu`'s device.
fn watch_errors(gpu: &GpuContext) -> DeviceErrors {
    let errors = DeviceErrors::default();
    let sink = Arc::clone(&errors);
    gpu.device()
        .on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
            sink.lock()
                .unwrap_or_else(PoisonError::into_inner)
                .push(error.to_string());
        }));
    errors
}

/// Takes the errors recorded so far.
fn take(errors: &DeviceErrors) -> Vec<String> {
    std::mem::take(&mut *errors.lock().unwrap_or_else(PoisonError::into_inner))
}

/// A JavaScript error carrying `error`'s message and its causes.
fn js_error(error: &dyn std::error::Error) -> JsError {
    let mut message = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        message.push_str(": ");
        message.push_str(&cause.to_string());
        source = cause.source();
    }
    JsError::new(&message)
}

#[wasm_bindgen]
impl WebDemo {
    /// Opens the browser's WebGPU adapter and builds the courtyard with the settings of
    /// `query` (a page address's query, `Settings::from_query`). Frames go onto `canvas`,
    /// resized to the settings' size, or stay offscreen when it is `undefined`.
    pub async fn create(
        canvas: Option<web_sys::HtmlCanvasElement>,
        query: String,
    ) -> Result<WebDemo, JsError> {
        let settings = Settings::from_query(&query).map_err(|e| JsError::new(&e))?;
        let gpu = GpuContext::new(&GpuOptions::default())
            .await
            .map_err(|e| match e {
                // The native message's advice (a Vulkan driver) does not apply in a page.
                renderer::GpuError::NoAdapter { .. } => JsError::new(
                    "the browser offered no WebGPU adapter (Chromium without a supported GPU \
                     needs --enable-unsafe-webgpu)",
                ),
                other => js_error(&other),
            })?;
        let errors = watch_errors(&gpu);
        let showcase = Showcase::courtyard(&settings);
        let renderer = showcase
            .renderer(&gpu, &settings)
            .map_err(|e| js_error(&e))?;
        let target = create_target(gpu.device(), renderer.config());
        let canvas = match canvas {
            Some(canvas) => Some(configure_canvas(&gpu, canvas, &settings)?),
            None => None,
        };
        let orbit = showcase.orbit;
        Ok(Self {
            state: Rc::new(RefCell::new(State {
                gpu,
                canvas,
                settings,
                showcase,
                renderer,
                target,
                orbit,
                timings: Vec::new(),
                errors,
            })),
        })
    }

    /// The adapter and what the renderer uses of it, as the native tools print it.
    pub fn adapter(&self) -> String {
        self.state.borrow().gpu.report().to_string()
    }

    /// The names the path switch offers (`RenderPath::name`), in the tools' order.
    pub fn paths() -> Vec<String> {
        renderer::frame::RenderPath::ALL
            .iter()
            .map(|p| p.name().to_owned())
            .collect()
    }

    /// The names of the running renderer's passes, in frame order (what the path switch
    /// changed).
    pub fn pass_names(&self) -> Vec<String> {
        self.state
            .borrow()
            .renderer
            .pass_names()
            .into_iter()
            .map(str::to_owned)
            .collect()
    }

    /// The MSAA counts this device can render with.
    pub fn msaa_counts(&self) -> Vec<u32> {
        self.state.borrow().gpu.capabilities().msaa_counts()
    }

    /// Renders one frame of the orbit camera and shows it on the canvas.
    pub fn frame(&mut self) -> Result<(), JsError> {
        self.state.borrow_mut().frame()
    }

    /// Whether frames are timed per pass: where the browser has `timestamp-query`. WebGPU
    /// writes timestamps only at the bounds of compute and render passes, so a graph pass's
    /// time is the sum of its compute and render passes; one that only copies is not listed.
    pub fn times_passes(&self) -> bool {
        self.state.borrow().gpu.capabilities().timestamp_query
    }

    /// The newest frame's graph passes in the order they were recorded: what
    /// [`WebDemo::timings`] names.
    pub fn graph_passes(&self) -> Vec<String> {
        self.state
            .borrow()
            .renderer
            .graph_passes()
            .unwrap_or_default()
    }

    /// Collects the frame timings that have arrived since the last frame, without rendering
    /// one ([`WebDemo::frame`] collects them too): for a page that reads one frame's timings.
    pub fn collect_timings(&mut self) {
        self.state.borrow_mut().collect_timings(None);
    }

    /// The newest per-pass GPU timings that have arrived, as `[pass, milliseconds]` pairs
    /// (empty where [`WebDemo::times_passes`] is false). They arrive a frame or more after the
    /// frame they time, and [`WebDemo::frame`] collects them.
    pub fn timings(&self) -> js_sys::Array {
        self.state
            .borrow()
            .timings
            .iter()
            .map(|t| js_sys::Array::of2(&JsValue::from_str(&t.pass), &JsValue::from_f64(t.gpu_ms)))
            .collect()
    }

    /// Switches to the path named `path` (`RenderPath::name`) at `msaa` samples per pixel,
    /// keeping the running renderer when the renderer refuses them (the error says why: a
    /// path whose kernels exceed the device's limits, an MSAA count it lacks). Nothing is
    /// rebuilt when both are already running.
    pub fn configure(&mut self, path: &str, msaa: u32) -> Result<(), JsError> {
        let path = path.parse().map_err(|e: String| JsError::new(&e))?;
        let mut state = self.state.borrow_mut();
        let settings = Settings {
            path,
            msaa,
            ..state.settings
        };
        if settings == state.settings {
            return Ok(());
        }
        state.rebuild(settings)
    }

    /// The running path's name.
    pub fn path(&self) -> String {
        self.state.borrow().settings.path.name().to_owned()
    }

    /// The running MSAA count.
    pub fn msaa(&self) -> u32 {
        self.state.borrow().settings.msaa
    }

    /// The frame's width in pixels.
    pub fn width(&self) -> u32 {
        self.state.borrow().settings.width
    }

    /// The frame's height in pixels.
    pub fn height(&self) -> u32 {
        self.state.borrow().settings.height
    }

    /// Replaces the scene with a glTF one (a `.glb`, or a `.gltf` with embedded buffers), with
    /// procedural lights, decals and particles placed in it as in the courtyard.
    pub fn load_gltf(&mut self, bytes: &[u8]) -> Result<(), JsError> {
        let mut state = self.state.borrow_mut();
        let showcase = Showcase::from_gltf(bytes, &state.settings).map_err(|e| js_error(&e))?;
        let renderer = showcase
            .renderer(&state.gpu, &state.settings)
            .map_err(|e| js_error(&e))?;
        state.orbit = showcase.orbit;
        state.showcase = showcase;
        state.renderer = renderer;
        state.timings.clear();
        Ok(())
    }

    /// Turns the camera by a pointer drag of `dx`, `dy` pixels.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.state.borrow_mut().orbit.drag(dx, dy);
    }

    /// Moves the camera closer (`factor` < 1) or further.
    pub fn zoom(&mut self, factor: f32) {
        self.state.borrow_mut().orbit.zoom(factor);
    }

    /// The errors the browser reported since the last call (validation, out of memory), each
    /// as its message; the page shows them.
    pub fn take_errors(&self) -> Vec<String> {
        take(&self.state.borrow().errors)
    }

    /// The last frame's pixels, RGBA8 rows top to bottom (sRGB-encoded), read back without
    /// blocking. Rejected when the browser reported an error since the last call of this or
    /// `take_errors`: a dropped submission leaves an older frame in the target.
    pub fn read_frame(&self) -> js_sys::Promise {
        let (gpu, target, errors) = {
            let state = self.state.borrow();
            (
                state.gpu.clone(),
                state.target.clone(),
                Arc::clone(&state.errors),
            )
        };
        wasm_bindgen_futures::future_to_promise(async move {
            let pixels =
                renderer::readback::read_texture_rgba8_async(gpu.device(), gpu.queue(), &target)
                    .await
                    .map_err(|e| JsValue::from(js_error(&e)))?;
            // The browser delivers a submission's errors before its later mappings complete.
            let reported = take(&errors);
            if !reported.is_empty() {
                return Err(JsError::new(&format!(
                    "the browser reported {} error(s) while rendering: {}",
                    reported.len(),
                    reported.join("; ")
                ))
                .into());
            }
            Ok(js_sys::Uint8Array::from(pixels.as_slice()).into())
        })
    }
}

impl State {
    fn camera(&self) -> FrameCamera {
        let aspect = self.settings.width as f32 / self.settings.height as f32;
        self.orbit.camera(aspect)
    }

    fn frame(&mut self) -> Result<(), JsError> {
        let camera = self.camera();
        let report = self
            .renderer
            .render(&camera, &self.target)
            .map_err(|e| js_error(&e))?;
        self.collect_timings(report.timings);
        let Some((surface, config)) = &self.canvas else {
            return Ok(());
        };
        let frame = match surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                surface.configure(self.gpu.device(), config);
                return Ok(());
            }
            other => return Err(JsError::new(&format!("no canvas texture: {other:?}"))),
        };
        let mut encoder =
            self.gpu
                .device()
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("frame onto the canvas"),
                });
        encoder.copy_texture_to_texture(
            self.target.as_image_copy(),
            frame.texture.as_image_copy(),
            self.target.size(),
        );
        self.gpu.queue().submit([encoder.finish()]);
        self.gpu.queue().present(frame);
        Ok(())
    }

    /// Keeps the newest timings that have arrived: those drained now, else `reported` (what a
    /// frame's report carried, older than any drained after it).
    fn collect_timings(&mut self, reported: Option<Vec<PassTiming>>) {
        if let Some(newest) = self.renderer.drain_timings().pop().or(reported) {
            self.timings = newest;
        }
    }

    /// A renderer for `settings`, replacing the current one only when it could be built.
    fn rebuild(&mut self, settings: Settings) -> Result<(), JsError> {
        let renderer = self
            .showcase
            .renderer(&self.gpu, &settings)
            .map_err(|e| js_error(&e))?;
        self.renderer = renderer;
        self.settings = settings;
        // The old renderer's timings are not this one's.
        self.timings.clear();
        Ok(())
    }
}

/// Sizes `canvas` to the frame and configures it as an `Rgba8Unorm` copy destination.
fn configure_canvas(
    gpu: &GpuContext,
    canvas: web_sys::HtmlCanvasElement,
    settings: &Settings,
) -> Result<(wgpu::Surface<'static>, wgpu::SurfaceConfiguration), JsError> {
    canvas.set_width(settings.width);
    canvas.set_height(settings.height);
    let surface = gpu
        .instance()
        .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
        .map_err(|e| js_error(&e))?;
    let config = wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST,
        format: wgpu::TextureFormat::Rgba8Unorm,
        width: settings.width,
        height: settings.height,
        present_mode: wgpu::PresentMode::Fifo,
        desired_maximum_frame_latency: 2,
        alpha_mode: wgpu::CompositeAlphaMode::Opaque,
        view_formats: vec![],
        color_space: wgpu::SurfaceColorSpace::default(),
    };
    surface.configure(gpu.device(), &config);
    Ok((surface, config))
}
