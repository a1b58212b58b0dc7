//! The material programs of a pass that shades surfaces (forward, G-buffer): glTF PBR's and
//! every registered one ([`crate::materials::MaterialProgram`]), each with its face pipelines;
//! and per frame, for every program number of the scene (`DrawBatch::program`), the program
//! and the bind group it needs besides the scene's: group 0 (the frame, through the program's
//! own layout, with its parameter records where it takes them).

use shaders_gen::forward::forward;

use super::bindings::FrameGroup;
use crate::frame_data::{DrawBatch, PreparedScene, RenderError};
use crate::graph::PassContext;
use crate::materials::{MaterialProgram, PARAMS_GROUP, PARAMS_NAME};
use crate::passes::{BatchState, FacePipelines, face_pipeline, face_pipelines};
use crate::shader::ShaderProgram;

/// One material program of a pass.
#[derive(Debug)]
pub(crate) struct ProgramPipelines {
    /// Its module name (what a scene's materials name).
    name: &'static str,
    program: ShaderProgram,
    faces: FacePipelines,
    /// Whether it binds parameter records (`PARAMS`).
    params: bool,
}

/// glTF PBR's program (first) and every registered material program's, of one variant key.
#[derive(Debug)]
pub(crate) struct MaterialPipelines(Vec<ProgramPipelines>);

/// The variant key of a pass: the list kind (0 naive, 1 tiled, 2 clustered), `blend`,
/// `scalarize`.
pub(crate) type FrameKey = (u32, bool, bool);

impl MaterialPipelines {
    /// The programs of `key`: glTF PBR's and each of `materials`', with `make(program,
    /// double_sided, mirrored)`'s pipelines.
    pub(crate) fn new(
        gpu: &crate::GpuContext,
        materials: &[MaterialProgram],
        key: FrameKey,
        make: impl Fn(&ShaderProgram, bool, bool) -> wgpu::RenderPipeline,
    ) -> Result<Self, RenderError> {
        let (list, blend, scalarize) = key;
        let gltf = forward::variant(forward::VariantKey {
            list: forward::List::from_value(list).unwrap_or(forward::List::List0),
            blend,
            scalarize,
            // The forward programs (the visibility kernels are `msaa` above 0).
            msaa: forward::Msaa::Msaa0,
            vis64: false,
        })?;
        let variants =
            std::iter::once(Ok((forward::MODULE.name, gltf))).chain(materials.iter().map(|m| {
                let variant = m.variant(list, blend, scalarize).ok_or_else(|| {
                    crate::materials::MaterialError::MissingVariant {
                        module: m.name().to_string(),
                        variant: format!("list {list}, blend {blend}, scalarize {scalarize}"),
                    }
                })?;
                Ok::<_, RenderError>((m.name(), variant))
            }));
        let mut out = Vec::new();
        for named in variants {
            let (name, variant) = named?;
            let program = gpu.program(variant)?;
            let faces =
                face_pipelines(|double_sided, mirrored| make(&program, double_sided, mirrored));
            out.push(ProgramPipelines {
                name,
                params: variant
                    .group(PARAMS_GROUP)
                    .any(|binding| binding.name == PARAMS_NAME),
                program,
                faces,
            });
        }
        Ok(Self(out))
    }

    /// This frame's programs for `scene`'s program numbers, with their groups 0; `None`
    /// after recording a binding error in `ctx`. A program number whose program this pass does
    /// not have (never so: the renderer refuses materials of unregistered programs) draws
    /// nothing.
    pub(crate) fn bind(
        &self,
        ctx: &mut PassContext<'_>,
        scene: &PreparedScene,
        frame: &FrameGroup,
        label: &str,
    ) -> Option<BoundPrograms> {
        let names = std::iter::once(forward::MODULE.name).chain(scene.material_program_names());
        let mut bound = Vec::new();
        for (number, name) in names.enumerate() {
            let Some(entry) = self.0.iter().position(|p| p.name == name) else {
                bound.push(None);
                continue;
            };
            let p = &self.0[entry];
            let params = match (p.params, scene.material_params(number as u32)) {
                (true, Some(buffer)) => Some(buffer),
                (true, None) => {
                    bound.push(None);
                    continue;
                }
                (false, _) => None,
            };
            let group0 = frame.bind_group(ctx, (&p.program, params), label)?;
            bound.push(Some(BoundProgram { entry, group0 }));
        }
        Some(BoundPrograms { bound })
    }
}

/// One program number's program and its bind groups for a frame.
pub(crate) struct BoundProgram {
    entry: usize,
    group0: wgpu::BindGroup,
}

/// A frame's programs, by the scene's program numbers.
pub(crate) struct BoundPrograms {
    bound: Vec<Option<BoundProgram>>,
}

impl BoundPrograms {
    /// The state `batch` draws with: its program's pipeline for its faces, the scene's
    /// material group 2, and its program's group 0; `None` for a program this pass
    /// does not have.
    pub(crate) fn state<'a>(
        &'a self,
        pipelines: &'a MaterialPipelines,
        batch: &DrawBatch,
        group2: &'a wgpu::BindGroup,
    ) -> Option<BatchState<'a>> {
        let b = self.bound.get(batch.program as usize)?.as_ref()?;
        let p = &pipelines.0[b.entry];
        Some(BatchState {
            pipeline: face_pipeline(&p.faces, batch.double_sided, batch.mirrored),
            group2: Some(group2),
            program_groups: Some((&b.group0, None)),
        })
    }

    /// glTF PBR's group 0 (the blended draws').
    pub(crate) fn gltf_group0(&self) -> Option<&wgpu::BindGroup> {
        self.bound.first()?.as_ref().map(|b| &b.group0)
    }
}
