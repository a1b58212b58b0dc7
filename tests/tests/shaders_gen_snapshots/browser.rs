//! Every `shaders_gen` variant in a real browser: headless Chromium (Tint and Dawn, on its
//! SwiftShader Vulkan driver) compiles each variant's browser WGSL (`codegen::web::browser_wgsl`),
//! builds its bind group and pipeline layouts from the variant's reflected bindings, and makes
//! a pipeline of each compute entry point, on a device with WebGPU's default limits and on one
//! with the adapter's (`tests/web/compile_variants.html`).
//!
//! Chromium is the reference `codegen::web::web_issues` is checked against, both ways: a variant
//! runs on a device exactly where the check finds nothing beyond that device's limits. Every
//! variant without 64-bit integers must compile, and every one with them must not (WebGPU has
//! none). Chromium found what naga cannot check: the light-culling kernels ran barriers in
//! control flow that depended on reads WGSL's uniformity analysis cannot prove uniform (a
//! `read_write` buffer, workgroup atomics; now shared with `uniform_load()`), and the
//! scalarized variants' subgroup operations needed `diagnostic(off, subgroup_uniformity)`. A
//! mutation that leaves `enable subgroups;` out fails here (every subgroup variant disagrees);
//! the limits' edges are the unit tests' (`codegen/src/web_tests.rs`, which fail with the
//! per-stage count off by one).

use std::time::Duration;

use codegen::rt::{BindingKind, SampleType, StorageAccess, Variant, ViewDimension};
use codegen::web::{WebLimits, browser_wgsl, web_issues};
use serde_json::{Value, json};
use tests::browser::{ServedFile, run_page};

/// The page's time to compile every variant on two devices on SwiftShader (measured: the whole
/// test takes about 160 s on a 2-core machine), with room for a loaded one.
const PAGE_TIMEOUT: Duration = Duration::from_secs(480);

/// A binding as a `GPUBindGroupLayoutEntry`'s resource member.
fn layout_entry(kind: &BindingKind) -> Value {
    let dimension = |d: &ViewDimension| match d {
        ViewDimension::D2Array => "2d-array",
        _ => "2d",
    };
    match kind {
        BindingKind::Uniform { .. } => json!({ "buffer": { "type": "uniform" } }),
        BindingKind::Storage { read_only, .. } => json!({ "buffer": {
            "type": if *read_only { "read-only-storage" } else { "storage" }
        } }),
        BindingKind::Texture {
            sample_type,
            view_dimension,
            multisampled,
        } => {
            let sample = match sample_type {
                SampleType::Float { filterable: true } => "float",
                SampleType::Float { filterable: false } => "unfilterable-float",
                SampleType::Depth => "depth",
                SampleType::Uint => "uint",
                SampleType::Sint => "sint",
            };
            json!({ "texture": {
                "sampleType": sample,
                "viewDimension": dimension(view_dimension),
                "multisampled": multisampled,
            } })
        }
        BindingKind::StorageTexture {
            format,
            access,
            view_dimension,
        } => json!({ "storageTexture": {
            "access": match access {
                StorageAccess::ReadOnly => "read-only",
                StorageAccess::WriteOnly => "write-only",
                StorageAccess::ReadWrite => "read-write",
            },
            "format": format!("{format:?}").to_lowercase(),
            "viewDimension": dimension(view_dimension),
        } }),
        // Non-filtering samplers may sample any float texture, filterable or not.
        BindingKind::Sampler { comparison } => json!({ "sampler": {
            "type": if *comparison { "comparison" } else { "non-filtering" }
        } }),
    }
}

/// The variant as the page reads it.
fn variant_json(module: &str, v: &Variant) -> Value {
    let bindings: Vec<Value> = v
        .bindings
        .iter()
        .map(|b| {
            // GPUShaderStage: VERTEX 1, FRAGMENT 2, COMPUTE 4.
            let vis = b.visibility;
            let stages =
                u32::from(vis.vertex) | u32::from(vis.fragment) << 1 | u32::from(vis.compute) << 2;
            json!({ "group": b.group, "binding": b.binding, "visibility": stages,
                    "entry": layout_entry(&b.kind) })
        })
        .collect();
    let compute: Vec<&str> = v
        .entry_points
        .iter()
        .filter(|e| e.stage == codegen::rt::Stage::Compute)
        .map(|e| e.name)
        .collect();
    json!({ "module": module, "name": v.name(), "wgsl": browser_wgsl(v),
            "bindings": bindings, "compute": compute })
}

/// The adapter's limits, as the page read them.
fn limits_of(page: &Value) -> WebLimits {
    let limit = |name: &str| {
        page["limits"][name]
            .as_u64()
            .and_then(|n| u32::try_from(n).ok())
            .unwrap_or_else(|| panic!("the page reports {name}"))
    };
    WebLimits {
        invocations_per_workgroup: limit("maxComputeInvocationsPerWorkgroup"),
        workgroup_size: [
            limit("maxComputeWorkgroupSizeX"),
            limit("maxComputeWorkgroupSizeY"),
            limit("maxComputeWorkgroupSizeZ"),
        ],
        workgroup_storage: limit("maxComputeWorkgroupStorageSize"),
        bind_groups: limit("maxBindGroups"),
        storage_buffers_per_stage: limit("maxStorageBuffersPerShaderStage"),
        storage_textures_per_stage: limit("maxStorageTexturesPerShaderStage"),
        sampled_textures_per_stage: limit("maxSampledTexturesPerShaderStage"),
        samplers_per_stage: limit("maxSamplersPerShaderStage"),
        uniform_buffers_per_stage: limit("maxUniformBuffersPerShaderStage"),
    }
}

/// Whether the page found nothing wrong with a variant on one device, and what it found.
fn outcome(result: &Value) -> (bool, String) {
    let compile: Vec<&str> = result["compile"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let pipelines: Vec<&str> = result["pipelines"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let layout = result["layout"].as_str();
    let ok = compile.is_empty() && layout.is_none() && pipelines.is_empty();
    let what = format!("compile {compile:?}, layout {layout:?}, pipelines {pipelines:?}");
    (ok, what)
}

#[test]
fn every_variant_runs_in_chromium_exactly_where_the_web_check_says() {
    let variants: Vec<(&str, &Variant)> = shaders_gen::MODULES
        .iter()
        .flat_map(|m| m.variants.iter().map(move |v| (m.name, v)))
        .collect();
    let listed: Vec<Value> = variants.iter().map(|(m, v)| variant_json(m, v)).collect();
    let files = vec![
        ServedFile {
            path: "index.html".into(),
            content_type: "text/html",
            bytes: include_bytes!("../../web/compile_variants.html").to_vec(),
        },
        ServedFile {
            path: "variants.json".into(),
            content_type: "application/json",
            bytes: serde_json::to_vec(&listed).expect("JSON"),
        },
    ];
    let posted = run_page(files, "index.html", PAGE_TIMEOUT).unwrap_or_else(|e| panic!("{e}"));
    let page: Value = serde_json::from_str(&posted).expect("the page posts JSON");
    if let Some(fatal) = page["fatal"].as_str() {
        panic!("the page failed: {fatal}");
    }
    let raised = limits_of(&page);
    eprintln!(
        "Chromium's adapter: {}, features {}, limits {raised:?}",
        page["adapter"], page["features"]
    );
    let results = page["results"].as_array().expect("results");
    assert_eq!(results.len(), variants.len(), "a result per variant");
    let mut wrong = Vec::new();
    let (mut fit_defaults, mut fit_raised) = (0, 0);
    for ((module, v), result) in variants.iter().zip(results) {
        let what = format!("{module}@{}", v.name());
        assert_eq!(
            result["name"].as_str(),
            Some(v.name()),
            "{what}: results in order"
        );
        for (device, limits) in [("defaults", WebLimits::DEFAULT), ("raised", raised)] {
            let (ok, found) = outcome(&result[device]);
            let issues = web_issues(v, &limits);
            let compiles = result[device]["compile"]
                .as_array()
                .is_some_and(Vec::is_empty);
            if compiles == v.features.int64 {
                wrong.push(format!(
                    "{what} ({device}): compiles {compiles} with int64 {}: {found}",
                    v.features.int64
                ));
            }
            if ok != issues.is_empty() {
                let issues: Vec<String> = issues.iter().map(ToString::to_string).collect();
                wrong.push(format!(
                    "{what} ({device}): Chromium {found}; the check: {issues:?}"
                ));
            }
            match (device, ok) {
                ("defaults", true) => fit_defaults += 1,
                ("raised", true) => fit_raised += 1,
                _ => {}
            }
        }
    }
    eprintln!(
        "{} variants: {fit_defaults} run with WebGPU's default limits, {fit_raised} with the \
         adapter's",
        variants.len()
    );
    assert!(
        wrong.is_empty(),
        "{} disagreements between Chromium and codegen::web:\n{}",
        wrong.len(),
        wrong.join("\n")
    );
    // 94 of 121 when written; the rest need 64-bit integers or more of a limit.
    assert!(
        fit_defaults * 2 > variants.len(),
        "most variants run in a browser ({fit_defaults} of {})",
        variants.len()
    );
}
