//! The particle simulation pass: one fixed step of every particle (`particle_simulation` in the
//! graph), then this frame's layout (`particle layout`: region sizes, the atlas plan and
//! allocation, and the back-to-front sort). It builds the systems' GPU state when the renderer
//! is given particles, reads the counters back asynchronously into the frame report, and warns
//! when the atlas had to shrink.
//!
//! In a further view of the frame (`Renderer::add_view`) the pass follows the main view's:
//! it lays out and sorts the particles the main view's step moved, for its own camera, and
//! never steps them itself, so every view shows the same particles, simulated once.

use std::sync::Arc;

use super::system::ParticleGpu;
use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameReport, FrameResources, ParticleReport, ParticleResources, RenderError,
};
use crate::graph::{BufferAccess, ImportAccess, RenderGraph};
use crate::passes::Pass;
use crate::readback_ring::ReadbackRing;

/// Words read back a frame: the simulation's four counters, then the layout's state.
const REPORT_WORDS: u64 = 4 + super::atlas::STATE_WORDS as u64;

/// The particle simulation and layout pass.
#[derive(Debug)]
pub struct ParticleSimPass {
    gpu: GpuContext,
    system: Option<Arc<ParticleGpu>>,
    /// Births of the step prepared for this frame.
    births: u32,
    readback: ReadbackRing,
    last: Option<ParticleReport>,
    /// In a further view: the main view's systems this frame (`None`: it has none), whose
    /// simulation this pass lays out without stepping it.
    follows: Option<Option<Arc<ParticleGpu>>>,
}

impl ParticleSimPass {
    pub fn new(gpu: &GpuContext) -> Self {
        Self {
            gpu: gpu.clone(),
            system: None,
            follows: None,
            births: 0,
            readback: ReadbackRing::new(gpu.device(), "particle counters readback", REPORT_WORDS),
            last: None,
        }
    }

    /// The newest particle counters that have arrived (polling first; none without particles).
    pub fn report(&mut self) -> Option<ParticleReport> {
        if let Some((frame, words)) = self.readback.poll(self.gpu.device()) {
            let layout = super::AtlasReport::from_words(&words[4..]);
            if layout.shrink > 0 {
                log::warn!(
                    "frame {frame}: the particle lighting atlas was full; every region was shrunk \
                     by {} size class(es) to fit {} visible particles (raise \
                     particle_atlas_side for full resolution)",
                    layout.shrink,
                    layout.visible
                );
            }
            self.last = Some(ParticleReport {
                alive: words[1],
                starved: words[2],
                visible: layout.visible,
                atlas_shrink: layout.shrink,
                shrunk_frames: layout.shrunk_frames,
                atlas_cells: layout.cells_used,
            });
        }
        self.last
    }

    /// Makes this the pass of a further view, following `main` (the main view's systems this
    /// frame, [`ParticleSimPass::system`]): it lays out their particles for its own camera
    /// and does not step them.
    pub(crate) fn follow(&mut self, main: Option<Arc<ParticleGpu>>) {
        self.follows = Some(main);
    }

    /// The systems' GPU state (none before the first frame with particles).
    pub fn system(&self) -> Option<&Arc<ParticleGpu>> {
        self.system.as_ref()
    }
}

impl Pass for ParticleSimPass {
    fn name(&self) -> &'static str {
        "particle simulation"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let Some(input) = &frame.particles else {
            self.system = None;
            return Ok(());
        };
        let side = frame.config.particle_atlas_side;
        let main = match &self.follows {
            Some(None) => {
                self.system = None;
                return Ok(());
            }
            Some(Some(main)) => Some(main),
            None => None,
        };
        let stale = self.system.as_ref().is_none_or(|s| {
            s.generation != input.generation
                || (side != 0 && s.atlas.side != side)
                || main.is_some_and(|m| !Arc::ptr_eq(&m.sim, &s.sim))
        });
        if stale {
            let system = match main {
                Some(m) => {
                    let sim = Arc::clone(&m.sim);
                    ParticleGpu::with_simulation(&self.gpu, sim, m.generation, side)?
                }
                None => ParticleGpu::new(&self.gpu, input, side)?,
            };
            self.system = Some(Arc::new(system));
            self.last = None;
        }
        if let Some(system) = &self.system {
            if main.is_none() {
                self.births = system.sim.write_step(frame.gpu.queue());
            }
            system
                .atlas
                .write_params(frame.gpu.queue(), &frame.camera, frame.config.height);
        }
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let Some(system) = &self.system else {
            return Ok(());
        };
        let following = self.follows.is_some();
        let simulated = match resources.main_particles {
            Some(stepped) if following => stepped,
            _ if following => return Ok(()),
            _ => resources.import_buffer(
                graph,
                "particles",
                &system.sim.particles,
                ImportAccess::ReadWrite,
            ),
        };
        let mut laid_out = resources.import_buffer(
            graph,
            "particle keys",
            &system.sort.keys,
            ImportAccess::ReadWrite,
        );
        let mut simulated = simulated;
        if !following {
            let (step, births) = (Arc::clone(system), self.births);
            graph
                .add_pass(self.name())
                .write_buffer(&mut simulated, BufferAccess::StorageWrite)
                .execute(move |ctx| step.sim.encode_step(&mut ctx.encoder, births));
        }
        let layout = Arc::clone(system);
        graph
            .add_pass("particle layout")
            .read_buffer(simulated, BufferAccess::StorageRead)
            .write_buffer(&mut laid_out, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                layout.atlas.encode(&mut ctx.encoder);
                layout.sort.record_in(&mut ctx.encoder);
            });
        system.write_view(frame, resources.particle_lists.as_ref().map(|l| l.method));
        resources.particles = Some(ParticleResources {
            simulated,
            laid_out,
            emitters: system.sim.emitters.clone(),
            particles: system.sim.particles.clone(),
            regions: system.atlas.regions.clone(),
            keys: system.sort.keys.clone(),
            state: system.atlas.state.clone(),
            owners: system.atlas.owners.clone(),
            view: system.view.clone(),
            atlas_side: system.atlas.side,
            lit_texels: system.lit_texels.clone(),
            atlas_texture: system.lit_atlas.clone(),
            lit_atlas: None,
            sprites: system.sprites.clone(),
            sampler: system.sampler.clone(),
        });
        Ok(())
    }

    fn after_execute(
        &mut self,
        frame: &FrameInputs,
        _resources: &FrameResources,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        if let Some(system) = &self.system {
            let sources = [
                (&system.sim.counters, 16),
                (&system.atlas.state, REPORT_WORDS * 4 - 16),
            ];
            self.readback.record(encoder, &sources, frame.index);
        }
    }

    fn after_submit(&mut self, _frame: &FrameInputs, report: &mut FrameReport) {
        self.readback.after_submit();
        if self.system.is_some() {
            report.particles = self.report();
        }
    }
}
