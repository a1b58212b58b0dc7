//! The parameter records of a scene's materials written in the shader DSL: per material program
//! that the scene's materials name, one storage buffer (`PARAMS`, group 3 of the program), with
//! each material's record at its material index (the `params` field of its `GpuMaterial`
//! record), so a material edit writes one record in place.
//!
//! Programs are numbered in the order the scene first names them, from 1 (0 is glTF PBR); the
//! number is what splits the draw batches (`BatchKey`), and it is never given to another
//! program while the scene lives.

use crate::scene::{Material, SceneError};

/// One program's parameter records.
#[derive(Debug, Clone)]
struct ProgramParams {
    name: String,
    /// Bytes per record (0: the program takes no parameters, and has no buffer).
    stride: usize,
    buffer: Option<wgpu::Buffer>,
    /// Records the buffer has room for.
    capacity: usize,
}

/// The material programs a scene names, and their parameter records.
#[derive(Debug, Clone, Default)]
pub(super) struct CustomPrograms {
    programs: Vec<ProgramParams>,
}

impl CustomPrograms {
    /// The programs of `materials` with every record written.
    pub(super) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        materials: &[Material],
    ) -> Result<Self, SceneError> {
        let mut out = Self::default();
        for index in 0..materials.len() {
            out.write(device, queue, materials, index)?;
        }
        Ok(out)
    }

    /// The program number of `material`: 0 for glTF PBR, else its program's (from 1).
    pub(super) fn program_of(&self, material: &Material) -> u32 {
        material.custom.as_ref().map_or(0, |c| {
            self.programs
                .iter()
                .position(|p| p.name == c.program)
                .map_or(0, |i| i as u32 + 1)
        })
    }

    /// The name of program `program` (from 1).
    pub(super) fn name(&self, program: u32) -> Option<&str> {
        let index = program.checked_sub(1)? as usize;
        self.programs.get(index).map(|p| p.name.as_str())
    }

    /// The names of every program, program 1 first.
    pub(super) fn names(&self) -> impl Iterator<Item = &str> {
        self.programs.iter().map(|p| p.name.as_str())
    }

    /// The parameter buffer of program `program`, if it takes parameters.
    pub(super) fn buffer(&self, program: u32) -> Option<&wgpu::Buffer> {
        let index = program.checked_sub(1)? as usize;
        self.programs.get(index)?.buffer.as_ref()
    }

    /// Writes material `index`'s parameter record (of `materials`), numbering its program if
    /// it is new and growing the program's buffer (records written again from `materials`)
    /// when the index is past it. A record whose size differs from its program's other
    /// materials' is refused, and nothing changes.
    pub(super) fn write(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        materials: &[Material],
        index: usize,
    ) -> Result<(), SceneError> {
        let Some(custom) = materials.get(index).and_then(|m| m.custom.as_ref()) else {
            return Ok(());
        };
        let position = self.programs.iter().position(|p| p.name == custom.program);
        let stride = custom.params.len();
        if let Some(p) = position.map(|p| &self.programs[p])
            && p.stride != stride
        {
            return Err(SceneError::Inconsistent(format!(
                "material {index} gives {stride} bytes of parameters to material program `{}`, whose other materials give {}",
                custom.program, p.stride
            )));
        }
        let position = position.unwrap_or_else(|| {
            self.programs.push(ProgramParams {
                name: custom.program.clone(),
                stride,
                buffer: None,
                capacity: 0,
            });
            self.programs.len() - 1
        });
        let program = &mut self.programs[position];
        if stride == 0 {
            return Ok(());
        }
        if index >= program.capacity {
            program.capacity = (materials.len() * 2).max(8);
            program.buffer = Some(records_buffer(device, program, materials));
            return Ok(());
        }
        if let Some(buffer) = &program.buffer {
            queue.write_buffer(buffer, (index * stride) as u64, &custom.params);
        }
        Ok(())
    }
}

/// A buffer of `program.capacity` records holding every record of `materials` that names it.
fn records_buffer(
    device: &wgpu::Device,
    program: &ProgramParams,
    materials: &[Material],
) -> wgpu::Buffer {
    use wgpu::util::DeviceExt as _;
    let mut bytes = vec![0u8; program.capacity * program.stride];
    for (index, m) in materials.iter().enumerate() {
        if let Some(c) = m.custom.as_ref().filter(|c| c.program == program.name) {
            let at = index * program.stride;
            bytes[at..at + program.stride].copy_from_slice(&c.params);
        }
    }
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("material parameters"),
        contents: &bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}
