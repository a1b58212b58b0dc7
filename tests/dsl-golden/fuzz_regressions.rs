// Golden: programs the generated differential test (`cargo xtask fuzz-dsl`) found wrong, shrunk.
// - `^` on `bool`: WGSL has none; naga rejected the printed `b0 ^ b1`. The front end now lowers
//   it to `!=`.
// - Runtime shift amounts: printed masked (`n & 31u`), WGSL's rule, where SPIR-V leaves amounts
//   of 32 or more undefined; a vector amount with a constant component >= 32 then compiles too.
#[shader_dsl::shader]
pub mod fuzz_regressions {
    pub struct Io {
        pub b: UVec4,
        pub i: IVec4,
        pub u: UVec4,
        pub out: UVec4,
    }

    #[storage(group = 0, binding = 0, read_write)]
    static IO: Io;

    #[compute(workgroup_size(1))]
    pub fn main() {
        let b0 = IO.b.x != 0u32;
        let b1 = IO.b.y != 0u32;
        let xor = b0 ^ b1;
        let shifted = IVec4::splat(IO.i.x) >> UVec4::new(IO.u.x, IO.u.y, 65536u32, IO.u.z);
        let left = IO.u.w << IO.u.x;
        IO.out = UVec4::new(
            select(xor, 1u32, 0u32),
            select(xor && b1, 1u32, 0u32),
            shifted.x as u32,
            left,
        );
    }
}
