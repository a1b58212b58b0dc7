//! The `#[shader]` macro end to end: generated host types, key types, variant table and
//! reflection, as user crates see them; and its compile errors: each `tests/ui/*.rs` must fail
//! with the committed `.stderr` (the DSL's message, at the offending span). Re-approve with
//! `TRYBUILD=overwrite`. The suite lives in this crate so that trybuild checks its cases against
//! this crate's few dependencies, not the renderer's.

/// The fixture crate's library resolves from here, so the case naming one it lacks fails for
/// that reason alone.
#[shader_dsl::shader(uses(dsl_library_crate::shared::tint))]
mod uses_the_fixture_library {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [Vec4];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = Vec4::new(tinted(Vec3::ONE).x, 0.0, 0.0, 1.0);
    }
}

#[test]
fn dsl_compile_errors() {
    assert!(!uses_the_fixture_library::MODULE.variants.is_empty());
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}

#[shader_dsl::shader(axes(tile: u32 = [8, 16] => "t", fast: bool = [false, true]), exclude(tile == 8 && fast))]
pub mod smoke {
    pub struct Light {
        pub position: Vec3,
        pub radius: f32,
        pub color: Vec3,
        pub kind: u32,
        pub dir: Vec2,
    }

    pub struct Camera {
        pub view: Mat4,
        pub inner: Light,
        pub count: u32,
    }

    pub struct Extra {
        pub m: Mat3,
        pub lights: [Light; 2],
        pub flags: UVec4,
        pub counter: Atomic<u32>,
    }

    const SCALE: f32 = 2.5;

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[storage(group = 0, binding = 1)]
    static LIGHTS: [Light];
    #[storage(group = 1, binding = 0, read_write)]
    static OUT: [f32];
    #[storage(group = 2, binding = 0, read_write)]
    static EXTRA: Extra;

    #[compute(workgroup_size(tile, 1, 1))]
    pub fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let l = LIGHTS[gid.x];
        let mut v = l.position.length() * SCALE + CAMERA.inner.radius;
        if fast {
            v = v * 2.0;
        }
        OUT[gid.x] = v + EXTRA.m.col(0).x + EXTRA.lights[1].radius;
        EXTRA.counter.fetch_add(1u32);
    }
}

#[test]
fn host_types_have_wgsl_layout() {
    use smoke::{Camera, Light};
    assert_eq!(size_of::<Light>(), 48);
    assert_eq!(std::mem::offset_of!(Light, radius), 12);
    assert_eq!(std::mem::offset_of!(Light, color), 16);
    assert_eq!(std::mem::offset_of!(Light, kind), 28);
    assert_eq!(std::mem::offset_of!(Light, dir), 32);
    assert_eq!(std::mem::offset_of!(Camera, inner), 64);
    // Mat3 columns are 16-byte strided on the GPU; arrays of structs keep the struct stride.
    assert_eq!(size_of::<smoke::Extra>(), 48 + 96 + 16 + 16);
    assert_eq!(std::mem::offset_of!(smoke::Extra, lights), 48);
    assert_eq!(std::mem::offset_of!(smoke::Extra, counter), 160);
    // A struct nested in a uniform buffer is 16-aligned and its size is rounded to 16.
    assert_eq!(size_of::<Camera>(), 128);
    let l = Light::new(glam::Vec3::ONE, 2.0, glam::Vec3::X, 7, glam::Vec2::Y);
    let bytes: &[u8] = bytemuck::bytes_of(&l);
    assert_eq!(bytes.len(), 48);
    assert_eq!(smoke::SCALE, 2.5);
}

#[test]
fn variant_keys_and_lookup() {
    use smoke::{Tile, VariantKey};
    assert_eq!(VariantKey::ALL.len(), 3);
    let key = VariantKey {
        tile: Tile::T16,
        fast: true,
    };
    assert_eq!(key.to_string(), "t16_fast");
    let v = smoke::variant(key).expect("not excluded");
    assert_eq!(v.entry_points[0].workgroup_size, [16, 1, 1]);
    assert!(v.wgsl.contains("@workgroup_size(16, 1, 1)"));
    assert_eq!(v.spirv[0], 0x0723_0203);
    let excluded = smoke::variant(VariantKey {
        tile: Tile::T8,
        fast: true,
    });
    assert!(excluded.is_err());
    assert_eq!(Tile::T8.value(), 8);
    assert_eq!(smoke::MODULE.variants.len(), 3);
    let b = &v.bindings;
    assert_eq!(b.len(), 4);
    assert_eq!((b[2].group, b[2].binding), (1, 0));
    assert!(matches!(
        b[1].kind,
        codegen::rt::BindingKind::Storage {
            read_only: true,
            min_size: 48
        }
    ));
    assert!(b[0].visibility.compute && !b[0].visibility.fragment);
}
