//! The render pipelines of one renderer configuration, from the DSL's generated variants.

use shaders_gen::forward::{forward, heatmap, prez, tonemap};

use super::{RenderError, RendererConfig};
use crate::passes::{forward::HDR_FORMAT, prez::DEPTH_FORMAT, stream};
use crate::shader::ShaderProgram;

/// Every pipeline a frame uses.
#[derive(Debug)]
pub struct Pipelines {
    pub prez_program: ShaderProgram,
    /// Pre-Z for alpha-masked materials (a fragment stage that discards below the cutoff).
    pub prez_mask_program: ShaderProgram,
    prez_mask: [wgpu::RenderPipeline; 2],
    pub forward_program: ShaderProgram,
    pub tonemap_program: ShaderProgram,
    prez: [wgpu::RenderPipeline; 2],
    /// `[blend][double_sided]`.
    forward: [[wgpu::RenderPipeline; 2]; 2],
    pub tonemap: wgpu::RenderPipeline,
    /// Present when the configuration's view is the light heatmap.
    pub heatmap: Option<HeatmapPipeline>,
}

/// The heatmap debug view's program and pipeline.
#[derive(Debug)]
pub struct HeatmapPipeline {
    pub program: ShaderProgram,
    pub pipeline: wgpu::RenderPipeline,
    /// Clustered lists need the depth buffer to find a pixel's slice.
    pub needs_depth: bool,
}

impl Pipelines {
    pub fn prez(&self, double_sided: bool) -> &wgpu::RenderPipeline {
        &self.prez[usize::from(double_sided)]
    }

    pub fn prez_mask(&self, double_sided: bool) -> &wgpu::RenderPipeline {
        &self.prez_mask[usize::from(double_sided)]
    }

    pub fn forward(&self, blend: bool, double_sided: bool) -> &wgpu::RenderPipeline {
        &self.forward[usize::from(blend)][usize::from(double_sided)]
    }

    pub fn new(
        device: &wgpu::Device,
        caps: &crate::Capabilities,
        config: &RendererConfig,
    ) -> Result<Self, RenderError> {
        let prez_program = ShaderProgram::new(
            device,
            caps,
            prez::variant(prez::VariantKey { alpha_mask: false }),
        )?;
        let list = config.path.list_axis();
        let key = |blend| forward::VariantKey {
            list,
            blend,
            scalarize: config.scalarize && config.path.is_culled(),
        };
        let forward_opaque = ShaderProgram::new(device, caps, forward::variant(key(false))?)?;
        let forward_blend = ShaderProgram::new(device, caps, forward::variant(key(true))?)?;
        let tonemap_program = ShaderProgram::new(
            device,
            caps,
            tonemap::variant(tonemap::VariantKey {
                curve: tonemap::Curve::Curve0,
            }),
        )?;
        let multisample = wgpu::MultisampleState {
            count: config.msaa,
            ..Default::default()
        };
        let cull = |double_sided: bool| {
            if double_sided {
                None
            } else {
                Some(wgpu::Face::Back)
            }
        };
        let prez_streams = [
            stream(0, wgpu::VertexFormat::Float32x3),
            stream(1, wgpu::VertexFormat::Float32x2),
        ];
        let prez_layouts: Vec<_> = prez_streams
            .iter()
            .zip([12, 8])
            .map(|(a, stride)| Some(layout(a, stride)))
            .collect();
        let prez_mask_program = ShaderProgram::new(
            device,
            caps,
            prez::variant(prez::VariantKey { alpha_mask: true }),
        )?;
        let prez_pipeline = |program: &ShaderProgram, masked: bool, double_sided: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if masked { "pre-z masked" } else { "pre-z" }),
                layout: Some(&program.pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &program.module,
                    entry_point: Some("vs_prez"),
                    compilation_options: Default::default(),
                    buffers: &prez_layouts,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: cull(double_sided),
                    ..Default::default()
                },
                depth_stencil: Some(depth_state(true, wgpu::CompareFunction::Less)),
                multisample,
                // Opaque draws need no fragment stage at all; masked ones discard.
                fragment: masked.then(|| wgpu::FragmentState {
                    module: &program.module,
                    entry_point: Some("fs_prez_mask"),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let prez = [false, true].map(|d| prez_pipeline(&prez_program, false, d));
        let prez_mask = [false, true].map(|d| prez_pipeline(&prez_mask_program, true, d));
        let forward_streams = [
            stream(0, wgpu::VertexFormat::Float32x3),
            stream(1, wgpu::VertexFormat::Float32x3),
            stream(2, wgpu::VertexFormat::Float32x2),
            stream(3, wgpu::VertexFormat::Float32x4),
        ];
        let forward_layouts: Vec<_> = forward_streams
            .iter()
            .zip([12, 12, 8, 16])
            .map(|(a, stride)| Some(layout(a, stride)))
            .collect();
        let forward_pipeline = |program: &ShaderProgram, blend: bool, double_sided: bool| {
            let target = wgpu::ColorTargetState {
                format: HDR_FORMAT,
                blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
                write_mask: wgpu::ColorWrites::ALL,
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if blend { "forward blend" } else { "forward" }),
                layout: Some(&program.pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &program.module,
                    entry_point: Some("vs_forward"),
                    compilation_options: Default::default(),
                    buffers: &forward_layouts,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: cull(double_sided),
                    ..Default::default()
                },
                // With a pre-pass, opaque surfaces are in the depth buffer already and blended
                // ones test against it; without one, opaque draws write depth themselves.
                depth_stencil: Some(if config.path.has_prepass() || blend {
                    depth_state(false, wgpu::CompareFunction::LessEqual)
                } else {
                    depth_state(true, wgpu::CompareFunction::Less)
                }),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: &program.module,
                    entry_point: Some("fs_forward"),
                    compilation_options: Default::default(),
                    targets: &[Some(target)],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let forward = [
            [
                forward_pipeline(&forward_opaque, false, false),
                forward_pipeline(&forward_opaque, false, true),
            ],
            [
                forward_pipeline(&forward_blend, true, false),
                forward_pipeline(&forward_blend, true, true),
            ],
        ];
        let tonemap = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("tonemap"),
            layout: Some(&tonemap_program.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &tonemap_program.module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &tonemap_program.module,
                entry_point: Some("fs_tonemap"),
                compilation_options: Default::default(),
                targets: &[Some(config.output_format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let heatmap = match (config.view, config.path) {
            (super::FrameView::Lit, _) => None,
            (
                super::FrameView::Heatmap,
                super::RenderPath::Naive | super::RenderPath::NaivePrez,
            ) => {
                return Err(RenderError::HeatmapNeedsLists);
            }
            (super::FrameView::Heatmap, path) => {
                let clustered = path == super::RenderPath::Clustered;
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
                let program = ShaderProgram::new(
                    device,
                    caps,
                    heatmap::variant(heatmap::VariantKey { list, msaa })?,
                )?;
                let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("light heatmap"),
                    layout: Some(&program.pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &program.module,
                        entry_point: Some("vs_fullscreen"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: None,
                    multisample: wgpu::MultisampleState::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &program.module,
                        entry_point: Some("fs_heatmap"),
                        compilation_options: Default::default(),
                        targets: &[Some(config.output_format.into())],
                    }),
                    multiview_mask: None,
                    cache: None,
                });
                Some(HeatmapPipeline {
                    program,
                    pipeline,
                    needs_depth: clustered,
                })
            }
        };
        Ok(Self {
            prez_program,
            prez_mask_program,
            prez_mask,
            forward_program: forward_opaque,
            tonemap_program,
            prez,
            forward,
            tonemap,
            heatmap,
        })
    }
}

fn layout(attributes: &[wgpu::VertexAttribute], stride: u64) -> wgpu::VertexBufferLayout<'_> {
    wgpu::VertexBufferLayout {
        array_stride: stride,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    }
}

fn depth_state(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}
