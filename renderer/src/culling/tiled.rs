//! Host side of the tiled and 2.5D culling kernel (`shaders_gen::culling::tile_cull`): the
//! variant for the frame's tile size / MSAA count / scalarization / depth mask, its buffers and
//! its dispatch.

use glam::{Mat4, UVec2};
use shaders_gen::culling::tile_cull::{self, CullParams, CullSphere, Msaa, Tile, VariantKey};

use super::CullError;
use super::lists::{CullReadback, LightLists};
use crate::shader::ShaderProgram;
use crate::{GpuContext, GpuError};

/// Settings of the tiled culling pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TileCullConfig {
    /// Tile edge in pixels: 8, 16 or 32.
    pub tile: u32,
    /// MSAA sample count of the depth buffer: 1, 2, 4 or 8.
    pub msaa: u32,
    /// Use the subgroup (scalarized) variant.
    pub scalarize: bool,
    /// 2.5D culling: test items against the tile's 32-cell geometry depth mask too.
    pub depth_mask: bool,
    /// Lists also serve blended surfaces, which the pre-Z depth does not hold: tiles span from
    /// the near plane (see `tile_cull::CullParams::include_transparent`).
    pub include_transparent: bool,
    /// Most items one tile may list (at most [`tile_cull::MAX_PER_TILE`]).
    pub max_per_tile: u32,
    /// Entries the index list holds.
    pub index_capacity: u32,
    /// Items the item buffer holds.
    pub item_capacity: u32,
}

/// The kernel's variant key for a configuration.
pub fn variant_key(config: &TileCullConfig) -> Result<VariantKey, CullError> {
    let tile = match config.tile {
        8 => Tile::T8,
        16 => Tile::T16,
        32 => Tile::T32,
        t => return Err(CullError::TileSize(t)),
    };
    let msaa = match config.msaa {
        1 => Msaa::Msaa1,
        2 => Msaa::Msaa2,
        4 => Msaa::Msaa4,
        8 => Msaa::Msaa8,
        s => return Err(CullError::SampleCount(s)),
    };
    Ok(VariantKey {
        tile,
        msaa,
        scalarize: config.scalarize,
        depth_mask: config.depth_mask,
    })
}

/// Tiled (or 2.5D) light culling for one target size and configuration.
#[derive(Debug)]
pub struct TiledCulling {
    pub config: TileCullConfig,
    pub tiles: UVec2,
    pub lists: LightLists,
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    items: wgpu::Buffer,
}

impl TiledCulling {
    pub fn new(
        gpu: &GpuContext,
        config: TileCullConfig,
        width: u32,
        height: u32,
    ) -> Result<Self, CullError> {
        if config.max_per_tile > tile_cull::MAX_PER_TILE {
            return Err(CullError::PerCellCapacity {
                asked: config.max_per_tile,
                limit: tile_cull::MAX_PER_TILE,
            });
        }
        super::check_index_capacity(&gpu.device, config.index_capacity)?;
        let variant = tile_cull::variant(variant_key(&config)?);
        let program = ShaderProgram::new(&gpu.device, gpu.capabilities(), variant)?;
        let pipeline = program.compute_pipeline(&gpu.device, "cull")?;
        let tiles = UVec2::new(width.div_ceil(config.tile), height.div_ceil(config.tile));
        let device = &gpu.device;
        Ok(Self {
            config,
            tiles,
            lists: LightLists::new(device, tiles.x * tiles.y, config.index_capacity),
            params: super::uniform_buffer::<CullParams>(device),
            items: super::item_buffer::<CullSphere>(device, config.item_capacity),
            program,
            pipeline,
        })
    }

    /// Uploads the camera and the items' world-space bounding spheres.
    pub fn upload(
        &self,
        gpu: &GpuContext,
        view: Mat4,
        projection: Mat4,
        screen: UVec2,
        items: &[CullSphere],
    ) -> Result<(), CullError> {
        super::check_item_count(items.len(), self.config.item_capacity)?;
        let params = CullParams::new(
            view,
            projection,
            projection.inverse(),
            screen,
            self.tiles,
            items.len() as u32,
            self.config.max_per_tile,
            self.config.index_capacity,
            u32::from(self.config.include_transparent),
        );
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        gpu.queue
            .write_buffer(&self.items, 0, bytemuck::cast_slice(items));
        Ok(())
    }

    /// Records the culling dispatch reading `depth` (the pre-Z buffer, `config.msaa` samples).
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
    ) {
        let resources = [
            self.params.as_entire_binding(),
            self.items.as_entire_binding(),
            self.lists.grid.as_entire_binding(),
            self.lists.indices.as_entire_binding(),
            self.lists.counters.as_entire_binding(),
            wgpu::BindingResource::TextureView(depth),
        ];
        let bind_group = super::bind_all(device, &self.program, &resources);
        encoder.clear_buffer(&self.lists.counters, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("tile cull"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(self.tiles.x, self.tiles.y, 1);
    }

    /// Per-tile capacity limit of the kernel.
    pub const PER_CELL_LIMIT: u32 = tile_cull::MAX_PER_TILE;

    /// The capacities in use.
    pub fn capacities(&self) -> super::overflow::Capacities {
        super::overflow::Capacities {
            per_cell: self.config.max_per_tile,
            index: self.config.index_capacity,
        }
    }

    /// Takes new capacities (from [`super::overflow::grow_for`]) for the next frame. The index
    /// list never grows past what one storage binding holds; beyond that, overflow stays counted.
    pub fn grow(&mut self, device: &wgpu::Device, caps: super::overflow::Capacities) {
        let caps = super::overflow::Capacities {
            index: caps.index.min(super::max_index_entries(device)),
            ..caps
        };
        self.config.max_per_tile = caps.per_cell.min(tile_cull::MAX_PER_TILE);
        if caps.index != self.config.index_capacity {
            self.config.index_capacity = caps.index;
            self.lists = LightLists::new(device, self.tiles.x * self.tiles.y, caps.index);
        }
    }

    /// Blocking readback of the results (tests and tools).
    pub fn read_back(&self, gpu: &GpuContext) -> Result<CullReadback, GpuError> {
        self.lists.read_back(gpu)
    }
}
