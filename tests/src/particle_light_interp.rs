//! `particle_light::light_atlas` run by the DSL's host interpreter on the inputs of a real frame.
//!
//! [`LightingInputsProbe`], a pass inserted right after particle lighting, copies what the
//! kernel bound that frame (the particle view, the lights with the frame's shadow indices, the
//! clustered light lists on a culled path, the emitters, particles, layout state and owners,
//! the shadow views and atlas) and what it wrote (the lit atlas texels). [`host_light_atlas`]
//! hands the same inputs to the kernel compiled from `shaders_gen`'s source text, dispatched
//! with the GPU's own indirect arguments.

use renderer::frame::ConfigError;
use std::sync::{Arc, Mutex};

use codegen::Compiled;
use codegen::interp::{Dispatch, EvalError, Schedule};
use renderer::frame::RenderError;
use renderer::frame_data::{FrameInputs, FrameResources};
use renderer::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};
use renderer::passes::Pass;
use renderer::passes::particles::atlas::DISPATCH_ARGS_OFFSET;

use crate::frame_probe::{ShadowCopies, ShadowInputs, copy_target, read_bytes};

/// Source text of the particle lighting module and the libraries it uses.
pub const LIGHT_SOURCE: &str = include_str!("../../shaders_gen/src/particles/light.rs");
const LIBRARY_SOURCES: [&str; 6] = [
    include_str!("../../shaders_gen/src/particles/common.rs"),
    include_str!("../../shaders_gen/src/particles/lighting.rs"),
    include_str!("../../shaders_gen/src/shared/lights.rs"),
    include_str!("../../shaders_gen/src/shared/brdf.rs"),
    include_str!("../../shaders_gen/src/shared/grid.rs"),
    include_str!("../../shaders_gen/src/shared/shadow.rs"),
];

/// Compiles the particle lighting module from `source` with its libraries.
pub fn compile(source: &str) -> Result<Compiled, String> {
    let mut modules =
        codegen::compile_source_all_with(source, &LIBRARY_SOURCES).map_err(|e| e.to_string())?;
    if modules.is_empty() {
        return Err("no shader module in the source".into());
    }
    let (name, compiled) = modules.swap_remove(0);
    compiled.map_err(|e| format!("{name} does not compile: {e}"))
}

/// The kernel's buffers by static name, as copied (`GRID` and `INDICES` only with lists).
const BUFFERS: [&str; 10] = [
    "VIEW",
    "LIGHTS",
    "DIRECTIONAL",
    "GRID",
    "INDICES",
    "EMITTERS",
    "PARTICLES",
    "STATE",
    "OWNERS",
    "LIT",
];

#[derive(Debug)]
struct Copies {
    /// `(static, copy)` for each buffer the frame bound.
    buffers: Vec<(&'static str, wgpu::Buffer)>,
    shadows: ShadowCopies,
}

/// A pass that copies the particle lighting kernel's inputs and output of every frame. Insert
/// it after `"particle lighting"`.
#[derive(Debug, Default)]
pub struct LightingInputsProbe {
    /// Shared with the frame's recording, which adds the light lists' copies.
    copies: Arc<Mutex<Option<Copies>>>,
}

/// Everything `particle_light::light_atlas` read and wrote in one frame.
#[derive(Debug, Clone)]
pub struct ProbedLighting {
    /// `(static, bytes)` per buffer, `LIT` being the GPU's output.
    pub buffers: Vec<(&'static str, Vec<u8>)>,
    pub shadows: ShadowInputs,
}

impl ProbedLighting {
    /// The bytes of buffer `name`.
    pub fn buffer(&self, name: &str) -> Option<&[u8]> {
        self.buffers
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, b)| b.as_slice())
    }

    /// The indirect dispatch the GPU ran: three words of `STATE` at `DISPATCH_ARGS_OFFSET`.
    pub fn dispatch(&self) -> Option<[u32; 3]> {
        let at = DISPATCH_ARGS_OFFSET as usize;
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(self.buffer("STATE")?.get(at..at + 12)?);
        Some([words[0], words[1], words[2]])
    }
}

impl LightingInputsProbe {
    /// What the last frame copied.
    pub fn take(&self, gpu: &renderer::GpuContext) -> Result<ProbedLighting, String> {
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
        Ok(ProbedLighting {
            buffers,
            shadows: copies.shadows.read(gpu)?,
        })
    }
}

impl Pass for LightingInputsProbe {
    fn name(&self) -> &'static str {
        "particle lighting probe"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "particle lighting probe",
                input,
            })
        };
        let p = resources.particles.clone().ok_or(missing("particles"))?;
        let lit = p.lit_atlas.ok_or(missing("lit particle atlas"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let lists = resources.particle_lists.clone();
        let device = frame.gpu.device();
        let lights = &frame.lights;
        let fixed = [
            ("VIEW", &p.view),
            ("LIGHTS", &lights.punctual_buffer),
            ("DIRECTIONAL", &lights.directional_buffer),
            ("EMITTERS", &p.emitters),
            ("PARTICLES", &p.particles),
            ("STATE", &p.state),
            ("OWNERS", &p.owners),
            ("LIT", &p.lit_texels),
        ];
        let mut sources: Vec<(&'static str, wgpu::Buffer)> = fixed
            .iter()
            .map(|(name, b)| (*name, (*b).clone()))
            .collect();
        let targets: Vec<(&'static str, wgpu::Buffer)> = sources
            .iter()
            .map(|(name, b)| (*name, copy_target(device, name, b.size())))
            .collect();
        let lit_copy = targets
            .iter()
            .find(|(n, _)| *n == "LIT")
            .map(|(_, b)| b.clone())
            .ok_or(missing("LIT copy"))?;
        // The LIT copy is the pass's tracked output, so the graph keeps the pass.
        let mut out =
            resources.import_buffer(graph, "probe lit", &lit_copy, ImportAccess::ReadWrite);
        let shadow_copies =
            ShadowCopies::new(device, &shadows, frame.config.fitted_shadows().atlas_size);
        let mut pass = graph.add_pass(self.name());
        pass.read_texture(lit, TextureAccess::CopySrc)
            .read_texture(shadows.atlas, TextureAccess::CopySrc)
            .write_buffer(&mut out, BufferAccess::CopyDst);
        if let Some(l) = &lists {
            pass.read_buffer(l.grid, BufferAccess::CopySrc)
                .read_buffer(l.indices, BufferAccess::CopySrc);
        }
        let mut recorded = targets.clone();
        let recorded_shadows = shadow_copies.clone();
        let shared = Arc::clone(&self.copies);
        pass.execute(move |ctx| {
            // The lists are graph buffers, known only now.
            if let Some(l) = &lists {
                for (name, h) in [("GRID", l.grid), ("INDICES", l.indices)] {
                    let from = ctx.buffer(h).clone();
                    let to = copy_target(ctx.device, name, from.size());
                    sources.push((name, from));
                    recorded.push((name, to));
                }
            }
            for ((_, from), (_, to)) in sources.iter().zip(&recorded) {
                ctx.encoder
                    .copy_buffer_to_buffer(from, 0, to, 0, from.size());
            }
            recorded_shadows.record(ctx, &shadows);
            if let Ok(mut slot) = shared.lock()
                && let Some(copies) = slot.as_mut()
            {
                copies.buffers = recorded.clone();
            }
        });
        if let Ok(mut slot) = self.copies.lock() {
            *slot = Some(Copies {
                buffers: targets,
                shadows: shadow_copies,
            });
        }
        Ok(())
    }
}

/// `particle_light::light_atlas` of `c`'s variant `list` run on the host over `frame`'s inputs
/// with the GPU's dispatch; the `LIT` buffer it wrote.
pub fn host_light_atlas(
    c: &Compiled,
    list: i64,
    frame: &ProbedLighting,
    subgroup_size: u32,
    schedule: Schedule,
) -> Result<Vec<u32>, EvalError> {
    let env = crate::cull_interp::variant(c, &[("list", list)]);
    let mut d = Dispatch::new(&c.module, env, "light_atlas")?
        .with_subgroup_size(subgroup_size)?
        .with_schedule(schedule)
        .with_unwritten_read_check(true);
    for name in BUFFERS {
        if (name == "GRID" || name == "INDICES") && list == 0 {
            continue;
        }
        let bytes = frame
            .buffer(name)
            .ok_or_else(|| EvalError::Type(format!("the probe copied no `{name}`")))?;
        if name == "LIT" {
            d.set_buffer(name, &vec![0; bytes.len()])?;
        } else {
            d.set_buffer(name, bytes)?;
        }
    }
    frame.shadows.bind(&mut d)?;
    let groups = frame
        .dispatch()
        .ok_or_else(|| EvalError::Type("the probe copied no dispatch arguments".into()))?;
    d.run(groups)?;
    Ok(bytemuck::pod_collect_to_vec(&d.buffer("LIT")?))
}

/// The linear RGB of `Rg11b10Ufloat` bits (red in bits 0–10, green 11–21, blue 22–31; each an
/// unsigned float with a 5-bit exponent, bias 15, and a 6- or 5-bit mantissa).
pub fn unpack_rg11b10(bits: u32) -> [f32; 3] {
    let ufloat = |v: u32, mantissa: u32| {
        let e = v >> mantissa;
        let m = (v & ((1 << mantissa) - 1)) as f32 / (1u32 << mantissa) as f32;
        match e {
            0 => m * 2f32.powi(-14),
            _ => (1.0 + m) * 2f32.powi(e as i32 - 15),
        }
    };
    [
        ufloat(bits & 0x7ff, 6),
        ufloat((bits >> 11) & 0x7ff, 6),
        ufloat(bits >> 22, 5),
    ]
}
