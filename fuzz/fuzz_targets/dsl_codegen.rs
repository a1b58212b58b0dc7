//! libFuzzer entry of the `dsl_codegen` target; the body is `fuzz::dsl_codegen::run_fuzzing`
//! (spans are not checked here: proc-macro2 records none under `--cfg fuzzing`).
#![no_main]

#[global_allocator]
static ALLOCATOR: fuzz::alloc_limit::LimitedAllocator = fuzz::alloc_limit::LimitedAllocator;

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::dsl_codegen::run_fuzzing(data));
