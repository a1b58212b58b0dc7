//! The culling hierarchy run by the DSL's host interpreter (`codegen::interp::Dispatch`): the
//! `shaders_gen` kernels compiled from their source text, given the same parameters, items and
//! depth samples as the GPU run, dispatched in the renderer's order (tile depth, super-tiles,
//! tiles), and read back as the GPU's lists are.

use codegen::Compiled;
use codegen::interp::{Dispatch, EvalError, HostTexture, Schedule};
use codegen::ir::Lit;
use glam::UVec2;
use renderer::culling::clustered::ClusteredCulling;
use renderer::culling::hierarchy::{CullItems, CullSphere, CullView, MethodParams};
use renderer::culling::lists::{CullCounters, CullReadback, GUARD_WORD, GUARD_WORDS};
use renderer::culling::tiled::TiledCulling;
use shaders_gen::culling::cull_prepare::{COARSE_CHUNK, COUNTER_COUNT, CullParams, ITEM_TYPES};

use crate::cull_run::GpuMethod;
use crate::cull_scene::CullScene;
use crate::gpu::gpu_test;

/// Source text of the culling kernels and the libraries they use.
pub const PREPARE_SOURCE: &str = include_str!("../../shaders_gen/src/culling/prepare.rs");
pub const TILED_SOURCE: &str = include_str!("../../shaders_gen/src/culling/tiled.rs");
pub const CLUSTERED_SOURCE: &str = include_str!("../../shaders_gen/src/culling/clustered.rs");
const LIBRARY_SOURCES: [&str; 3] = [
    include_str!("../../shaders_gen/src/shared/grid.rs"),
    include_str!("../../shaders_gen/src/shared/append.rs"),
    include_str!("../../shaders_gen/src/visibility/samples64.rs"),
];

/// Compiles the first shader module of `source` with the culling libraries.
pub fn compile(source: &str) -> Compiled {
    let mut modules =
        codegen::compile_source_all_with(source, &LIBRARY_SOURCES).expect("the source parses");
    assert!(!modules.is_empty(), "no shader module in the source");
    let (name, compiled) = modules.swap_remove(0);
    compiled.unwrap_or_else(|e| panic!("{name} does not compile: {e}"))
}

/// The variant of `c` whose axes have the given values (`bool` axes: 0 or 1).
pub fn variant<'c>(c: &'c Compiled, axes: &[(&str, i64)]) -> &'c codegen::variants::Env {
    let wanted = |k: &codegen::variants::Key| {
        axes.iter().all(|(name, value)| {
            let Some(i) = c.module.axis(name) else {
                return false;
            };
            match k.env.values[i] {
                Lit::Int(v, _) => v == i128::from(*value),
                Lit::Bool(b) => i64::from(b) == *value,
                Lit::Float(..) => false,
            }
        })
    };
    &c.keys
        .iter()
        .find(|k| wanted(k))
        .unwrap_or_else(|| panic!("no variant of {} with {axes:?}", c.module.name))
        .env
}

/// What the host run needs of a GPU culling method's configuration.
struct MethodShape {
    tile: u32,
    msaa: u32,
    brute_force: bool,
    index_capacity: u32,
    item_capacity: u32,
    /// The fine kernel's axes besides `tile`.
    fine_axes: Vec<(&'static str, i64)>,
}

fn shape(method: GpuMethod) -> MethodShape {
    match method {
        GpuMethod::Tiled(c) => MethodShape {
            tile: c.tile,
            msaa: c.msaa,
            brute_force: c.brute_force,
            index_capacity: c.index_capacity,
            item_capacity: c.item_capacity,
            fine_axes: vec![("depth_mask", c.depth_mask.into())],
        },
        GpuMethod::Clustered(c) => MethodShape {
            tile: c.grid.tile,
            msaa: c.msaa,
            brute_force: c.brute_force,
            index_capacity: c.index_capacity,
            item_capacity: c.item_capacity,
            fine_axes: vec![],
        },
    }
}

/// The culling parameters and super-tile stride the GPU's `method` uses for `s`.
pub fn method_params(s: &CullScene, method: GpuMethod) -> (CullParams, u32) {
    gpu_test(|gpu| {
        let (w, h) = (s.camera.width, s.camera.height);
        let spheres = spheres(s);
        let camera = CullView {
            view: s.camera.view,
            projection: s.camera.projection,
            screen: UVec2::new(w, h),
        };
        let items = CullItems::lights(&spheres);
        let levels = match method {
            GpuMethod::Tiled(config) => {
                TiledCulling::new(gpu, config, w, h)
                    .expect("culling setup")
                    .levels
            }
            GpuMethod::Clustered(config) => {
                ClusteredCulling::new(gpu, config, w, h)
                    .expect("culling setup")
                    .levels
            }
        };
        let method_params = match method {
            GpuMethod::Tiled(config) => MethodParams {
                transparent: config.transparent_lists,
                ..MethodParams::default()
            },
            GpuMethod::Clustered(config) => MethodParams {
                transparent: false,
                all_slices: !config.skip_empty,
                slices: config.grid.slices,
                slice_near: config.grid.near,
                slice_far: config.grid.far,
            },
        };
        (
            levels.params(&camera, &items, method_params),
            levels.coarse_stride,
        )
    })
}

fn spheres(s: &CullScene) -> Vec<CullSphere> {
    s.lights
        .iter()
        .map(|l| CullSphere::new(l.center, l.radius))
        .collect()
}

/// How the host run is scheduled.
#[derive(Debug, Clone, Copy)]
pub struct HostRun {
    pub subgroup_size: u32,
    pub schedule: Schedule,
}

/// Culling of `s` (lights only) on the host as the GPU's `method` culls it, with `prepare` the
/// compiled `cull_prepare` and `fine` the method's fine kernel (`tile_cull` or `cluster_cull`,
/// perhaps mutated); the lists as the GPU's readback.
pub fn run_on_host(
    s: &CullScene,
    method: GpuMethod,
    (prepare, fine): (&Compiled, &Compiled),
    run: HostRun,
) -> Result<CullReadback, EvalError> {
    let (params, stride) = method_params(s, method);
    let config = shape(method);
    let (w, h, samples) = (s.camera.width, s.camera.height, s.depth.samples);
    let tiles = params.tiles.x * params.tiles.y;
    let supers = params.super_tiles.x * params.super_tiles.y;
    let words = |n: u32| vec![0u8; n as usize * 4];
    let lights = spheres(s);
    let mut shared: Vec<(&str, Vec<u8>)> = vec![
        ("PARAMS", bytemuck::bytes_of(&params).to_vec()),
        ("ITEMS", bytemuck::cast_slice(&lights).to_vec()),
        ("GRID", words(params.grid_section * ITEM_TYPES * 2)),
        (
            "INDICES",
            bytemuck::cast_slice(&vec![
                GUARD_WORD;
                (config.index_capacity + GUARD_WORDS) as usize
            ])
            .to_vec(),
        ),
        ("COUNTERS", words(COUNTER_COUNT)),
        ("TILE_DEPTH", words(tiles * 4)),
        ("COARSE", words(supers * (4 + stride))),
        (
            "SPHERES",
            words((supers * stride + config.item_capacity) * 4),
        ),
        ("BOXES", vec![]),
    ];
    let depth = HostTexture::depth(w, h, samples, &s.depth.depth);
    let prepare_env = variant(
        prepare,
        &[("tile", config.tile.into()), ("msaa", config.msaa.into())],
    );
    let mut fine_axes = config.fine_axes.clone();
    fine_axes.push(("tile", config.tile.into()));
    let fine_env = variant(fine, &fine_axes);
    let chunks = params.item_count.div_ceil(COARSE_CHUNK);
    let steps = [
        (
            prepare,
            prepare_env,
            "tile_depth",
            [params.tiles.x, params.tiles.y, 1],
        ),
        (
            prepare,
            prepare_env,
            "coarse_cull",
            [params.super_tiles.x, params.super_tiles.y, chunks],
        ),
        (fine, fine_env, "cull", [params.tiles.x, params.tiles.y, 1]),
    ];
    for (compiled, env, entry, groups) in steps {
        if config.brute_force && entry == "coarse_cull" {
            continue;
        }
        let mut d = Dispatch::new(&compiled.module, env, entry)?
            .with_subgroup_size(run.subgroup_size)?
            .with_schedule(run.schedule)
            .with_unwritten_read_check(true);
        for (name, bytes) in &shared {
            d.set_buffer(name, bytes)?;
        }
        let texture = if samples == 1 { "DEPTH" } else { "DEPTH_MS" };
        if compiled.module.globals.iter().any(|g| g.name == texture) {
            d.set_texture(texture, depth.clone())?;
        }
        d.run(groups)?;
        for (name, bytes) in &mut shared {
            *bytes = d.buffer(name)?;
        }
    }
    let read = |name: &str| -> Vec<u32> {
        let bytes = &shared
            .iter()
            .find(|(n, _)| *n == name)
            .expect("a shared buffer")
            .1;
        bytemuck::pod_collect_to_vec(bytes)
    };
    let grid: Vec<u32> = read("GRID");
    Ok(CullReadback {
        grid: grid
            .chunks_exact(2)
            .map(|p| UVec2::new(p[0], p[1]))
            .take((params.grid_section * ITEM_TYPES) as usize)
            .collect(),
        indices: read("INDICES"),
        counters: CullCounters::from_words(&read("COUNTERS")),
    })
}
