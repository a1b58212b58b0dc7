//! Host side of the clustered culling kernel (`shaders_gen::culling::cluster_cull`): the froxel
//! grid, the optional occupancy pass, and the dispatch.

use glam::{Mat4, UVec2, UVec3};
use shaders_gen::culling::cluster_cull::{self, ClusterParams, CullSphere, Msaa, VariantKey};

use super::CullError;
use super::lists::{CullReadback, LightLists};
use super::reference::ClusterGrid;
use crate::shader::ShaderProgram;
use crate::{GpuContext, GpuError};

/// Settings of the clustered culling pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterCullConfig {
    pub grid: ClusterGrid,
    /// MSAA sample count of the depth buffer (used to find occupied froxels).
    pub msaa: u32,
    pub scalarize: bool,
    /// Give froxels without any depth sample empty lists.
    pub skip_empty: bool,
    pub max_per_cluster: u32,
    pub index_capacity: u32,
    pub item_capacity: u32,
}

/// The kernel's variant key for a configuration.
pub fn variant_key(config: &ClusterCullConfig) -> Result<VariantKey, CullError> {
    let msaa = match config.msaa {
        1 => Msaa::Msaa1,
        2 => Msaa::Msaa2,
        4 => Msaa::Msaa4,
        8 => Msaa::Msaa8,
        s => return Err(CullError::SampleCount(s)),
    };
    Ok(VariantKey {
        msaa,
        scalarize: config.scalarize,
    })
}

/// Clustered light culling for one target size and configuration.
#[derive(Debug)]
pub struct ClusteredCulling {
    pub config: ClusterCullConfig,
    pub lists: LightLists,
    program: ShaderProgram,
    mark: wgpu::ComputePipeline,
    cull: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    items: wgpu::Buffer,
    occupied: wgpu::Buffer,
    screen: UVec2,
}

impl ClusteredCulling {
    pub fn new(
        gpu: &GpuContext,
        config: ClusterCullConfig,
        width: u32,
        height: u32,
    ) -> Result<Self, CullError> {
        let g = config.grid;
        if g.x == 0 || g.y == 0 || g.z == 0 || !(g.near > 0.0 && g.far > g.near) {
            return Err(CullError::Grid(format!("{g:?}")));
        }
        if config.max_per_cluster > cluster_cull::MAX_PER_CLUSTER {
            return Err(CullError::PerCellCapacity {
                asked: config.max_per_cluster,
                limit: cluster_cull::MAX_PER_CLUSTER,
            });
        }
        super::check_index_capacity(&gpu.device, config.index_capacity)?;
        let variant = cluster_cull::variant(variant_key(&config)?);
        let program = ShaderProgram::new(&gpu.device, gpu.capabilities(), variant)?;
        let device = &gpu.device;
        let cells = g.x * g.y * g.z;
        Ok(Self {
            config,
            lists: LightLists::new(device, cells, config.index_capacity),
            mark: program.compute_pipeline(device, "mark_occupied")?,
            cull: program.compute_pipeline(device, "cull")?,
            params: super::uniform_buffer::<ClusterParams>(device),
            items: super::item_buffer::<CullSphere>(device, config.item_capacity),
            occupied: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("occupied froxels"),
                size: u64::from(cells) * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            program,
            screen: UVec2::new(width, height),
        })
    }

    /// Uploads the camera and the items' world-space bounding spheres.
    pub fn upload(
        &self,
        gpu: &GpuContext,
        view: Mat4,
        projection: Mat4,
        items: &[CullSphere],
    ) -> Result<(), CullError> {
        super::check_item_count(items.len(), self.config.item_capacity)?;
        let g = self.config.grid;
        let params = ClusterParams::new(
            view,
            projection,
            projection.inverse(),
            self.screen,
            UVec3::new(g.x, g.y, g.z),
            g.near,
            g.far,
            items.len() as u32,
            self.config.max_per_cluster,
            self.config.index_capacity,
            u32::from(self.config.skip_empty),
        );
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        gpu.queue
            .write_buffer(&self.items, 0, bytemuck::cast_slice(items));
        Ok(())
    }

    /// Records the occupancy pass (when `skip_empty`) and the culling dispatch.
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
            self.occupied.as_entire_binding(),
            wgpu::BindingResource::TextureView(depth),
        ];
        let bind_group = super::bind_all(device, &self.program, &resources);
        encoder.clear_buffer(&self.lists.counters, 0, None);
        encoder.clear_buffer(&self.occupied, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("cluster cull"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &bind_group, &[]);
        if self.config.skip_empty {
            pass.set_pipeline(&self.mark);
            pass.dispatch_workgroups(self.screen.x.div_ceil(8), self.screen.y.div_ceil(8), 1);
        }
        let g = self.config.grid;
        pass.set_pipeline(&self.cull);
        pass.dispatch_workgroups(g.x, g.y, g.z);
    }

    /// Per-froxel capacity limit of the kernel.
    pub const PER_CELL_LIMIT: u32 = cluster_cull::MAX_PER_CLUSTER;

    /// The capacities in use.
    pub fn capacities(&self) -> super::overflow::Capacities {
        super::overflow::Capacities {
            per_cell: self.config.max_per_cluster,
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
        self.config.max_per_cluster = caps.per_cell.min(cluster_cull::MAX_PER_CLUSTER);
        if caps.index != self.config.index_capacity {
            self.config.index_capacity = caps.index;
            self.lists = LightLists::new(device, self.lists.cells, caps.index);
        }
    }

    /// Blocking readback of the results (tests and tools).
    pub fn read_back(&self, gpu: &GpuContext) -> Result<CullReadback, GpuError> {
        self.lists.read_back(gpu)
    }
}
