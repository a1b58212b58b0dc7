//! `u64` and `Atomic<u64>` through the compiler: the printed WGSL (bare 64-bit atomic
//! statements, `lu` literals, sign-extending `i32 as u64`), the `int64` feature exactly where a
//! variant's WGSL has a 64-bit type, the SPIR-V capabilities, the errors at their spans, and the
//! host interpreter's `u64` semantics against plain Rust.

use codegen::interp::{Dispatch, Value};

use super::{check_err, compile};

/// A compute rasteriser's packing, with `u64` arithmetic, casts, shifts and `min`/`max`; the
/// `wide` axis adds the 64-bit binding and code only where it is `true`.
const RASTER: &str = r#"#[shader(axes(wide: bool = [false, true] => "wide"))]
mod raster {
    #[storage(group = 0, binding = 0, read_write)]
    #[when(wide)]
    static VIS64: [Atomic<u64>];
    #[storage(group = 0, binding = 1, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(64))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let id = gid.x;
        if wide {
            let depth_bits = (id as f32 * 0.5).to_bits();
            let packed: u64 = ((depth_bits as u64) << 32u32) | (id as u64);
            VIS64[id].fetch_min(packed);
            let big = 5u64;
            let m = packed.min(big + 1).max(big);
            OUT[id] = (m >> 32u32) as u32 + m as u32;
        } else {
            OUT[id] = id;
        }
    }
}
"#;

/// Whether the SPIR-V declares `OpCapability cap` (opcode 17).
fn has_capability(words: &[u32], cap: u32) -> bool {
    let mut i = 5;
    while i < words.len() {
        let (len, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if op == 17 && words.get(i + 1) == Some(&cap) {
            return true;
        }
        i += len.max(1);
    }
    false
}

const INT64: u32 = 11;
const INT64_ATOMICS: u32 = 12;

#[test]
fn u64_atomics_are_bare_statements_and_only_their_variants_need_int64() {
    let c = compile(RASTER);
    assert_eq!(c.variants.len(), 2);
    let narrow = &c.variants[0];
    let wide = &c.variants[1];
    assert_eq!(wide.names, ["wide"]);
    // No result: the statement form naga lowers with `result: None`, which is what
    // SHADER_INT64_ATOMIC_MIN_MAX allows.
    assert!(
        wide.wgsl.contains("\n    atomicMin(&VIS64[id], packed);\n"),
        "{}",
        wide.wgsl
    );
    assert!(!wide.wgsl.contains("= atomicMin"), "{}", wide.wgsl);
    assert!(wide.wgsl.contains("let big: u64 = 5lu;"), "{}", wide.wgsl);
    assert!(
        wide.wgsl.contains("max(min(packed, big + 1), big)"),
        "{}",
        wide.wgsl
    );
    assert!(wide.reflection.features.int64);
    assert!(has_capability(&wide.spirv, INT64) && has_capability(&wide.spirv, INT64_ATOMICS));
    // Without the binding and the code nothing 64-bit is printed, so the variant is validated
    // without the capabilities and needs none.
    assert!(!narrow.wgsl.contains("u64"), "{}", narrow.wgsl);
    assert!(!narrow.reflection.features.int64);
    assert!(!has_capability(&narrow.spirv, INT64));
    let plain = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(1))]
            fn main() { OUT[0] = 1u32 << 31u32; }
        }",
    );
    assert!(!plain.variants[0].reflection.features.int64);
    // A conversion is all the 64-bit code there is: still validated with SHADER_INT64.
    let cast = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(1))]
            fn main() { OUT[0] = ((OUT[1] as u64) * (OUT[2] as u64) >> 32u32) as u32; }
        }",
    );
    assert!(cast.variants[0].reflection.features.int64);
    assert!(has_capability(&cast.variants[0].spirv, INT64));
}

#[test]
fn u64_literals_cover_64_bits_and_constants_fold() {
    let c = compile(
        "#[shader] mod m {
            const TOP: u64 = (1u64 << 63u32) | 1u64;
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u64];
            #[compute(workgroup_size(1))]
            fn main() {
                OUT[0] = 18446744073709551615u64;
                OUT[1] = u64::MAX - TOP;
                OUT[2] = OUT[0] + 4294967295;
            }
        }",
    );
    let wgsl = &c.variants[0].wgsl;
    assert!(wgsl.contains("OUT[0] = 18446744073709551615lu;"), "{wgsl}");
    // naga's constant evaluator has no `u64` operators: the constant is printed folded.
    assert!(
        wgsl.contains("const TOP: u64 = 9223372036854775809lu;"),
        "{wgsl}"
    );
    assert!(wgsl.contains("OUT[2] = OUT[0] + 4294967295;"), "{wgsl}");
    assert!(c.variants[0].reflection.features.int64);
}

fn kernel(body: &str) -> String {
    format!(
        "#[shader]\nmod m {{\n    #[storage(group = 0, binding = 0, read_write)]\n    static V64: [Atomic<u64>];\n    #[compute(workgroup_size(1))]\n    fn main(#[builtin(global_invocation_id)] gid: UVec3) {{\n{body}\n    }}\n}}\n"
    )
}

#[test]
fn u64_errors_point_at_the_construct() {
    check_err(
        &kernel("        let old = V64[0].fetch_add(1u64);"),
        "`fetch_add` is not available on `Atomic<u64>`: the device's 64-bit atomics (wgpu's SHADER_INT64_ATOMIC_MIN_MAX) are only `fetch_min(v)` and `fetch_max(v)`, without a returned value",
        7,
        25,
    );
    check_err(
        &kernel("        let v = V64[gid.x].load();"),
        "`load` is not available on `Atomic<u64>`",
        7,
        27,
    );
    check_err(
        &kernel("        V64[0].fetch_min(1u32);"),
        "mismatched types: expected `u64`, found `u32`",
        7,
        25,
    );
    check_err(
        "#[shader]\nmod m {\n    #[workgroup]\n    static NEAREST: [Atomic<u64>; 64];\n}\n",
        "`Atomic<u64>` lives only in `#[storage(.., read_write)]` buffers",
        4,
        20,
    );
    check_err(
        &kernel("        let v: U64Vec2 = 0;"),
        "`U64Vec2` is not supported in shader code: the DSL has no vectors of 64-bit integers",
        7,
        15,
    );
    check_err(
        &kernel("        let v = UVec2::new(1u64, 2u32);"),
        "`UVec2::new` takes `u32` components, found `u64`",
        7,
        27,
    );
    check_err(
        &kernel("        let n = 3u64.count_ones();"),
        "`count_ones` is not available on `u64`",
        7,
        21,
    );
    check_err(
        &kernel("        let n = 3u64 << 2u64;"),
        "shift amounts are `u32` (also for a `u64` value)",
        7,
        24,
    );
    check_err(
        &kernel("        let n = 3u64 + 2u32;"),
        "cannot apply `+` to `u64` and `u32`; convert the other side with `as u64`",
        7,
        21,
    );
    check_err(
        &kernel("        let n = 4294967296;"),
        "integer literal out of range for 32 bits; write a `u64` suffix",
        7,
        16,
    );
    check_err(
        "#[shader]\nmod m {\n    #[fragment]\n    fn fs(#[location(0)] #[interpolate(flat)] id: u64) -> Vec4 {\n        Vec4::ZERO\n    }\n}\n",
        "`u64` cannot be a `#[location]` input or output",
        4,
        50,
    );
}

/// `u64` in the host interpreter, against plain Rust with WGSL's rules: wrapping arithmetic,
/// shifts by the amount's low 6 bits, `x / 0 == x`, `i32 as u64` sign-extending, `u64 as u32`
/// truncating and `f32 as u64` saturating; and the atomics with 64-bit and unsuffixed operands.
#[test]
fn the_interpreter_computes_u64_as_wgsl_defines() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0)]
            static IN: [u32];
            #[storage(group = 0, binding = 1, read_write)]
            static OUT: [u64];
            #[storage(group = 0, binding = 2, read_write)]
            static V64: [Atomic<u64>];
            #[compute(workgroup_size(1))]
            fn main() {
                V64[0].fetch_max(4294967296u64);
                V64[0].fetch_min(4294967297u64);
                V64[1].fetch_max(3);
                let a = (IN[0] as u64) << 32u32 | IN[1] as u64;
                let b = IN[2] as u64;
                let s = IN[3];
                OUT[0] = a + a * b - 7;
                OUT[1] = a << s;
                OUT[2] = a >> s;
                OUT[3] = a / (b - b) + a % (b - b);
                OUT[4] = (IN[4] as i32) as u64;
                OUT[5] = ((a as u32) as u64) | ((a as i32 as u32 as u64) << 1u32);
                OUT[6] = (1e30 as u64) + ((-5.0 as u64) << 8u32) + ((a as f32) as u64);
                OUT[7] = select(a > b, a.min(b), a.max(b)) ^ !0u64;
            }
        }",
    );
    let u64s = |b: &[u8]| -> Vec<u64> {
        b.chunks_exact(8)
            .map(|w| u64::from_le_bytes(w.try_into().unwrap()))
            .collect()
    };
    let input = [0xdead_beef_u32, 0x1234_5678, 0x9abc, 70, (-3i32) as u32];
    let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main").unwrap();
    d.set_buffer(
        "IN",
        &input
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect::<Vec<_>>(),
    )
    .unwrap();
    d.set_buffer("OUT", &[0; 64]).unwrap();
    d.set_buffer("V64", &[0; 16]).unwrap();
    d.run([1, 1, 1]).unwrap();
    assert_eq!(u64s(&d.buffer("V64").unwrap()), [1 << 32, 3]);
    let out = u64s(&d.buffer("OUT").unwrap());
    let a = 0xdead_beef_1234_5678_u64;
    let b = 0x9abc_u64;
    let f32_max_below_2_64 = 18_446_742_974_197_923_840_u64;
    let expected = [
        a.wrapping_add(a.wrapping_mul(b)).wrapping_sub(7),
        a << (70 & 63),
        a >> (70 & 63),
        a,
        u64::MAX - 2,
        0x1234_5678 | (0x1234_5678 << 1),
        f32_max_below_2_64.wrapping_add(a as f32 as u64),
        !a.min(b),
    ];
    assert_eq!(out, expected, "{out:x?}");
    assert_eq!(Value::U64(7).to_string(), "7u64");
}
