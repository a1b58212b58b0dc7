//! An engine that embeds the renderer: a pass of its own, inserted after light culling, that
//! takes a census of the frame's culled light lists. Its shader uses the renderer's
//! `light_lists` library, so it reads the lists under the renderer's own binding contract, and
//! the pass binds the renderer's buffers by name through the generated builders
//! (`light_set::Group0`, `light_lists::Group0`), with no binding number written here.

use renderer::GpuContext;
use renderer::extend::{FrameInputs, FrameResources, LightListHandles, ListGeometry, Pass};
use renderer::frame::ConfigError;
use renderer::frame::RenderError;
use renderer::graph::{BufferAccess, ImportAccess, RenderGraph};
use renderer::shader::ShaderProgram;

/// Counts what the culled light lists hold, one invocation per cell.
#[shader_dsl::shader(
    axes(list: u32 = [1, 2] => "list"),
    uses(shaders_gen::shared::light_lists),
)]
pub mod light_census {
    /// `x`: the cells of the light section of the grid.
    #[uniform(group = 1, binding = 0)]
    static CELLS: UVec4;
    /// `[0]` entries over every cell, `[1]` the longest list, `[2]` entries naming a light with
    /// a positive intensity.
    #[storage(group = 1, binding = 1, read_write)]
    static CENSUS: [Atomic<u32>];

    #[compute(workgroup_size(64, 1, 1))]
    pub fn count(#[builtin(global_invocation_id)] gid: UVec3) {
        if gid.x < CELLS.x {
            let range = GRID[gid.x];
            CENSUS[0].fetch_add(range.y);
            CENSUS[1].fetch_max(range.y);
            for j in 0u32..range.y {
                if LIGHTS[INDICES[range.x + j]].intensity > 0.0 {
                    CENSUS[2].fetch_add(1u32);
                }
            }
        }
    }
}

/// What the census found in a frame's lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Census {
    /// List entries over every cell.
    pub entries: u32,
    /// The longest list.
    pub longest: u32,
    /// Entries that name a light with a positive intensity.
    pub lit_entries: u32,
}

/// The census pass: reads the light lists the renderer's culling wrote this frame.
#[derive(Debug)]
pub struct LightCensusPass {
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
    queue: wgpu::Queue,
    cells: wgpu::Buffer,
    census: wgpu::Buffer,
}

impl LightCensusPass {
    /// The pass for a renderer whose path culls lights into `list` (1 tiled, 2 clustered).
    pub fn new(gpu: &GpuContext, list: light_census::List) -> Result<Self, RenderError> {
        let variant = light_census::variant(light_census::VariantKey { list });
        let program = ShaderProgram::new(gpu.device(), gpu.capabilities(), variant)?;
        let pipeline = program.compute_pipeline(gpu.device(), "count")?;
        let buffer = |label, size, usage| {
            gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let copy = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        Ok(Self {
            program,
            pipeline,
            queue: gpu.queue().clone(),
            cells: buffer("census cells", 16, wgpu::BufferUsages::UNIFORM | copy),
            census: buffer("census", 16, wgpu::BufferUsages::STORAGE | copy),
        })
    }

    /// The census of the last frame rendered (blocks until the GPU is done with it).
    pub fn read(&self, gpu: &GpuContext) -> Result<Census, renderer::GpuError> {
        let words: Vec<u32> =
            renderer::readback::read_buffer(gpu.device(), gpu.queue(), &self.census)?;
        Ok(Census {
            entries: words[0],
            longest: words[1],
            lit_entries: words[2],
        })
    }
}

impl Pass for LightCensusPass {
    fn name(&self) -> &'static str {
        "light census"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let lists = resources.light_lists.clone().ok_or(RenderError::Config(
            ConfigError::MissingInput {
                pass: "light census",
                input: "light lists",
            },
        ))?;
        let geometry = ListGeometry::new(Some(lists.method), &frame.config, &frame.camera);
        let cells = geometry.tiles.x * geometry.tiles.y * geometry.slices;
        let mut census =
            resources.import_buffer(graph, "light census", &self.census, ImportAccess::ReadWrite);
        let census_handle = census;
        let mut pass = graph.add_pass(self.name());
        LightListHandles::read_by(Some(&lists), &mut pass);
        pass.write_buffer(&mut census, BufferAccess::StorageWrite);
        let (program, pipeline) = (self.program.clone(), self.pipeline.clone());
        let cells_buffer = self.cells.clone();
        let lights = std::sync::Arc::clone(&frame.lights);
        pass.execute(move |ctx| {
            let census = ctx.buffer(census_handle).clone();
            ctx.encoder.clear_buffer(&census, 0, None);
            let lists_group = light_census::Group0 {
                light_set: lights.bindings(),
                light_lists: LightListHandles::bindings(Some(&lists), ctx),
            }
            .bind_group(
                ctx.device,
                program.layout(0),
                program.variant,
                "census lists",
            );
            let own_group = light_census::Group1 {
                cells: cells_buffer.as_entire_buffer_binding(),
                census: census.as_entire_buffer_binding(),
            }
            .bind_group(ctx.device, program.layout(1), program.variant, "census");
            let (Some(lists_group), Some(own_group)) = (ctx.bind(lists_group), ctx.bind(own_group))
            else {
                return;
            };
            let mut compute = ctx.encoder.begin_compute("census");
            compute.set_pipeline(&pipeline);
            compute.set_bind_group(0, &lists_group, &[]);
            compute.set_bind_group(1, &own_group, &[]);
            compute.dispatch_workgroups(cells.div_ceil(64), 1, 1);
        });
        // Lands before the frame's submission, as every queue write made while it is built.
        self.queue
            .write_buffer(&self.cells, 0, bytemuck::cast_slice(&[cells, 0, 0, 0]));
        Ok(())
    }
}
