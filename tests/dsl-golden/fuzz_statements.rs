// Golden: statement programs the generated differential test (`cargo xtask fuzz-dsl
// --statements N`) found wrong, shrunk, or that it now checks:
// - `b ^= c` on `bool` printed as `^=`, which WGSL does not have (naga rejected it). The front
//   end lowers it to `b = b != c`.
// - `for i in 0..n` printed `i < n` as WGSL's condition, re-evaluated every iteration: a body
//   that changes `n` changed the trip count (Rust reads the end once). An end the body could
//   change is now read into a `let` first; a constant end is left in place.
// - `for i in a..=u32::MAX` printed `i <= 4294967295u; i++`, which wraps and never ends. An
//   inclusive range whose end is not a literal below the maximum is now a `loop` whose
//   `continuing` block breaks after the last value.
// - `x >>= n` with a runtime `n` was printed unmasked (undefined in SPIR-V for n >= 32, and a
//   vector amount with a constant lane >= 32 did not compile); compound shifts are masked like
//   `x >> n`.
// - `i32` `abs`: lavapipe took SPIR-V's SAbs to be non-negative and folded
//   `abs(abs(i32::MIN) >> n)` wrongly; it is printed through a `dsl_abs_i32` helper.
#[shader_dsl::shader]
pub mod fuzz_statements {
    pub struct Io {
        pub a: UVec4,
        pub out: UVec4,
    }

    #[storage(group = 0, binding = 0, read_write)]
    static IO: Io;

    #[compute(workgroup_size(1))]
    pub fn main() {
        let mut flag = IO.a.x != 0u32;
        flag ^= IO.a.y != 0u32;
        let mut n = IO.a.z % 8u32;
        let mut trips = 0u32;
        for i in 0..n {
            n += 1u32;
            trips += i;
        }
        let mut top = 0u32;
        for k in (u32::MAX - IO.a.w % 4u32)..=u32::MAX {
            top += 1u32;
            if k == 3u32 {
                continue;
            }
        }
        for k in 1u32..=4u32 {
            top += k;
        }
        let mut bits = IO.a.x as i32;
        bits >>= IO.a.y;
        let mut lanes = UVec2::new(IO.a.z, IO.a.w);
        lanes <<= UVec2::new(IO.a.x, 33u32);
        let magnitude = (bits.abs() >> IO.a.z).abs() + IVec2::splat(bits).abs().x;
        IO.out = UVec4::new(
            select(flag, 1u32, 0u32) + lanes.x + lanes.y,
            trips,
            n + magnitude as u32,
            top,
        );
    }
}
