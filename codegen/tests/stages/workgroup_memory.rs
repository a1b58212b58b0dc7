//! Each entry point's workgroup memory as WebGPU's `maxComputeWorkgroupStorageSize` counts it:
//! the workgroup variables it uses (directly or through the functions it calls), each rounded
//! up to 16 bytes; a variable only another entry point uses is not counted. And
//! `uniform_load()`, which only workgroup statics (and their elements and fields) take.

use super::compile;

const TILES: &str = r#"#[shader(axes(tile: u32 = [8, 16] => "t"))]
mod tiles {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [f32];
    #[workgroup]
    static DEPTHS: [f32; tile * tile];
    #[workgroup]
    static COUNT: Atomic<u32>;
    #[workgroup]
    static OTHER: [Vec4; 100];

    fn count_one() {
        COUNT.fetch_add(1u32);
    }

    #[compute(workgroup_size(tile, tile, 1))]
    fn reduce(#[builtin(local_invocation_index)] i: u32) {
        DEPTHS[i] = 1.0;
        count_one();
        workgroup_barrier();
        OUT[i] = DEPTHS[0];
    }

    #[compute(workgroup_size(64))]
    fn other(#[builtin(local_invocation_index)] i: u32) {
        OTHER[i] = Vec4::ZERO;
        OUT[i] = OTHER[0].x;
    }

    #[compute(workgroup_size(64))]
    fn none(#[builtin(local_invocation_index)] i: u32) {
        OUT[i] = 0.0;
    }
}
"#;

#[test]
fn workgroup_memory_counts_what_each_entry_point_uses_rounded_to_16_bytes() {
    let c = compile(TILES);
    let memory = |variant: usize| -> Vec<(String, u32)> {
        c.variants[variant]
            .reflection
            .entry_points
            .iter()
            .map(|e| (e.name.clone(), e.workgroup_memory))
            .collect()
    };
    // Tile 8: 64 depths (256 bytes) and the counter (4, counted as 16), through `count_one`.
    assert_eq!(
        memory(0),
        [
            ("reduce".into(), 256 + 16),
            ("other".into(), 1600),
            ("none".into(), 0)
        ]
    );
    // Tile 16: 256 depths (1,024 bytes).
    assert_eq!(memory(1)[0], ("reduce".into(), 1024 + 16));
}

#[test]
fn uniform_load_reads_workgroup_statics_only() {
    let module = |body: &str| {
        format!(
            "#[shader]\nmod m {{\n    #[storage(group = 0, binding = 0, read_write)]\n    static OUT: [u32];\n    #[workgroup]\n    static W: [u32; 4];\n    #[compute(workgroup_size(4))]\n    fn main() {{\n        {body}\n    }}\n}}\n"
        )
    };
    // An element of a workgroup array loads; a storage element and a local do not.
    let ok = compile(&module("OUT[0] = W[1].uniform_load();"));
    assert!(ok.variants[0].wgsl.contains("workgroupUniformLoad(&W[1])"));
    super::check_err(
        &module("OUT[0] = OUT[1].uniform_load();"),
        "`uniform_load()` reads a `#[workgroup]` static",
        9,
        17,
    );
    super::check_err(
        &module("let x = 1u32;\n        OUT[0] = x.uniform_load();"),
        "`uniform_load()` reads a `#[workgroup]` static",
        10,
        17,
    );
    super::check_err(
        &module("OUT[0] = W.uniform_load(1u32);"),
        "uniform_load",
        9,
        17,
    );
}
