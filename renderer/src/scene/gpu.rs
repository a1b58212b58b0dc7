//! A loaded [`Scene`] on the GPU: every mesh's vertices in one shared buffer per vertex
//! attribute and every index in one shared index buffer (a primitive is a range of each). The
//! scene's images go to the material atlas (`frame_data`'s material table).
//!
//! Meshes can be added after the upload ([`GpuScene::add_mesh`]) and removed
//! ([`GpuScene::remove_mesh`]): an added mesh takes free ranges of the streams (best fit, among
//! those removed meshes gave back) and uploads its own vertices and nothing else; where none is
//! long enough the streams grow by doubling, their contents copied on the GPU.
//!
//! A pass binds the streams its shader reads once and draws each primitive with its index range
//! and base vertex, so drawing a scene records no vertex or index buffer per draw. A primitive
//! without `TEXCOORD_1` has its `TEXCOORD_0` copied into that stream, and one without `COLOR_0`
//! white.

use wgpu::util::DeviceExt as _;

use std::ops::Range;

use super::free_ranges::FreeRanges;
use super::{Primitive, Scene};

/// One primitive's place in the shared buffers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpuPrimitive {
    /// Its first index in [`GeometryBuffers::indices`].
    pub first_index: u32,
    /// How many indices it draws (three per triangle).
    pub index_count: u32,
    /// Added to each of its indices: its first vertex in every vertex stream.
    pub base_vertex: i32,
    /// Its [`Primitive::material`]: an index into the scene's materials, `None` for the
    /// default material.
    pub material: Option<usize>,
}

impl GpuPrimitive {
    /// Its index range in [`GeometryBuffers::indices`].
    pub fn indices(&self) -> Range<u32> {
        self.first_index..self.first_index + self.index_count
    }

    /// Its `DrawIndexedIndirect` arguments, one instance numbered `instance` (the index the
    /// vertex shader reads its draw record by).
    pub fn indirect_args(&self, instance: u32) -> [u32; 5] {
        let base_vertex = self.base_vertex as u32;
        [self.index_count, 1, self.first_index, base_vertex, instance]
    }
}

/// The vertex streams and indices of every primitive of a scene, one buffer each.
#[derive(Debug, Clone)]
pub struct GeometryBuffers {
    /// `POSITION`, `Float32x3`.
    pub positions: wgpu::Buffer,
    /// `NORMAL`, `Float32x3`.
    pub normals: wgpu::Buffer,
    /// `TEXCOORD_0`, `Float32x2`.
    pub uvs: wgpu::Buffer,
    /// `TEXCOORD_1` (`TEXCOORD_0` where a primitive has none), `Float32x2`.
    pub uvs1: wgpu::Buffer,
    /// `COLOR_0`, linear RGBA (white where a primitive has none), `Float32x4`.
    pub colors: wgpu::Buffer,
    /// `TANGENT`, `Float32x4`.
    pub tangents: wgpu::Buffer,
    /// `u32` indices, each primitive's relative to its own first vertex.
    pub indices: wgpu::Buffer,
    /// Which vertices and indices are taken (by meshes) and free (never used, or given back by
    /// removed meshes), and the room each stream has.
    vertex_space: FreeRanges,
    index_space: FreeRanges,
}

/// Bytes per vertex of each stream, in [`GeometryBuffers::vertex_streams_mut`] order.
const STREAM_STRIDES: [u64; 6] = [12, 12, 8, 8, 16, 16];

impl GeometryBuffers {
    /// The vertices and indices the streams hold for meshes.
    pub fn counts(&self) -> (u64, u64) {
        (self.vertex_space.taken(), self.index_space.taken())
    }

    /// The vertices and indices the streams have room for (taken or free).
    pub fn capacity(&self) -> (u64, u64) {
        (self.vertex_space.capacity(), self.index_space.capacity())
    }

    fn vertex_streams_mut(&mut self) -> [&mut wgpu::Buffer; 6] {
        [
            &mut self.positions,
            &mut self.normals,
            &mut self.uvs,
            &mut self.uvs1,
            &mut self.colors,
            &mut self.tangents,
        ]
    }

    /// Writes `packed` into free ranges of the streams (growing them first where none is long
    /// enough); returns the vertex and index ranges it took.
    fn place(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        packed: &PackedGeometry,
    ) -> (Range<u64>, Range<u64>) {
        let (vertices, indices) = (packed.positions.len() as u64, packed.indices.len() as u64);
        let mut vertex_range = self.vertex_space.take(vertices);
        let mut index_range = self.index_space.take(indices);
        if vertex_range.is_none() || index_range.is_none() {
            let (vertex_room, index_room) = self.capacity();
            let grown_vertices = if vertex_range.is_none() {
                (vertex_room + vertices).max(2 * vertex_room)
            } else {
                vertex_room
            };
            let grown_indices = if index_range.is_none() {
                (index_room + indices).max(2 * index_room)
            } else {
                index_room
            };
            self.grow(device, queue, grown_vertices, grown_indices);
            vertex_range = vertex_range.or_else(|| self.vertex_space.take(vertices));
            index_range = index_range.or_else(|| self.index_space.take(indices));
        }
        #[expect(
            clippy::expect_used,
            reason = "the streams just grew by at least what was asked past their old room"
        )]
        let (vertex_range, index_range) = (
            vertex_range.expect("grown vertex streams have room"),
            index_range.expect("a grown index buffer has room"),
        );
        let new_streams: [&[u8]; 6] = [
            bytemuck::cast_slice(&packed.positions),
            bytemuck::cast_slice(&packed.normals),
            bytemuck::cast_slice(&packed.uvs),
            bytemuck::cast_slice(&packed.uvs1),
            bytemuck::cast_slice(&packed.colors),
            bytemuck::cast_slice(&packed.tangents),
        ];
        let first = vertex_range.start;
        for ((buffer, stride), bytes) in self
            .vertex_streams_mut()
            .into_iter()
            .zip(STREAM_STRIDES)
            .zip(new_streams)
        {
            queue.write_buffer(buffer, first * stride, bytes);
        }
        queue.write_buffer(
            &self.indices,
            index_range.start * 4,
            bytemuck::cast_slice(&packed.indices),
        );
        (vertex_range, index_range)
    }

    /// Gives a removed mesh's ranges back: later meshes may take them.
    fn give_back(&mut self, (vertices, indices): (Range<u64>, Range<u64>)) {
        self.vertex_space.give_back(vertices);
        self.index_space.give_back(indices);
    }

    /// New streams with room for at least `vertices` and `indices`, what meshes took of the old
    /// ones copied over on the GPU.
    fn grow(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, vertices: u64, indices: u64) {
        let (vertex_room, index_room) = self.capacity();
        let vertex_capacity = vertices.max(vertex_room);
        let index_capacity = indices.max(index_room);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("scene geometry growth"),
        });
        // A buffer of `size` bytes in place of `buffer`, its first `used` bytes copied over.
        let mut replace = |buffer: &mut wgpu::Buffer, size: u64, used: u64, usage, label| {
            let grown = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                // Storage too: the visibility path reads the streams by index.
                usage: usage
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(buffer, 0, &grown, 0, used);
            *buffer = grown;
        };
        let vertices_used = self.vertex_space.end_taken();
        for (buffer, stride) in self.vertex_streams_mut().into_iter().zip(STREAM_STRIDES) {
            let (size, used) = (stride * vertex_capacity, stride * vertices_used);
            replace(
                buffer,
                size,
                used,
                wgpu::BufferUsages::VERTEX,
                "scene vertex stream",
            );
        }
        let (size, used) = (4 * index_capacity, 4 * self.index_space.end_taken());
        replace(
            &mut self.indices,
            size,
            used,
            wgpu::BufferUsages::INDEX,
            "scene indices",
        );
        queue.submit([encoder.finish()]);
        self.vertex_space.grow_to(vertex_capacity);
        self.index_space.grow_to(index_capacity);
    }
}

/// Which vertex streams a program reads, at slots 0.. in this order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VertexStreams {
    /// Position only: opaque depth (pre-Z, shadow casters).
    Position,
    /// Position, `TEXCOORD_0`, `TEXCOORD_1`, `COLOR_0`: alpha-masked depth.
    Mask,
    /// Position, normal, `TEXCOORD_0`, tangent, `TEXCOORD_1`, `COLOR_0`: `vs_forward`.
    Forward,
}

/// Every mesh primitive of a scene, uploaded (its images go to the material atlas).
#[derive(Debug, Clone)]
pub struct GpuScene {
    /// `meshes[m][p]` is primitive `p` of mesh `m` (none once the mesh is removed).
    pub meshes: Vec<Vec<GpuPrimitive>>,
    /// The shared vertex streams and index buffer every primitive draws from.
    pub geometry: GeometryBuffers,
    /// The vertex and index ranges each mesh took (empty once it is removed).
    mesh_ranges: Vec<(Range<u64>, Range<u64>)>,
}

/// The scene's vertex streams and indices concatenated on the CPU, before upload.
#[derive(Default)]
struct PackedGeometry {
    positions: Vec<glam::Vec3>,
    normals: Vec<glam::Vec3>,
    uvs: Vec<glam::Vec2>,
    uvs1: Vec<glam::Vec2>,
    colors: Vec<glam::Vec4>,
    tangents: Vec<glam::Vec4>,
    indices: Vec<u32>,
}

impl PackedGeometry {
    /// Appends `p`'s vertices and indices; returns where they went.
    fn push(&mut self, p: &Primitive) -> GpuPrimitive {
        let placed = GpuPrimitive {
            first_index: self.indices.len() as u32,
            index_count: p.indices.len() as u32,
            base_vertex: self.positions.len() as i32,
            material: p.material,
        };
        let n = p.positions.len();
        self.positions.extend_from_slice(&p.positions);
        self.normals.extend_from_slice(&p.normals);
        self.uvs.extend_from_slice(&p.uvs);
        self.uvs1
            .extend_from_slice(if p.uvs1.is_empty() { &p.uvs } else { &p.uvs1 });
        if p.colors.is_empty() {
            self.colors.resize(self.colors.len() + n, glam::Vec4::ONE);
        } else {
            self.colors.extend_from_slice(&p.colors);
        }
        self.tangents.extend_from_slice(&p.tangents);
        self.indices.extend_from_slice(&p.indices);
        placed
    }

    /// The buffers (each holds at least one element, so an empty scene still binds).
    fn upload(mut self, device: &wgpu::Device) -> GeometryBuffers {
        if self.positions.is_empty() {
            self.push(&Primitive {
                positions: vec![glam::Vec3::ZERO],
                normals: vec![glam::Vec3::Y],
                uvs: vec![glam::Vec2::ZERO],
                tangents: vec![glam::Vec4::X],
                indices: vec![0],
                uvs1: Vec::new(),
                colors: Vec::new(),
                material: None,
                bounds: super::Aabb::EMPTY,
            });
        }
        let buffer = |label: &str, bytes: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                // Storage too: the visibility path reads the streams by index.
                usage: usage
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
            })
        };
        let (vertices, indices) = (self.positions.len() as u64, self.indices.len() as u64);
        let vertex = wgpu::BufferUsages::VERTEX;
        GeometryBuffers {
            positions: buffer("positions", bytemuck::cast_slice(&self.positions), vertex),
            normals: buffer("normals", bytemuck::cast_slice(&self.normals), vertex),
            uvs: buffer("uvs", bytemuck::cast_slice(&self.uvs), vertex),
            uvs1: buffer("uvs1", bytemuck::cast_slice(&self.uvs1), vertex),
            colors: buffer("colors", bytemuck::cast_slice(&self.colors), vertex),
            tangents: buffer("tangents", bytemuck::cast_slice(&self.tangents), vertex),
            indices: buffer(
                "indices",
                bytemuck::cast_slice(&self.indices),
                wgpu::BufferUsages::INDEX,
            ),
            vertex_space: FreeRanges::new(vertices, vertices),
            index_space: FreeRanges::new(indices, indices),
        }
    }
}

impl GpuScene {
    /// Uploads every mesh of `scene`, in order (mesh `m` is `meshes[m]`). The scene must have
    /// passed [`Scene::check_for_device`]; its images go to the material atlas separately.
    pub fn upload(device: &wgpu::Device, scene: &Scene) -> Self {
        let mut packed = PackedGeometry::default();
        let mut mesh_ranges = Vec::with_capacity(scene.meshes.len());
        let meshes = scene
            .meshes
            .iter()
            .map(|mesh| {
                let start = (packed.positions.len() as u64, packed.indices.len() as u64);
                let placed = mesh.primitives.iter().map(|p| packed.push(p)).collect();
                let end = (packed.positions.len() as u64, packed.indices.len() as u64);
                mesh_ranges.push((start.0..end.0, start.1..end.1));
                placed
            })
            .collect();
        Self {
            meshes,
            geometry: packed.upload(device),
            mesh_ranges,
        }
    }

    /// Uploads `mesh`'s primitives into free ranges of the streams (given back by removed
    /// meshes, or past the others; the streams grow if they must) and returns its index in
    /// [`GpuScene::meshes`].
    pub fn add_mesh(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &super::Mesh,
    ) -> usize {
        let mut packed = PackedGeometry::default();
        let placed: Vec<GpuPrimitive> = mesh.primitives.iter().map(|p| packed.push(p)).collect();
        let (vertices, indices) = self.geometry.place(device, queue, &packed);
        self.meshes.push(
            placed
                .into_iter()
                .map(|p| GpuPrimitive {
                    first_index: p.first_index + indices.start as u32,
                    base_vertex: p.base_vertex + vertices.start as i32,
                    ..p
                })
                .collect(),
        );
        self.mesh_ranges.push((vertices, indices));
        self.meshes.len() - 1
    }

    /// Removes mesh `mesh` (its index stays, naming no primitive): its vertices and indices
    /// are given back for later meshes. Nothing may draw it any more.
    pub fn remove_mesh(&mut self, mesh: usize) {
        if let (Some(primitives), Some(ranges)) =
            (self.meshes.get_mut(mesh), self.mesh_ranges.get_mut(mesh))
        {
            primitives.clear();
            self.geometry.give_back(std::mem::take(ranges));
        }
    }

    /// Binds `streams` at vertex slots 0.. and the shared index buffer.
    pub fn bind_streams<'a>(&'a self, pass: &mut wgpu::RenderPass<'a>, streams: VertexStreams) {
        let g = &self.geometry;
        let buffers: &[&wgpu::Buffer] = match streams {
            VertexStreams::Position => &[&g.positions],
            VertexStreams::Mask => &[&g.positions, &g.uvs, &g.uvs1, &g.colors],
            VertexStreams::Forward => &[
                &g.positions,
                &g.normals,
                &g.uvs,
                &g.tangents,
                &g.uvs1,
                &g.colors,
            ],
        };
        for (slot, buffer) in buffers.iter().enumerate() {
            pass.set_vertex_buffer(slot as u32, buffer.slice(..));
        }
        pass.set_index_buffer(g.indices.slice(..), wgpu::IndexFormat::Uint32);
    }
}
