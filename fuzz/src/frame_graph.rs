//! Frame-graph building → compile, from random pass and resource declarations.
//!
//! The fuzzer's bytes become a list of [`Op`]s (through `arbitrary`): create or import textures
//! and buffers, add passes that read and write them through current, stale or foreign handles,
//! order passes explicitly, mark side effects. The graph is compiled and, when it compiles, held
//! to the graph's contract against a model built alongside:
//! - every kept pass runs once, after the pass that wrote each version it reads and after the
//!   passes it was ordered after;
//! - a pass with side effects, or that writes a writable import, is kept;
//! - transients sharing a pool slot have equal descriptors and disjoint lifetimes.
//!
//! Mistakes the builder must catch (a stale write, a foreign handle, a write to a read-only
//! import, a read of a transient no pass wrote) must be compile errors, never panics.

use arbitrary::{Arbitrary, Unstructured};
use renderer::graph::{
    Buffer, BufferAccess, BufferDesc, Handle, ImportAccess, Lifetime, PassId, RenderGraph, Texture,
    TextureAccess, TextureDesc,
};

/// One declaration.
#[derive(Debug, Arbitrary)]
pub enum Op {
    CreateTexture {
        size: u8,
        format: u8,
        samples: u8,
    },
    CreateBuffer {
        size: u8,
    },
    ImportTexture {
        size: u8,
        writable: bool,
    },
    ImportBuffer {
        size: u8,
        writable: bool,
    },
    /// A handle of another graph, which every use must reject.
    ForeignTexture,
    Pass(PassOps),
}

/// What one pass declares.
#[derive(Debug, Arbitrary)]
pub struct PassOps {
    pub uses: Vec<Use>,
    pub after: Vec<u8>,
    pub side_effects: bool,
}

/// One access by a pass: `resource` picks a handle (current or an earlier copy).
#[derive(Debug, Arbitrary)]
pub struct Use {
    pub resource: u8,
    /// Use an earlier copy of the handle (possibly stale) instead of the current one.
    pub stale: Option<u8>,
    pub access: u8,
}

#[derive(Clone, Copy)]
enum AnyHandle {
    Texture(Handle<Texture>),
    Buffer(Handle<Buffer>),
}

/// What the model knows of one resource.
struct ModelResource {
    name: String,
    /// Current handle and every earlier copy of it.
    history: Vec<AnyHandle>,
    transient: bool,
    import: Option<ImportAccess>,
    desc: Desc,
    foreign: bool,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Desc {
    Texture(TextureDesc),
    Buffer(BufferDesc),
}

struct ModelPass {
    name: String,
    /// (resource, writer pass of the version read) for reads of a written version.
    reads_from: Vec<usize>,
    after: Vec<usize>,
    must_keep: bool,
}

const TEXTURE_ACCESS: [TextureAccess; 7] = [
    TextureAccess::Sampled,
    TextureAccess::StorageWrite,
    TextureAccess::ColorAttachment,
    TextureAccess::DepthWrite,
    TextureAccess::DepthRead,
    TextureAccess::CopySrc,
    TextureAccess::CopyDst,
];
const BUFFER_ACCESS: [BufferAccess; 8] = [
    BufferAccess::Uniform,
    BufferAccess::StorageRead,
    BufferAccess::StorageWrite,
    BufferAccess::Indirect,
    BufferAccess::Vertex,
    BufferAccess::Index,
    BufferAccess::CopySrc,
    BufferAccess::CopyDst,
];
const FORMATS: [wgpu::TextureFormat; 3] = [
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Depth32Float,
    wgpu::TextureFormat::R32Uint,
];

fn texture_desc(size: u8, format: u8, samples: u8) -> TextureDesc {
    let side = 1 + u32::from(size % 4) * 32;
    TextureDesc::new_2d(side, side, FORMATS[usize::from(format) % FORMATS.len()])
        .with_samples([1, 4][usize::from(samples % 2)])
}

/// Builds, compiles and checks the graph `data` describes. Panics only on a broken contract.
pub fn run(data: &[u8]) {
    let mut u = Unstructured::new(data);
    let Ok(ops) = Vec::<Op>::arbitrary(&mut u) else {
        return;
    };
    check(&ops);
}

/// [`run`] on already decoded operations.
pub fn check(ops: &[Op]) {
    let mut graph = RenderGraph::new();
    let mut other = RenderGraph::new();
    let mut resources: Vec<ModelResource> = Vec::new();
    let mut passes: Vec<ModelPass> = Vec::new();
    let mut pass_ids: Vec<PassId> = Vec::new();
    // Which pass wrote each (resource, version); version 0 of a transient is undefined.
    let mut writers: Vec<Vec<Option<usize>>> = Vec::new();
    let mut expect_error = false;
    for op in ops.iter().take(64) {
        let n = resources.len();
        let (handle, transient, import, desc, foreign) = match *op {
            Op::CreateTexture {
                size,
                format,
                samples,
            } => {
                let d = texture_desc(size, format, samples);
                let h = graph.create_texture(&format!("t{n}"), d);
                (AnyHandle::Texture(h), true, None, Desc::Texture(d), false)
            }
            Op::CreateBuffer { size } => {
                let d = BufferDesc {
                    size: 256 * (1 + u64::from(size % 4)),
                };
                let h = graph.create_buffer(&format!("b{n}"), d);
                (AnyHandle::Buffer(h), true, None, Desc::Buffer(d), false)
            }
            Op::ImportTexture { size, writable } => {
                let d = texture_desc(size, 0, 0);
                let access = import_access(writable);
                let h = graph.import_texture(&format!("it{n}"), d, access);
                (
                    AnyHandle::Texture(h),
                    false,
                    Some(access),
                    Desc::Texture(d),
                    false,
                )
            }
            Op::ImportBuffer { size, writable } => {
                let d = BufferDesc {
                    size: 256 * (1 + u64::from(size % 4)),
                };
                let access = import_access(writable);
                let h = graph.import_buffer(&format!("ib{n}"), d, access);
                (
                    AnyHandle::Buffer(h),
                    false,
                    Some(access),
                    Desc::Buffer(d),
                    false,
                )
            }
            Op::ForeignTexture => {
                let d = texture_desc(0, 0, 0);
                let h = other.create_texture("foreign", d);
                (AnyHandle::Texture(h), true, None, Desc::Texture(d), true)
            }
            Op::Pass(ref p) => {
                let index = passes.len();
                let name = format!("p{index}");
                let mut model = ModelPass {
                    name: name.clone(),
                    reads_from: Vec::new(),
                    after: Vec::new(),
                    must_keep: p.side_effects,
                };
                let mut builder = graph.add_pass(&name);
                for use_ in p.uses.iter().take(8) {
                    let Some(r) = resources.get_mut(usize::from(use_.resource) % n.max(1)) else {
                        continue;
                    };
                    let pick = use_
                        .stale
                        .map_or(r.history.len() - 1, |s| usize::from(s) % r.history.len());
                    let mut handle = r.history[pick];
                    let stale = pick + 1 != r.history.len();
                    let (write, version) = match &mut handle {
                        AnyHandle::Texture(h) => {
                            let access = TEXTURE_ACCESS[usize::from(use_.access) % 7];
                            let version = h.version();
                            if access.is_write() {
                                builder.write_texture(h, access);
                            } else {
                                builder.read_texture(*h, access);
                            }
                            (access.is_write(), version)
                        }
                        AnyHandle::Buffer(h) => {
                            let access = BUFFER_ACCESS[usize::from(use_.access) % 8];
                            let version = h.version();
                            if access.is_write() {
                                builder.write_buffer(h, access);
                            } else {
                                builder.read_buffer(*h, access);
                            }
                            (access.is_write(), version)
                        }
                    };
                    let resource = usize::from(use_.resource) % n.max(1);
                    if r.foreign {
                        expect_error = true;
                        continue;
                    }
                    if write {
                        if stale || r.import == Some(ImportAccess::ReadOnly) {
                            expect_error = true;
                            continue;
                        }
                        r.history.push(handle);
                        writers[resource].push(Some(index));
                        if r.import == Some(ImportAccess::ReadWrite) {
                            model.must_keep = true;
                        }
                    } else {
                        match writers[resource].get(version as usize).copied().flatten() {
                            Some(w) => model.reads_from.push(w),
                            // Version 0 of a transient: nothing wrote it.
                            None if r.transient => expect_error = true,
                            None => {}
                        }
                    }
                }
                for &a in p.after.iter().take(4) {
                    if let Some(&id) = pass_ids.get(usize::from(a)) {
                        builder.after(id);
                        model.after.push(usize::from(a));
                    }
                }
                if p.side_effects {
                    builder.side_effects();
                }
                pass_ids.push(builder.finish());
                passes.push(model);
                continue;
            }
        };
        resources.push(ModelResource {
            name: graph_name(&graph, handle, foreign),
            history: vec![handle],
            transient,
            import,
            desc,
            foreign,
        });
        // Imports arrive written (version 1, by no pass).
        writers.push(if import.is_some() {
            vec![None, None]
        } else {
            vec![None]
        });
    }
    let compiled = match graph.compile() {
        Ok(c) => c,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    assert!(
        !expect_error,
        "the graph compiled although it misuses a handle or reads an unwritten transient"
    );
    let order = compiled.pass_order();
    let position = |p: usize| order.iter().position(|&n| n == passes[p].name);
    for (i, pass) in passes.iter().enumerate() {
        let Some(at) = position(i) else {
            assert!(
                !pass.must_keep,
                "pass {} has effects but was culled",
                pass.name
            );
            continue;
        };
        assert_eq!(order.iter().filter(|&&n| n == pass.name).count(), 1);
        for &w in pass
            .reads_from
            .iter()
            .chain(&pass.after)
            .filter(|&&w| w != i)
        {
            let before = position(w);
            if pass.reads_from.contains(&w) {
                assert!(
                    before.is_some(),
                    "{} reads from culled {}",
                    pass.name,
                    passes[w].name
                );
            }
            if let Some(b) = before {
                assert!(
                    b < at,
                    "{} runs before {} it depends on",
                    pass.name,
                    passes[w].name
                );
            }
        }
    }
    let transients: Vec<(&ModelResource, usize, Lifetime)> = resources
        .iter()
        .filter(|r| r.transient && !r.foreign)
        .filter_map(|r| Some((r, compiled.slot(&r.name)?, compiled.lifetime(&r.name)?)))
        .collect();
    for (i, &(a, slot_a, life_a)) in transients.iter().enumerate() {
        assert!(life_a.first <= life_a.last && life_a.last < order.len());
        for &(b, slot_b, life_b) in &transients[i + 1..] {
            if slot_a == slot_b {
                assert_eq!(a.desc, b.desc, "{} and {} share a slot", a.name, b.name);
                assert!(
                    life_a.last < life_b.first || life_b.last < life_a.first,
                    "{} {life_a:?} and {} {life_b:?} share a slot while both alive",
                    a.name,
                    b.name
                );
            }
        }
    }
    assert!(compiled.slot_count() <= transients.len());
    assert!(compiled.to_dot().starts_with("digraph"));
}

fn import_access(writable: bool) -> ImportAccess {
    if writable {
        ImportAccess::ReadWrite
    } else {
        ImportAccess::ReadOnly
    }
}

fn graph_name(graph: &RenderGraph, handle: AnyHandle, foreign: bool) -> String {
    if foreign {
        return "foreign".into();
    }
    let name = match handle {
        AnyHandle::Texture(h) => graph.resource_name(h),
        AnyHandle::Buffer(h) => graph.resource_name(h),
    };
    name.unwrap_or("unnamed").to_owned()
}
