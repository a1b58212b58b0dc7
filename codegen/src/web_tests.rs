//! The web checks on hand-built variants: each limit at its edge and one past it.

use super::*;
use crate::rt::{Binding, EntryPoint, Features, Visibility};

const COMPUTE: Visibility = Visibility {
    compute: true,
    vertex: false,
    fragment: false,
};
const VERTEX: Visibility = Visibility {
    compute: false,
    vertex: true,
    fragment: false,
};

fn storage(name: &'static str, binding: u32, read_only: bool, visibility: Visibility) -> Binding {
    Binding {
        name,
        group: 0,
        binding,
        visibility,
        kind: BindingKind::Storage {
            read_only,
            min_size: 4,
        },
    }
}

fn kernel(size: [u32; 3], workgroup_memory: u32) -> EntryPoint {
    EntryPoint {
        name: "main",
        stage: Stage::Compute,
        workgroup_size: size,
        workgroup_memory,
        inputs: &[],
        outputs: &[],
    }
}

fn variant(
    entry_points: &'static [EntryPoint],
    bindings: &'static [Binding],
    features: Features,
) -> Variant {
    Variant {
        module: "m",
        names: &["v"],
        wgsl: "@compute @workgroup_size(1) fn main() {}\n",
        spirv: &[],
        spirv_version: (1, 0),
        entry_points,
        bindings,
        features,
    }
}

fn leak<T>(v: Vec<T>) -> &'static [T] {
    Vec::leak(v)
}

#[test]
fn a_kernel_at_every_default_limit_fits_and_one_past_each_does_not() {
    let d = WebLimits::DEFAULT;
    let at_limit = leak(vec![kernel([16, 16, 1], 16_384)]);
    let buffers = leak((0..8).map(|i| storage("b", i, false, COMPUTE)).collect());
    let fits = variant(at_limit, buffers, Features::default());
    assert_eq!(web_issues(&fits, &d), vec![]);

    let over = leak(vec![kernel([32, 32, 1], 16_400)]);
    let nine = leak((0..9).map(|i| storage("b", i, false, COMPUTE)).collect());
    let v = variant(over, nine, Features::default());
    let issues = web_issues(&v, &d);
    assert_eq!(
        issues,
        vec![
            WebIssue::Invocations {
                entry: "main",
                invocations: 1024,
                max: 256
            },
            WebIssue::WorkgroupStorage {
                entry: "main",
                bytes: 16_400,
                max: 16_384
            },
            WebIssue::PerStage {
                stage: Stage::Compute,
                kind: "storage buffers",
                count: 9,
                max: 8
            },
        ]
    );
    assert!(issues.iter().all(WebIssue::is_limit));
    // The same variant against an adapter's larger limits (SwiftShader's in Chromium).
    let larger = WebLimits {
        invocations_per_workgroup: 1024,
        workgroup_size: [1024, 1024, 64],
        workgroup_storage: 32_768,
        storage_buffers_per_stage: 10,
        ..d
    };
    assert_eq!(web_issues(&v, &larger), vec![]);
}

#[test]
fn an_axis_over_its_own_limit_and_a_fifth_group_are_issues() {
    let tall = leak(vec![kernel([1, 1, 65], 0)]);
    let far = leak(vec![Binding {
        group: 4,
        ..storage("far", 0, true, COMPUTE)
    }]);
    let issues = web_issues(
        &variant(tall, far, Features::default()),
        &WebLimits::DEFAULT,
    );
    assert_eq!(
        issues,
        vec![
            WebIssue::WorkgroupSize {
                entry: "main",
                size: [1, 1, 65],
                max: [256, 256, 64]
            },
            WebIssue::BindGroups { count: 5, max: 4 },
        ]
    );
}

#[test]
fn int64_and_writable_vertex_storage_are_not_limits() {
    let ep = leak(vec![kernel([64, 1, 1], 0)]);
    let read = leak(vec![storage("positions", 0, true, VERTEX)]);
    let fits = variant(ep, read, Features::default());
    assert_eq!(web_issues(&fits, &WebLimits::DEFAULT), vec![]);
    let written = leak(vec![storage("positions", 0, false, VERTEX)]);
    let int64 = Features {
        int64: true,
        ..Features::default()
    };
    let issues = web_issues(&variant(ep, written, int64), &WebLimits::DEFAULT);
    assert_eq!(
        issues,
        vec![
            WebIssue::Int64,
            WebIssue::WritableInVertex {
                binding: "positions"
            }
        ]
    );
    assert!(issues.iter().all(|i| !i.is_limit()));
    assert_eq!(
        issues[1].to_string(),
        "`positions` is writable and seen by the vertex stage"
    );
}

#[test]
fn browser_wgsl_enables_subgroups_only_where_the_variant_uses_them() {
    let ep = leak(vec![kernel([64, 1, 1], 0)]);
    let plain = variant(ep, &[], Features::default());
    assert_eq!(browser_wgsl(&plain), plain.wgsl);
    let subgroup = variant(
        ep,
        &[],
        Features {
            subgroup: true,
            ..Features::default()
        },
    );
    assert_eq!(
        browser_wgsl(&subgroup),
        format!(
            "enable subgroups;\ndiagnostic(off, subgroup_uniformity);\n{}",
            subgroup.wgsl
        )
    );
}
