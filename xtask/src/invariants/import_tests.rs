//! The import-graph checks on in-memory crates: each passes on a clean tree and fails when its
//! invariant is broken.

use super::graph::FileGraph;
use super::*;

fn crate_of(files: &[(&str, &str)]) -> Vec<(String, String)> {
    files
        .iter()
        .map(|(p, t)| ((*p).to_owned(), (*t).to_owned()))
        .collect()
}

/// `from -> to` edges of the file graph, with the paths that make them.
fn edges(files: &[(&str, &str)]) -> Vec<String> {
    let graph = FileGraph::new(&crate_of(files)).expect("parses");
    let mut edges: Vec<String> = graph
        .edges
        .iter()
        .map(|e| {
            format!(
                "{}:{} -> {} ({})",
                graph.file(e.from),
                e.line,
                graph.file(e.to),
                e.path
            )
        })
        .collect();
    edges.sort();
    edges
}

fn circles_of(files: &[(&str, &str)]) -> Vec<Violation> {
    check_no_import_circles(&crate_of(files))
}

/// A crate whose files form a layered graph: lib -> a -> b, every kind of path included.
const CLEAN: &[(&str, &str)] = &[
    (
        "k/src/lib.rs",
        "mod a;\nmod b;\npub use a::run;\npub fn entry() { a::run(); }\n",
    ),
    (
        "k/src/a.rs",
        "use crate::b::{self, Config as Cfg};\nuse super::b::*;\nuse wgpu::Device;\n\
         pub fn run() -> Cfg { let _ = b::make(); assert_eq!(crate::b::LIMIT, 3); Cfg }\n",
    ),
    (
        "k/src/b.rs",
        "pub struct Config;\npub const LIMIT: u32 = 3;\npub fn make() -> Config { Config }\n",
    ),
];

#[test]
fn a_layered_crate_has_no_circle() {
    assert!(circles_of(CLEAN).is_empty());
    // Groups, renames, globs, code paths and macro arguments are edges; `mod` and `pub use` are
    // not, nor are paths into other crates.
    assert_eq!(
        edges(CLEAN),
        [
            "k/src/a.rs:1 -> k/src/b.rs (crate::b::Config)",
            "k/src/a.rs:4 -> k/src/b.rs (Cfg)",
            "k/src/a.rs:4 -> k/src/b.rs (b::make)",
            "k/src/a.rs:4 -> k/src/b.rs (crate::b::LIMIT)",
            "k/src/lib.rs:4 -> k/src/a.rs (a::run)",
        ]
    );
}

#[test]
fn two_files_using_each_other_are_a_circle() {
    let v = circles_of(&[
        ("k/src/lib.rs", "mod a;\nmod b;\n"),
        ("k/src/a.rs", "pub struct A;\npub fn f(_: crate::b::B) {}\n"),
        ("k/src/b.rs", "use super::a::A;\npub struct B(A);\n"),
    ]);
    assert_eq!(v.len(), 1, "{v:?}");
    assert_eq!(v[0].invariant, "no import circle between files");
    assert!(
        v[0].detail.starts_with(
            "2 files import each other: k/src/a.rs -> k/src/b.rs (line 2: crate::b::B) -> \
             k/src/a.rs (line 1: super::a::A)"
        ),
        "{}",
        v[0].detail
    );
}

#[test]
fn a_three_file_ring_is_a_circle() {
    let v = circles_of(&[
        ("k/src/lib.rs", "mod a;\nmod b;\nmod c;\n"),
        ("k/src/a.rs", "pub struct A(pub crate::b::B);\n"),
        ("k/src/b.rs", "pub struct B(pub super::c::C);\n"),
        (
            "k/src/c.rs",
            "pub struct C;\nfn g() { let _ = self::h(crate::a::A); }\nfn h<T>(_: T) {}\n",
        ),
    ]);
    assert_eq!(v.len(), 1, "{v:?}");
    let d = &v[0].detail;
    assert!(
        d.starts_with("3 files import each other: k/src/a.rs -> k/src/b.rs"),
        "{d}"
    );
    for example in [
        "k/src/a.rs:1 crate::b::B -> k/src/b.rs",
        "k/src/b.rs:1 super::c::C -> k/src/c.rs",
        "k/src/c.rs:2 crate::a::A -> k/src/a.rs",
    ] {
        assert!(d.contains(example), "{example} missing in {d}");
    }
}

/// "mod.rs re-exports its children; children use `super::Foo`": each use reaches the file that
/// defines the item and mod.rs, whose re-export it goes through; mod.rs uses none of them, so
/// there is no circle.
#[test]
fn a_reexport_through_mod_rs_is_not_a_circle() {
    let files = [
        ("k/src/lib.rs", "pub mod g;\n"),
        (
            "k/src/g/mod.rs",
            "mod build;\nmod dot;\nmod run;\npub use build::{Graph, Node};\n\
             pub(crate) use run::*;\npub use dot::to_dot;\n",
        ),
        ("k/src/g/build.rs", "pub struct Graph;\npub struct Node;\n"),
        (
            "k/src/g/run.rs",
            "use super::{Graph, Node as N};\npub fn execute(_: Graph) { let _: Option<N> = None; }\n",
        ),
        (
            "k/src/g/dot.rs",
            "pub fn to_dot(g: super::Graph) { super::execute(g) }\n",
        ),
    ];
    assert!(circles_of(&files).is_empty(), "{:?}", circles_of(&files));
    assert_eq!(
        edges(&files),
        [
            "k/src/g/dot.rs:1 -> k/src/g/build.rs (super::Graph)",
            "k/src/g/dot.rs:1 -> k/src/g/mod.rs (super::Graph)",
            "k/src/g/dot.rs:1 -> k/src/g/mod.rs (super::execute)",
            "k/src/g/dot.rs:1 -> k/src/g/run.rs (super::execute)",
            "k/src/g/run.rs:1 -> k/src/g/build.rs (super::Graph)",
            "k/src/g/run.rs:1 -> k/src/g/build.rs (super::Node)",
            "k/src/g/run.rs:1 -> k/src/g/mod.rs (super::Graph)",
            "k/src/g/run.rs:1 -> k/src/g/mod.rs (super::Node)",
            "k/src/g/run.rs:2 -> k/src/g/build.rs (Graph)",
            "k/src/g/run.rs:2 -> k/src/g/build.rs (N)",
            "k/src/g/run.rs:2 -> k/src/g/mod.rs (Graph)",
            "k/src/g/run.rs:2 -> k/src/g/mod.rs (N)",
        ],
        "each edge names the defining file, and mod.rs where a re-export there carries it"
    );
    // `internal_use!(tree)` re-exports as `pub use` does; as an ordinary macro its paths would
    // be uses of build.rs by mod.rs, and build.rs using mod.rs's items a circle.
    let mut by_macro = files;
    by_macro[1].1 = "mod build;\nmod dot;\nmod run;\ninternal_use!(build::Graph);\n\
                     internal_use!(build::Node);\npub(crate) use run::*;\npub use dot::to_dot;\n\
                     pub struct Marker;\n";
    by_macro[2].1 = "pub struct Graph;\npub struct Node;\nfn go(_: super::Marker) {}\n";
    assert!(
        circles_of(&by_macro).is_empty(),
        "{:?}",
        circles_of(&by_macro)
    );
    // Once build.rs calls back into run.rs (through the glob re-export), the circle is real.
    let mut calls_back = files;
    calls_back[2].1 = "pub struct Graph;\npub struct Node;\nfn go() { super::execute(Graph) }\n";
    let v = circles_of(&calls_back);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(
        v[0].detail
            .contains("k/src/g/build.rs -> k/src/g/run.rs (line 3: super::execute)")
    );
}

/// `lists.rs` takes a constant through `hierarchy.rs`'s re-export of another crate's item while
/// `hierarchy.rs` calls `lists.rs`: a circle, though the constant is defined in neither file.
/// Taking the constant from its origin removes it.
#[test]
fn a_circle_through_a_reexport_of_another_crate_is_a_circle() {
    let circle = [
        ("k/src/lib.rs", "mod culling;\n"),
        ("k/src/culling/mod.rs", "mod hierarchy;\nmod lists;\n"),
        (
            "k/src/culling/hierarchy.rs",
            "pub use shaders::cull::{ITEM_TYPES, CullBox};\n\
             pub fn build() -> u32 { super::lists::cells() }\n",
        ),
        (
            "k/src/culling/lists.rs",
            "use super::hierarchy::ITEM_TYPES;\npub fn cells() -> u32 { 8 * ITEM_TYPES }\n",
        ),
    ];
    let v = circles_of(&circle);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(
        v[0].detail.starts_with(
            "2 files import each other: k/src/culling/hierarchy.rs -> k/src/culling/lists.rs \
             (line 2: super::lists::cells) -> k/src/culling/hierarchy.rs (line 1: \
             super::hierarchy::ITEM_TYPES)"
        ),
        "{}",
        v[0].detail
    );
    let mut from_the_origin = circle;
    from_the_origin[3].1 =
        "use shaders::cull::ITEM_TYPES;\npub fn cells() -> u32 { 8 * ITEM_TYPES }\n";
    assert!(circles_of(&from_the_origin).is_empty());
    assert_eq!(
        edges(&from_the_origin),
        ["k/src/culling/hierarchy.rs:2 -> k/src/culling/lists.rs (super::lists::cells)"]
    );
}

/// The same circle when the re-exported item is the crate's own (defined in a third file, and
/// reached through two re-exports and a glob): the user depends on each re-exporting file and on
/// the defining one.
#[test]
fn a_circle_through_chained_reexports_is_a_circle() {
    let files = [
        ("k/src/lib.rs", "mod types;\nmod prelude;\nmod a;\nmod b;\n"),
        ("k/src/types.rs", "pub const N: u32 = 4;\n"),
        ("k/src/prelude.rs", "pub use crate::types::*;\n"),
        (
            "k/src/b.rs",
            "pub use crate::prelude::N;\npub fn f() { crate::a::g(); }\n",
        ),
        ("k/src/a.rs", "pub fn g() -> u32 { crate::b::N }\n"),
    ];
    assert_eq!(
        edges(&files),
        [
            "k/src/a.rs:1 -> k/src/b.rs (crate::b::N)",
            "k/src/a.rs:1 -> k/src/prelude.rs (crate::b::N)",
            "k/src/a.rs:1 -> k/src/types.rs (crate::b::N)",
            "k/src/b.rs:2 -> k/src/a.rs (crate::a::g)",
        ]
    );
    let v = circles_of(&files);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(
        v[0].detail
            .starts_with("2 files import each other: k/src/a.rs -> k/src/b.rs"),
        "{}",
        v[0].detail
    );
}

/// A parent that calls into its child, while the child uses a type the parent defines.
#[test]
fn a_parent_and_child_using_each_other_are_a_circle() {
    let parent_child = [
        ("k/src/lib.rs", "mod front;\n"),
        (
            "k/src/front/mod.rs",
            "mod items;\npub struct Ctx;\npub fn lower() { items::lower_axes(&Ctx); }\n",
        ),
        (
            "k/src/front/items.rs",
            "use super::Ctx;\npub fn lower_axes(_: &Ctx) {}\n",
        ),
    ];
    let v = circles_of(&parent_child);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(
        v[0].detail.contains(
            "k/src/front/items.rs -> k/src/front/mod.rs (line 1: super::Ctx) -> \
             k/src/front/items.rs (line 3: items::lower_axes)"
        ),
        "{}",
        v[0].detail
    );
    // A `mod` declaration alone is not an edge: without the call, no circle.
    let mut declared_only = parent_child;
    declared_only[1].1 = "mod items;\npub struct Ctx;\n";
    assert!(circles_of(&declared_only).is_empty());
}

#[test]
fn use_super_glob_in_an_inline_test_module_is_no_edge() {
    let files = [
        ("k/src/lib.rs", "mod a;\nmod b;\n"),
        (
            "k/src/a.rs",
            "pub struct A;\n#[cfg(test)]\nmod tests {\n    use super::*;\n    #[test]\n    \
             fn t() { let _ = A; let _ = super::A; }\n}\n",
        ),
        ("k/src/b.rs", "pub fn f() -> crate::a::A { crate::a::A }\n"),
    ];
    assert_eq!(edges(&files), ["k/src/b.rs:1 -> k/src/a.rs (crate::a::A)",]);
    assert!(circles_of(&files).is_empty());
}

#[test]
fn a_pass_importing_the_frame_is_a_violation() {
    let renderer = |pass: &'static str| {
        crate_of(&[
            (
                "renderer/src/lib.rs",
                "pub mod frame;\npub mod passes;\npub mod graph;\n",
            ),
            ("renderer/src/graph/mod.rs", "pub struct RenderGraph;\n"),
            (
                "renderer/src/frame/mod.rs",
                "pub struct FrameGpu;\npub use crate::graph::RenderGraph;\n\
                 fn build() { crate::passes::prez::add(); }\n",
            ),
            ("renderer/src/passes/mod.rs", "pub mod prez;\n"),
            ("renderer/src/passes/prez.rs", pass),
        ])
    };
    let clean =
        renderer("use crate::graph::RenderGraph;\npub fn add() -> RenderGraph { RenderGraph }\n");
    assert!(check_passes_do_not_import_frame(&clean).is_empty());
    assert!(check_no_import_circles(&clean).is_empty());

    let v = check_passes_do_not_import_frame(&renderer(
        "use crate::frame::FrameGpu;\npub fn add(_: FrameGpu) {}\n",
    ));
    assert_eq!(v.len(), 1, "{v:?}");
    assert_eq!(v[0].invariant, "passes never import the frame orchestrator");
    assert!(
        v[0].detail.starts_with(
            "renderer/src/passes/prez.rs uses the frame orchestrator (line 1: \
             crate::frame::FrameGpu, line 2: FrameGpu)"
        ),
        "{}",
        v[0].detail
    );
    // Reaching a re-export through the frame counts too, even though graph/ defines the item.
    let v = check_passes_do_not_import_frame(&renderer(
        "pub fn add() { let _ = super::super::frame::RenderGraph; }\n",
    ));
    assert_eq!(v.len(), 1, "{v:?}");
    // And the pass that uses the frame, which calls the pass, is also a circle.
    let v = check_no_import_circles(&renderer(
        "pub fn add(gpu: crate::frame::FrameGpu) -> crate::frame::FrameGpu { gpu }\n",
    ));
    assert_eq!(v.len(), 1, "{v:?}");
}

#[test]
fn an_unparsable_file_is_reported() {
    let v = circles_of(&[("k/src/lib.rs", "fn (\n")]);
    assert_eq!(v.len(), 1);
    assert!(
        v[0].detail.starts_with("cannot parse k/src/lib.rs:1:"),
        "{}",
        v[0].detail
    );
}
