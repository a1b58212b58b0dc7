//! GPU-free tests of graph compilation: culling, ordering, lifetimes, pool reuse and errors.

use super::*;

fn tex(w: u32) -> TextureDesc {
    TextureDesc::new_2d(w, w, wgpu::TextureFormat::Rgba16Float)
}

/// pre-Z → culling → forward → output, plus a debug pass nobody reads.
fn forward_graph() -> (RenderGraph, Handle<Texture>) {
    let mut g = RenderGraph::new();
    let mut output = g.import_texture("output", tex(64), ImportAccess::ReadWrite);
    let mut depth = g.create_texture(
        "depth",
        TextureDesc::new_2d(64, 64, wgpu::TextureFormat::Depth32Float),
    );
    let mut grid = g.create_buffer("light grid", BufferDesc { size: 256 });
    let lights = g.import_buffer("lights", BufferDesc { size: 1024 }, ImportAccess::ReadOnly);
    let mut hdr = g.create_texture("hdr", tex(64));
    let mut debug = g.create_texture("debug", tex(64));
    g.add_pass("pre-z")
        .write_texture(&mut depth, TextureAccess::DepthWrite)
        .finish();
    g.add_pass("light culling")
        .read_texture(depth, TextureAccess::Sampled)
        .read_buffer(lights, BufferAccess::StorageRead)
        .write_buffer(&mut grid, BufferAccess::StorageWrite)
        .finish();
    g.add_pass("debug view")
        .read_buffer(grid, BufferAccess::StorageRead)
        .write_texture(&mut debug, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("forward")
        .read_texture(depth, TextureAccess::DepthRead)
        .read_buffer(grid, BufferAccess::StorageRead)
        .read_buffer(lights, BufferAccess::StorageRead)
        .write_texture(&mut hdr, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("tonemap")
        .read_texture(hdr, TextureAccess::Sampled)
        .write_texture(&mut output, TextureAccess::ColorAttachment)
        .finish();
    (g, output)
}

#[test]
fn unread_passes_are_culled_and_the_rest_ordered() {
    let (g, _) = forward_graph();
    let c = g.compile().expect("valid graph");
    assert_eq!(
        c.pass_order(),
        ["pre-z", "light culling", "forward", "tonemap"]
    );
    assert_eq!(c.culled_passes(), ["debug view"]);
}

#[test]
fn side_effect_passes_are_kept() {
    let mut g = RenderGraph::new();
    let mut t = g.create_texture("readback source", tex(8));
    g.add_pass("write")
        .write_texture(&mut t, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("readback")
        .read_texture(t, TextureAccess::CopySrc)
        .side_effects()
        .finish();
    let c = g.compile().expect("valid graph");
    assert_eq!(c.pass_order(), ["write", "readback"]);
    let mut g = RenderGraph::new();
    let mut t = g.create_texture("unused", tex(8));
    g.add_pass("write")
        .write_texture(&mut t, TextureAccess::ColorAttachment)
        .finish();
    assert!(g.compile().expect("valid graph").pass_order().is_empty());
}

#[test]
fn order_follows_dependencies_not_declaration() {
    let mut g = RenderGraph::new();
    let mut out = g.import_texture("out", tex(8), ImportAccess::ReadWrite);
    let mut a = g.create_texture("a", tex(8));
    let producer_of_a = g
        .add_pass("make a")
        .write_texture(&mut a, TextureAccess::ColorAttachment)
        .finish();
    // Declared before "late", but must run after it.
    let mut b = g.create_texture("b", tex(8));
    g.add_pass("late")
        .after(producer_of_a)
        .write_texture(&mut b, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("combine")
        .read_texture(a, TextureAccess::Sampled)
        .read_texture(b, TextureAccess::Sampled)
        .write_texture(&mut out, TextureAccess::ColorAttachment)
        .finish();
    let c = g.compile().expect("valid graph");
    assert_eq!(c.pass_order(), ["make a", "late", "combine"]);
}

#[test]
fn readers_of_a_version_run_before_it_is_overwritten() {
    let mut g = RenderGraph::new();
    let mut out = g.import_texture("out", tex(8), ImportAccess::ReadWrite);
    let mut color = g.create_texture("color", tex(8));
    let mut copy = g.create_texture("copy", tex(8));
    g.add_pass("draw")
        .write_texture(&mut color, TextureAccess::ColorAttachment)
        .finish();
    let color_v1 = color;
    // Overwrite declared before the reader of v1: the reader must still come first.
    g.add_pass("overdraw")
        .write_texture(&mut color, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("snapshot v1")
        .read_texture(color_v1, TextureAccess::CopySrc)
        .write_texture(&mut copy, TextureAccess::CopyDst)
        .finish();
    g.add_pass("present")
        .read_texture(color, TextureAccess::Sampled)
        .read_texture(copy, TextureAccess::Sampled)
        .write_texture(&mut out, TextureAccess::ColorAttachment)
        .finish();
    let c = g.compile().expect("valid graph");
    assert_eq!(
        c.pass_order(),
        ["draw", "snapshot v1", "overdraw", "present"]
    );
}

#[test]
fn lifetimes_span_first_to_last_use() {
    let (g, _) = forward_graph();
    let c = g.compile().expect("valid graph");
    assert_eq!(c.lifetime("depth"), Some(Lifetime { first: 0, last: 2 }));
    assert_eq!(
        c.lifetime("light grid"),
        Some(Lifetime { first: 1, last: 2 })
    );
    assert_eq!(c.lifetime("hdr"), Some(Lifetime { first: 2, last: 3 }));
    assert_eq!(c.lifetime("debug"), None, "only the culled pass used it");
}

#[test]
fn pool_reuses_slots_for_disjoint_lifetimes_with_equal_descriptors() {
    let mut g = RenderGraph::new();
    let mut out = g.import_texture("out", tex(8), ImportAccess::ReadWrite);
    let mut a = g.create_texture("a", tex(8));
    let mut b = g.create_texture("b", tex(8));
    let mut c_tex = g.create_texture("c", tex(8));
    let mut other = g.create_texture("other size", tex(16));
    g.add_pass("1")
        .write_texture(&mut a, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("2")
        .read_texture(a, TextureAccess::Sampled)
        .write_texture(&mut b, TextureAccess::ColorAttachment)
        .finish();
    // a is dead after pass 2, so c can take its slot; b is still live.
    g.add_pass("3")
        .read_texture(b, TextureAccess::Sampled)
        .write_texture(&mut c_tex, TextureAccess::StorageWrite)
        .write_texture(&mut other, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("4")
        .read_texture(c_tex, TextureAccess::Sampled)
        .read_texture(other, TextureAccess::Sampled)
        .write_texture(&mut out, TextureAccess::ColorAttachment)
        .finish();
    let c = g.compile().expect("valid graph");
    assert_eq!(
        c.slot("a"),
        c.slot("c"),
        "disjoint lifetimes, same descriptor"
    );
    assert_ne!(c.slot("a"), c.slot("b"), "overlapping lifetimes");
    assert_ne!(c.slot("other size"), c.slot("a"), "different descriptor");
    assert_eq!(c.slot("out"), None, "imports are not pooled");
    assert_eq!(c.slot_count(), 3);
}

#[test]
fn reading_a_transient_nobody_wrote_is_an_error() {
    let mut g = RenderGraph::new();
    let mut out = g.import_texture("out", tex(8), ImportAccess::ReadWrite);
    let never_written = g.create_texture("shadow atlas", tex(8));
    g.add_pass("forward")
        .read_texture(never_written, TextureAccess::Sampled)
        .write_texture(&mut out, TextureAccess::ColorAttachment)
        .finish();
    let err = g.compile().unwrap_err();
    assert_eq!(
        err,
        GraphError::ReadBeforeWrite {
            pass: "forward".into(),
            resource: "shadow atlas".into()
        }
    );
    assert!(err.to_string().contains("no pass writes first"));
}

#[test]
fn writing_a_read_only_import_is_an_error() {
    let mut g = RenderGraph::new();
    let mut lights = g.import_buffer("lights", BufferDesc { size: 64 }, ImportAccess::ReadOnly);
    g.add_pass("oops")
        .write_buffer(&mut lights, BufferAccess::StorageWrite)
        .finish();
    assert_eq!(
        g.compile().unwrap_err(),
        GraphError::WriteToReadOnlyImport {
            pass: "oops".into(),
            resource: "lights".into()
        }
    );
}

#[test]
fn a_stale_handle_write_is_an_error() {
    let mut g = RenderGraph::new();
    let mut t = g.create_texture("t", tex(8));
    let mut stale = t;
    g.add_pass("first")
        .write_texture(&mut t, TextureAccess::ColorAttachment)
        .finish();
    g.add_pass("second")
        .write_texture(&mut stale, TextureAccess::ColorAttachment)
        .finish();
    assert!(matches!(
        g.compile().unwrap_err(),
        GraphError::StaleWrite {
            used: 0,
            latest: 1,
            ..
        }
    ));
}

#[test]
fn a_cycle_is_an_error_naming_its_passes() {
    let mut g = RenderGraph::new();
    let mut out = g.import_texture("out", tex(8), ImportAccess::ReadWrite);
    let mut a = g.create_texture("a", tex(8));
    let first = g.add_pass("first").finish();
    let second = g
        .add_pass("second")
        .after(first)
        .write_texture(&mut a, TextureAccess::ColorAttachment)
        .finish();
    // The public API cannot express a cycle (handles are versioned and `after` only names
    // passes that already exist), so the compile-time check guards an invariant: build one
    // through the internals to prove it is reported. "first" now runs after "second", which
    // runs after "first".
    g.passes[first.index].after.push(second.index);
    g.add_pass("sink")
        .read_texture(a, TextureAccess::Sampled)
        .write_texture(&mut out, TextureAccess::ColorAttachment)
        .finish();
    assert_eq!(
        g.compile().unwrap_err(),
        GraphError::Cycle {
            passes: vec!["first".into(), "second".into(), "sink".into()]
        }
    );
}

#[test]
fn handles_from_another_graph_are_an_error() {
    let mut other = RenderGraph::new();
    let foreign = other.create_texture("foreign", tex(8));
    let mut g = RenderGraph::new();
    g.add_pass("p")
        .read_texture(foreign, TextureAccess::Sampled)
        .finish();
    assert_eq!(
        g.compile().unwrap_err(),
        GraphError::ForeignHandle { pass: "p".into() }
    );
}

#[test]
fn dot_dump_shows_passes_resources_and_culling() {
    let (g, _) = forward_graph();
    let dot = g.compile().expect("valid graph").to_dot();
    assert!(dot.starts_with("digraph frame {"));
    assert!(dot.contains("label=\"#0 pre-z\""), "{dot}");
    assert!(
        dot.contains("style=dashed, label=\"culled debug view\""),
        "{dot}"
    );
    assert!(dot.contains("imported ReadOnly"), "{dot}");
    assert!(dot.contains("-> p3 [label=\"v1\"]"), "{dot}");
}

/// A graph of one transient written by "a" and read by "b" (kept by an imported output), its
/// transient `size` texels wide.
fn two_passes(size: u32) -> RenderGraph {
    let mut g = RenderGraph::new();
    let desc = TextureDesc::new_2d(size, 4, wgpu::TextureFormat::Rgba8Unorm);
    let mut t = g.create_texture("t", desc);
    let mut out = g.import_texture("out", desc, ImportAccess::ReadWrite);
    g.add_pass("a")
        .write_texture(&mut t, TextureAccess::ColorAttachment)
        .execute(|_| {});
    g.add_pass("b")
        .read_texture(t, TextureAccess::Sampled)
        .write_texture(&mut out, TextureAccess::ColorAttachment)
        .execute(|_| {});
    g
}

#[test]
fn a_graph_of_the_same_shape_reuses_the_plan_and_another_compiles() {
    let mut cache = GraphCache::new();
    assert_eq!(cache.to_dot(), None);
    let first = two_passes(8).compile_cached(&mut cache).expect("valid");
    let fresh = two_passes(8).compile().expect("valid");
    assert_eq!(first.plan, fresh.plan);
    assert_eq!(cache.counts(), (1, 0));
    let again = two_passes(8).compile_cached(&mut cache).expect("valid");
    assert_eq!(cache.counts(), (1, 1), "the same shape reuses the plan");
    assert!(std::sync::Arc::ptr_eq(&first.plan, &again.plan));
    assert_eq!(cache.to_dot(), Some(fresh.to_dot()));
    // Another size is another shape: compiled again, and drawn so.
    let wider = two_passes(16).compile_cached(&mut cache).expect("valid");
    assert_eq!(cache.counts(), (2, 1));
    assert_eq!(wider.plan, two_passes(16).compile().expect("valid").plan);
    // A pass reading something else is another shape too.
    let mut g = two_passes(16);
    let extra = g.create_buffer("extra", BufferDesc { size: 4 });
    g.add_pass("c").read_buffer(extra, BufferAccess::Uniform);
    assert!(g.compile_cached(&mut cache).is_err(), "read before write");
    assert_eq!(cache.counts(), (2, 1), "an invalid graph changes nothing");
    let mut g = two_passes(16);
    g.add_pass("c").side_effects().execute(|_| {});
    g.compile_cached(&mut cache).expect("valid");
    assert_eq!(cache.counts(), (3, 1), "an added pass compiles again");
}

fn scope(
    label: &str,
    seconds: Option<(f64, f64)>,
    nested: Vec<wgpu_profiler::GpuTimerQueryResult>,
) -> wgpu_profiler::GpuTimerQueryResult {
    wgpu_profiler::GpuTimerQueryResult {
        label: label.to_owned(),
        pid: 0,
        tid: std::thread::current().id(),
        time: seconds.map(|(start, end)| start..end),
        nested_queries: nested,
    }
}

/// Timings from the profiler's scopes: a timed scope lists itself and then its nested scopes;
/// an untimed one whose compute and render passes carry timestamps (WebGPU) is timed as their
/// sum, without listing them; one with no time anywhere is left out.
#[test]
fn pass_timings_sum_whole_pass_timestamps_under_an_untimed_scope() {
    let results = [
        scope(
            "light culling",
            Some((1.0, 1.004)),
            vec![scope("cull: tiles", Some((1.001, 1.003)), vec![])],
        ),
        scope(
            "forward",
            None,
            vec![
                scope("forward", Some((2.0, 2.002)), vec![]),
                scope("resolve", Some((2.003, 2.004)), vec![]),
            ],
        ),
        scope("particle fade depth", None, vec![]),
    ];
    let timings = PassTiming::from_profiler(&results);
    let listed: Vec<(&str, i64)> = timings
        .iter()
        .map(|t| (t.pass.as_str(), (t.gpu_ms * 1000.0).round() as i64))
        .collect();
    assert_eq!(
        listed,
        [
            ("light culling", 4000),
            ("cull: tiles", 2000),
            ("forward", 3000)
        ]
    );
}
