// Golden: `#[builtin(sample_mask)]` input and output. naga 30 writes the SampleMask builtin as a
// scalar, which `spirv-val` rejects; the DSL's SPIR-V step (codegen/src/spirv_fix.rs)
// makes both variables `array<u32, 1>`, and codegen/tests/golden.rs checks the result with
// `spirv-val` and a disassembly snapshot.
#[shader_dsl::shader]
pub mod sample_mask {
    pub struct FsOut {
        #[location(0)]
        pub color: Vec4,
        #[builtin(sample_mask)]
        pub mask: u32,
    }

    #[fragment]
    pub fn fs(#[builtin(sample_mask)] coverage: u32, #[builtin(sample_index)] sample: u32) -> FsOut {
        FsOut { color: Vec4::ONE, mask: coverage & (1u32 << sample) }
    }
}
