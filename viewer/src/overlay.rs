//! The on-screen overlay: per-pass GPU timings and the settings, drawn with egui (egui-winit for
//! input, egui-wgpu for drawing) over the frame in the swapchain texture.

use renderer::GpuContext;
use renderer::graph::PassTiming;
use winit::event::WindowEvent;
use winit::window::Window;

/// egui's context, input state and wgpu renderer.
pub struct Overlay {
    ctx: egui::Context,
    state: egui_winit::State,
    painter: egui_wgpu::Renderer,
}

impl Overlay {
    pub fn new(window: &Window, device: &wgpu::Device, format: wgpu::TextureFormat) -> Overlay {
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        let painter =
            egui_wgpu::Renderer::new(device, format, egui_wgpu::RendererOptions::default());
        Overlay {
            ctx,
            state,
            painter,
        }
    }

    /// Gives a window event to egui; `true` when egui used it (the camera should not).
    pub fn on_event(&mut self, window: &Window, event: &WindowEvent) -> bool {
        self.state.on_window_event(window, event).consumed
    }

    /// Draws the overlay over `target`.
    pub fn draw(
        &mut self,
        window: &Window,
        gpu: &GpuContext,
        target: &wgpu::Texture,
        timings: &[PassTiming],
        status: &[String],
    ) {
        let input = self.state.take_egui_input(window);
        let output = self.ctx.run_ui(input, |ui| {
            egui::Window::new("renderer")
                .default_pos([12.0, 12.0])
                .resizable(false)
                .show(ui.ctx(), |ui| {
                    for line in status {
                        ui.label(line);
                    }
                    ui.separator();
                    egui::Grid::new("timings").striped(true).show(ui, |ui| {
                        for t in timings {
                            ui.label(t.pass.to_string());
                            ui.monospace(format!("{:8.3} ms", t.gpu_ms));
                            ui.end_row();
                        }
                        let total: f64 = timings.iter().map(|t| t.gpu_ms).sum();
                        ui.strong("GPU total");
                        ui.monospace(format!("{total:8.3} ms"));
                        ui.end_row();
                    });
                    ui.separator();
                    ui.small("WASD/QE fly, drag to look, 1-9 path (6, 7: TBDR; 8: light volumes; 9: visibility buffer), M MSAA, T tile, H heatmap, C decal heatmap, V shadow atlas, P particle lighting (atlas / per pixel), O particle atlas, F shading frequency (deferred paths), +/- lights");
                });
        });
        self.state
            .handle_platform_output(window, output.platform_output);
        let jobs = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [target.width(), target.height()],
            pixels_per_point: output.pixels_per_point,
        };
        let mut textures = output.textures_delta;
        for (id, deltas) in textures.set.drain() {
            for delta in &deltas {
                self.painter
                    .update_texture(gpu.device(), gpu.queue(), id, delta);
            }
        }
        let mut encoder = gpu
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("overlay"),
            });
        let extra =
            self.painter
                .update_buffers(gpu.device(), gpu.queue(), &mut encoder, &jobs, &screen);
        let view = target.create_view(&wgpu::TextureViewDescriptor::default());
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("overlay"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.painter
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        gpu.queue()
            .submit(extra.into_iter().chain([encoder.finish()]));
        for id in textures.free.drain() {
            self.painter.free_texture(&id);
        }
    }
}
