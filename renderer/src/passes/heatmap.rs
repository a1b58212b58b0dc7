//! Light-count and decal-count heatmap debug views: each pixel coloured by how many lights (or
//! decals) its tile or froxel lists (reference 000's "Visualize Light Count"), with a legend
//! strip along the bottom. It replaces forward shading and tonemapping in the frame's pass list.

use crate::frame_data::ConfigError;
use shaders_gen::forward::heatmap;

use super::{Pass, draw_fullscreen, fullscreen_pipeline};
use crate::GpuContext;
use crate::culling::Method;
use crate::frame_data::{
    FrameInputs, FrameResources, LightListHandles, ListGeometry, RenderError, RenderPath,
    RendererConfig,
};
use crate::graph::{RenderGraph, TextureAccess};
use crate::shader::ShaderProgram;

/// The heatmap pass: its program, pipeline and parameters.
#[derive(Debug)]
pub struct HeatmapPass {
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    /// Clustered lists need the depth buffer to find a pixel's slice.
    needs_depth: bool,
    /// Show the decal lists rather than the light lists.
    decals: bool,
}

impl HeatmapPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let clustered = match config.path {
            RenderPath::Naive | RenderPath::NaivePrez => {
                return Err(RenderError::Config(ConfigError::HeatmapNeedsLists));
            }
            path => path == RenderPath::Clustered,
        };
        let msaa = match (clustered, config.msaa) {
            (true, 2) => heatmap::Msaa::Msaa2,
            (true, 4) => heatmap::Msaa::Msaa4,
            (true, 8) => heatmap::Msaa::Msaa8,
            _ => heatmap::Msaa::Msaa1,
        };
        let list = if clustered {
            heatmap::List::List2
        } else {
            heatmap::List::List1
        };
        let variant = heatmap::variant(heatmap::VariantKey { list, msaa })?;
        let program = gpu.program(variant)?;
        Ok(Self {
            pipeline: fullscreen_pipeline(
                gpu.device(),
                &program,
                "fs_heatmap",
                config.output_format,
            ),
            program,
            params: gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("heatmap"),
                size: size_of::<heatmap::HeatmapParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            needs_depth: clustered,
            decals: config.view == crate::frame_data::FrameView::DecalHeatmap,
        })
    }

    fn write_params(&self, frame: &FrameInputs, method: Method) {
        let c = &frame.config;
        let camera = &frame.camera;
        let g = ListGeometry::new(Some(method), c, camera);
        let params = heatmap::HeatmapParams::new(
            camera.projection.inverse(),
            frame.screen(),
            g.tiles,
            g.tile,
            g.slices,
            g.near,
            g.far,
            if self.decals {
                c.decal_heatmap_max
            } else {
                c.heatmap_max
            },
            if self.decals { g.decal_section } else { 0 },
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }
}

impl Pass for HeatmapPass {
    fn name(&self) -> &'static str {
        if self.decals {
            "decal heatmap"
        } else {
            "light heatmap"
        }
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "light heatmap",
                input,
            })
        };
        let lists = resources
            .light_lists
            .clone()
            .ok_or(missing("light lists"))?;
        let depth = resources.depth.ok_or(missing("depth buffer"))?;
        self.write_params(frame, lists.method);
        let (target, output_format) = (resources.output, frame.config.output_format);
        let needs_depth = self.needs_depth;
        let program = self.program.clone();
        let (pipeline, params) = (self.pipeline.clone(), self.params.clone());
        let lights = std::sync::Arc::clone(&frame.lights);
        let mut pass = graph.add_pass(self.name());
        LightListHandles::read_by(Some(&lists), &mut pass);
        pass.write_texture(&mut resources.output, TextureAccess::ColorAttachment);
        if needs_depth {
            pass.read_texture(depth, TextureAccess::Sampled);
        }
        pass.execute(move |ctx| {
            let depth_view =
                needs_depth.then(|| ctx.texture(depth).create_view(&Default::default()));
            let out_view = crate::frame_data::output_view(ctx.texture(target), output_format);
            let group = heatmap::Group0 {
                params: params.as_entire_buffer_binding(),
                light_set: lights.bindings(),
                light_lists: LightListHandles::bindings(Some(&lists), ctx),
                depth: depth_view.as_ref(),
                depth_ms: depth_view.as_ref(),
            }
            .bind_group(
                ctx.device,
                program.layout(0),
                program.variant,
                "light heatmap",
            );
            draw_fullscreen(ctx, "light heatmap", &pipeline, group, &out_view);
        });
        Ok(())
    }
}
