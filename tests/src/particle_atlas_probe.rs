//! What the particle lighting reference tests read from a frame and put back into another.
//!
//! [`AtlasProbe`], a pass inserted after `"particle lighting"`, copies the inputs the response
//! depends on (the particle view, lights, emitters, particles, regions, sorted keys and layout
//! state, the shadow views and atlas depth) and the lit atlas *texture* the draw samples.
//! [`AtlasOverride`], inserted at the same place in a second renderer, writes a probed frame's
//! particles, regions, keys and state and an atlas of given texels over that frame's own, so
//! the second frame draws the first frame's particles, in the first frame's atlas layout, lit
//! by those texels (slots and regions come from GPU atomics, so two frames of the same
//! particles need not share a layout).

use renderer::frame::ConfigError;
use std::sync::{Arc, Mutex};

use renderer::GpuContext;
use renderer::frame::RenderError;
use renderer::frame_data::{FrameInputs, FrameResources};
use renderer::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};
use renderer::passes::Pass;
use wgpu::util::DeviceExt;

use crate::frame_probe::{ShadowCopies, ShadowInputs, copy_target, padded_row, read_bytes, unpad};
use crate::particle_light_reference::{LightingScene, Region, scene_from_bytes};

/// The buffers copied, by the kernels' static names.
const NAMES: [&str; 8] = [
    "VIEW",
    "LIGHTS",
    "DIRECTIONAL",
    "EMITTERS",
    "PARTICLES",
    "REGIONS",
    "KEYS",
    "STATE",
];

#[derive(Debug)]
struct Copies {
    buffers: Vec<(&'static str, wgpu::Buffer)>,
    atlas: wgpu::Buffer,
    side: u32,
    shadows: ShadowCopies,
}

/// Copies a frame's particle lighting inputs and lit atlas; insert after `"particle lighting"`.
#[derive(Debug, Default)]
pub struct AtlasProbe {
    copies: Mutex<Option<Copies>>,
}

/// One frame's particle lighting inputs and lit atlas, read back.
#[derive(Debug, Clone)]
pub struct ProbedAtlas {
    pub buffers: Vec<(&'static str, Vec<u8>)>,
    /// The atlas texture's texels (`Rg11b10Ufloat` bits), row-major.
    pub atlas: Vec<u32>,
    pub side: u32,
    pub shadows: ShadowInputs,
}

impl ProbedAtlas {
    /// The bytes of buffer `name` (empty when not copied).
    pub fn buffer(&self, name: &str) -> &[u8] {
        self.buffers
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(&[], |(_, b)| b.as_slice())
    }

    /// The regions of the visible particles: the first `STATE[17]` sorted keys' slots.
    pub fn regions(&self) -> Vec<Region> {
        let state: Vec<u32> = bytemuck::pod_collect_to_vec(self.buffer("STATE"));
        let keys: Vec<[u32; 2]> = bytemuck::pod_collect_to_vec(self.buffer("KEYS"));
        let regions: Vec<u32> = bytemuck::pod_collect_to_vec(self.buffer("REGIONS"));
        keys.iter()
            .take(state[17] as usize)
            .map(|k| Region::unpack(k[1], regions[k[1] as usize]))
            .collect()
    }

    /// The response's inputs, for the CPU evaluation.
    pub fn scene(&self) -> LightingScene {
        scene_from_bytes(
            self.buffer("VIEW"),
            self.buffer("LIGHTS"),
            self.buffer("DIRECTIONAL"),
            self.buffer("EMITTERS"),
            self.buffer("PARTICLES"),
            self.shadows.clone(),
        )
    }
}

impl AtlasProbe {
    /// What the last frame copied.
    pub fn take(&self, gpu: &GpuContext) -> Result<ProbedAtlas, String> {
        let copies = self
            .copies
            .lock()
            .map_err(|_| "the probe's lock is poisoned")?
            .take()
            .ok_or("no frame was probed")?;
        let mut buffers = vec![];
        for (name, b) in &copies.buffers {
            buffers.push((*name, read_bytes(gpu, b)?));
        }
        let rows = unpad(
            &read_bytes(gpu, &copies.atlas)?,
            copies.side * 4,
            copies.side,
        );
        Ok(ProbedAtlas {
            buffers,
            atlas: bytemuck::pod_collect_to_vec(&rows),
            side: copies.side,
            shadows: copies.shadows.read(gpu)?,
        })
    }
}

fn missing(pass: &'static str, input: &'static str) -> RenderError {
    RenderError::Config(ConfigError::MissingInput { pass, input })
}

impl Pass for AtlasProbe {
    fn name(&self) -> &'static str {
        "particle atlas probe"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let name = self.name();
        let p = resources
            .particles
            .clone()
            .ok_or(missing(name, "particles"))?;
        let lit = p.lit_atlas.ok_or(missing(name, "lit particle atlas"))?;
        let shadows = resources.shadows.clone().ok_or(missing(name, "shadows"))?;
        let device = frame.gpu.device();
        let lights = &frame.lights;
        let sources = [
            &p.view,
            &lights.punctual_buffer,
            &lights.directional_buffer,
            &p.emitters,
            &p.particles,
            &p.regions,
            &p.keys,
            &p.state,
        ]
        .map(Clone::clone);
        let targets: Vec<(&'static str, wgpu::Buffer)> = NAMES
            .iter()
            .zip(&sources)
            .map(|(n, b)| (*n, copy_target(device, n, b.size())))
            .collect();
        let side = p.atlas_side;
        let atlas = copy_target(
            device,
            "probe particle atlas",
            u64::from(padded_row(side * 4)) * u64::from(side),
        );
        // The atlas copy is the pass's tracked output, so the graph keeps the pass.
        let mut out =
            resources.import_buffer(graph, "probe atlas", &atlas, ImportAccess::ReadWrite);
        let shadow_copies =
            ShadowCopies::new(device, &shadows, frame.config.fitted_shadows().atlas_size);
        graph
            .add_pass(name)
            .read_texture(lit, TextureAccess::CopySrc)
            .read_texture(shadows.atlas, TextureAccess::CopySrc)
            .write_buffer(&mut out, BufferAccess::CopyDst)
            .execute({
                let (targets, atlas, shadow_copies) =
                    (targets.clone(), atlas.clone(), shadow_copies.clone());
                move |ctx| {
                    for (from, (_, to)) in sources.iter().zip(&targets) {
                        ctx.encoder
                            .copy_buffer_to_buffer(from, 0, to, 0, from.size());
                    }
                    let texture = ctx.texture(lit).clone();
                    ctx.encoder.copy_texture_to_buffer(
                        texture.as_image_copy(),
                        wgpu::TexelCopyBufferInfo {
                            buffer: &atlas,
                            layout: wgpu::TexelCopyBufferLayout {
                                offset: 0,
                                bytes_per_row: Some(padded_row(side * 4)),
                                rows_per_image: Some(side),
                            },
                        },
                        texture.size(),
                    );
                    shadow_copies.record(ctx, &shadows);
                }
            });
        if let Ok(mut slot) = self.copies.lock() {
            *slot = Some(Copies {
                buffers: targets,
                atlas,
                side,
                shadows: shadow_copies,
            });
        }
        Ok(())
    }
}

/// Puts a probed frame's particles, layout and the given atlas texels into a frame; insert
/// after `"particle lighting"`.
#[derive(Debug)]
pub struct AtlasOverride {
    /// `PARTICLES`, `REGIONS`, `KEYS` and `STATE` of the probed frame.
    buffers: Arc<[Vec<u8>; 4]>,
    /// The atlas, `Rg11b10Ufloat` bits row-major.
    texels: Arc<Vec<u32>>,
}

impl AtlasOverride {
    pub fn new(frame: &ProbedAtlas, texels: Vec<u32>) -> Self {
        let b = |n| frame.buffer(n).to_vec();
        Self {
            buffers: Arc::new([b("PARTICLES"), b("REGIONS"), b("KEYS"), b("STATE")]),
            texels: Arc::new(texels),
        }
    }
}

impl Pass for AtlasOverride {
    fn name(&self) -> &'static str {
        "particle atlas override"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let name = self.name();
        let device = frame.gpu.device();
        let p = resources
            .particles
            .as_mut()
            .ok_or(missing(name, "particles"))?;
        let mut lit = p.lit_atlas.ok_or(missing(name, "lit particle atlas"))?;
        let upload = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::COPY_SRC,
            })
        };
        let sources: Vec<wgpu::Buffer> = self
            .buffers
            .iter()
            .map(|b| upload("override particle buffer", b))
            .collect();
        let texels = upload("override atlas", bytemuck::cast_slice(&self.texels));
        let destinations = [&p.particles, &p.regions, &p.keys, &p.state].map(Clone::clone);
        let side = p.atlas_side;
        graph
            .add_pass(name)
            .write_buffer(&mut p.simulated, BufferAccess::StorageWrite)
            .write_buffer(&mut p.laid_out, BufferAccess::StorageWrite)
            .write_texture(&mut lit, TextureAccess::CopyDst)
            .execute(move |ctx| {
                for (from, to) in sources.iter().zip(&destinations) {
                    ctx.encoder
                        .copy_buffer_to_buffer(from, 0, to, 0, from.size().min(to.size()));
                }
                let texture = ctx.texture(lit).clone();
                ctx.encoder.copy_buffer_to_texture(
                    wgpu::TexelCopyBufferInfo {
                        buffer: &texels,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(side * 4),
                            rows_per_image: Some(side),
                        },
                    },
                    texture.as_image_copy(),
                    texture.size(),
                );
            });
        p.lit_atlas = Some(lit);
        Ok(())
    }
}
